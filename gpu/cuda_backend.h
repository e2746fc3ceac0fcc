// Host API of the CUDA backend; includes no CUDA header, so apps/ and tests compile with a plain
// C++ compiler. Errors are thrown as std::runtime_error subclasses with one-line messages.
#pragma once

#include <stdexcept>
#include <string>

#include "core/backend/backend.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

class CudaError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// True when a CUDA device answers; `why` gets its name and compute capability, or the reason
// (no driver, no device) in one line. Never throws.
bool cudaDevicePresent(std::string& why);

// The backend's registry entry: the core kernel, one thread per pixel (or ray).
BackendDesc cudaBackend();

}  // namespace oct
