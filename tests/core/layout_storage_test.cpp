// Each layout's View is its storage (core/octree/layout.h): the arrays it lists in forEachArray
// are what the CUDA launcher uploads and what its byte count sums. A layout that forgot an array
// there would trace host memory on the device; the skip reasons it declares are what `octrace
// explain` can label. Checked for every layout of the registry.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/octree/skip_reasons.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"

namespace oct {
namespace {

using octtest::kTeapot;

// Rays through the scene's box from a shell around it (a few miss, most hit).
std::vector<Ray> shellRays(const Scene& scene, int n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    auto u = [&] { return float(double(rng() >> 11) * 0x1p-53); };
    const Aabb b = scene.bounds();
    const Vec3 c = b.center();
    const float r = length(b.extent());
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Vec3 o = c + normalize(Vec3{u() - 0.5f, u() - 0.5f, u() - 0.5f}) * r;
        const Vec3 target = b.lo + Vec3{u(), u(), u()} * b.extent();
        rays.push_back({o, normalize(target - o), 0.0f, INFINITY});
    }
    return rays;
}

// Records which skip reasons a traversal reports: children skipped, and boxes missed or entered
// beyond the closest hit.
struct ReasonRecorder : NoObserver {
    uint32_t seen = 0;
    float best = INFINITY;
    void childSkipped(uint64_t, SkipReason why) { seen |= skipReasonBit(why); }
    void boxTested(uint64_t, int, const Aabb&, bool hit, float, float) {
        if (!hit) seen |= skipReasonBit(SkipReason::Missed);
    }
    void nodePopped(uint64_t, float, bool visited) {
        if (!visited) seen |= skipReasonBit(SkipReason::BeyondHit);
    }
};

TEST(LayoutStorage, BytesAreTheListedArraysAndTheReportAgrees) {
    const Scene scene = loadScene(kTeapot);
    LayoutOptions o;
    const auto tree = buildSharedOctree(scene, o.build);
    for (const LayoutDesc& l : layouts()) {
        SCOPED_TRACE(l.name);
        const BuiltScene b = convertLayout(scene, l.usesOctree ? tree : nullptr, l, o);
        uint64_t listed = 0;
        b.visit([&](const auto& view) { listed = arrayBytes(view); });
        EXPECT_EQ(b.layoutBytes(), listed);
        if (l.usesOctree) {
            EXPECT_EQ(l.report(scene, *tree, o).bytes, listed);
        }
    }
}

// The CUDA upload in miniature: every listed array copied to new memory and the view re-pointed
// there (rebindArrays), then the host storage and the canonical tree destroyed. The copy must
// trace exactly as the original did; an array missing from forEachArray would still point into
// the freed host memory (a use-after-free the sanitizer build reports, and wrong answers here).
TEST(LayoutStorage, AViewRepointedToCopiesOfItsListedArraysTracesTheSame) {
    const Scene scene = loadScene(kTeapot);
    const std::vector<Ray> rays = shellRays(scene, 2000, 7);
    for (const LayoutDesc& l : layouts()) {
        SCOPED_TRACE(l.name);
        LayoutOptions o;
        auto tree = buildSharedOctree(scene, o.build);
        auto built =
            std::make_unique<BuiltScene>(convertLayout(scene, l.usesOctree ? tree : nullptr, l, o));
        tree.reset();
        std::vector<Hit> before;
        built->visit([&](const auto& view) {
            for (const Ray& r : rays) {
                TraceCost cost = {0, 0};
                before.push_back(closestHit(view, r, cost));
            }
        });
        std::vector<std::vector<uint8_t>> copies;
        LayoutStorage copied;
        visitLayoutType(l, [&](auto tag) {
            using View = typename decltype(tag)::View;
            auto copy = [&](const char*, const auto& span) {
                using T = typename std::decay_t<decltype(span)>::Element;
                copies.emplace_back(span.bytes() + 1);
                if (span.bytes()) std::memcpy(copies.back().data(), span.data, span.bytes());
                return reinterpret_cast<const T*>(copies.back().data());
            };
            copied = makeLayoutStorage(
                rebindArrays(built->storage.as<View>(), primitivesView(scene), copy), nullptr);
        });
        built.reset();
        size_t differ = 0;
        size_t i = 0;
        visitLayoutView(l, copied, [&](const auto& view) {
            for (const Ray& r : rays) {
                TraceCost cost = {0, 0};
                const Hit h = closestHit(view, r, cost);
                differ += h.prim != before[i].prim || !(h.t == before[i].t || h.t != h.t);
                ++i;
            }
        });
        EXPECT_EQ(differ, 0u);
    }
}

// Every reason has a phrase for explain's text and a distinct key for its JSON.
TEST(SkipReasons, EveryReasonHasItsLabels) {
    std::set<std::string> keys;
    for (SkipReason r : kAllSkipReasons) {
        ASSERT_NE(skipReasonText(r), nullptr) << int(r);
        ASSERT_NE(skipReasonKey(r), nullptr) << int(r);
        EXPECT_TRUE(keys.insert(skipReasonKey(r)).second) << skipReasonKey(r);
    }
    uint32_t all = 0;
    for (SkipReason r : kAllSkipReasons) all |= skipReasonBit(r);
    for (const LayoutDesc& l : layouts())
        EXPECT_EQ(l.skipReasons & ~all, 0u) << l.name << " declares a reason with no labels";
}

// What a layout's traversal reports is what it declares, and on the teapot every declared reason
// occurs (so a declaration cannot go stale unnoticed).
TEST(SkipReasons, EachLayoutReportsExactlyTheReasonsItDeclares) {
    const Scene scene = loadScene(kTeapot);
    LayoutOptions o;
    const auto tree = buildSharedOctree(scene, o.build);
    std::vector<Ray> rays = shellRays(scene, 3000, 11);
    // A ray that misses the root (Missed) and one from outside every cell, for all layouts.
    const Aabb b = scene.bounds();
    rays.push_back({b.hi + b.extent() * 2.0f, {1.0f, 0.0f, 0.0f}, 0.0f, INFINITY});
    for (const LayoutDesc& l : layouts()) {
        SCOPED_TRACE(l.name);
        const BuiltScene built = convertLayout(scene, l.usesOctree ? tree : nullptr, l, o);
        ReasonRecorder rec;
        built.visit([&](const auto& view) {
            for (const Ray& r : rays) {
                TraceCost cost = {0, 0};
                closestHit(view, r, cost, rec);
            }
        });
        // Absent at the root is for an empty tree only; an octree layout need not meet it here.
        const uint32_t optional = skipReasonBit(SkipReason::Absent);
        EXPECT_EQ(rec.seen & ~l.skipReasons, 0u) << "reported but not declared: " << rec.seen;
        EXPECT_EQ(l.skipReasons & ~rec.seen & ~optional, 0u)
            << "declared, never seen: " << rec.seen;
    }
}

}  // namespace
}  // namespace oct
