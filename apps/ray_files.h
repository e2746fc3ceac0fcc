// Stand-ins for two helpers being moved into core/io by another change: the ray-file reader
// (today `loadRays` in cmd_trace.cpp) and checkOutputPaths (core/io/output_file.h). `octrace
// rays` and `octrace certify` call them only through these two functions, so switching to the
// core/io versions is one line each.
#pragma once

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/npy.h"

namespace oct {
namespace cli_stopgap {

// A ray file (docs/TRACE_FORMAT.md): float32 (N, 8), finite origins, finite non-zero
// directions, tmin finite and tmin <= tmax (tmax may be +inf). The first bad row is named.
inline std::vector<float> readRayRows(const std::string& path) {
    NpyArray a = readNpy(path);
    if (a.descr != "<f4" || a.shape.size() != 2 || a.shape[1] != 8)
        throw IoError("'" + path +
                      "' must be a float32 array of shape (N, 8): ox oy oz dx dy dz tmin tmax "
                      "(got dtype " +
                      a.descr + ")");
    std::vector<float> rays(a.elementCount());
    if (!rays.empty()) std::memcpy(rays.data(), a.data.data(), a.data.size());
    for (uint64_t i = 0; i < a.shape[0]; ++i) {
        const float* r = &rays[8 * i];
        bool finite = true;
        for (int k = 0; k < 7; ++k) finite = finite && std::isfinite(r[k]);
        bool zeroDir = r[3] == 0.0f && r[4] == 0.0f && r[5] == 0.0f;
        if (!finite || zeroDir || std::isnan(r[7]) || r[6] > r[7])
            throw IoError("'" + path + "' row " + std::to_string(i) +
                          ": needs finite origin, a finite non-zero direction and tmin <= tmax");
    }
    return rays;
}

// Refuses, before any work, an output that is also an input or another output (paths compared
// after making them absolute and normal, so ./a and a are the same file): never destroy a file.
inline void refuseClobber(const std::vector<std::string>& outputs,
                          const std::vector<std::string>& inputs) {
    namespace fs = std::filesystem;
    auto key = [](const std::string& p) { return fs::weakly_canonical(fs::absolute(p)).string(); };
    for (size_t i = 0; i < outputs.size(); ++i) {
        if (outputs[i].empty() || outputs[i] == "-") continue;
        for (const std::string& in : inputs)
            if (!in.empty() && key(outputs[i]) == key(in))
                throw IoError("output '" + outputs[i] + "' is also an input ('" + in +
                              "'): choose another output name");
        for (size_t j = 0; j < i; ++j)
            if (!outputs[j].empty() && outputs[j] != "-" && key(outputs[i]) == key(outputs[j]))
                throw IoError("'" + outputs[i] +
                              "' is named as two outputs: choose distinct names");
    }
}

}  // namespace cli_stopgap
}  // namespace oct
