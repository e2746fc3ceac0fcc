// The one portability macro of octrace: code marked OCT_HD is compiled for the host and, under
// nvcc, for the device as well, so the OpenMP and CUDA backends run the same source.
#pragma once

#if defined(__CUDACC__)
#define OCT_HD __host__ __device__
#else
#define OCT_HD
#endif

#include <cstdint>
