// The one checking macro for CUDA calls and launches: on failure it throws CudaError naming the
// call's text, file, line and cudaGetErrorName / cudaGetErrorString.
#pragma once

#include <cuda_runtime.h>

#include <string>

#include "gpu/cuda_backend.h"

namespace oct {

[[noreturn]] inline void throwCudaError(cudaError_t e, const char* call, const char* file,
                                        int line) {
    throw CudaError(std::string("CUDA ") + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) +
                    ") in " + call + " at " + file + ":" + std::to_string(line));
}

}  // namespace oct

#define OCT_CUDA_CHECK(call)                                                                   \
    do {                                                                                       \
        cudaError_t octErr_ = (call);                                                          \
        if (octErr_ != cudaSuccess) ::oct::throwCudaError(octErr_, #call, __FILE__, __LINE__); \
    } while (0)

// After every launch: the launch configuration error now, the execution error at the sync.
#define OCT_CUDA_CHECK_LAUNCH()                  \
    do {                                         \
        OCT_CUDA_CHECK(cudaGetLastError());      \
        OCT_CUDA_CHECK(cudaDeviceSynchronize()); \
    } while (0)
