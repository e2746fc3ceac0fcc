// Depth limits shared by the host builder and the kernels' fixed-size traversal stack.
#pragma once

namespace oct {

// Deepest level the traversal stack is sized for and the Morton key can address (root = 0):
// 3 bits a level plus the leading 1 fill 64 bits at 21 (morton.h).
constexpr int kMaxOctreeDepth = 21;
// A depth-first traversal pops one node and pushes at most 8 children per level, so its stack
// never holds more than 7 entries per level plus the 8 of the deepest internal node.
constexpr int kTraversalStackSize = 7 * kMaxOctreeDepth + 8;

}  // namespace oct
