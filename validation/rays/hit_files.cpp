#include "validation/rays/hit_files.h"

#include <cstring>

#include "core/io/npy.h"

namespace oct {
namespace {

std::string shapeText(const std::vector<uint64_t>& shape) {
    std::string s = "(";
    for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

// The array of one file, checked against what certify expects.
NpyArray readColumn(const std::string& path, const char* descr, const char* what, uint64_t n,
                    const std::string& raysPath) {
    // Checked on the header, before the data are read.
    return readNpy(path, "hits", [&](const NpyArray& a) {
        if (a.descr != descr || a.shape.size() != 1 || a.shape[0] != n)
            throw IoError("'" + path + "' holds dtype " + a.descr + " shape " + shapeText(a.shape) +
                          "; expected " + what + " (" + descr + ") of shape (" + std::to_string(n) +
                          ",), one per row of '" + raysPath + "' (docs/TRACE_FORMAT.md)");
    });
}

}  // namespace

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
        h.prim.resize(rays);
        if (rays) std::memcpy(h.prim.data(), p.data.data(), size_t(rays) * sizeof(int32_t));
    }
    return h;
}

}  // namespace oct
