// The one portability macro of octrace: code marked OCT_HD is compiled for the host and, under
// nvcc, for the device as well, so the OpenMP and CUDA backends run the same source.
#pragma once

#if defined(__CUDACC__)
#define OCT_HD __host__ __device__
#else
#define OCT_HD
#endif

#include <cstdint>

namespace oct {

// Loads of the read-only data a kernel traverses: node records, leaf index lists, primitives.
// Built with OCT_READONLY_LOADS, the CUDA device pass reads them through the read-only data
// cache (ld.global.nc, __ldg), the path the paper reached through texture memory on 2010
// hardware; everywhere else, and by default, they are plain loads. The value is the same either
// way, so films stay bit for bit equal; only the memory path (and so the speed) can differ.
// Callers bind the result to a const reference, which fits both forms.
// Device arrays come from cudaMalloc (256-byte aligned) and T's size is a multiple of 4 (of 8
// or 16 where the wider loads are taken), so every element is aligned for the loads below.
#if defined(__CUDA_ARCH__) && defined(OCT_READONLY_LOADS)
template <class T>
OCT_HD inline T loadReadOnly(const T* p) {
    static_assert(sizeof(T) % 4 == 0, "read-only loads move whole 32-bit words");
    T out;
    if constexpr (sizeof(T) % 16 == 0) {
        const uint4* src = reinterpret_cast<const uint4*>(p);
        uint4* dst = reinterpret_cast<uint4*>(&out);
#pragma unroll
        for (int i = 0; i < int(sizeof(T) / 16); ++i) dst[i] = __ldg(src + i);
    } else if constexpr (sizeof(T) % 8 == 0) {
        const uint2* src = reinterpret_cast<const uint2*>(p);
        uint2* dst = reinterpret_cast<uint2*>(&out);
#pragma unroll
        for (int i = 0; i < int(sizeof(T) / 8); ++i) dst[i] = __ldg(src + i);
    } else {
        const unsigned int* src = reinterpret_cast<const unsigned int*>(p);
        unsigned int* dst = reinterpret_cast<unsigned int*>(&out);
#pragma unroll
        for (int i = 0; i < int(sizeof(T) / 4); ++i) dst[i] = __ldg(src + i);
    }
    return out;
}
#else
// A reference, not a copy: callers bind `const T& x = loadReadOnly(p)`, which then reads the
// fields in place (a node copied per visit costs the CPU path: docs/PERFORMANCE.md, "Kernel
// choices").
template <class T>
OCT_HD inline const T& loadReadOnly(const T* p) {
    return *p;
}
#endif

}  // namespace oct
