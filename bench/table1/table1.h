// The paper's Table 1 (Barboza & Clua 2011) for our meshes: name, vertices, faces and "octree
// faces", the sum over leaves of their primitive list lengths (a triangle in k leaves counts
// k times), for the committed meshes and the fetched ones in meshes/cache/ (`octrace validate
// --table1`).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/octree/octree.h"

namespace oct {

struct Table1Row {
    std::string name;  // file name, e.g. "bunny.obj"
    std::string path;
    uint64_t vertices = 0;  // vertices in the file (3 per facet for STL)
    uint64_t faces = 0;     // triangles traced (after fan triangulation and dropped faces)
    uint64_t octreeFaces = 0;
    int depth = 0;  // deepest level of the octree
    uint64_t nodes = 0;
    double buildSeconds = 0.0;
};

// Mesh files (.obj .ply .off .stl) directly in `dir` and in `dir`/cache, committed ones first,
// each group sorted by name. Throws std::runtime_error when `dir` is not a directory.
std::vector<std::string> table1Meshes(const std::string& dir);

Table1Row table1Row(const std::string& path, const BuildParams& params);

// The table as JSON (one object per row) and as text (a header and one line per row).
nlohmann::json toJson(const std::vector<Table1Row>& rows);
std::string humanTable1(const std::vector<Table1Row>& rows);

}  // namespace oct
