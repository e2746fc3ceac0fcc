// Embree 3 ground truth. EmbreeTracer owns an Embree device and a robust scene
// (RTC_SCENE_FLAG_ROBUST) of the same primitives, in the same order, so Embree's primID is our
// primitive id. Without the flag (robust = false, the `embree-fast` backend) it is Embree in its
// default mode, a third-party tracer `octrace certify` can be shown on. EmbreeAccel plugs into the
// core kernel's closestHit/anyHit overloads, so a frame traced by Embree is shaded by exactly the
// code that shades our layouts.
#pragma once

#include <embree3/rtcore.h>

#include <stdexcept>

#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace oct {

class EmbreeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct EmbreeAccel {
    RTCScene scene;
};

class EmbreeTracer {
public:
    // Throws EmbreeError with Embree's message.
    explicit EmbreeTracer(const Scene& scene, bool robust = true);
    ~EmbreeTracer();
    EmbreeTracer(const EmbreeTracer&) = delete;
    EmbreeTracer& operator=(const EmbreeTracer&) = delete;

    EmbreeAccel accel() const { return {scene_}; }
    double buildSeconds() const { return buildSeconds_; }

private:
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    double buildSeconds_ = 0.0;
};

// Host-only overloads: Embree's query in place of our traversal. Embree counts no nodes and
// reports no steps to an observer.
Hit closestHit(const EmbreeAccel& a, const Ray& r, TraceCost& cost);
bool anyHit(const EmbreeAccel& a, const Ray& r, TraceCost& cost);
template <class Obs>
Hit closestHit(const EmbreeAccel& a, const Ray& r, TraceCost& cost, Obs&) {
    return closestHit(a, r, cost);
}
template <class Obs>
bool anyHit(const EmbreeAccel& a, const Ray& r, TraceCost& cost, Obs&) {
    return anyHit(a, r, cost);
}

}  // namespace oct
