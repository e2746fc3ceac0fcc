// The real `octrace` binary, run as a user would: its JSON report, its image and array outputs
// checked byte by byte and against the same frame rendered in process, the trace round trip
// against an in-process Embree trace, and every error path (one line on stderr, non-zero exit,
// nothing written, an existing output never clobbered).
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/io/npy.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "validation/policy/film_compare.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::kMeshes;
using octtest::kTeapot;
const std::string kCornell = kMeshes + "/cornell_box.obj";
// Octree runs use a shallow tree: the default depth 7 makes the linear layout allocate 115 MB
// per run, which costs a second per invocation and tests nothing more here.
const std::string kShallow = " --max-depth 5";

using octtest::isOneLineError;
using octtest::quote;
using octtest::readFile;
using octtest::RunResult;
using octtest::show;

void writeFile(const fs::path& p, const std::string& bytes) {
    ASSERT_TRUE(octtest::writeFile(p, bytes)) << "cannot write " << p;
}

// Each test gets its own folder: `work` holds the inputs and receives the outputs; the
// captured stdout/stderr go elsewhere so that `work` lists exactly what octrace left behind.
class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = std::make_unique<octtest::TempDir>("cli_test");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
    }
    void TearDown() override { root_.reset(); }

    RunResult run(const std::string& args) const {
        return octtest::runOctrace(args, root_->path() / "capture");
    }

    std::string path(const std::string& name) const { return (work_ / name).string(); }
    std::string q(const std::string& name) const { return quote(path(name)); }

    std::set<std::string> listing() const {
        std::set<std::string> names;
        for (const auto& e : fs::directory_iterator(work_)) names.insert(e.path().filename());
        return names;
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
};

uint32_t bigEndian32(const std::string& s, size_t at) {
    return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
           uint32_t(uint8_t(s[at + 2])) << 8 | uint32_t(uint8_t(s[at + 3]));
}

// The 8-byte PNG signature, then the IHDR chunk (length 13) with the image size.
::testing::AssertionResult isPngOfSize(const std::string& bytes, uint32_t w, uint32_t h) {
    const char sig[] = "\x89PNG\r\n\x1a\n";
    if (bytes.size() < 33 || bytes.compare(0, 8, std::string(sig, 8)) != 0)
        return ::testing::AssertionFailure() << "no PNG signature";
    if (bigEndian32(bytes, 8) != 13 || bytes.compare(12, 4, "IHDR") != 0)
        return ::testing::AssertionFailure() << "first chunk is not IHDR";
    if (bigEndian32(bytes, 16) != w || bigEndian32(bytes, 20) != h)
        return ::testing::AssertionFailure()
               << "IHDR says " << bigEndian32(bytes, 16) << "x" << bigEndian32(bytes, 20)
               << ", expected " << w << "x" << h;
    return ::testing::AssertionSuccess();
}

template <class T>
std::vector<T> npyVector(const NpyArray& a) {
    std::vector<T> v(a.elementCount());
    std::memcpy(v.data(), a.data.data(), v.size() * sizeof(T));
    return v;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// --- (a) info --json ----------------------------------------------------------------------

TEST_F(Cli, InfoJsonDescribesTheTeapot) {
    RunResult r = run("info " + quote(kTeapot) + " --json");
    ASSERT_EQ(r.status, 0) << show(r);
    nlohmann::json j;
    ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
    EXPECT_EQ(j["scene"]["primitives"].get<uint64_t>(), 992u);
    EXPECT_EQ(j["scene"]["kind"], "triangles");
    EXPECT_EQ(j["load"]["dropped"]["total"].get<uint64_t>(), 0u);
    const auto& tree = j["octree"];
    EXPECT_GE(tree["octree_faces"].get<uint64_t>(), 992u);
    uint64_t byType = 0;
    for (const auto& [type, count] : tree["nodes_by_type"].items()) byType += count.get<uint64_t>();
    EXPECT_EQ(byType, tree["nodes"].get<uint64_t>());
    EXPECT_GT(tree["nodes"].get<uint64_t>(), 1u);
    uint64_t byDepth = 0;
    for (const auto& level : tree["nodes_by_depth"])
        for (const auto& [type, count] : level.items()) byDepth += count.get<uint64_t>();
    EXPECT_EQ(byDepth, tree["nodes"].get<uint64_t>());
}

// --- (b) render outputs -------------------------------------------------------------------

TEST_F(Cli, RenderWritesPngAndArraysEqualToAnInProcessFrame) {
    const int w = 64, h = 40;  // not square, so a swapped (W, H) would show
    RunResult r = run("render " + quote(kCornell) + " --backend cpu --accel hash" + kShallow +
                      " --size 64x40 --out " + q("out.png") + " --depth " + q("t.npy") +
                      " --prim " + q("prim.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "t.npy", "prim.npy"}));

    std::string png = readFile(path("out.png"));
    ASSERT_TRUE(isPngOfSize(png, w, h));
    NpyArray t = readNpy(path("t.npy"));
    NpyArray prim = readNpy(path("prim.npy"));
    EXPECT_EQ(t.descr, "<f4");
    EXPECT_EQ(prim.descr, "<i4");
    ASSERT_EQ(t.shape, (std::vector<uint64_t>{uint64_t(h), uint64_t(w)}));
    ASSERT_EQ(prim.shape, (std::vector<uint64_t>{uint64_t(h), uint64_t(w)}));

    // The same frame in process, traced exhaustively: the CLI must have produced exactly it.
    Scene scene = loadScene(kCornell);
    CameraOptions cam;
    cam.width = w;
    cam.height = h;
    FrameParams frame = makeFrame(scene.bounds(), cam);
    BuiltScene built = buildScene(scene, findLayout("exhaustive"), LayoutOptions{});
    Film film;
    renderWith(hostBackend(), built, frame, film);
    EXPECT_TRUE(sameBits(npyVector<float>(t), film.t));
    EXPECT_EQ(npyVector<int32_t>(prim), film.prim);
    int pw = 0, ph = 0, channels = 0;
    stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(png.data()),
                                            int(png.size()), &pw, &ph, &channels, 3);
    ASSERT_NE(pixels, nullptr) << "the PNG does not decode";
    EXPECT_EQ(pw, w);
    EXPECT_EQ(ph, h);
    EXPECT_TRUE(std::equal(film.rgb.begin(), film.rgb.end(), pixels)) << "colours differ";
    stbi_image_free(pixels);
}

// --- (c) trace round trip -----------------------------------------------------------------

// Seeded rays over and through a scene's box: random origins around and inside the box,
// random (non-unit) directions, rays aimed at random triangle points (so most of those hit),
// axis-parallel rays, rays from inside the box, finite [tmin, tmax] windows.
std::vector<float> makeRays(const Scene& scene, uint32_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    Aabb b = scene.bounds();
    Vec3 lo = b.lo, ext = b.extent();
    float diag = length(ext);
    auto inBox = [&](float margin) {
        return Vec3{lo.x - margin * ext.x + (1 + 2 * margin) * ext.x * u01(rng),
                    lo.y - margin * ext.y + (1 + 2 * margin) * ext.y * u01(rng),
                    lo.z - margin * ext.z + (1 + 2 * margin) * ext.z * u01(rng)};
    };
    auto onTriangle = [&]() {
        const Triangle& t = scene.triangles[rng() % scene.triangles.size()];
        float a = u01(rng), c = u01(rng);
        if (a + c > 1.0f) a = 1.0f - a, c = 1.0f - c;
        return t.v0 + (t.v1 - t.v0) * a + (t.v2 - t.v0) * c;
    };
    std::vector<float> rays;
    rays.reserve(size_t(n) * 8);
    for (uint32_t i = 0; i < n; ++i) {
        Vec3 o, d;
        switch (i % 4) {
            case 0:  // from around the box towards a point on a triangle
                o = inBox(0.5f);
                d = onTriangle() - o;
                break;
            case 1:  // from inside the box, random direction
                o = inBox(0.0f);
                d = Vec3{u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f};
                break;
            case 2: {  // axis-parallel, from inside or around the box
                o = inBox(i % 8 == 2 ? 0.0f : 0.3f);
                int axis = int(rng() % 3);
                float sign = rng() % 2 ? 1.0f : -1.0f;
                d = Vec3{0.0f, 0.0f, 0.0f};
                (axis == 0 ? d.x : axis == 1 ? d.y : d.z) = sign;
                break;
            }
            default:  // anywhere, anywhere
                o = inBox(1.0f);
                d = Vec3{u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f};
                break;
        }
        if (length(d) == 0.0f) d = Vec3{0.0f, 0.0f, 1.0f};
        d = d * ((0.25f + 2.0f * u01(rng)) / length(d));  // non-unit on purpose
        float tmin = 0.0f, tmax = INFINITY;
        if (i % 5 == 3) {  // a finite window, in units of the direction's length
            tmin = u01(rng) * diag / length(d) * 0.5f;
            tmax = tmin + u01(rng) * diag / length(d);
        }
        const float row[8] = {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax};
        rays.insert(rays.end(), row, row + 8);
    }
    return rays;
}

// At most 0.05% of the rays (3 of 6000) may differ in hit/miss from Embree (shared edges and
// silhouettes where two watertight tests may round differently), and as many in distance when
// a double-precision recheck shows the ray grazing the triangle both tracers report (see
// isGrazingSameHit). Measured when this test was written, for every accel: 0 hit/miss
// everywhere; distance mismatches 0 on the Cornell box, 1 on the teapot (|cos| 3.2e-4, double
// t 24.73144: Embree 24.73311, octrace 24.73385) and 1 on wuson (|cos| 2.8e-4, double t
// 1.831830: Embree 1.831750, octrace 1.831796).
constexpr double kMaxHitMissRate = 5e-4;
constexpr double kMaxGrazingRate = 5e-4;
// The policy's grazing threshold (docs/VALIDATION.md, "The per-pixel policy"): |cos(ray, normal)|.
constexpr double kGrazingCos = 1e-3;

// A distance mismatch where both tracers report the same triangle and the ray meets its plane
// at |cos| <= kGrazingCos. There t = (distance to the plane) / (|d| cos) turns sub-ulp
// differences in where the ray meets the plane into large differences in t: an ambiguous
// configuration of the policy, not a wrong answer. Also requires the double-precision hit
// point to lie inside the triangle (barycentrics >= -1e-6), so it is a real grazing hit.
::testing::AssertionResult isGrazingSameHit(const Scene& scene, const float* ray, int32_t primA,
                                            int32_t primB) {
    if (primA != primB || primA < 0 || scene.kind != PrimKind::Triangles)
        return ::testing::AssertionFailure() << "different primitives " << primA << ", " << primB;
    const Triangle& tri = scene.triangles[size_t(primA)];
    auto d3 = [](Vec3 v) { return std::array<double, 3>{v.x, v.y, v.z}; };
    auto sub = [](std::array<double, 3> a, std::array<double, 3> b) {
        return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    };
    auto crossD = [](std::array<double, 3> a, std::array<double, 3> b) {
        return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                     a[0] * b[1] - a[1] * b[0]};
    };
    auto dotD = [](std::array<double, 3> a, std::array<double, 3> b) {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    };
    std::array<double, 3> o = {ray[0], ray[1], ray[2]}, d = {ray[3], ray[4], ray[5]};
    std::array<double, 3> a = d3(tri.v0), b = d3(tri.v1), c = d3(tri.v2);
    std::array<double, 3> n = crossD(sub(b, a), sub(c, a));
    double nn = dotD(n, n), dn = dotD(d, n);
    double cosine = dn / std::sqrt(nn * dotD(d, d));
    double t = dotD(n, sub(a, o)) / dn;
    std::array<double, 3> p = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
    double u = dotD(crossD(sub(b, p), sub(c, p)), n) / nn;
    double v = dotD(crossD(sub(c, p), sub(a, p)), n) / nn;
    double w = 1.0 - u - v;
    if (!(std::fabs(cosine) <= kGrazingCos))
        return ::testing::AssertionFailure() << "not grazing: |cos| " << std::fabs(cosine);
    if (!(u >= -1e-6 && v >= -1e-6 && w >= -1e-6))
        return ::testing::AssertionFailure() << "double hit point outside the triangle";
    return ::testing::AssertionSuccess()
           << "grazing, |cos| " << std::fabs(cosine) << ", double t " << t;
}

class TraceRoundTrip : public Cli, public ::testing::WithParamInterface<std::string> {};

TEST_P(TraceRoundTrip, EveryAccelMatchesInProcessEmbree) {
    const std::string scenePath = kMeshes + "/" + GetParam();
    const uint32_t n = 6000;
    Scene scene = loadScene(scenePath);
    std::vector<float> rays = makeRays(scene, n, 20240531);
    writeNpy(path("rays.npy"), "<f4", {n, 8}, rays.data(), 4);

    // Ground truth in process.
    std::vector<float> tRef(n);
    std::vector<int32_t> pRef(n);
    {
        EmbreeTracer embree(scene);
        traceRaysCpu(embree.accel(), RayBatchView{rays.data(), tRef.data(), pRef.data(), n});
    }
    uint64_t refHits =
        uint64_t(std::count_if(pRef.begin(), pRef.end(), [](int32_t p) { return p >= 0; }));
    EXPECT_GT(refHits, n / 4) << "the ray set should hit the scene often";
    const double extent = length(scene.bounds().extent());

    auto traceCli = [&](const std::string& backend, const std::string& accel, std::vector<float>& t,
                        std::vector<int32_t>& p) {
        std::string prefix = backend + "_" + accel;
        RunResult r = run("trace " + quote(scenePath) + " --rays " + q("rays.npy") + " --out " +
                          q(prefix) + " --backend " + backend + " --accel " + accel + kShallow);
        ASSERT_EQ(r.status, 0) << show(r);
        NpyArray ta = readNpy(path(prefix + ".t.npy"));
        NpyArray pa = readNpy(path(prefix + ".prim.npy"));
        ASSERT_EQ(ta.descr, "<f4");
        ASSERT_EQ(pa.descr, "<i4");
        ASSERT_EQ(ta.shape, std::vector<uint64_t>{n});
        ASSERT_EQ(pa.shape, std::vector<uint64_t>{n});
        t = npyVector<float>(ta);
        p = npyVector<int32_t>(pa);
    };

    std::vector<float> tExhaustive;
    std::vector<int32_t> pExhaustive;
    for (const LayoutDesc& layout : layouts()) {
        const std::string accel = layout.name;
        SCOPED_TRACE(accel);
        std::vector<float> t;
        std::vector<int32_t> p;
        ASSERT_NO_FATAL_FAILURE(traceCli("cpu", accel, t, p));
        // The documented contract of the output arrays.
        for (uint32_t i = 0; i < n; ++i) {
            if (p[i] < 0) {
                EXPECT_TRUE(std::isinf(t[i]) && t[i] > 0) << "ray " << i;
            } else {
                EXPECT_LT(p[i], int32_t(scene.primitiveCount())) << "ray " << i;
                EXPECT_GE(t[i], rays[8 * i + 6]) << "ray " << i;
                EXPECT_LE(t[i], rays[8 * i + 7]) << "ray " << i;
            }
        }
        FilmComparison c = compareHits(t, p, tRef, pRef, extent);
        std::printf(
            "[ %-8s ] %-16s %-10s vs embree: rays %llu, both miss %llu, agree %llu, ties "
            "%llu, hit/miss %llu, distance %llu, max |dt|/extent %.3g\n",
            "trace", GetParam().c_str(), accel.c_str(), (unsigned long long)c.pixels,
            (unsigned long long)c.bothMiss, (unsigned long long)c.bothHitAgree,
            (unsigned long long)c.ties, (unsigned long long)c.hitMissMismatch,
            (unsigned long long)c.distanceMismatch, c.maxRelativeDt);
        EXPECT_LE(double(c.hitMissMismatch), kMaxHitMissRate * n);
        // Every distance mismatch must be a grazing hit on the same triangle. The comparison
        // keeps up to 16 mismatching rays, so no more than that can be vouched for.
        uint64_t grazing = 0;
        for (const PixelMismatch& m : c.worst) {
            if (m.primA < 0 || m.primB < 0) continue;  // hit/miss, bounded above
            ::testing::AssertionResult g =
                isGrazingSameHit(scene, &rays[8 * size_t(m.x)], m.primA, m.primB);
            std::printf("[ %-8s ]   ray %d: t %.9g vs embree %.9g, prim %d: %s\n", "trace", m.x,
                        double(m.tA), double(m.tB), m.primA, g.message());
            if (g) ++grazing;
        }
        EXPECT_EQ(c.distanceMismatch, grazing) << "distance mismatches that are not grazing";
        EXPECT_LE(double(c.distanceMismatch), kMaxGrazingRate * n);
        if (!layout.usesOctree) {
            tExhaustive = t;
            pExhaustive = p;
        } else {
            // Same primitive tests, same tie rule: bit for bit the exhaustive answer.
            EXPECT_TRUE(sameBits(t, tExhaustive));
            EXPECT_EQ(p, pExhaustive);
        }
    }

    std::vector<float> tEmbree;
    std::vector<int32_t> pEmbree;
    ASSERT_NO_FATAL_FAILURE(traceCli("embree", "linear", tEmbree, pEmbree));
    EXPECT_TRUE(sameBits(tEmbree, tRef));
    EXPECT_EQ(pEmbree, pRef);
}

INSTANTIATE_TEST_SUITE_P(Meshes, TraceRoundTrip,
                         ::testing::Values("cornell_box.obj", "teapot.obj", "wuson.obj"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string s = info.param.substr(0, info.param.find('.'));
                             s.erase(std::remove(s.begin(), s.end(), '_'), s.end());
                             return s;
                         });

// --- (d) error paths ----------------------------------------------------------------------

// Runs a command that must fail and checks that `work` is unchanged afterwards (no output, no
// temporary file).
#define EXPECT_FAILS_CLEANLY(args)                                                    \
    do {                                                                              \
        std::set<std::string> before = listing();                                     \
        RunResult r_ = run(args);                                                     \
        EXPECT_TRUE(isOneLineError(r_)) << "octrace " << (args);                      \
        EXPECT_EQ(listing(), before) << "octrace " << (args) << " left files behind"; \
    } while (0)

TEST_F(Cli, RenderErrorsAreOneLineAndWriteNothing) {
    writeFile(path("scene.abc"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string out = " --out " + q("out.png") + " --depth " + q("t.npy");
    const std::string teapot = "render " + quote(kTeapot) + " --backend cpu" + out;
    EXPECT_FAILS_CLEANLY("render " + q("missing.obj") + " --backend cpu" + out);
    EXPECT_FAILS_CLEANLY("render " + quote(work_.string()) + " --backend cpu" + out);
    EXPECT_FAILS_CLEANLY("render " + q("scene.abc") + " --backend cpu" + out);
    for (const char* size : {"0x10", "10", "-5x5", "99999x1", "abcxdef", "16385x16", "8x8x8"})
        EXPECT_FAILS_CLEANLY(teapot + " --size " + size);
    EXPECT_FAILS_CLEANLY(teapot + " --accel octree");
    EXPECT_FAILS_CLEANLY("render " + quote(kTeapot) + " --backend vulkan" + out);
    EXPECT_FAILS_CLEANLY(teapot + " --eye 1,2,3 --target 1,2,3");
    EXPECT_FAILS_CLEANLY(teapot + " --eye nan,0,0");
    EXPECT_FAILS_CLEANLY(teapot + " --eye 1,2");
    EXPECT_FAILS_CLEANLY(teapot + " --max-depth 22");
    EXPECT_FAILS_CLEANLY(teapot + " --fov 180");
    EXPECT_FAILS_CLEANLY("render " + quote(kTeapot) + " --backend cpu");  // no --out
    EXPECT_FAILS_CLEANLY("render --backend cpu" + out);                   // no scene
    EXPECT_FAILS_CLEANLY("rendr " + quote(kTeapot));                      // no such command
}

TEST_F(Cli, InfoErrorsAreOneLine) {
    EXPECT_FAILS_CLEANLY("info " + q("missing.obj"));
    EXPECT_FAILS_CLEANLY("info " + quote(kTeapot) + " --max-depth 22");
    EXPECT_FAILS_CLEANLY("info " + quote(kTeapot) + " --max-prims 0");
    EXPECT_FAILS_CLEANLY("info grid:0");
    // The teapot's hash layout with one slot per bucket does not fit in 1 MiB: refused by name.
    const std::string tight = "info " + quote(kTeapot) + " --hash-slots 1 --hash-budget 1";
    EXPECT_FAILS_CLEANLY(tight);
    EXPECT_NE(run(tight).err.find("--hash-budget"), std::string::npos);
}

// --radius: a short, honest line for every value it refuses (not the range of a double, and
// no advice to give a value it then refuses).
TEST_F(Cli, RadiusErrorsAreShortAndHonest) {
    writeFile(path("p.xyz"), "0 0 0\n1 0 0\n");
    for (const char* radius : {"0", "-1", "nan", "inf", "-inf", "1e999", "abc", "1e-50", "1e39"}) {
        SCOPED_TRACE(radius);
        const RunResult r = run("info " + q("p.xyz") + " --radius " + radius);
        EXPECT_TRUE(isOneLineError(r));
        EXPECT_LT(r.err.size(), 200u) << r.err;
        EXPECT_NE(r.err.find("--radius"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("999999"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find(" 0 for"), std::string::npos) << r.err;
    }
    EXPECT_EQ(run("info " + q("p.xyz") + " --radius 0.25").status, 0);
}

TEST_F(Cli, TraceErrorsAreOneLineAndWriteNothing) {
    const uint64_t n = 16;
    std::vector<float> good(n * 8);
    for (uint64_t i = 0; i < n; ++i) {
        const float row[8] = {278, 273, -800, 0, 0, 1, 0, INFINITY};
        std::copy(row, row + 8, &good[8 * i]);
    }
    writeNpy(path("good.npy"), "<f4", {n, 8}, good.data(), 4);
    writeNpy(path("shape7.npy"), "<f4", {n, 7}, good.data(), 4);
    writeNpy(path("flat.npy"), "<f4", {n * 8}, good.data(), 4);
    std::vector<int32_t> ints(n * 8, 1);
    writeNpy(path("ints.npy"), "<i4", {n, 8}, ints.data(), 4);
    std::string bytes = readFile(path("good.npy"));
    writeFile(path("truncated.npy"), bytes.substr(0, bytes.size() - 5));
    writeFile(path("garbage.npy"), "this is not an npy file at all, just text\n");
    auto withRow = [&](const char* name, int column, float value) {
        std::vector<float> r = good;
        r[8 * 5 + column] = value;
        writeNpy(path(name), "<f4", {n, 8}, r.data(), 4);
    };
    withRow("nandir.npy", 4, std::nanf(""));
    withRow("infdir.npy", 3, INFINITY);
    withRow("nanorg.npy", 0, std::nanf(""));
    withRow("tmaxnan.npy", 7, std::nanf(""));
    {
        std::vector<float> r = good;
        r[8 * 5 + 3] = r[8 * 5 + 4] = r[8 * 5 + 5] = 0.0f;
        writeNpy(path("zerodir.npy"), "<f4", {n, 8}, r.data(), 4);
        r = good;
        r[8 * 5 + 6] = 10.0f;
        r[8 * 5 + 7] = 5.0f;
        writeNpy(path("window.npy"), "<f4", {n, 8}, r.data(), 4);
    }

    auto trace = [&](const std::string& rays, const std::string& extra = " --backend cpu") {
        return "trace " + quote(kCornell) + " --rays " + q(rays) + " --out " + q("hits") + extra;
    };
    for (const char* bad :
         {"shape7.npy", "flat.npy", "ints.npy", "truncated.npy", "garbage.npy", "nandir.npy",
          "infdir.npy", "nanorg.npy", "tmaxnan.npy", "zerodir.npy", "window.npy", "missing.npy"})
        EXPECT_FAILS_CLEANLY(trace(bad));
    EXPECT_FAILS_CLEANLY(trace("good.npy", " --backend cpu --accel bvh"));
    EXPECT_FAILS_CLEANLY(trace("good.npy", " --backend gpu"));
    EXPECT_FAILS_CLEANLY(trace("good.npy", " --backend cpu --max-depth 22"));
    EXPECT_FAILS_CLEANLY("trace " + q("missing.obj") + " --rays " + q("good.npy") + " --out " +
                         q("hits") + " --backend cpu");
    EXPECT_FAILS_CLEANLY("trace " + quote(kCornell) + " --out " + q("hits") + " --backend cpu");

    // The good file does trace (so the failures above are about the rays, not the set-up).
    RunResult ok = run(trace("good.npy"));
    EXPECT_EQ(ok.status, 0) << show(ok);
    EXPECT_TRUE(fs::exists(path("hits.t.npy")));
    EXPECT_TRUE(fs::exists(path("hits.prim.npy")));
}

// The default backend is `auto`, which reports its choice on stderr. On a failing run the
// error must still be the only line the user sees.
TEST_F(Cli, ErrorWithTheDefaultBackendIsOneLine) {
    EXPECT_FAILS_CLEANLY("render " + q("missing.obj") + " --out " + q("out.png"));
    EXPECT_FAILS_CLEANLY("render " + quote(kTeapot) + " --out " + q("out.png") + " --size 0x0");
}

TEST_F(Cli, CudaBackendInABuildWithoutCudaIsAnError) {
    const std::string args =
        "render " + quote(kCornell) + " --backend cuda --size 8x8 --out " + q("out.png");
    RunResult probe = run(args);
    if (probe.status == 0 || probe.err.find("without CUDA") == std::string::npos)
        GTEST_SKIP() << "this octrace has CUDA: " << probe.err;
    fs::remove(path("out.png"));
    EXPECT_FAILS_CLEANLY(args);
    EXPECT_FAILS_CLEANLY("trace " + quote(kCornell) + " --rays " + q("none.npy") + " --out " +
                         q("hits") + " --backend cuda");
}

TEST_F(Cli, HelpOfEachSubcommandListsItsOptions) {
    struct Case {
        std::string command;
        std::vector<std::string> mentions;
    };
    const std::vector<Case> cases = {
        {"--help", {"info", "render", "trace"}},
        {"info --help", {"--json", "--max-depth", "--max-prims", "--radius", "scene"}},
        {"render --help",
         {"--out", "--size", "--accel", "--backend", "--eye", "--target", "--fov", "--light",
          "--depth", "--prim", "--max-depth",
          // The heat map's default top is what heatmapImage uses (teach/heatmap.cpp).
          "99th percentile"}},
        {"trace --help", {"--rays", "--out", "--accel", "--backend", "--max-depth"}},
    };
    for (const Case& c : cases) {
        RunResult r = run(c.command);
        EXPECT_EQ(r.status, 0) << c.command << "\n" << show(r);
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << c.command << "\n" << show(r);
        for (const std::string& m : c.mentions)
            EXPECT_NE(r.out.find(m), std::string::npos) << c.command << " does not mention " << m;
        EXPECT_TRUE(listing().empty());
    }
}

// --- (e) existing outputs -----------------------------------------------------------------

TEST_F(Cli, FailingRunKeepsAnExistingOutputAndASuccessfulOneReplacesIt) {
    const std::string keep = "existing bytes, not a PNG\n";
    writeFile(path("out.png"), keep);
    writeFile(path("t.npy"), keep);
    const std::string out = " --out " + q("out.png") + " --depth " + q("t.npy");

    // Fails after parsing and camera set-up, when loading the scene.
    RunResult fail = run("render " + q("missing.obj") + " --backend cpu" + out);
    EXPECT_TRUE(isOneLineError(fail));
    // Fails while checking the options.
    fail = run("render " + quote(kCornell) + " --backend cpu --size 0x16" + out);
    EXPECT_TRUE(isOneLineError(fail));
    EXPECT_EQ(readFile(path("out.png")), keep);
    EXPECT_EQ(readFile(path("t.npy")), keep);
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "t.npy"}));

    RunResult ok =
        run("render " + quote(kCornell) + " --backend cpu --size 16x12" + kShallow + out);
    ASSERT_EQ(ok.status, 0) << show(ok);
    EXPECT_TRUE(isPngOfSize(readFile(path("out.png")), 16, 12));
    EXPECT_EQ(readNpy(path("t.npy")).shape, (std::vector<uint64_t>{12, 16}));
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "t.npy"}));

    // The same for trace's two outputs.
    writeFile(path("hits.t.npy"), keep);
    writeFile(path("hits.prim.npy"), keep);
    std::vector<float> nanRay = {0, 0, 0, std::nanf(""), 0, 1, 0, INFINITY};
    writeNpy(path("bad.npy"), "<f4", {1, 8}, nanRay.data(), 4);
    fail = run("trace " + quote(kCornell) + " --rays " + q("bad.npy") + " --out " + q("hits") +
               " --backend cpu");
    EXPECT_TRUE(isOneLineError(fail));
    EXPECT_EQ(readFile(path("hits.t.npy")), keep);
    EXPECT_EQ(readFile(path("hits.prim.npy")), keep);
}

// A render writes several files; when a later one cannot be written (here --depth into a
// folder that does not exist) the run fails, and the earlier output must not be left behind
// or have replaced an existing file either.
TEST_F(Cli, FailureWritingALaterOutputKeepsTheEarlierOneUnchanged) {
    const std::string args = "render " + quote(kCornell) + " --backend cpu --size 8x8" + kShallow +
                             " --out " + q("out.png") + " --depth " + q("no_such_folder/t.npy");
    EXPECT_FAILS_CLEANLY(args);
    const std::string keep = "existing bytes, not a PNG\n";
    writeFile(path("out.png"), keep);
    RunResult r = run(args);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_EQ(readFile(path("out.png")), keep);
}

}  // namespace
}  // namespace oct
