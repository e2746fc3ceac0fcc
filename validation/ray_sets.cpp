#include "validation/ray_sets.h"

#include <cmath>
#include <random>

#include "core/octree/octree.h"

namespace oct {
namespace {

struct Rng {
    std::mt19937_64 engine;
    double u01() { return double(engine() >> 11) * 0x1p-53; }  // [0, 1)
    double range(double lo, double hi) { return lo + (hi - lo) * u01(); }
    uint64_t below(uint64_t n) { return engine() % n; }
};

Vec3 unitVector(Rng& rng) {
    double z = 2.0 * rng.u01() - 1.0;
    double phi = 2.0 * M_PI * rng.u01();
    double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)};
}

Vec3 pointIn(Rng& rng, const Aabb& b) {
    return {float(rng.range(b.lo.x, b.hi.x)), float(rng.range(b.lo.y, b.hi.y)),
            float(rng.range(b.lo.z, b.hi.z))};
}

// Boundary coordinates of the nodes of depth `depth` along one axis: the same float midpoints
// childBox() takes, so the planes are exactly the node faces of the canonical octree.
std::vector<float> boundaryPlanes(float lo, float hi, int depth) {
    std::vector<float> cuts = {lo, hi};
    for (int d = 0; d < depth; ++d) {
        std::vector<float> next;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) {
            next.push_back(cuts[i]);
            next.push_back((cuts[i] + cuts[i + 1]) * 0.5f);
        }
        next.push_back(cuts.back());
        cuts = std::move(next);
    }
    return cuts;
}

void push(ValidationRays& out, RayKind kind, Vec3 o, Vec3 d, float tmin, float tmax) {
    const float r[8] = {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax};
    out.rays.insert(out.rays.end(), r, r + 8);
    out.kind.push_back(kind);
}

}  // namespace

const char* rayKindName(RayKind k) {
    switch (k) {
        case RayKind::Inside:
            return "inside";
        case RayKind::Axis:
            return "axis";
        case RayKind::Around:
        default:
            return "around";
    }
}

ValidationRays makeValidationRays(const Scene& scene, uint64_t n, uint64_t seed) {
    ValidationRays out;
    out.rays.reserve(8 * n);
    out.kind.reserve(n);
    Rng rng{std::mt19937_64(seed)};
    const Aabb bounds = scene.bounds();
    const Aabb root = rootCube(scene);
    const Vec3 centre = bounds.center();
    float radius = 0.5f * length(bounds.extent());
    if (!(radius > 0.0f)) radius = 0.5f * length(root.extent());

    const uint64_t nAround = (n + 2) / 3, nInside = (n + 1) / 3, nAxis = n / 3;
    for (uint64_t i = 0; i < nAround; ++i) {
        Vec3 o = centre + unitVector(rng) * (1.5f * radius);
        Vec3 d = pointIn(rng, bounds) - o;
        if (!(length(d) > 0.0f)) d = centre - o;
        push(out, RayKind::Around, o, normalize(d), 0.0f, INFINITY);
    }
    for (uint64_t i = 0; i < nInside; ++i) {
        Vec3 o = pointIn(rng, root);
        Vec3 d = unitVector(rng);
        float tmax = rng.below(4) == 0 ? float(rng.u01() * radius) : INFINITY;
        push(out, RayKind::Inside, o, d, 0.0f, tmax);
    }
    std::vector<float> planes[3][4];  // [axis][depth]
    for (int a = 0; a < 3; ++a)
        for (int d = 1; d <= 3; ++d) planes[a][d] = boundaryPlanes(root.lo[a], root.hi[a], d);
    for (uint64_t i = 0; i < nAxis; ++i) {
        Vec3 o = pointIn(rng, root);
        int axis = int(rng.below(3));
        Vec3 d = {0.0f, 0.0f, 0.0f};
        d[axis] = rng.below(2) ? 1.0f : -1.0f;
        if (i % 2 == 1) {  // into a node face: move one other coordinate onto a split plane
            int other = (axis + 1 + int(rng.below(2))) % 3;
            const std::vector<float>& p = planes[other][1 + rng.below(3)];
            o[other] = p[rng.below(p.size())];
        }
        push(out, RayKind::Axis, o, d, 0.0f, INFINITY);
    }
    return out;
}

}  // namespace oct
