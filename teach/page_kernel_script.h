// The explain page's kernel: teach/wasm/page_kernel.cpp and the core it calls (camera, octree
// builder, layouts, traversal with its observer, primitives, shading, explain) compiled to
// WebAssembly by emscripten at build time, as one script with the module inlined in base64
// (emcc -sSINGLE_FILE), and compiled into the binary like the viewer (see teach/teach.cmake),
// so the page opens offline from one file.
#pragma once

#include <string>

namespace oct {

// False in a build without emscripten (or configured with -DOCT_PAGE_KERNEL=OFF): pages then
// show the recorded pixel only, and say so.
bool pageKernelAvailable();
// The script defining the factory OctracePageKernel() ("" without the kernel).
const std::string& pageKernelScript();
// "emscripten 3.1.6" (what compiled it), or "not built".
const char* pageKernelVersion();

}  // namespace oct
