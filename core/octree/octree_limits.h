// Depth limits shared by the host builder and the kernels' fixed-size traversal stack.
#pragma once

#include <cstdint>

namespace oct {

// Deepest level the traversal stack is sized for and the Morton key can address (root = 0):
// 3 bits a level plus the leading 1 fill 64 bits at 21 (morton.h).
constexpr int kMaxOctreeDepth = 21;
// A depth-first traversal pops one node and pushes at most 8 children per level, so its stack
// never holds more than 7 entries per level plus the 8 of the deepest internal node.
constexpr int kTraversalStackSize = 7 * kMaxOctreeDepth + 8;

// The builder's node budget (BuildParams::maxNodes, --node-budget). The default, 2^25 nodes, is
// 1.5 GiB of 48-byte node records, above every scene of the benchmark (16 M grid points at
// --cloud-max-prims 1 need 19 M nodes); the most, 2^31, keeps every node index, a uint32, far
// from overflowing.
constexpr uint64_t kDefaultNodeBudget = uint64_t(1) << 25;
constexpr uint64_t kMaxNodeBudget = uint64_t(1) << 31;

}  // namespace oct
