#include "core/io/ray_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "core/geometry/numeric_range.h"
#include "core/io/input_file.h"
#include "core/io/npy.h"

namespace oct {
namespace {

// The data are read straight into floats: '<f4' is the host's own layout.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "ray files are read on little-endian hosts");

[[noreturn]] void bad(const std::string& path, const std::string& why) {
    throw IoError("'" + path + "' is not a valid .npy file: " + why);
}

std::string number(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

}  // namespace

namespace {

// Which part of the rule a row breaks: the rule itself, decided with a few compares and no
// message, which only the one row reported needs (rayRowProblem).
enum class RowFault { None, Origin, Direction, ZeroDirection, DirectionRange, Tmin, Tmax };

// The bounds as float32, the type of the file: 1e-19 written by numpy is float(1e-19).
const float kMaxOriginF = float(kMaxRayOrigin);
const float kMinDirectionF = float(kMinRayDirection), kMaxDirectionF = float(kMaxRayDirection);

float largestDirection(const float* r) {
    return std::max(std::max(std::fabs(r[3]), std::fabs(r[4])), std::fabs(r[5]));
}

// The part of the rule row r breaks, and for an origin or direction component, which one.
struct RowCheck {
    RowFault fault;
    int component;
};

inline RowCheck rowFault(const float* r) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(r[k]) || std::fabs(r[k]) > kMaxOriginF) return {RowFault::Origin, k};
    for (int k = 3; k < 6; ++k)
        if (!std::isfinite(r[k])) return {RowFault::Direction, k};
    const float largest = largestDirection(r);
    if (largest == 0.0f) return {RowFault::ZeroDirection, 0};
    if (largest < kMinDirectionF || largest > kMaxDirectionF) return {RowFault::DirectionRange, 0};
    if (!std::isfinite(r[6]) || r[6] < 0.0f) return {RowFault::Tmin, 6};
    if (std::isnan(r[7]) || r[7] < r[6]) return {RowFault::Tmax, 7};
    return {RowFault::None, 0};
}

}  // namespace

std::string rayRowProblem(const float* r) {
    const RowCheck c = rowFault(r);
    switch (c.fault) {
        case RowFault::None:
            return "";
        case RowFault::Origin:
            return "origin component " + number(r[c.component]) + " is not finite or beyond +-" +
                   number(kMaxRayOrigin) +
                   ", where float32 tracing stops being exact enough (docs/ROBUSTNESS.md, "
                   "numeric range); move the origin closer to the scene";
        case RowFault::Direction:
            return "direction component " + number(r[c.component]) + " is not finite";
        case RowFault::ZeroDirection:
            return "the direction is zero";
        case RowFault::DirectionRange:
            return "the direction's largest component " + number(largestDirection(r)) +
                   " is outside [" + number(kMinRayDirection) + ", " + number(kMaxRayDirection) +
                   "]; scale the direction (t is measured in its units)";
        case RowFault::Tmin:
            return "tmin " + number(r[6]) +
                   " must be finite and >= 0 (Embree, the ground truth, traces no negative "
                   "tmin); move the origin to o + tmin * d and trace [0, tmax - tmin]";
        case RowFault::Tmax:
            return "tmax " + number(r[7]) + " must be >= tmin " + number(r[6]) + " (+inf allowed)";
    }
    return "";
}

namespace {

// The lowest row index that breaks the rule, or rows when none does. The rows are checked in
// parallel (a file holds millions); the answer is the lowest index, as a sequential scan gives.
uint64_t firstBadRow(const float* rays, uint64_t rows) {
    uint64_t first = rows;
    const int64_t n = int64_t(rows);
#pragma omp parallel for schedule(static) reduction(min : first)
    for (int64_t i = 0; i < n; ++i)
        if (uint64_t(i) < first && rowFault(rays + 8 * i).fault != RowFault::None)
            first = uint64_t(i);
    return first;
}

// Throws "WHAT row I: why" when `first` is a row of rays (below `rows`): checkRayRows' refusal.
void refuseRow(const std::string& what, const float* rays, uint64_t first, uint64_t rows) {
    if (first < rows) throw IoError(badRayRowMessage(what, first, &rays[8 * first]));
}

// Rows read and checked at a time: 2 MiB, within a core's share of the last-level cache.
constexpr uint64_t kCheckPieceRows = 65536;

}  // namespace

uint64_t readRayFileInto(const std::string& path, const std::function<float*(uint64_t)>& allocate) {
    float* rays = nullptr;
    uint64_t firstBad = 0;
    const uint64_t rows = readRayFileRowsInto(
        path,
        [](uint64_t n) {
            return std::vector<RowSpan>{{0, n}};
        },
        [&](uint64_t n) { return rays = allocate(n); }, &firstBad);
    refuseRow("'" + path + "'", rays, firstBad, rows);
    return rows;
}

uint64_t readRayFileRowsInto(const std::string& path,
                             const std::function<std::vector<RowSpan>(uint64_t rows)>& rowsOf,
                             const std::function<float*(uint64_t)>& allocate, uint64_t* firstBad) {
    InputFile in(path, "the ray file", "save the rays with numpy.save and give that file");
    const uint64_t fileSize = in.size();

    const NpyHeader h = readNpyHeader(in, path);
    const std::vector<uint64_t>& shape = h.shape;
    if (h.descr != "<f4" || shape.size() != 2 || shape[1] != 8)
        throw IoError("'" + path +
                      "' must be a float32 array of shape (N, 8): ox oy oz dx dy dz tmin tmax; "
                      "it holds dtype " +
                      h.descr + ", shape " + npyShapeText(shape));
    const uint64_t available = fileSize - h.dataStart;
    const uint64_t rows = shape[0];
    if (rows > available / 32 || rows * 32 != available)
        bad(path, "shape " + npyShapeText(shape) + " needs " +
                      (rows > available / 32 ? std::string("more") : std::to_string(rows * 32)) +
                      " data bytes but the file has " + std::to_string(available) +
                      " (truncated or wrong header)");

    const std::vector<RowSpan> spans = rowsOf(rows);
    uint64_t mine = 0, last = 0;
    for (const RowSpan& sp : spans) {
        if (sp.begin < last || sp.begin > sp.end || sp.end > rows)
            throw std::invalid_argument("readRayFileRowsInto: rows " + std::to_string(sp.begin) +
                                        ".." + std::to_string(sp.end) + " of " +
                                        std::to_string(rows) + " (spans in row order)");
        last = sp.end;
        mine += sp.end - sp.begin;
    }
    float* rays = allocate(mine);   // the final buffer: read into directly, one pass
    uint64_t at = 0, position = 0;  // rows so far; the file's row the next read starts at
    if (firstBad) *firstBad = mine;
    for (const RowSpan& sp : spans) {
        const uint64_t count = sp.end - sp.begin;
        if (count == 0) continue;
        if (sp.begin != position) in.seekTo(h.dataStart + sp.begin * 32);
        // In pieces, each checked while it is still in cache: a second pass over the whole
        // buffer went to memory for every row (the check was 9 % of a 4M-ray trace's run).
        for (uint64_t done = 0; done < count;) {
            const uint64_t piece = std::min(count - done, kCheckPieceRows);
            float* dst = rays + 8 * (at + done);
            if (in.read(dst, piece * 32) != piece * 32)
                bad(path, "the file changed while it was read");
            if (firstBad && *firstBad == mine) {
                const uint64_t b = firstBadRow(dst, piece);
                if (b < piece) *firstBad = at + done + b;
            }
            done += piece;
        }
        at += count;
        position = sp.end;
    }
    if (position == rows && !in.atEnd()) bad(path, "the file changed while it was read");
    return rows;
}

void checkRayRows(const float* rays, uint64_t rows, const std::string& what) {
    refuseRow(what, rays, firstBadRow(rays, rows), rows);
}

std::string badRayRowMessage(const std::string& what, uint64_t row, const float* r) {
    return what + " row " + std::to_string(row) + ": " + rayRowProblem(r);
}

std::vector<float> readRayFile(const std::string& path) {
    std::vector<float> rays;
    readRayFileInto(path, [&rays](uint64_t rows) {
        rays.resize(rows * 8);
        return rays.data();
    });
    return rays;
}

}  // namespace oct
