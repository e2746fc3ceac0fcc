// Point clouds as scenes: one sphere per finite point (loader_detail.h).
#include <utility>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {

Scene sphereScene(const std::string& path, const std::vector<Vec3>& points, LoadReport report,
                  const LoadOptions& opts) {
    if (points.empty())
        throw SceneError("cannot load " + inQuotes(path) + ": it has no usable points (" +
                         std::to_string(report.verticesRead) + " read, " +
                         std::to_string(report.droppedNonFinite) +
                         " dropped as non-finite); give at least one finite point");
    Scene scene;
    scene.name = path;
    scene.kind = PrimKind::Spheres;
    scene.report = std::move(report);
    const float radius = opts.radius > 0.0f ? opts.radius : defaultPointRadius(points);
    scene.spheres.reserve(points.size());
    for (const Vec3& p : points) scene.spheres.push_back({p, radius});
    return scene;
}

std::vector<Vec3> finitePoints(const std::vector<Vec3>& points, LoadReport& report) {
    std::vector<Vec3> kept;
    kept.reserve(points.size());
    for (const Vec3& p : points) {
        if (isFinite(p))
            kept.push_back(p);
        else
            ++report.droppedNonFinite;
    }
    return kept;
}

}  // namespace oct::scene_detail
