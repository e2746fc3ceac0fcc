// One typed array of a layout as a kernel sees it: a pointer and an element count, in host or
// device memory alike. A layout's View lists its arrays as ArraySpans, once, in forEachArray
// (layout.h): the host view, the CUDA upload and the layout's byte count all derive from it.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/platform.h"

namespace oct {

// 16 bytes: data (8), count (8).
template <class T>
struct ArraySpan {
    using Element = T;
    const T* data;
    uint64_t count;

    OCT_HD uint64_t bytes() const { return count * sizeof(T); }
};
static_assert(sizeof(ArraySpan<uint32_t>) == 16, "ArraySpan byte layout is documented above");
static_assert(std::is_trivially_copyable<ArraySpan<uint32_t>>::value, "views are copied");

}  // namespace oct
