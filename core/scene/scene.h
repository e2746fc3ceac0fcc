// A scene as the rest of octrace sees it: flat arrays of one primitive kind, plus an account of
// everything loading dropped. Host-only (std containers); kernels see PrimitivesView instead.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/aabb.h"
#include "core/geometry/primitives.h"  // Triangle, Sphere, PrimKind

namespace oct {

// Thrown for any problem with a scene file or generator spec. The message names the file,
// the offending value and what the user can do about it (one line, no trailing newline).
class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
    SceneError(const std::string& what, int osError)
        : std::runtime_error(what), osError_(osError) {}
    // The errno of a scene file that could not be opened or read (ENOENT, EACCES, EISDIR; EINVAL
    // for a pipe or device), so that callers can tell a file they could not read (Python's
    // OSError) from one that was read and refused (ValueError); 0 for the latter.
    int osError() const { return osError_; }

private:
    int osError_ = 0;
};

// What loading saw and what it dropped; nothing is dropped without being counted here.
struct LoadReport {
    std::string format;                  // "obj", "ply", "off", "stl", "xyz", "grid"
    uint64_t verticesRead = 0;           // vertices (or points) in the file
    uint64_t facesRead = 0;              // faces in the file, any arity
    uint64_t polygonsTriangulated = 0;   // faces with more than 3 vertices, fan-triangulated
    uint64_t droppedInvalidIndex = 0;    // faces referencing a vertex that does not exist
    uint64_t droppedNonFinite = 0;       // faces (or points) with a NaN/inf coordinate
    uint64_t droppedDegenerate = 0;      // triangles of zero area (incl. repeated vertices)
    uint64_t droppedTooFewVertices = 0;  // faces with fewer than 3 vertices

    uint64_t totalDropped() const {
        return droppedInvalidIndex + droppedNonFinite + droppedDegenerate + droppedTooFewVertices;
    }
};

// The kind as files and reports spell it: "triangles" or "spheres" (manifests, JSON, reports).
inline const char* primKindName(PrimKind k) {
    return k == PrimKind::Triangles ? "triangles" : "spheres";
}

struct Scene {
    std::string name;  // path it came from, or the generator spec
    PrimKind kind = PrimKind::Triangles;
    std::vector<Triangle> triangles;   // kind == Triangles: file face order (polygons fanned)
    std::vector<uint32_t> sourceFace;  // kind == Triangles: file face index of each triangle
    std::vector<Sphere> spheres;       // kind == Spheres: file point order
    LoadReport report;

    // Generated grid clouds fix the root box and the grid depth so that each cell is exactly
    // one deepest leaf (see grid_cloud.h); loaded scenes leave these empty.
    std::optional<Aabb> domain;
    int gridDepth = -1;

    uint32_t primitiveCount() const {
        return static_cast<uint32_t>(kind == PrimKind::Triangles ? triangles.size()
                                                                 : spheres.size());
    }
    Aabb bounds() const;  // tight box around all primitives (spheres include their radius)
};

// The scene's size for every distance tolerance (render --compare-embree, octrace validate): the
// diagonal of bounds() in double, 1 for a point-sized or non-finite box so nothing divides by 0.
double sceneExtent(const Scene& scene);

struct LoadOptions {
    // Sphere radius for point clouds; 0 selects the default rule documented in load_scene.h.
    float radius = 0.0f;
};

}  // namespace oct
