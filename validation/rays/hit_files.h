// A tracer's answers as files (docs/TRACE_FORMAT.md): PREFIX.t.npy, float32 (N,), +inf on a
// miss, and PREFIX.prim.npy, int32 (N,), -1 on a miss, one entry per row of the ray file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/ray.h"
#include "core/io/output_file.h"

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
std::string hitRunPath(const std::string& prefix);   // PREFIX.run.json

// The record `octrace trace` writes beside its pair, in the same set of outputs, so that certify
// can tell a pair from two runs (one run's t, another's prim: whole files of the right length)
// from a pair one run wrote:
//   {"format": "octrace-hits", "version": 1, "octrace_run": "<16 hex digits, random>",
//    "rows": N, "t": {"file": "PREFIX.t.npy", "fnv1a64": "<16 hex digits>", "inode": I,
//                     "mtime_ns": T},
//    "prim": {...the same for PREFIX.prim.npy}}
// fnv1a64 is the hash of each file's data section (the array's bytes after the .npy header);
// inode and mtime_ns are the file's as staged in `staged` (a rename keeps both). A file is
// vouched for when all three still hold: another tracer that finds the same ids writes a new
// file (or rewrites this one), so its pair is judged, while a pair from two octrace runs has one
// file the record vouches for and one it does not, and is refused.
// A sidecar file rather than a key in the .npy headers: numpy refuses a header dict with any
// key beyond descr, fortran_order and shape ("Header does not contain the correct keys").
std::string hitRunRecord(const std::string& prefix, const float* t, const int32_t* prim,
                         uint64_t rows, const OutputSet& staged);

// Reads the answers for `rays` rays (`raysPath` names the ray file in messages); without
// primIds only PREFIX.t.npy. Throws IoError with one line naming the file, what it holds
// (dtype, shape) and what is expected, for a missing or unreadable file, another dtype (any
// byte order or width other than <f4 / <i4), another shape than (N,), or another length.
// With primIds and PREFIX.run.json beside the pair (hitRunRecord): a pair where the record
// vouches for one file and not the other is refused, naming both (one of them was written by
// another run or program since). A record that vouches for neither says nothing about this pair
// (another tracer wrote both over octrace's) and is ignored, as is a pair without one (every
// tracer but octrace trace). The values are not judged here: NaN, negative t or huge ids are
// the certification's findings.
HitArrays readHitFiles(const std::string& prefix, uint64_t rays, const std::string& raysPath,
                       bool primIds = true);

}  // namespace oct
