// `octrace explain`: one pixel's (or one user ray's) traversal, step by step, as the kernel does
// it. The kernel's own tracePixel (core/render/kernel.h) runs with a StepRecorder as its
// observer (core/octree/traversal_observer.h), dispatched through BuiltScene::visit, so the
// steps are the kernel's steps and their count is the Film's cost for that pixel. The recorder
// knows the observer calls only, never a layout: a layout that reports its steps through the
// observer is explained without a line changing here.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/octree/traversal_observer.h"
#include "core/render/camera.h"

namespace oct {

enum class StepEvent : uint8_t {
    Box,    // a node's box tested against the ray (boxTested)
    Skip,   // a child not tested: empty leaf or absent (childSkipped)
    Pop,    // a node taken from the stack, entered or dropped (nodePopped)
    Prim,   // a primitive tested (primTested)
    Probe,  // one slot of a hash bucket looked at (hashProbe)
};

// One observer call. Fields not listed for an event are 0.
struct ExplainStep {
    StepEvent event = StepEvent::Box;
    // Box: the box was met; Pop: entered (false: dropped); Prim: hit; Probe: the slot held key.
    bool hit = false;
    // Box missed: Missed, or BeyondHit when the ray's whole segment meets the box but not the
    // part before the closest hit so far; Pop dropped: BeyondHit; Skip: the traversal's reason.
    SkipReason why = SkipReason::Missed;
    int depth = 0;         // Box: the node's depth
    uint64_t key = 0;      // Box, Skip, Pop, Probe: the node's Morton key
    Aabb box{};            // Box: the node's box
    float t0 = 0, t1 = 0;  // Box: [t enter, t exit] (for BeyondHit over the whole segment);
                           // Pop: t0 = t enter; Prim hit: t0 = t
    float bestT = 0;       // Box BeyondHit, Pop dropped, Prim: closest hit before this step
    uint32_t prim = 0;     // Prim
    uint32_t slot = 0;     // Probe
    uint64_t bucket = 0;   // Probe
    uint64_t slotKey = 0;  // Probe: the key found in the slot (0: empty slot)
};

// The observer `octrace explain` passes to the kernel: it records every call in order (host
// only). finish() then adds what the calls do not carry, from the ray alone: the closest hit
// before each step, and whether a missed box lies on the ray beyond that hit.
struct StepRecorder {
    void boxTested(uint64_t key, int depth, const Aabb& box, bool hit, float t0, float t1);
    void childSkipped(uint64_t key, SkipReason why);
    void nodePopped(uint64_t key, float tEnter, bool visited);
    void primTested(uint32_t prim, bool hit, float t);
    void hashProbe(uint64_t key, uint64_t bucket, uint32_t slot, uint64_t slotKey);
    // `ray` is the ray that was traced (its tmin and tmax included).
    void finish(const Ray& ray);

    std::vector<ExplainStep> steps;
};

// What the recorded steps add up to. boxTests and primTests are the kernel's TraceCost
// (nodesVisited, primsTested) counted from the steps.
struct StepTotals {
    uint64_t boxTests = 0, boxesHit = 0, primTests = 0, primHits = 0;
    uint64_t entered = 0, dropped = 0, skipped = 0;  // nodes entered, dropped; children skipped
    uint64_t probes = 0, lookups = 0;                // hash slots looked at; lookups they served
};
StepTotals countSteps(const std::vector<ExplainStep>& steps);
// The nodes entered (Pop events that entered), numbered 1..n in the order the traversal entered
// them: the numbering the page's cells and the 2D view's cells share.
std::map<uint64_t, int> visitOrder(const std::vector<ExplainStep>& steps);

// Why a ray misses a box, and how near it comes.
struct BoxMiss {
    std::string reason;   // which slab excluded the ray, as a sentence
    double distance = 0;  // closest approach of the ray's segment to the box
    double t = 0;         // where along the ray
    Vec3 point{0, 0, 0};  // the ray's point there
};
// Slab by slab (Kay & Kajiya), in double; meaningful when the segment misses the box.
BoxMiss analyseBoxMiss(const Ray& ray, const Aabb& box);

struct RayTrace {
    std::string role;  // "primary" or "shadow"
    Ray ray;
    bool anyHit = false;  // the shadow ray: the first hit ends the search
    Hit hit = {INFINITY, -1};
    std::vector<ExplainStep> steps;
    StepTotals totals;
    std::optional<BoxMiss> miss;  // the ray misses the root box
};

struct Explanation {
    std::string scene, layout;
    uint32_t primitives = 0;
    PrimKind kind = PrimKind::Triangles;
    bool pixelMode = true;
    int x = 0, y = 0, width = 0, height = 0;  // pixel mode
    Aabb root{};                              // the octree's root cube (the scene's, for
                                              // layouts without an octree)
    RayTrace primary;
    std::optional<RayTrace> shadow;  // cast only when the surface faces the light
    uint8_t shadowState = 0;         // kNoShadowRay, kLit, kOccluded (core/render/film.h)
    Vec3 light{0, 0, 0};
    Vec3 normal{0, 0, 0};  // at the hit, facing the ray
    uint8_t rgb[3] = {0, 0, 0};
    TraceCost cost = {0, 0};  // the kernel's cost for the pixel: the Film's nodes, primsTested
};

// Throws TeachError naming --pixel, the value and the image's range when (x, y) is outside a
// width x height image.
void checkPixelInImage(int x, int y, int width, int height);

// The pixel (x, y) of `frame` traced by the kernel's tracePixel with recorders. Throws
// TeachError for a pixel outside the image, and when the recorded steps do not add up to the
// kernel's cost (a layout that does not report all its steps: never explained wrongly).
Explanation explainPixel(const BuiltScene& bs, const FrameParams& frame, int x, int y);
// A user's ray as a row of a ray file (ox oy oz dx dy dz tmin tmax, core/io/ray_file.h): its
// closest hit, then the kernel's shadow query (shadowQuery, anyHit) towards frame.shading.light
// when it hits. The row must pass the ray file's rule (rayRowProblem; TeachError naming --ray
// and the rule otherwise). The ray traced is trace's (scaledRay, core/render/kernel.h) with its
// direction normalised and tmin, tmax scaled to match, so every t explained is a distance.
Explanation explainRay(const BuiltScene& bs, const FrameParams& frame, const float* row);
// The same for a ray from `origin` along `dir` with t from 0 to +inf.
Explanation explainRay(const BuiltScene& bs, const FrameParams& frame, Vec3 origin, Vec3 dir);
// The ray explainRay traces for a row that passes the rule.
Ray explainedRay(const float* row);

// Throws TeachError unless the recorded steps add up to the kernel's cost (e.cost): box tests
// to nodesVisited, primitive tests to primsTested. explainPixel and explainRay call it, so an
// explanation that describes a different traversal from the one the Film counts is refused.
void verifyExplanation(const Explanation& e);

// A Morton key in octal: "1" is the root, each further digit an octant (x + 2y + 4z).
std::string keyOctal(uint64_t key);

// The explanation as readable lines. `step` is the 1-based index of the first step a line
// covers (0: a heading or summary), `key` the cell it names (0: none), `prim` the primitive
// (-1: none). The text output and the HTML page's step list are these lines.
struct ExplainLine {
    size_t step = 0;
    int rayIndex = 0;  // 0 primary, 1 shadow
    uint64_t key = 0;
    int64_t prim = -1;
    std::string text;
};
std::vector<ExplainLine> explainLines(const Explanation& e, int rayIndex);
std::string explainText(const Explanation& e);
// Every step, the hits, the totals and the kernel's cost (the layout of `octrace explain
// --json`, documented in docs/TEACHING.md).
std::string explainJson(const Explanation& e);

}  // namespace oct
