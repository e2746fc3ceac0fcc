// Depth limits shared by the host builder and the kernels' fixed-size traversal state.
#pragma once

#include <cstdint>

namespace oct {

// Deepest level the traversal state is sized for and the Morton key can address (root = 0):
// 3 bits a level plus the leading 1 fill 64 bits at 21 (morton.h). The traversals keep one
// entry a level of internal nodes, depths 0 .. kMaxOctreeDepth - 1 (traversal.h).
constexpr int kMaxOctreeDepth = 21;

// The builder's node budget (BuildParams::maxNodes, --node-budget). The default, 2^25 nodes, is
// 1.5 GiB of 48-byte node records, above every scene of the benchmark (16 M grid points at
// --cloud-max-prims 1 need 19 M nodes); the most, 2^31, keeps every node index, a uint32, far
// from overflowing.
constexpr uint64_t kDefaultNodeBudget = uint64_t(1) << 25;
constexpr uint64_t kMaxNodeBudget = uint64_t(1) << 31;
// The most node records a linear array or a hash table may hold: the traversal keeps a level's
// node as a 32-bit record index (traversal.h), so the layouts refuse more (4 Gi records are
// 192 GiB, past every device; linear depth 11 needs 9.8 Gi).
constexpr uint64_t kMaxNodeRecords = uint64_t(1) << 32;

}  // namespace oct
