// Morton keys as the paper's hash octree uses them: the root's key is 1 and a child appends its
// 3-bit octant digit, key(child i of k) = k << 3 | i. The leading 1 marks the depth, so a 64-bit
// key holds 21 levels below the root (1 + 3 * 21 = 64 bits).
//
// Octant digit i: bit 0 = upper half in x, bit 1 = upper in y, bit 2 = upper in z (childBox()).
#pragma once

#include <cstdint>

#include "core/octree/octree_limits.h"
#include "core/platform.h"

namespace oct {

constexpr uint64_t kRootKey = 1;

OCT_HD inline uint64_t childKey(uint64_t key, int octant) {
    return (key << 3) | static_cast<uint64_t>(octant);
}
OCT_HD inline uint64_t parentKey(uint64_t key) { return key >> 3; }
OCT_HD inline int octantOf(uint64_t key) { return static_cast<int>(key & 7u); }

// Depth of a key: the position of its leading 1, in 3-bit steps (root: 0).
OCT_HD inline int keyDepth(uint64_t key) {
    int bits = 0;
    while (key > 1) {
        key >>= 3;
        ++bits;
    }
    return bits;
}

// Spreads the low 21 bits of v so that bit b lands at 3b (the classic magic-number dilation).
OCT_HD inline uint64_t dilate3(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}
OCT_HD inline uint32_t compact3(uint64_t v) {
    v &= 0x1249249249249249ull;
    v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ull;
    v = (v ^ (v >> 4)) & 0x100f00f00f00f00full;
    v = (v ^ (v >> 8)) & 0x1f0000ff0000ffull;
    v = (v ^ (v >> 16)) & 0x1f00000000ffffull;
    v = (v ^ (v >> 32)) & 0x1fffffull;
    return static_cast<uint32_t>(v);
}

// Key of the cell (x, y, z) of the 2^depth grid over the root box.
OCT_HD inline uint64_t encodeMorton(uint32_t x, uint32_t y, uint32_t z, int depth) {
    uint64_t code = dilate3(x) | dilate3(y) << 1 | dilate3(z) << 2;
    return (uint64_t(1) << (3 * depth)) | code;
}
OCT_HD inline void decodeMorton(uint64_t key, uint32_t& x, uint32_t& y, uint32_t& z) {
    int d = keyDepth(key);
    uint64_t code = key ^ (uint64_t(1) << (3 * d));
    x = compact3(code);
    y = compact3(code >> 1);
    z = compact3(code >> 2);
}

// Position of a key in the complete (linear) octree, where the children of p sit at 8p+1..8p+8:
// walking the digits from the root, p <- 8p + 1 + digit.
OCT_HD inline uint64_t linearIndexOfKey(uint64_t key) {
    int d = keyDepth(key);
    uint64_t p = 0;
    for (int level = d - 1; level >= 0; --level) p = 8 * p + 1 + ((key >> (3 * level)) & 7u);
    return p;
}

}  // namespace oct
