// The node record of the paper (Barboza & Clua 2011, sec. 4): Morton key, index of the node's
// primitive list, type, depth and bounding box. Both GPU layouts store this same record.
#pragma once

#include <cstdint>

#include "core/geometry/aabb.h"

namespace oct {

enum class NodeType : uint8_t {
    Internal = 0,   // has 8 children, owns no primitives
    Leaf = 1,       // owns a primitive list (offset, count) into the global index array
    EmptyLeaf = 2,  // a leaf with no primitives: rays pass through it
    Invalid = 3,    // a slot of the complete linear array below a leaf: no node here
};

// Byte layout (48 bytes, 8-aligned):
//   0  uint64 key         Morton key, root 1, child = key << 3 | octant; 0 = no node
//   8  uint32 primOffset  first entry of this leaf's list in the global primitive index array
//  12  uint32 primCount   entries in that list (0 for internal and empty leaves)
//  16  Aabb   box         lo.xyz, hi.xyz as 6 floats
//  40  uint8  type        NodeType
//  41  uint8  depth       0 at the root
//  42  6 bytes padding
struct OctreeNode {
    uint64_t key;
    uint32_t primOffset;
    uint32_t primCount;
    Aabb box;
    uint8_t type;
    uint8_t depth;
    uint8_t pad[6];

    OCT_HD NodeType nodeType() const { return static_cast<NodeType>(type); }
};
static_assert(sizeof(OctreeNode) == 48, "OctreeNode byte layout is documented above");

}  // namespace oct
