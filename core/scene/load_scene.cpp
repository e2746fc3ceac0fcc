// loadScene: a generator spec or a readable file of a known format (scene_formats.h), loaded by
// that format's loader (core/scene/format_*.cpp), then checked against octrace's range limits.
// loader_detail.h describes how the loaders work; docs/ROBUSTNESS.md lists the malformed inputs
// they are tested and fuzzed against.
#include "core/scene/load_scene.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>

#include "core/scene/loader_detail.h"
#include "core/scene/scene_formats.h"
#include "core/scene/scene_generators.h"

namespace oct {
namespace {

namespace fs = std::filesystem;
using namespace scene_detail;

void checkReadableFile(const std::string& path) {
    std::error_code ec;
    fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found)
        throw SceneError(
            "cannot open " + inQuotes(path) + ": No such file or directory; check the path",
            ENOENT);
    if (ec) throw SceneError("cannot open " + inQuotes(path) + ": " + ec.message(), ec.value());
    if (fs::is_directory(status))
        throw SceneError("cannot load " + inQuotes(path) + ": it is a directory; give a " +
                             sceneExtensionList(" or ") + " file",
                         EISDIR);
    // A FIFO would block the read forever and a device such as /dev/zero never ends.
    if (!fs::is_regular_file(status))
        throw SceneError("cannot load " + inQuotes(path) +
                             ": it is not a regular file (a pipe, socket or device); copy the "
                             "scene into a file first",
                         EINVAL);
    std::ifstream probe(path, std::ios::binary);
    if (!probe) {
        const int error = errno;
        throw SceneError("cannot open " + inQuotes(path) + ": " + std::strerror(error) +
                             "; check the file's permissions",
                         error);
    }
}

// Largest |coordinate| (sphere centres plus the radius) of the scene's primitives.
double largestCoordinate(const Scene& scene) {
    double m = 0.0;
    auto take = [&](const Vec3& v, double pad) {
        m = std::max({m, std::fabs(double(v.x)) + pad, std::fabs(double(v.y)) + pad,
                      std::fabs(double(v.z)) + pad});
    };
    for (const Triangle& t : scene.triangles) {
        take(t.v0, 0.0);
        take(t.v1, 0.0);
        take(t.v2, 0.0);
    }
    for (const Sphere& s : scene.spheres) take(s.center, double(s.radius));
    return m;
}

std::string shortNumber(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

// The numeric range of core/geometry/numeric_range.h (load_scene.h says why).
void checkSceneRange(const Scene& scene) {
    if (uint64_t(scene.triangles.size()) + scene.spheres.size() >= UINT32_MAX)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": it has more than 2^32 - 2 " +
                         "primitives, beyond octrace's 32-bit primitive ids; split the scene");
    const std::string where =
        " (docs/ROBUSTNESS.md, numeric range: float32 ray tests, ours and Embree's, are only "
        "correct inside it); rescale the scene";
    const double largest = largestCoordinate(scene);
    if (largest > kMaxCoordinate)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": its coordinates reach " +
                         shortNumber(largest) + ", beyond +-" + shortNumber(kMaxCoordinate) +
                         where);
    const Vec3 e = scene.bounds().extent();
    const double extent = std::max({double(e.x), double(e.y), double(e.z)});
    if (extent < double(float(kMinSceneExtent)))  // as float: "1e-6" in a file is accepted
        throw SceneError("cannot load " + inQuotes(scene.name) + ": its extent " +
                         shortNumber(extent) + " is below " + shortNumber(kMinSceneExtent) + where);
    uint64_t tiny = 0;
    double smallest = INFINITY;
    for (const Triangle& t : scene.triangles) {
        const double ax = double(t.v1.x) - t.v0.x, ay = double(t.v1.y) - t.v0.y,
                     az = double(t.v1.z) - t.v0.z;
        const double bx = double(t.v2.x) - t.v0.x, by = double(t.v2.y) - t.v0.y,
                     bz = double(t.v2.z) - t.v0.z;
        const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
        const double twiceArea = std::sqrt(cx * cx + cy * cy + cz * cz);
        if (twiceArea < kMinTriangleArea2) {
            ++tiny;
            smallest = std::min(smallest, twiceArea);
        }
    }
    if (tiny > 0)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": " + std::to_string(tiny) +
                         " of its triangles have an area below " +
                         shortNumber(kMinTriangleArea2 / 2) + " (the smallest " +
                         shortNumber(smallest / 2) +
                         "), too small for a float32 ray test ever to hit" + where);
    double smallestRadius = INFINITY;
    for (const Sphere& s : scene.spheres)
        smallestRadius = std::min(smallestRadius, double(s.radius));
    if (smallestRadius < kMinSphereRadius)
        throw SceneError("cannot load " + inQuotes(scene.name) + ": a sphere radius of " +
                         shortNumber(smallestRadius) + " is below " +
                         shortNumber(kMinSphereRadius) + where + " or give a larger --radius");
}

// LoadOptions::radius 0 means "none given" (the default rule); a negative or non-finite one is
// refused. The message shows it in its shortest form (std::to_string wrote 1e38 with 39 digits)
// and does not suggest 0, which the command line's --radius refuses.
void checkRadiusOption(const std::string& path, const LoadOptions& opts) {
    if (std::isfinite(opts.radius) && opts.radius >= 0.0f) return;
    std::ostringstream value;
    value << opts.radius;
    throw SceneError("invalid sphere radius " + value.str() + " for " + inQuotes(path) +
                     "; give a positive finite radius, or none for the default rule");
}

}  // namespace

Scene loadScene(const std::string& path, const LoadOptions& opts) {
    checkRadiusOption(path, opts);
    try {
        if (const SceneGenerator* generator = findSceneGenerator(path))
            return generator->generate(path, opts);
        checkReadableFile(path);
        const SceneFormat* format = findSceneFormat(path);
        if (!format) {
            const std::string ext = lowerExtension(path);
            throw SceneError("unknown scene format " +
                             (ext.empty() ? "(no extension)" : inQuotes("." + ext)) + " of " +
                             inQuotes(path) + "; use " + sceneExtensionList(", ") + " or " +
                             sceneGeneratorList(" or "));
        }
        Scene scene = format->load(path, opts);
        checkSceneRange(scene);
        return scene;
    } catch (const SceneError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw SceneError("out of memory while loading " + inQuotes(path) +
                         "; use a smaller scene or a machine with more memory");
    } catch (const std::exception& e) {
        throw SceneError("cannot load " + inQuotes(path) + ": " + e.what());
    }
}

namespace {

// The first row of an array scene that a loader would drop, as a refusal naming it.
[[noreturn]] void refuseRow(const std::string& name, uint64_t row, uint64_t count,
                            const std::string& why) {
    throw SceneError("cannot use " + inQuotes(name) + ": row " + std::to_string(row) + " of " +
                     std::to_string(count) + " " + why +
                     "; remove such rows (octrace numbers the primitives by row, so none is "
                     "dropped)");
}

void checkArrayCount(const std::string& name, uint64_t count, const char* what) {
    if (count == 0)
        throw SceneError("cannot use " + inQuotes(name) + ": it holds no " + what +
                         "; give at least one");
    if (count >= UINT32_MAX)
        throw SceneError("cannot use " + inQuotes(name) + ": it has more than 2^32 - 2 " + what +
                         ", beyond octrace's 32-bit primitive ids; split the scene");
}

}  // namespace

Scene sceneFromTriangles(const float* rows, uint64_t count, const std::string& name) {
    checkArrayCount(name, count, "triangles");
    Scene scene;
    scene.name = name;
    scene.kind = PrimKind::Triangles;
    scene.report.format = "array";
    scene.report.verticesRead = 3 * count;
    scene.report.facesRead = count;
    scene.triangles.reserve(count);
    scene.sourceFace.reserve(count);
    for (uint64_t i = 0; i < count; ++i) {
        const float* r = rows + 9 * i;
        const Triangle t{{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, {r[6], r[7], r[8]}};
        if (!isFinite(t.v0) || !isFinite(t.v1) || !isFinite(t.v2))
            refuseRow(name, i, count, "has a non-finite coordinate");
        if (isDegenerate(t)) refuseRow(name, i, count, "is a triangle of zero area");
        scene.triangles.push_back(t);
        scene.sourceFace.push_back(uint32_t(i));
    }
    checkSceneRange(scene);
    return scene;
}

Scene sceneFromPoints(const float* rows, uint64_t count, const LoadOptions& opts,
                      const std::string& name) {
    checkRadiusOption(name, opts);
    checkArrayCount(name, count, "points");
    std::vector<Vec3> points(count);
    for (uint64_t i = 0; i < count; ++i) {
        points[i] = {rows[3 * i], rows[3 * i + 1], rows[3 * i + 2]};
        if (!isFinite(points[i])) refuseRow(name, i, count, "has a non-finite coordinate");
    }
    LoadReport report;
    report.format = "array";
    report.verticesRead = count;
    Scene scene = sphereScene(name, points, report, opts);
    checkSceneRange(scene);
    return scene;
}

}  // namespace oct
