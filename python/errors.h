// octrace's exceptions as Python's, each with octrace's one-line message:
//   a scene file that could not be opened or read (SceneError with an errno) -> OSError, of the
//     errno's subclass (FileNotFoundError, PermissionError, IsADirectoryError);
//   a malformed file, an array of the wrong shape or dtype, a bad option value, rays a manifest
//     does not describe (SceneError, OctreeError, FrameError, IoError, TeachError,
//     std::invalid_argument, std::out_of_range) -> ValueError;
//   not enough memory for the request (ResourceError, std::bad_alloc) -> MemoryError;
//   anything else (a backend that cannot run here: CudaError) -> RuntimeError.
// Never a crash of the interpreter: every call into octrace is behind these.
#pragma once

#include <pybind11/pybind11.h>

namespace oct::python {

void registerErrorTranslator();

// Sets OSError(error, message) as the pending Python error (the caller then throws
// pybind11::error_already_set): for a file the module itself finds it cannot read.
void setOsError(int error, const char* message);

}  // namespace oct::python
