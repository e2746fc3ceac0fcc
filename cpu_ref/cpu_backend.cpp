#include "cpu_ref/cpu_backend.h"

#include "cpu_ref/render_cpu.h"

namespace oct {
namespace {

class CpuTracer : public SceneTracer {
public:
    explicit CpuTracer(const BuiltScene& scene) : scene_(scene) {}
    double prepareSeconds() const override { return 0.0; }
    std::vector<double> render(const FrameParams& frame, Film& film, int warmup,
                               int repeats) override {
        film = Film(frame.width, frameRows(frame));
        const FilmView fv = film.view();
        const PrimitivesView prims = scene_.prims();
        return timeFrames(warmup, repeats, [&] {
            scene_.visit([&](const auto& view) { renderFrameCpu(frame, view, prims, fv); });
        });
    }
    double trace(RayBatchView batch) override {
        return timeFrames(
            0, 1, [&] { scene_.visit([&](const auto& view) { traceRaysCpu(view, batch); }); })[0];
    }

private:
    const BuiltScene& scene_;
};

std::unique_ptr<SceneTracer> prepare(const BuiltScene& scene) {
    return std::make_unique<CpuTracer>(scene);
}

}  // namespace

BackendDesc cpuBackend() {
    BackendDesc d;
    d.name = "cpu";
    d.summary = "the core kernel on the host, OpenMP over pixels or rays";
    d.usesLayouts = true;
    d.available = &availableOnHost;
    d.prepare = &prepare;
    return d;
}

}  // namespace oct
