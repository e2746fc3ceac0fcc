// Ray files (docs/TRACE_FORMAT.md): a NumPy .npy file, little-endian float32 ('<f4'), C order,
// shape (N, 8), row i = ox oy oz dx dy dz tmin tmax. `octrace trace` reads them, and every
// command that takes a user's rays uses this one reader and this one row rule.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/io/output_file.h"

namespace oct {

// Reads the file in one pass, straight into the returned buffer (N * 8 floats; no second copy),
// and checks every row with rayRowProblem. Throws IoError with one line naming the path and:
//  - a path that is not a regular file (a FIFO, a device, a directory, a socket; also through a
//    symlink): refused without reading, so a FIFO without a writer cannot block and /dev/zero
//    cannot be read forever;
//  - a bad .npy preamble or header (versions 1.0, 2.0 and 3.0; keys and strings in single or
//    double quotes), Fortran order, a dtype or shape other than '<f4' (N, 8) (both named), a
//    data size that disagrees with the shape (checked before allocating, overflow-safe), a file
//    that changes size while read;
//  - the first row that breaks the rule, as "row I" counted from 0.
std::vector<float> readRayFile(const std::string& path);

// The same reader into storage of the caller's: allocate(rows) returns room for rows * 8 floats,
// which the file's bytes then fill (so it need not be zeroed: trace passes new float[]).
// Returns the row count.
uint64_t readRayFileInto(const std::string& path, const std::function<float*(uint64_t)>& allocate);

// One MPI rank's rows of the file (dist/): rowsOf(N), given the row count N the header declares,
// names the rows to read as spans in row order, and allocate(their total) the room, which they
// fill span after span (a seek each): no rank holds all rays. The header and the data size are
// checked as readRayFileInto checks them; the rows are checked by the rule as they are read
// when `firstBad` is given, which then receives the lowest bad row among those read, counted
// in the packed buffer (their total when none): the ranks then agree on the lowest bad row, so
// the run names the row a whole read names. Returns N.
struct RowSpan {
    uint64_t begin = 0, end = 0;
};
uint64_t readRayFileRowsInto(const std::string& path,
                             const std::function<std::vector<RowSpan>(uint64_t rows)>& rowsOf,
                             const std::function<float*(uint64_t)>& allocate,
                             uint64_t* firstBad = nullptr);

// Why row r (8 floats) cannot be traced, or "" when it can. The rule (the numeric range of
// core/geometry/numeric_range.h, the same for every backend): the origin finite and within
// +-kMaxRayOrigin; the direction finite with its largest |component| within
// [kMinRayDirection, kMaxRayDirection]; tmin finite and >= 0 (Embree, the ground truth, takes
// no negative tmin); tmax not NaN and >= tmin (+inf allowed).
std::string rayRowProblem(const float* r);
// Every row of rays (rows x 8 floats) by that rule, as the reader checks a file's: throws IoError
// "WHAT row I: why" for the first that breaks it (`what` names the rays: the file in quotes).
void checkRayRows(const float* rays, uint64_t rows, const std::string& what);
// What checkRayRows throws for row r (8 floats), the file's row `row`.
std::string badRayRowMessage(const std::string& what, uint64_t row, const float* r);

}  // namespace oct
