// How reports name a SkipReason (traversal_observer.h), and the set of reasons a layout declares
// its traversal reports (the registry entry's kSkipReasons, layout.h). Host code.
#pragma once

#include <cstdint>
#include <initializer_list>

#include "core/octree/traversal_observer.h"

namespace oct {

// Every reason, in enum order (a test checks that each has its labels).
constexpr SkipReason kAllSkipReasons[] = {SkipReason::Missed, SkipReason::BeyondHit,
                                          SkipReason::Empty, SkipReason::Absent,
                                          SkipReason::OutsideBounds};

// Bit i set: reason i is declared.
constexpr uint32_t skipReasonBit(SkipReason r) { return 1u << uint32_t(r); }
template <class... R>
constexpr uint32_t skipReasonBits(R... reasons) {
    return (0u | ... | skipReasonBit(reasons));
}

// The phrase `octrace explain` prints ("empty leaf: nothing to hit"), and the key its JSON
// writes ("empty"); null for a value outside the enum.
inline const char* skipReasonText(SkipReason r) {
    switch (r) {
        case SkipReason::Missed:
            return "missed";
        case SkipReason::BeyondHit:
            return "beyond the closest hit";
        case SkipReason::Empty:
            return "empty leaf: nothing to hit";
        case SkipReason::Absent:
            return "no node stored there";
        case SkipReason::OutsideBounds:
            return "the ray misses the bounds of what the cell holds";
    }
    return nullptr;
}
inline const char* skipReasonKey(SkipReason r) {
    switch (r) {
        case SkipReason::Missed:
            return "missed";
        case SkipReason::BeyondHit:
            return "beyond_hit";
        case SkipReason::Empty:
            return "empty";
        case SkipReason::Absent:
            return "absent";
        case SkipReason::OutsideBounds:
            return "outside_bounds";
    }
    return nullptr;
}

}  // namespace oct
