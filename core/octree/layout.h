// What every acceleration layout provides, so that one list (layout_registry.h) names them all
// and nothing outside core/ switches on a layout.
//
// A layout is a struct of static members (see exhaustive_layout.h, linear_octree.h,
// hash_octree.h):
//   kName, kSummary              its --accel name and a one-line description for help texts
//   kUsesOctree                  whether it is converted from the canonical octree
//   using View = ...             the plain, trivially copyable struct its kernels receive
//   convert(scene, tree, options) host: the layout's arrays (LayoutStorage), from the canonical
//                                octree (null when kUsesOctree is false) over the scene's
//                                primitives; throws OctreeError naming the bytes when a budget
//                                is exceeded
//   report(scene, tree, options) host: its size and shape for `octrace info`, without
//                                allocating more than convert() would
//   view(arrays, prims)          builds the View from a LayoutArrays of host or device pointers
// and the traversal overloads closestHit(View, Ray, TraceCost&) / anyHit(View, Ray, TraceCost&).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/octree.h"

namespace oct {

// Default memory budgets of the layouts that can grow past any machine: 4 GiB each.
constexpr uint64_t kDefaultLinearBudget = 4ull << 30;
constexpr uint64_t kDefaultHashBudget = 4ull << 30;

struct HashParams {
    uint32_t bucketSlots = 4;  // B: the fixed-size list each bucket keeps instead of rehashing
    // m grows until no bucket holds more than B keys; a small B can need m far above the node
    // count (B = 1 is a perfect hash: m ~ n^2 / 2). Past this budget buildHash refuses.
    uint64_t budgetBytes = kDefaultHashBudget;
};

// Everything a layout's conversion may be told: the canonical build, and each layout's own
// shape and memory limits.
struct LayoutOptions {
    BuildParams build;
    HashParams hash;
    uint64_t linearBudget = kDefaultLinearBudget;
};

// One array of a layout: host or device memory, `bytes` long.
struct LayoutArray {
    const void* data;  // 8 bytes
    uint64_t bytes;    // 8 bytes
};

// A layout's arrays and scalars as plain values. The host fills it with its own vectors'
// pointers (LayoutStorage); the CUDA launcher uploads each array and fills a copy with device
// pointers. Each layout fixes what its slots mean (e.g. linear: array 0 nodes, array 1 the
// leaf index list). 96 bytes: 4 x 16 bytes of arrays, 4 x 8 bytes of scalars.
struct LayoutArrays {
    static constexpr int kMaxArrays = 4;
    static constexpr int kMaxScalars = 4;
    LayoutArray arrays[kMaxArrays];
    uint64_t scalars[kMaxScalars];

    template <class T>
    const T* array(int i) const {
        return static_cast<const T*>(arrays[i].data);
    }
    template <class T>
    uint64_t count(int i) const {
        return arrays[i].bytes / sizeof(T);
    }
};

// A figure of a layout's shape, for `octrace info` (JSON key and value): a count or bytes
// (exact, 64-bit) or a real number.
struct LayoutFact {
    std::string key;
    bool integer;
    uint64_t count;  // when integer
    double value;    // otherwise
};
inline LayoutFact countFact(std::string key, uint64_t n) { return {std::move(key), true, n, 0.0}; }
inline LayoutFact realFact(std::string key, double v) { return {std::move(key), false, 0, v}; }

// Size and shape of a layout over one canonical octree.
struct LayoutReport {
    uint64_t bytes = 0;  // the layout's own arrays (nodes, slots, leaf index list)
    std::vector<LayoutFact> facts;
    std::string summary;  // one line for `octrace info`
    double convertSeconds = 0.0;
};

// A converted layout on the host: `owner` keeps the arrays alive (the layout's own vectors and,
// where it shares them, the canonical octree's leaf index list).
struct LayoutStorage {
    std::shared_ptr<const void> owner;
    LayoutArrays arrays{};
    uint64_t bytes = 0;

    template <class T>
    const T& as() const {
        return *static_cast<const T*>(owner.get());
    }
};

// Helpers for layouts' conversions.
inline LayoutArray layoutArray(const void* data, uint64_t bytes) { return {data, bytes}; }
template <class T>
LayoutArray layoutArray(const std::vector<T>& v) {
    return {v.data(), uint64_t(v.size()) * sizeof(T)};
}
// "12 MiB (12582912 bytes)", or "more than 2^64 bytes" for a saturated figure.
std::string mibText(uint64_t bytes);

}  // namespace oct
