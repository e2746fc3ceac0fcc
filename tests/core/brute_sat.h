// An independent reference for triangle/box overlap, used by the tests only: the separating
// axis theorem written out directly in double precision with GLM, sharing no code with
// core/geometry/tri_box.h. For float inputs it is exact up to the final rounding of the
// cross products and dot products (differences of floats and products of two such
// differences are exact in double), so it serves as ground truth for the float test.
//
// Besides the yes/no answer it returns a classification margin: for each axis the signed gap
// between the projection intervals (positive = separated), measured in units of that axis's
// natural scale (1 for box normals, L for edge crosses, L^2 for the triangle normal, where L
// is the size of the coordinates involved). Float rounding perturbs each gap by about
// 2^-24 in those units, so a pair whose decision could flip under rounding is "borderline".
#pragma once

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

namespace octtest {

struct SatResult {
    bool overlap;         // no axis separates (touching counts as overlap)
    bool borderline;      // the decision could flip under a relative perturbation of eps
    double maxScaledGap;  // largest scaled gap over all axes (> 0: separated)
};

// Closed box [lo, hi] against the closed triangle (a, b, c). eps: relative tolerance of the
// borderline classification.
inline SatResult bruteSat(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c,
                          double eps) {
    // L: the scale of the box and the triangle relative to the box centre. The float test
    // first subtracts the centre, which rounds relative to the result (the difference of two
    // floats is correctly rounded), so the distance from the origin does not enter.
    const glm::dvec3 ctr = (lo + hi) * 0.5, half = (hi - lo) * 0.5;
    double L = std::max({half.x, half.y, half.z});
    for (const glm::dvec3& p : {a, b, c}) {
        glm::dvec3 r = p - ctr;
        L = std::max({L, std::fabs(r.x), std::fabs(r.y), std::fabs(r.z)});
    }
    L = std::max(L, 1e-300);

    const glm::dvec3 e[3] = {b - a, c - b, a - c};
    glm::dvec3 axes[13];
    double axisScale[13];
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 u(0.0);
        u[i] = 1.0;
        axes[n] = u;
        axisScale[n++] = 1.0;
    }
    double eMax =
        std::sqrt(std::max({glm::dot(e[0], e[0]), glm::dot(e[1], e[1]), glm::dot(e[2], e[2])}));
    axes[n] = glm::cross(e[0], e[1]);
    axisScale[n++] = L * eMax;
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 u(0.0);
        u[i] = 1.0;
        for (int j = 0; j < 3; ++j) {
            axes[n] = glm::cross(u, e[j]);
            axisScale[n++] = L;
        }
    }

    bool anyClearSeparation = false;  // an axis separating by more than the tolerance
    bool anyNear = false;             // an axis whose gap is within the tolerance of zero
    double maxGap = -INFINITY;
    bool separated = false;
    for (int k = 0; k < n; ++k) {
        const glm::dvec3& ax = axes[k];
        // A zero axis (degenerate triangle, or an edge parallel to a box axis) separates
        // nothing; crosses of exact float differences are exactly zero in that case.
        if (glm::dot(ax, ax) == 0.0) continue;
        double pa = glm::dot(ax, a), pb = glm::dot(ax, b), pc = glm::dot(ax, c);
        double tLo = std::min({pa, pb, pc}), tHi = std::max({pa, pb, pc});
        // Box interval: over the 8 corners, via centre and radius.
        double pc0 = glm::dot(ax, ctr);
        double rad = std::fabs(ax.x) * half.x + std::fabs(ax.y) * half.y + std::fabs(ax.z) * half.z;
        double bLo = pc0 - rad, bHi = pc0 + rad;
        double gap = std::max(tLo - bHi, bLo - tHi);  // > 0: disjoint intervals
        if (gap > 0.0) separated = true;
        double scaled = gap / (axisScale[k] * L);
        maxGap = std::max(maxGap, scaled);
        if (scaled > eps) anyClearSeparation = true;
        if (std::fabs(scaled) <= eps) anyNear = true;
    }
    SatResult r;
    r.overlap = !separated;
    r.borderline = !anyClearSeparation && anyNear;
    r.maxScaledGap = maxGap;
    return r;
}

}  // namespace octtest
