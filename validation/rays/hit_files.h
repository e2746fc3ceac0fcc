// A tracer's answers as files (docs/TRACE_FORMAT.md): PREFIX.t.npy, float32 (N,), +inf on a
// miss, and PREFIX.prim.npy, int32 (N,), -1 on a miss, one entry per row of the ray file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/ray.h"

namespace oct {

// A tracer's answers, one per ray: PREFIX.t.npy and PREFIX.prim.npy (docs/TRACE_FORMAT.md).
struct HitArrays {
    std::vector<float> t;       // +inf on a miss
    std::vector<int32_t> prim;  // -1 on a miss; empty when primIds is false
    bool primIds = true;        // false: certify distances only (--no-prim)
    uint64_t count() const { return t.size(); }
    Hit at(uint64_t i) const { return {t[i], primIds ? prim[i] : int32_t(-1)}; }
};

std::string hitTPath(const std::string& prefix);     // PREFIX.t.npy
std::string hitPrimPath(const std::string& prefix);  // PREFIX.prim.npy

// Reads the answers for `rays` rays (`raysPath` names the ray file in messages); without
// primIds only PREFIX.t.npy. Throws IoError with one line naming the file, what it holds
// (dtype, shape) and what is expected, for a missing or unreadable file, another dtype (any
// byte order or width other than <f4 / <i4), another shape than (N,), or another length.
// The values are not judged here: NaN, negative t or huge ids are the certification's findings.
HitArrays readHitFiles(const std::string& prefix, uint64_t rays, const std::string& raysPath,
                       bool primIds = true);

}  // namespace oct
