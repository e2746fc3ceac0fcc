#include "validation/rays/verdict_files.h"

#include <cstring>

#include "core/io/npy.h"
#include "core/io/output_file.h"

namespace oct {
namespace {

constexpr uint8_t kClassValues = 5, kLeakValues = 5;  // HitClass, LeakState

template <class T>
std::vector<T> readColumn(const std::string& path, const char* descr, uint64_t rows) {
    const NpyArray a = readNpy(path);
    if (a.descr != descr || a.shape.size() != 1)
        throw IoError(path + ": holds " + a.descr + " of " + std::to_string(a.shape.size()) +
                      " dimensions; a verdict file of octrace certify --verdicts is " + descr +
                      " (N,)");
    if (a.shape[0] != rows)
        throw IoError(path + ": " + std::to_string(a.shape[0]) + " rows, but the ray file has " +
                      std::to_string(rows) + ": give the verdicts of the same ray file");
    std::vector<T> out(rows);
    if (rows) std::memcpy(out.data(), a.data.data(), rows * sizeof(T));
    return out;
}

void checkRange(const std::string& path, const std::vector<uint8_t>& v, uint8_t values) {
    for (size_t i = 0; i < v.size(); ++i)
        if (v[i] >= values)
            throw IoError(path + ": row " + std::to_string(i) + " holds " + std::to_string(v[i]) +
                          ", not a value of its kind (0.." + std::to_string(values - 1) + ")");
}

}  // namespace

std::string verdictClassPath(const std::string& prefix) { return prefix + ".class.npy"; }
std::string verdictReasonsPath(const std::string& prefix) { return prefix + ".reasons.npy"; }
std::string verdictLeakPath(const std::string& prefix) { return prefix + ".leak.npy"; }

void writeVerdictFiles(const std::string& prefix, const VerdictArrays& v) {
    const std::vector<uint64_t> shape = {uint64_t(v.cls.size())};
    OutputSet out;
    stageNpy(out, verdictClassPath(prefix), "|u1", shape, v.cls.data(), 1);
    stageNpy(out, verdictReasonsPath(prefix), "<u4", shape, v.reasons.data(), 4);
    stageNpy(out, verdictLeakPath(prefix), "|u1", shape, v.leak.data(), 1);
    out.commit();
}

VerdictArrays readVerdictFiles(const std::string& prefix, uint64_t rows) {
    VerdictArrays v;
    v.cls = readColumn<uint8_t>(verdictClassPath(prefix), "|u1", rows);
    checkRange(verdictClassPath(prefix), v.cls, kClassValues);
    v.reasons = readColumn<uint32_t>(verdictReasonsPath(prefix), "<u4", rows);
    v.leak = readColumn<uint8_t>(verdictLeakPath(prefix), "|u1", rows);
    checkRange(verdictLeakPath(prefix), v.leak, kLeakValues);
    return v;
}

}  // namespace oct
