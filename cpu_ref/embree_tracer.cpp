#include "cpu_ref/embree_tracer.h"

#include <chrono>
#include <cmath>
#include <string>

namespace oct {
namespace {

void checkDevice(RTCDevice device, const char* what) {
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE)
        throw EmbreeError(std::string("Embree failed in ") + what + ": error code " +
                          std::to_string(int(e)));
}

RTCGeometry triangleGeometry(RTCDevice device, const Scene& scene) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    size_t n = scene.triangles.size();
    // Embree's vertex buffers are read with 16-byte loads: the last vertex needs 4 spare bytes,
    // which rtcSetNewGeometryBuffer's allocation provides.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
    if (!v || !idx) return g;  // the device error is reported by the caller
    for (size_t i = 0; i < n; ++i) {
        const Triangle& t = scene.triangles[i];
        const Vec3 vs[3] = {t.v0, t.v1, t.v2};
        for (int k = 0; k < 3; ++k) {
            v[9 * i + 3 * k + 0] = vs[k].x;
            v[9 * i + 3 * k + 1] = vs[k].y;
            v[9 * i + 3 * k + 2] = vs[k].z;
            idx[3 * i + k] = unsigned(3 * i + k);
        }
    }
    return g;
}

RTCGeometry sphereGeometry(RTCDevice device, const Scene& scene) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    size_t n = scene.spheres.size();
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
    if (!v) return g;
    for (size_t i = 0; i < n; ++i) {
        const Sphere& s = scene.spheres[i];
        v[4 * i + 0] = s.center.x;
        v[4 * i + 1] = s.center.y;
        v[4 * i + 2] = s.center.z;
        v[4 * i + 3] = s.radius;
    }
    return g;
}

void fillRay(RTCRay& r, const Ray& ray) {
    r.org_x = ray.org.x;
    r.org_y = ray.org.y;
    r.org_z = ray.org.z;
    r.dir_x = ray.dir.x;
    r.dir_y = ray.dir.y;
    r.dir_z = ray.dir.z;
    r.tnear = ray.tmin;
    r.tfar = ray.tmax;
    r.time = 0.0f;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
}

}  // namespace

EmbreeTracer::EmbreeTracer(const Scene& scene, bool robust) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw EmbreeError("cannot create an Embree device");
    // The clock starts after the device: creating it (thread pool, ISA probe) is a one-off cost
    // of the process, not of building this scene's BVH, which is what octree builds compare to.
    auto start = std::chrono::steady_clock::now();
    scene_ = rtcNewScene(device_);
    if (robust) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = scene.kind == PrimKind::Triangles ? triangleGeometry(device_, scene)
                                                      : sphereGeometry(device_, scene);
    checkDevice(device_, "creating the geometry");
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene_, g, 0);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_);
    checkDevice(device_, "building the scene");
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeTracer::~EmbreeTracer() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

Hit closestHit(const EmbreeAccel& a, const Ray& ray, TraceCost&) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(16) RTCRayHit rh;
    fillRay(rh.ray, ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(a.scene, &ctx, &rh);
    // Embree's robust triangle test computes T = 2 dot(v0, Ng), the cube of the coordinates:
    // past float range it reports tfar = +inf with a valid primitive. Never a hit at +inf; the
    // numeric range (core/geometry/numeric_range.h) keeps every accepted input below it.
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || !(rh.ray.tfar < INFINITY))
        return {INFINITY, -1};
    return {rh.ray.tfar, static_cast<int32_t>(rh.hit.primID)};
}

bool anyHit(const EmbreeAccel& a, const Ray& ray, TraceCost&) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(16) RTCRay r;
    fillRay(r, ray);
    rtcOccluded1(a.scene, &ctx, &r);
    return r.tfar == -INFINITY;  // Embree marks an occluded ray by tfar = -inf
}

}  // namespace oct
