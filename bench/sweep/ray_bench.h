// `octrace bench --rays`: one ray file, one scene, traced through every requested layout on
// each backend that runs our layouts and through each backend with its own structure (Embree,
// robust and fast), so the figures a reader compares come from one run on the same rays. The
// cases are traced in interleaved rounds (round 1: every case, round 2: every case, ...; each
// round starting one case later), so a change of the machine's load falls on every case alike
// instead of on whichever ran last. Every case's hits are compared with one octree case's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/layout_registry.h"
#include "core/scene/scene.h"

namespace oct {

struct RayBenchOptions {
    std::vector<const LayoutDesc*> layouts;    // traced by each backend that uses layouts
    std::vector<const BackendDesc*> backends;  // in the order asked
    int warmup = 1;                            // untimed rounds first
    int repeats = 5;                           // timed rounds
    LayoutOptions layout;                      // the octree's build and the layouts' budgets
    bool progress = true;                      // a line per round on stderr
};

// A case's hits against the compared case's, ray by ray.
struct HitAgreement {
    uint64_t otherPrim = 0;  // another primitive, or a hit against a miss
    uint64_t otherT = 0;     // the same primitive at another t (any bit of the float)
    // The largest |t - t'| / t' over the rays of otherT: how far apart the same hits are.
    double maxRelativeDt = 0.0;
    bool exact() const { return otherPrim == 0 && otherT == 0; }
};

struct RayBenchCase {
    const LayoutDesc* layout = nullptr;  // null for a backend with its own structure
    const BackendDesc* backend = nullptr;
    double treeSeconds = 0.0;     // the canonical octree, built once and shared by the layouts
    double convertSeconds = 0.0;  // converting it to this layout
    double prepareSeconds = 0.0;  // the backend's preparation (Embree's BVH, a CUDA upload)
    uint64_t layoutBytes = 0;
    std::vector<double> traceSeconds;  // the timed rounds, in round order
    std::vector<float> t;              // the hits of the last round traced
    std::vector<int32_t> prim;
    uint64_t hits = 0;
    HitAgreement agreement;  // against RayBenchResult::compared (itself: exact)

    // The layout's name, or the structure of a backend with its own (embree-bvh).
    std::string structure() const;
    // Our structure (octree and layout) or the backend's own: the time to make what is traced.
    double buildSeconds() const;
    // What the backend's preparation costs beyond the build: a CUDA upload (Embree's
    // preparation is its build, counted there).
    double uploadSeconds() const;
};

// Ray by ray over `rays` rows: `c`'s hits against `with`'s (both sized).
HitAgreement compareHits(const RayBenchCase& c, const RayBenchCase& with, uint64_t rays);

struct RayBenchResult {
    uint64_t rays = 0;
    uint32_t primitives = 0;
    double readSeconds = 0.0;  // reading and checking the ray file (the caller's)
    double loadSeconds = 0.0;  // loading the scene (the caller's)
    std::vector<RayBenchCase> cases;
    size_t compared = 0;  // the case whose hits every other's are compared with
    // The cases of backends with their own structure, in order: each case has a ratio to each.
    std::vector<size_t> references;
};

// Builds the canonical octree once (when a layout needs one), converts it to each layout,
// prepares each case's backend once, then traces the rays warmup + repeats rounds and compares
// the hits. `rays` holds result.rays rows of 8 floats, checked (core/io/ray_file.h). Throws
// naming the case when one cannot be built or prepared (a layout over its budget).
void runRayBench(const Scene& scene, const float* rays, const RayBenchOptions& options,
                 RayBenchResult& result);

// The median of a case's timed rounds; its rays per second at the median, in millions.
double medianTraceSeconds(const RayBenchCase& c);
double mraysPerSecond(const RayBenchResult& r, const RayBenchCase& c);
// What a one-shot `octrace trace` of this case spends outside tracing: reading the rays,
// loading the scene, building (our octree and layout, or Embree's BVH) and uploading.
double outsideSeconds(const RayBenchResult& r, const RayBenchCase& c);
// The cases that must agree with the compared case exactly and do not: those on its backend
// (the same kernel on the same canonical octree, with the deterministic tie rule of
// core/geometry/primitives_view.h). Other backends' differences are reported, not judged.
std::vector<const RayBenchCase*> disagreeingCases(const RayBenchResult& r);

// The printed table: a row per case with its median trace time, Mrays/s, ratio to each
// reference, build and outside seconds, and its hits against the compared case.
std::string rayBenchTable(const RayBenchResult& r);
// DIR/rays-bench.json (format octrace-rays-bench/1: machine, config, the figures of the ray
// file and the scene, a row per case) and DIR/rays-bench.csv (the rows' scalar fields), each
// written to a temporary name and renamed.
nlohmann::ordered_json rayBenchJson(const RayBenchResult& r, const nlohmann::ordered_json& machine,
                                    const nlohmann::ordered_json& config);
void writeRayBench(const std::filesystem::path& dir, const RayBenchResult& r,
                   const nlohmann::ordered_json& machine, const nlohmann::ordered_json& config);

}  // namespace oct
