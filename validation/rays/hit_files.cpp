#include "validation/rays/hit_files.h"

#include <sys/stat.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "core/io/input_file.h"
#include "core/io/npy.h"
#include "validation/rays/ray_sets.h"

namespace oct {
namespace {

// The array of one file, checked against what certify expects.
NpyArray readColumn(const std::string& path, const char* descr, const char* what, uint64_t n,
                    const std::string& raysPath) {
    // Checked on the header, before the data are read.
    return readNpy(path, "hits", [&](const NpyArray& a) {
        if (a.descr != descr || a.shape.size() != 1 || a.shape[0] != n)
            throw IoError("'" + path + "' holds dtype " + a.descr + " shape " +
                          npyShapeText(a.shape) + "; expected " + what + " (" + descr +
                          ") of shape (" + std::to_string(n) + ",), one per row of '" + raysPath +
                          "' (docs/TRACE_FORMAT.md)");
    });
}

constexpr uint64_t kMaxRecordBytes = 64 * 1024;

// 64 random bits, as 16 hex digits: tells one run from another in the record and the messages.
std::string randomRunId() {
    uint64_t v = 0;
    randomBytes(&v, sizeof v);
    return hex64(v);
}

std::string fileName(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// What the record says of one file: its data's hash and the identity the file had when trace
// renamed it into place.
struct Vouched {
    std::string hash;
    uint64_t inode = 0;
    int64_t mtimeNs = 0;
};

struct RunRecord {
    std::string run;  // the run id
    Vouched t, prim;
};

RunRecord readRunRecord(const std::string& path) {
    const char* hint =
        "written by octrace trace beside its pair; remove it if the pair is not "
        "octrace's";
    const std::string bytes = readSmallInput(path, "the hits record", kMaxRecordBytes, hint);
    const nlohmann::json j = nlohmann::json::parse(bytes, nullptr, false);
    auto text = [&](const nlohmann::json& o, const char* key) {
        if (!o.is_object() || !o.contains(key) || !o[key].is_string())
            throw IoError("hits record '" + path + "': no text '" + key + "' (" + hint + ")");
        return o[key].get<std::string>();
    };
    if (j.is_discarded() || !j.is_object())
        throw IoError("hits record '" + path + "' is not JSON (" + hint + ")");
    if (text(j, "format") != "octrace-hits")
        throw IoError("hits record '" + path + "': 'format' is not \"octrace-hits\" (" + hint +
                      ")");
    auto file = [&](const char* key) {
        const nlohmann::json o = j.value(key, nlohmann::json());
        Vouched v;
        v.hash = text(o, "fnv1a64");
        if (!o["inode"].is_number_unsigned() || !o["mtime_ns"].is_number_integer())
            throw IoError("hits record '" + path + "': no 'inode' and 'mtime_ns' for '" + key +
                          "' (" + hint + ")");
        v.inode = o["inode"].get<uint64_t>();
        v.mtimeNs = o["mtime_ns"].get<int64_t>();
        return v;
    };
    RunRecord r;
    r.run = text(j, "octrace_run");
    r.t = file("t");
    r.prim = file("prim");
    return r;
}

// A file the record vouches for: the same file trace renamed into place (inode and mtime: a
// file written anew, renamed over it or rewritten in place is another) with the same data.
bool vouchedFor(const Vouched& v, const std::string& path, const NpyArray& a) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return false;
    const int64_t mtimeNs = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
    return uint64_t(st.st_ino) == v.inode && mtimeNs == v.mtimeNs &&
           hex64(fnv1a64(a.data.data(), a.data.size())) == v.hash;
}

// The check readHitFiles makes with both arrays read (hit_files.h).
void checkSameRun(const std::string& prefix, const NpyArray& t, const NpyArray& prim) {
    const std::string recordPath = hitRunPath(prefix);
    struct stat st;
    if (::lstat(recordPath.c_str(), &st) != 0) return;  // not octrace trace's pair: no record
    const RunRecord r = readRunRecord(recordPath);
    const bool tOurs = vouchedFor(r.t, hitTPath(prefix), t);
    const bool primOurs = vouchedFor(r.prim, hitPrimPath(prefix), prim);
    if (tOurs == primOurs) return;
    const std::string vouched = tOurs ? hitTPath(prefix) : hitPrimPath(prefix);
    const std::string other = tOurs ? hitPrimPath(prefix) : hitTPath(prefix);
    throw IoError("'" + hitTPath(prefix) + "' and '" + hitPrimPath(prefix) +
                  "' are not the pair one run wrote: '" + recordPath + "' (octrace trace run " +
                  r.run + ") vouches for '" + vouched + "' but not for '" + other +
                  "', which another run or program has written since; trace again into one "
                  "prefix, or remove the record if another tracer wrote both files");
}

}  // namespace

std::string hitRunPath(const std::string& prefix) { return prefix + ".run.json"; }

std::string hitRunRecord(const std::string& prefix, const float* t, const int32_t* prim,
                         uint64_t rows, const OutputSet& staged) {
    const size_t bytes = size_t(rows) * 4;
    auto file = [&](const std::string& path, const void* data) {
        const OutputSet::Stamp st = staged.stamp(path);
        return nlohmann::ordered_json{{"file", fileName(path)},
                                      {"fnv1a64", hex64(fnv1a64(data, bytes))},
                                      {"inode", st.inode},
                                      {"mtime_ns", st.mtimeNs}};
    };
    const nlohmann::ordered_json j = {
        {"format", "octrace-hits"},       {"version", 1},
        {"octrace_run", randomRunId()},   {"rows", rows},
        {"t", file(hitTPath(prefix), t)}, {"prim", file(hitPrimPath(prefix), prim)}};
    return j.dump(2) + "\n";
}

std::string hitTPath(const std::string& prefix) { return prefix + ".t.npy"; }
std::string hitPrimPath(const std::string& prefix) { return prefix + ".prim.npy"; }

HitArrays readHitFiles(const std::string& prefix, uint64_t rays, const std::string& raysPath,
                       bool primIds) {
    HitArrays h;
    h.primIds = primIds;
    NpyArray t = readColumn(hitTPath(prefix), "<f4", "float32 distances", rays, raysPath);
    h.t.resize(rays);
    if (rays) std::memcpy(h.t.data(), t.data.data(), size_t(rays) * sizeof(float));
    if (primIds) {
        NpyArray p = readColumn(hitPrimPath(prefix), "<i4", "int32 primitive ids", rays, raysPath);
        checkSameRun(prefix, t, p);
        h.prim.resize(rays);
        if (rays) std::memcpy(h.prim.data(), p.data.data(), size_t(rays) * sizeof(int32_t));
    }
    return h;
}

}  // namespace oct
