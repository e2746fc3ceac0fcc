#include "validation/exact/box_contract.h"

#include <gmp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/geometry/aabb.h"
#include "core/octree/compact_octree.h"

namespace oct {
namespace {

constexpr size_t kMaxErrors = 16;
constexpr int kKinds = 4;  // leave a boundary, end at the entry, graze, general position
constexpr int kAttempts = 64;

struct Rng {
    std::mt19937_64 engine;
    double u01() { return double(engine() >> 11) * 0x1p-53; }
    float range(float lo, float hi) { return float(lo + (hi - lo) * u01()); }
    uint64_t below(uint64_t n) { return engine() % n; }
};

// A direction through a point uniform in the cube [-1, 1]^3: not uniform on the sphere, but
// every direction can come, which is all the contract needs.
Vec3 direction(Rng& rng) {
    for (;;) {
        const Vec3 p = {rng.range(-1.0f, 1.0f), rng.range(-1.0f, 1.0f), rng.range(-1.0f, 1.0f)};
        if (dot(p, p) > 1e-6f) return normalize(p);
    }
}

struct TestRay {
    Vec3 o, d;
    float tmin = 0.0f, tmax = INFINITY;
};

// One GMP rational, owned.
struct Rational {
    mpq_t v;
    Rational() { mpq_init(v); }
    ~Rational() { mpq_clear(v); }
    Rational(const Rational&) = delete;
    Rational& operator=(const Rational&) = delete;
};

enum class Meet { Miss, Touch, Through };

// Does {o + t d : t in [tmin, tmax]} meet the closed box [lo, hi], in exact arithmetic on the
// given values (floats and doubles are dyadic rationals, so mpq_set_d is exact)?
class ExactSlabs {
public:
    Meet meet(const TestRay& r, const double lo[3], const double hi[3]) {
        mpq_set_d(enter_.v, r.tmin);
        const bool bounded = std::isfinite(r.tmax);
        if (bounded) mpq_set_d(exit_.v, r.tmax);
        bool haveExit = bounded;
        for (int a = 0; a < 3; ++a) {
            const double o = r.o[a], d = r.d[a];
            if (d == 0.0) {
                if (o < lo[a] || o > hi[a]) return Meet::Miss;
                continue;
            }
            planeT(lo[a], o, d, ta_);
            planeT(hi[a], o, d, tb_);
            const bool aNear = mpq_cmp(ta_.v, tb_.v) <= 0;
            mpq_srcptr nearT = aNear ? ta_.v : tb_.v, farT = aNear ? tb_.v : ta_.v;
            if (mpq_cmp(nearT, enter_.v) > 0) mpq_set(enter_.v, nearT);
            if (!haveExit || mpq_cmp(farT, exit_.v) < 0) {
                mpq_set(exit_.v, farT);
                haveExit = true;
            }
        }
        if (!haveExit) return Meet::Through;  // unbounded and parallel to every slab: inside
        const int c = mpq_cmp(enter_.v, exit_.v);
        return c > 0 ? Meet::Miss : (c == 0 ? Meet::Touch : Meet::Through);
    }

private:
    void planeT(double plane, double o, double d, Rational& t) {
        mpq_set_d(num_.v, plane);
        mpq_set_d(den_.v, o);
        mpq_sub(num_.v, num_.v, den_.v);
        mpq_set_d(den_.v, d);
        mpq_div(t.v, num_.v, den_.v);
    }
    Rational enter_, exit_, ta_, tb_, num_, den_;
};

// The box, grown on every side by `grow` (absolute).
void bounds(const Aabb& b, double grow, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; ++a) {
        lo[a] = double(b.lo[a]) - grow;
        hi[a] = double(b.hi[a]) + grow;
    }
}

// The tightness margin: kBoxContractSlack of the box's edge or of its distance from the origin,
// whichever is larger. The kernel's t at a plane is rounded relative to t, so a box far from the
// origin is widened by rounding in proportion to that distance (about 2e-7 of it), not to its
// size.
double tightMargin(const TestRay& r, const Aabb& b) {
    const Vec3 c = b.center();
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) d2 += (double(r.o[a]) - c[a]) * (double(r.o[a]) - c[a]);
    return kBoxContractSlack * std::max(double(b.hi.x) - double(b.lo.x), std::sqrt(d2));
}

// Is plane - o exact in float for every plane of the box and its children's, so the kernel's t
// at those planes (an axis direction of +-1) is the exact t?
bool exactDifferences(const TestRay& r, const Aabb& b) {
    const Vec3 mid = b.center();
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] == 0.0f) continue;
        for (float plane : {b.lo[a], mid[a], b.hi[a]})
            if (double(plane - r.o[a]) != double(plane) - double(r.o[a])) return false;
    }
    return true;
}

float stepUlps(float x, int steps) {
    for (; steps > 0; --steps) x = std::nextafter(x, INFINITY);
    for (; steps < 0; ++steps) x = std::nextafter(x, -INFINITY);
    return x;
}

// An origin on the box's boundary (a face, an edge or a corner), leaving it: the exact
// interval is [0, 0] or, along a face, [0, something].
TestRay leaveBoundary(Rng& rng, const Aabb& b) {
    TestRay r;
    int side[3];
    bool any = false;
    for (int a = 0; a < 3; ++a) {
        side[a] = int(rng.below(3));  // 0 lo, 1 hi, 2 inside
        any = any || side[a] < 2;
    }
    if (!any) side[rng.below(3)] = int(rng.below(2));
    for (;;) {
        r.d = direction(rng);
        for (int a = 0; a < 3; ++a) {
            r.o[a] =
                side[a] == 0 ? b.lo[a] : (side[a] == 1 ? b.hi[a] : rng.range(b.lo[a], b.hi[a]));
            if (side[a] < 2) r.d[a] = side[a] == 1 ? std::fabs(r.d[a]) : -std::fabs(r.d[a]);
        }
        if (rng.below(4) == 0) r.d[rng.below(3)] = 0.0f;  // along a face or an edge
        if (r.d.x != 0.0f || r.d.y != 0.0f || r.d.z != 0.0f) return r;
    }
}

// A segment that ends exactly where it enters the box (tmax == the exact entry t), with axis
// directions so the kernel's entry t is exact. Returns false when no exact draw was found.
bool endAtEntry(Rng& rng, const Aabb& b, TestRay& r) {
    const float edge = b.hi.x - b.lo.x;
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
        const int axis = int(rng.below(3));
        Vec3 p, d;
        for (int a = 0; a < 3; ++a) {
            d[a] = float(int(rng.below(3)) - 1);
            const uint64_t where = rng.below(3);
            p[a] = where == 0 ? b.lo[a] : (where == 1 ? b.hi[a] : rng.range(b.lo[a], b.hi[a]));
        }
        d[axis] = rng.below(2) ? 1.0f : -1.0f;
        p[axis] = d[axis] > 0.0f ? b.lo[axis] : b.hi[axis];
        // A distance with few mantissa bits, so p - k d is exact more often.
        const float k = std::ldexp(float(1 + rng.below(32)), std::ilogb(edge) - 4);
        for (int a = 0; a < 3; ++a) r.o[a] = p[a] - d[a] * k;
        r.d = d;
        r.tmin = 0.0f;
        r.tmax = (p[axis] - r.o[axis]) * d[axis];
        if (exactDifferences(r, b) && r.tmax > 0.0f) return true;
    }
    return false;
}

// Through a point within a few ulps of an edge or a corner, either side, from any direction.
TestRay graze(Rng& rng, const Aabb& b) {
    TestRay r;
    Vec3 p;
    const int free = rng.below(4) == 0 ? -1 : int(rng.below(3));  // -1: a corner
    for (int a = 0; a < 3; ++a) {
        if (a == free) {
            p[a] = rng.range(b.lo[a], b.hi[a]);
        } else {
            const float plane = rng.below(2) ? b.hi[a] : b.lo[a];
            p[a] = stepUlps(plane, int(rng.below(7)) - 3);
        }
    }
    // From 0.5 to 8192 edges away, log-uniform: an exact interval shorter than the rounding of
    // t (about 2e-7 t) is what the far scaling is for, and a far origin makes t large against
    // the distance by which the ray misses or clears the edge (the rounding of the origin).
    const float edge = b.hi.x - b.lo.x;
    r.d = direction(rng);
    const float s = std::ldexp(float(0.5 + 0.5 * rng.u01()), int(rng.below(15))) * edge;
    r.o = p - r.d * s;
    return r;
}

TestRay general(Rng& rng, const Aabb& b) {
    const Vec3 c = b.center();
    const float h = 1.5f * (b.hi.x - b.lo.x);
    TestRay r;
    r.o = {rng.range(c.x - h, c.x + h), rng.range(c.y - h, c.y + h), rng.range(c.z - h, c.z + h)};
    r.d = direction(rng);
    return r;
}

std::string describe(const char* what, const char* test, const TestRay& r, const Aabb& b,
                     const OctreeNode& n, int child) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "%s: %s of node key %llu (depth %d%s%s): ray o=(%a, %a, %a) d=(%a, %a, %a) "
                  "t=[%a, %a], box lo=(%a, %a, %a) hi=(%a, %a, %a)",
                  what, test, (unsigned long long)n.key, int(n.depth), child >= 0 ? ", child " : "",
                  child >= 0 ? std::to_string(child).c_str() : "", r.o.x, r.o.y, r.o.z, r.d.x,
                  r.d.y, r.d.z, r.tmin, r.tmax, b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    return buf;
}

class Checker {
public:
    Checker(BoxContractReport& rep, const BoxTests& tests) : rep_(rep), tests_(tests) {}

    // One float answer against the exact one, for the box b.
    void judge(const char* test, bool floatHit, const TestRay& r, const Aabb& b,
               const OctreeNode& n, int child) {
        ++rep_.tests;
        double lo[3], hi[3];
        bounds(b, 0.0, lo, hi);
        const Meet m = exact_.meet(r, lo, hi);
        if (m != Meet::Miss) ++rep_.meets;
        if (m == Meet::Touch) ++rep_.touching;
        if (m != Meet::Miss && !floatHit) {
            ++rep_.culled;
            note(describe(m == Meet::Touch ? "culled a touching ray" : "culled a meeting ray", test,
                          r, b, n, child));
        }
        if (floatHit && m == Meet::Miss) {
            bounds(b, tightMargin(r, b), lo, hi);
            if (exact_.meet(r, lo, hi) == Meet::Miss) {
                ++rep_.loose;
                note(describe("accepted a ray that misses the grown box", test, r, b, n, child));
            }
        }
    }

    void check(const TestRay& r, const OctreeNode& n) {
        ++rep_.rays;
        const RaySlabs s = makeRaySlabs(r.o, r.d);
        judge("intersectBox", tests_.box(s, n.box, r.tmin, r.tmax), r, n.box, n, -1);
        if (n.nodeType() != NodeType::Internal) return;
        const uint32_t mask = tests_.children(s, n.box, r.tmin, r.tmax);
        for (int i = 0; i < 8; ++i)
            judge("childIntervals", (mask >> i) & 1u, r, childBox(n.box, i), n, i);
    }

private:
    void note(std::string e) {
        if (rep_.errors.size() < kMaxErrors) rep_.errors.push_back(std::move(e));
    }
    BoxContractReport& rep_;
    const BoxTests& tests_;
    ExactSlabs exact_;
};

bool kernelBox(const RaySlabs& s, const Aabb& b, float tmin, float tmax) {
    float t0 = 0.0f, t1 = 0.0f;
    return intersectBox(s, b, tmin, tmax, t0, t1);
}

uint32_t kernelChildren(const RaySlabs& s, const Aabb& parent, float tmin, float tmax) {
    float enter[8], exit[8];
    return compact_detail::childIntervals(s, parent, tmin, tmax, enter, exit);
}

}  // namespace

BoxTests kernelBoxTests() { return {kernelBox, kernelChildren}; }

BoxContractReport checkBoxContract(const Octree& canonical, uint64_t rays, uint64_t seed,
                                   const BoxTests& tests) {
    BoxContractReport rep;
    if (canonical.nodes.empty()) return rep;
    Rng rng{std::mt19937_64(seed ^ 0xB0C5C0A7ull)};
    Checker checker(rep, tests);
    // Internal nodes test both functions; draw them half the time when there are any.
    std::vector<uint32_t> internal;
    for (uint32_t i = 0; i < canonical.nodes.size(); ++i)
        if (canonical.nodes[i].nodeType() == NodeType::Internal) internal.push_back(i);
    for (uint64_t i = 0; i < rays; ++i) {
        const bool pickInternal = !internal.empty() && rng.below(2) == 0;
        const OctreeNode& n = canonical.nodes[pickInternal ? internal[rng.below(internal.size())]
                                                           : rng.below(canonical.nodes.size())];
        TestRay r;
        switch (i % kKinds) {
            case 0:
                r = leaveBoundary(rng, n.box);
                break;
            case 1:
                if (!endAtEntry(rng, n.box, r)) r = general(rng, n.box);
                break;
            case 2:
                r = graze(rng, n.box);
                break;
            default:
                r = general(rng, n.box);
                break;
        }
        checker.check(r, n);
    }
    return rep;
}

}  // namespace oct
