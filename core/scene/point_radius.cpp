// The default sphere radius of point clouds, defaultPointRadius (the rule is stated in
// load_scene.h): half the median nearest-neighbour distance over a deterministic sample, found
// with a uniform hash grid over the distinct points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/scene/load_scene.h"

namespace oct {
namespace {

// Uniform hash grid over all points for nearest-neighbour queries (see defaultPointRadius).
class PointGrid {
public:
    PointGrid(const std::vector<Vec3>& points, const Aabb& box, double cell)
        : points_(points), lo_(box.lo), cell_(cell) {
        std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
        for (size_t i = 0; i < points.size(); ++i)
            keyed[i] = {keyOf(cellOf(points[i])), uint32_t(i)};
        std::sort(keyed.begin(), keyed.end());
        order_.resize(keyed.size());
        for (size_t i = 0; i < keyed.size(); ++i) {
            order_[i] = keyed[i].second;
            auto& range = ranges_[keyed[i].first];
            if (range.second == 0) range.first = uint32_t(i);
            range.second = uint32_t(i + 1);
        }
    }

    // Points sharing the cell of point i (the cost of a query near it).
    size_t occupancy(const Vec3& p) const {
        auto it = ranges_.find(keyOf(cellOf(p)));
        return it == ranges_.end() ? 0 : it->second.second - it->second.first;
    }

    // Distance from q to the nearest point at a non-zero distance; infinity when none.
    double nearestDistinct(const Vec3& q) const {
        const Cell c = cellOf(q);
        double best = std::numeric_limits<double>::infinity();
        for (int64_t r = 0;; ++r) {
            // Points in ring r are at least (r - 1) cells away.
            if (double(r - 1) * cell_ >= best || r > kMaxCellsPerAxis) return best;
            const double ringCells = double(2 * r + 1) * double(2 * r + 1) * double(2 * r + 1);
            if (ringCells > 8.0 * double(ranges_.size()) + 64.0) return bruteForce(q, best);
            scanRing(q, c, r, best);
        }
    }

    static constexpr int64_t kMaxCellsPerAxis = int64_t(1) << 20;

private:
    struct Cell {
        int64_t x, y, z;
    };
    Cell cellOf(const Vec3& p) const {
        auto axis = [&](float v, float lo) {
            return std::clamp(int64_t(std::floor((double(v) - lo) / cell_)), int64_t(0),
                              kMaxCellsPerAxis - 1);
        };
        return {axis(p.x, lo_.x), axis(p.y, lo_.y), axis(p.z, lo_.z)};
    }
    static uint64_t keyOf(const Cell& c) {
        return (uint64_t(c.x) << 42) | (uint64_t(c.y) << 21) | uint64_t(c.z);
    }
    static double distance(const Vec3& a, const Vec3& b) {
        double dx = double(a.x) - b.x, dy = double(a.y) - b.y, dz = double(a.z) - b.z;
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    void scanCell(const Vec3& q, const Cell& c, double& best) const {
        if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= kMaxCellsPerAxis || c.y >= kMaxCellsPerAxis ||
            c.z >= kMaxCellsPerAxis)
            return;
        auto it = ranges_.find(keyOf(c));
        if (it == ranges_.end()) return;
        for (uint32_t i = it->second.first; i < it->second.second; ++i) {
            double d = distance(q, points_[order_[i]]);
            if (d > 0.0 && d < best) best = d;
        }
    }
    void scanRing(const Vec3& q, const Cell& c, int64_t r, double& best) const {
        for (int64_t dx = -r; dx <= r; ++dx)
            for (int64_t dy = -r; dy <= r; ++dy) {
                const bool onShell = std::abs(dx) == r || std::abs(dy) == r;
                for (int64_t dz = -r; dz <= r; dz += onShell ? 1 : std::max<int64_t>(2 * r, 1))
                    scanCell(q, {c.x + dx, c.y + dy, c.z + dz}, best);
            }
    }
    double bruteForce(const Vec3& q, double best) const {
        for (const Vec3& p : points_) {
            double d = distance(q, p);
            if (d > 0.0 && d < best) best = d;
        }
        return best;
    }

    const std::vector<Vec3>& points_;
    Vec3 lo_;
    double cell_;
    std::vector<uint32_t> order_;
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges_;
};

constexpr size_t kRadiusSampleSize = 10000;

std::vector<uint32_t> radiusSample(size_t n) {
    std::vector<uint32_t> sample;
    const size_t k = std::min(n, kRadiusSampleSize);
    for (size_t i = 0; i < k; ++i) sample.push_back(uint32_t(uint64_t(i) * n / k));
    return sample;
}

Aabb pointBounds(const std::vector<Vec3>& points) {
    Aabb box = emptyAabb();
    for (const Vec3& p : points) grow(box, p);
    return box;
}

double boxDiagonal(const Aabb& box) {
    double dx = double(box.hi.x) - box.lo.x, dy = double(box.hi.y) - box.lo.y,
           dz = double(box.hi.z) - box.lo.z;
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double meanSampleOccupancy(const PointGrid& grid, const std::vector<Vec3>& points,
                           const std::vector<uint32_t>& sample) {
    double sum = 0.0;
    for (uint32_t i : sample) sum += double(grid.occupancy(points[i]));
    return sum / double(sample.size());
}

// Cell edge: start at diagonal / cbrt(n) (about one point a cell for a filled box), then shrink
// while the sampled points' cells are crowded (flat or clustered clouds), so that a query scans
// few points. Exact duplicates keep a cell crowded, hence the cap on rounds.
double chooseCellSize(const std::vector<Vec3>& points, const Aabb& box,
                      const std::vector<uint32_t>& sample) {
    const double diag = boxDiagonal(box);
    const double minCell = diag / double(PointGrid::kMaxCellsPerAxis / 2);
    double cell = diag / std::cbrt(double(points.size()));
    for (int round = 0; round < 12 && cell > minCell; ++round) {
        double occupancy = meanSampleOccupancy(PointGrid(points, box, cell), points, sample);
        if (occupancy <= 8.0) break;
        cell = std::max(minCell, cell / std::max(2.0, std::cbrt(occupancy / 2.0)));
    }
    return cell;
}

}  // namespace

float defaultPointRadius(const std::vector<Vec3>& points) {
    const Aabb box = pointBounds(points);
    const double diag = points.empty() ? 0.0 : boxDiagonal(box);
    const float fallback = diag > 0.0 ? float(1e-3 * diag) : 1e-3f;
    if (points.size() < 2 || diag == 0.0) return fallback;
    const std::vector<uint32_t> sample = radiusSample(points.size());
    // The search runs over the distinct points: exact duplicates are at distance zero and
    // ignored anyway, and a cloud of many copies of a few points would otherwise make every
    // query scan all copies in its cell (seconds to minutes for a million copies).
    std::vector<Vec3> distinct(points);
    auto less = [](const Vec3& a, const Vec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(distinct.begin(), distinct.end(), less);
    distinct.erase(std::unique(distinct.begin(), distinct.end(),
                               [](const Vec3& a, const Vec3& b) {
                                   return a.x == b.x && a.y == b.y && a.z == b.z;
                               }),
                   distinct.end());
    PointGrid grid(distinct, box, chooseCellSize(distinct, box, radiusSample(distinct.size())));
    std::vector<double> distances;
    for (uint32_t i : sample) {
        double d = grid.nearestDistinct(points[i]);
        if (std::isfinite(d)) distances.push_back(d);
    }
    if (distances.empty()) return fallback;
    auto median = distances.begin() + distances.size() / 2;
    std::nth_element(distances.begin(), median, distances.end());
    return float(0.5 * *median);
}

}  // namespace oct
