// `octrace explain`'s library (teach/explain.h): the recorded steps of every pixel add up to the
// cost the Film holds for it, for every layout of the registry; recording changes nothing; the
// recorder's own reasoning (culled vs missed boxes, hash lookups, why a ray misses the root box)
// checked on hand-made cases against independent computations.
#include "teach/explain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <random>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/skip_reasons.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/teach_error.h"
#include "tests/paths.h"

namespace oct {
namespace {

using octtest::kMeshes;

bool sameFloat(float a, float b) { return std::memcmp(&a, &b, 4) == 0; }

// A teapot (triangles) and a grid cloud (spheres), each seen from a default and a grazing
// camera (low over the scene, where rays cross many cells).
struct Case {
    std::string scene;
    std::optional<Vec3> eye;
};

Scene loadCase(const Case& c) { return loadScene(c.scene, {}); }

std::vector<Case> cases() {
    return {{kMeshes + "/teapot.obj", std::nullopt},
            {kMeshes + "/teapot.obj", Vec3{60.0f, 1.0f, 5.0f}},
            {"grid:300:7", std::nullopt},
            {"grid:300:7", Vec3{2.5f, 0.55f, 0.4f}}};
}

TEST(ExplainCost, EveryPixelsStepsAddUpToTheFilmForEveryLayout) {
    for (const Case& c : cases()) {
        const Scene scene = loadCase(c);
        CameraOptions cam;
        cam.width = 20;
        cam.height = 16;
        cam.eye = c.eye;
        const FrameParams frame = makeFrame(scene.bounds(), cam);
        for (const LayoutDesc& layout : layouts()) {
            SCOPED_TRACE(c.scene + " layout " + layout.name);
            const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
            Film film;
            std::string note;
            renderWith(resolveBackend("cpu", note), bs, frame, film);
            uint64_t shadowRays = 0, hits = 0;
            for (int y = 0; y < frame.height; ++y)
                for (int x = 0; x < frame.width; ++x) {
                    const size_t i = size_t(y) * frame.width + x;
                    const Explanation e = explainPixel(bs, frame, x, y);
                    const StepTotals p = countSteps(e.primary.steps);
                    const StepTotals s = e.shadow ? countSteps(e.shadow->steps) : StepTotals{};
                    ASSERT_EQ(p.boxTests + s.boxTests, film.nodes[i]) << "pixel " << x << "," << y;
                    ASSERT_EQ(p.primTests + s.primTests, film.primsTested[i])
                        << "pixel " << x << "," << y;
                    ASSERT_EQ(e.primary.hit.prim, film.prim[i]);
                    ASSERT_TRUE(sameFloat(e.primary.hit.t, film.t[i]));
                    ASSERT_EQ(e.shadowState, film.shadow[i]);
                    ASSERT_EQ(0, std::memcmp(e.rgb, &film.rgb[3 * i], 3));
                    shadowRays += e.shadow.has_value();
                    hits += e.primary.hit.prim >= 0;
                }
            // The cases exercise hits, misses and shadow rays.
            EXPECT_GT(hits, 0u);
            EXPECT_LT(hits, uint64_t(frame.width) * frame.height);
            EXPECT_GT(shadowRays, 0u);
        }
    }
}

// The same queries with NoObserver (what the kernels run) and with the recorder agree in hit
// and cost: recording observes, it does not change the traversal.
TEST(ExplainCost, RecordingChangesNothing) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    const FrameParams frame = makeFrame(scene.bounds(), CameraOptions{});
    const Aabb b = scene.bounds();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        for (int k = 0; k < 200; ++k) {
            const Vec3 origin = b.center() + b.extent() * Vec3{u(rng), u(rng), u(rng)} * 1.5f;
            const Vec3 toward = b.center() + b.extent() * Vec3{u(rng), u(rng), u(rng)} * 0.4f;
            const Vec3 dir = normalize(toward - origin);
            const Explanation e = explainRay(bs, frame, origin, dir);
            Hit plain = missHit();
            TraceCost cost = {0, 0};
            const Ray ray = e.primary.ray;  // explainRay normalises the direction once more
            bs.visit([&](const auto& view) { plain = closestHit(view, ray, cost); });
            ASSERT_EQ(e.primary.hit.prim, plain.prim);
            ASSERT_TRUE(sameFloat(e.primary.hit.t, plain.t));
            const StepTotals p = countSteps(e.primary.steps);
            ASSERT_EQ(p.boxTests, cost.nodesVisited);
            ASSERT_EQ(p.primTests, cost.primsTested);
        }
    }
}

TEST(ExplainCost, AnExplanationThatDoesNotAddUpIsRefused) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    CameraOptions cam;
    cam.width = cam.height = 8;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    for (const LayoutDesc& layout : layouts()) {
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        Explanation e = explainPixel(bs, frame, 4, 4);
        EXPECT_NO_THROW(verifyExplanation(e));
        ASSERT_FALSE(e.primary.steps.empty());
        // As if a layout skipped one observer call.
        e.primary.steps.erase(
            std::find_if(e.primary.steps.begin(), e.primary.steps.end(), [](const ExplainStep& s) {
                return s.event == StepEvent::Box || s.event == StepEvent::Prim;
            }));
        EXPECT_THROW(verifyExplanation(e), TeachError) << layout.name;
    }
}

TEST(ExplainPixel, OutsideTheImageIsRefusedWithTheRange) {
    EXPECT_NO_THROW(checkPixelInImage(0, 0, 64, 48));
    EXPECT_NO_THROW(checkPixelInImage(63, 47, 64, 48));
    for (auto [x, y] : {std::pair{64, 0}, {0, 48}, {-1, 3}, {3, -1}}) {
        try {
            checkPixelInImage(x, y, 64, 48);
            ADD_FAILURE() << x << "," << y << " accepted";
        } catch (const TeachError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("--pixel " + std::to_string(x) + "," + std::to_string(y)),
                      std::string::npos)
                << m;
            EXPECT_NE(m.find("0..63"), std::string::npos) << m;
        }
    }
}

// --- the recorder's reasoning ----------------------------------------------------------------

TEST(StepRecorder, TellsACulledBoxFromAMissedOne) {
    // Ray along +x from the origin; a primitive hit at t = 2, then two boxes tested against
    // [0, 2]: one on the ray at t 3..4 (culled by the hit), one off the ray (missed).
    const Ray ray = {{0, 0, 0}, {1, 0, 0}, 0.0f, INFINITY};
    StepRecorder r;
    r.primTested(7, true, 2.0f);
    r.boxTested(012, 1, {{3, -1, -1}, {4, 1, 1}}, false, 0, 0);
    r.boxTested(013, 1, {{3, 5, 5}, {4, 6, 6}}, false, 0, 0);
    r.nodePopped(014, 2.5f, false);
    r.finish(ray);
    ASSERT_EQ(r.steps.size(), 4u);
    EXPECT_EQ(r.steps[1].why, SkipReason::BeyondHit);
    EXPECT_FLOAT_EQ(r.steps[1].t0, 3.0f);
    EXPECT_FLOAT_EQ(r.steps[1].bestT, 2.0f);
    EXPECT_EQ(r.steps[2].why, SkipReason::Missed);
    EXPECT_EQ(r.steps[3].why, SkipReason::BeyondHit);
    EXPECT_FLOAT_EQ(r.steps[3].bestT, 2.0f);
    EXPECT_FLOAT_EQ(r.steps[0].bestT, INFINITY);  // before the hit
}

TEST(StepRecorder, GroupsHashProbesIntoLookups) {
    StepRecorder r;
    r.hashProbe(012, 5, 0, 077);  // another key
    r.hashProbe(012, 5, 1, 012);  // found
    r.boxTested(012, 1, {{0, 0, 0}, {1, 1, 1}}, true, 0, 1);
    r.hashProbe(013, 6, 0, 0);  // empty slot: not stored
    r.childSkipped(013, SkipReason::Absent);
    r.hashProbe(014, 6, 0, 014);  // found at once
    r.hashProbe(015, 6, 0, 015);  // next lookup, same bucket
    const StepTotals t = countSteps(r.steps);
    EXPECT_EQ(t.probes, 5u);
    EXPECT_EQ(t.lookups, 4u);
    EXPECT_EQ(t.boxTests, 1u);
    EXPECT_EQ(t.skipped, 1u);
}

// Every layout whose steps include hash probes reports well-formed lookups: one per node the
// traversal reaches (box tested or child skipped), each ending where the key is found or an
// empty slot says it is absent.
TEST(StepRecorder, HashLookupsAreWellFormed) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    CameraOptions cam;
    cam.width = cam.height = 6;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    bool sawProbes = false;
    for (const LayoutDesc& layout : layouts()) {
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) {
                const Explanation e = explainPixel(bs, frame, x, y);
                const std::vector<ExplainStep>& st = e.primary.steps;
                const StepTotals t = countSteps(st);
                if (t.probes == 0) continue;
                sawProbes = true;
                EXPECT_EQ(t.lookups, t.boxTests + t.skipped) << layout.name;
                for (size_t i = 0; i < st.size(); ++i) {
                    if (st[i].event != StepEvent::Probe) continue;
                    const bool last = i + 1 == st.size() || st[i + 1].event != StepEvent::Probe ||
                                      st[i + 1].key != st[i].key || st[i].hit;
                    if (!last) {
                        EXPECT_NE(st[i].slotKey, 0u) << "an empty slot must end the lookup";
                    }
                }
            }
    }
    EXPECT_TRUE(sawProbes) << "the registry's hash layout reports no probes";
}

// --- why a ray misses a box ------------------------------------------------------------------

// Closest approach by brute force: the distance from many points along the segment.
double bruteClosest(const Ray& r, const Aabb& b, double tEnd) {
    double best = INFINITY;
    for (int i = 0; i <= 200000; ++i) {
        const double t = r.tmin + (tEnd - r.tmin) * i / 200000.0;
        double d2 = 0;
        const double p[3] = {r.org.x + t * r.dir.x, r.org.y + t * r.dir.y, r.org.z + t * r.dir.z};
        const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
        for (int a = 0; a < 3; ++a) {
            const double e = p[a] < lo[a] ? lo[a] - p[a] : p[a] > hi[a] ? p[a] - hi[a] : 0;
            d2 += e * e;
        }
        best = std::min(best, std::sqrt(d2));
    }
    return best;
}

TEST(BoxMiss, NamesTheSlabAndTheClosestApproach) {
    const Aabb box = {{0, 0, 0}, {1, 1, 1}};
    struct Expect {
        Ray ray;
        const char* says;
    };
    const Vec3 slanted = normalize(Vec3{1.0f, -0.4f, 0.0f});
    const Expect cases[] = {
        {{{2, 0.5f, 0.5f}, {0, 1, 0}, 0, INFINITY}, "parallel to the x slab [0, 1]"},
        {{{-1, 2, 0.5f}, slanted, 0, INFINITY}, "leaves the x slab [0, 1]"},
        {{{3, 0.5f, 0.5f}, {1, 0, 0}, 0, INFINITY}, "behind the ray"},
        {{{-5, 0.5f, 0.5f}, {1, 0, 0}, 0, 2.0f}, "beyond the segment's end"},
    };
    for (const Expect& c : cases) {
        const BoxMiss m = analyseBoxMiss(c.ray, box);
        EXPECT_NE(m.reason.find(c.says), std::string::npos) << m.reason;
        const double tEnd = std::isfinite(c.ray.tmax) ? c.ray.tmax : 20.0;
        EXPECT_NEAR(m.distance, bruteClosest(c.ray, box, tEnd), 1e-4) << m.reason;
        EXPECT_GT(m.distance, 0.0);
    }
    // The slanted ray leaves the x slab at t = 2 before it enters the y slab at t = 2.5 (in
    // units of its unit direction, scaled by 1 / |(1, -0.4)|).
    const BoxMiss m = analyseBoxMiss(cases[1].ray, box);
    EXPECT_NE(m.reason.find("enters the y slab [0, 1]"), std::string::npos) << m.reason;
}

TEST(ExplainRay, AMissOfTheRootBoxIsExplainedForEveryLayout) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    const FrameParams frame = makeFrame(scene.bounds(), CameraOptions{});
    for (const LayoutDesc& layout : layouts()) {
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        const Explanation e = explainRay(bs, frame, {500, 500, 500}, {1, 0, 0});
        EXPECT_EQ(e.primary.hit.prim, -1);
        ASSERT_TRUE(e.primary.miss.has_value()) << layout.name;
        EXPECT_FALSE(e.shadow.has_value());
        EXPECT_NE(explainText(e).find("misses the root box"), std::string::npos);
        // A ray through the scene's centre is not a root miss.
        const Explanation through = explainRay(bs, frame, {0, 0, 500}, {0, 0, -1});
        EXPECT_FALSE(through.primary.miss.has_value());
    }
}

// --- text and JSON ---------------------------------------------------------------------------

TEST(ExplainOutput, JsonHoldsEveryStepAndTheKernelsCost) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    CameraOptions cam;
    cam.width = cam.height = 32;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    for (const LayoutDesc& layout : layouts()) {
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        const Explanation e = explainPixel(bs, frame, 16, 16);
        ASSERT_GE(e.primary.hit.prim, 0) << "the centre pixel should hit the teapot";
        const nlohmann::json j = nlohmann::json::parse(explainJson(e));
        EXPECT_EQ(j["layout"], layout.name);
        ASSERT_EQ(j["rays"][0]["steps"].size(), e.primary.steps.size());
        EXPECT_EQ(j["rays"][0]["hit"]["prim"], e.primary.hit.prim);
        EXPECT_EQ(j["version"], 2);
        EXPECT_EQ(j["cost"]["boxes_tested"], e.cost.nodesVisited);
        EXPECT_EQ(j["cost"]["prims_tested"], e.cost.primsTested);
        uint64_t boxes = 0, prims = 0;
        for (const auto& ray : j["rays"]) {
            boxes += ray["totals"]["boxes_tested"].get<uint64_t>();
            prims += ray["totals"]["prims_tested"].get<uint64_t>();
            // The JSON's events are the text's words: a node entered or dropped, never "pop".
            uint64_t entered = 0, dropped = 0;
            for (const auto& s : ray["steps"]) {
                EXPECT_NE(s["event"], "pop");
                entered += s["event"] == "enter";
                dropped += s["event"] == "drop";
            }
            EXPECT_EQ(entered, ray["totals"]["nodes_entered"].get<uint64_t>());
            EXPECT_EQ(dropped, ray["totals"]["nodes_dropped"].get<uint64_t>());
        }
        EXPECT_EQ(boxes, e.cost.nodesVisited);
        EXPECT_EQ(prims, e.cost.primsTested);
        const std::string text = explainText(e);
        EXPECT_NE(text.find("hit   primitive " + std::to_string(e.primary.hit.prim)),
                  std::string::npos);
        EXPECT_NE(text.find("pixel cost  " + std::to_string(e.cost.nodesVisited) +
                            " boxes tested, " + std::to_string(e.cost.primsTested)),
                  std::string::npos)
            << text;
    }
}

// Every skipped child is written with its own reason, in the text and in the JSON: the compact
// layout's cells whose quantised bounds the ray misses were once printed as "missed" and written
// as "absent".
TEST(ExplainOutput, EverySkipIsLabelledWithItsOwnReason) {
    const Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    CameraOptions cam;
    cam.width = cam.height = 24;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    uint32_t seen = 0;
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        for (int y = 0; y < frame.height; y += 3)
            for (int x = 0; x < frame.width; x += 3) {
                const Explanation e = explainPixel(bs, frame, x, y);
                const nlohmann::json j = nlohmann::json::parse(explainJson(e));
                const std::vector<ExplainLine> lines = explainLines(e, 0);
                const auto& steps = j["rays"][0]["steps"];
                ASSERT_EQ(steps.size(), e.primary.steps.size());
                for (size_t i = 0; i < e.primary.steps.size(); ++i) {
                    const ExplainStep& s = e.primary.steps[i];
                    if (s.event != StepEvent::Skip) continue;
                    seen |= skipReasonBit(s.why);
                    EXPECT_EQ(steps[i]["why"], skipReasonKey(s.why));
                    bool labelled = false;
                    for (const ExplainLine& line : lines)
                        labelled = labelled ||
                                   (line.step == i + 1 &&
                                    line.text.find(skipReasonText(s.why)) != std::string::npos);
                    EXPECT_TRUE(labelled) << "step " << i + 1 << " " << skipReasonKey(s.why);
                }
            }
    }
    EXPECT_TRUE(seen & skipReasonBit(SkipReason::OutsideBounds)) << "no compact bounds skip seen";
    EXPECT_TRUE(seen & skipReasonBit(SkipReason::Empty)) << "no empty leaf seen";
}

// The lines say which hit is the closest so far with the kernel's tie rule (considerPrimitive:
// nearer, or as near with a lower id).
TEST(ExplainOutput, ClosestSoFarFollowsTheTieRule) {
    Explanation e;
    e.primary.ray = {{0, 0, 0}, {0, 0, 1}, 0.0f, INFINITY};
    StepRecorder r;
    r.primTested(5, true, 2.0f);
    r.primTested(3, true, 2.0f);  // as near, lower id: the new closest
    r.primTested(9, true, 2.0f);  // as near, higher id: not
    r.primTested(8, true, 3.0f);  // farther
    r.primTested(7, true, 1.5f);  // nearer
    r.finish(e.primary.ray);
    e.primary.steps = r.steps;
    const std::vector<ExplainLine> lines = explainLines(e, 0);
    ASSERT_EQ(lines.size(), 5u);
    EXPECT_NE(lines[0].text.find("5 hit at t 2 (closest so far)"), std::string::npos);
    EXPECT_NE(lines[1].text.find("3 hit at t 2 (closest so far)"), std::string::npos);
    EXPECT_NE(lines[2].text.find("9 hit at t 2 (not nearer than t 2, primitive 3)"),
              std::string::npos)
        << lines[2].text;
    EXPECT_NE(lines[3].text.find("(not nearer than t 2, primitive 3)"), std::string::npos);
    EXPECT_NE(lines[4].text.find("7 hit at t 1.5 (closest so far)"), std::string::npos);
    for (const ExplainLine& l : lines) EXPECT_GE(l.prim, 0);
}

TEST(ExplainOutput, KeysAreOctalDigitsAfterTheRoot) {
    EXPECT_EQ(keyOctal(1), "1");
    EXPECT_EQ(keyOctal((1u << 3) | 5), "15");
    EXPECT_EQ(keyOctal((((1u << 3) | 7) << 3) | 0), "170");
}

}  // namespace
}  // namespace oct
