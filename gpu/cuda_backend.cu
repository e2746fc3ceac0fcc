// The CUDA backend: uploads the scene and the chosen layout's View, and runs the core per-pixel
// function (core/render/kernel.h) one thread per pixel, or traceRayAt one thread per ray.
// Nothing here traces or shades.
#include <algorithm>
#include <chrono>
#include <memory>
#include <type_traits>
#include <vector>

#include "core/system/launcher.h"
#include "core/time_spread.h"
#include "gpu/cuda_backend.h"
#include "gpu/device_buffer.h"

namespace oct {

// Every kernel runs in blocks of kBlockThreads threads and is compiled for at least
// kMinBlocksPerSm resident blocks a multiprocessor: 1,024 threads, so ptxas keeps a thread within
// 65,536 / 1,024 = 64 registers (Hopper's register file), the budget scripts/check-gpu-budget
// holds every kernel to, with its stack (at most 512 bytes).
constexpr int kBlockThreads = 128;
constexpr int kMinBlocksPerSm = 8;

template <class Accel>
__global__ void __launch_bounds__(kBlockThreads, kMinBlocksPerSm)
    renderKernel(FrameParams p, Accel accel, PrimitivesView prims, FilmView film) {
    int x = blockIdx.x * blockDim.x + threadIdx.x;
    int j = int(blockIdx.y * blockDim.y + threadIdx.y);  // the Film's row (camera.h, bands)
    if (x < p.width && j < frameRows(p)) renderPixel(x, imageRowOf(p, j), p, accel, prims, film);
}

template <class Accel>
__global__ void __launch_bounds__(kBlockThreads, kMinBlocksPerSm)
    traceKernel(Accel accel, RayBatchView batch) {
    uint64_t i = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < batch.count) traceRayAt(i, accel, batch);
}

namespace {

// The scene's primitives and the chosen layout's arrays in device memory, and the layout's View
// re-pointed to them: every array the View lists (forEachArray) is uploaded by rebindArrays, and
// kernels receive the View through the same registry dispatch as on the host, so this file
// names no layout.
struct DeviceScene {
    DeviceBuffer<Triangle> tris;
    DeviceBuffer<Sphere> spheres;
    std::vector<DeviceBuffer<uint8_t>> arrays;
    LayoutStorage storage;  // the View over device memory (its owner holds no arrays)
    PrimitivesView prims{};
    const LayoutDesc* layout = nullptr;

    explicit DeviceScene(const BuiltScene& b) : layout(b.layout) {
        const Scene& s = *b.scene;
        tris.upload(s.triangles, "the triangles");
        spheres.upload(s.spheres, "the spheres");
        prims = b.prims();
        prims.tris = tris.get();
        prims.spheres = spheres.get();
        visitLayoutType(*layout, [&](auto tag) {
            using View = typename decltype(tag)::View;
            auto upload = [&](const char* what, const auto& span) {
                using T = typename std::decay_t<decltype(span)>::Element;
                DeviceBuffer<uint8_t> buffer;
                buffer.upload(reinterpret_cast<const uint8_t*>(span.data), span.bytes(), what);
                const T* device = reinterpret_cast<const T*>(buffer.get());
                arrays.push_back(std::move(buffer));
                return device;
            };
            storage = makeLayoutStorage(rebindArrays(b.storage.as<View>(), prims, upload), nullptr);
        });
    }

    template <class F>
    void visit(F&& f) const {
        visitLayoutView(*layout, storage, f);
    }
};

struct DeviceFilm {
    DeviceBuffer<uint8_t> rgb, shadow;
    DeviceBuffer<float> t;
    DeviceBuffer<int32_t> prim;
    DeviceBuffer<uint32_t> nodes, primsTested;

    explicit DeviceFilm(size_t n) {
        rgb.allocate(3 * n, "the image");
        shadow.allocate(n, "the shadow flags");
        t.allocate(n, "the hit distances");
        prim.allocate(n, "the primitive ids");
        nodes.allocate(n, "the node counts");
        primsTested.allocate(n, "the primitive counts");
    }
    FilmView view(int w, int h) const {
        return {rgb.get(), t.get(), prim.get(), nodes.get(), primsTested.get(), shadow.get(), w, h};
    }
    void download(Film& f) const {
        size_t n = f.pixelCount();
        rgb.download(f.rgb.data(), 3 * n);
        shadow.download(f.shadow.data(), n);
        t.download(f.t.data(), n);
        prim.download(f.prim.data(), n);
        nodes.download(f.nodes.data(), n);
        primsTested.download(f.primsTested.data(), n);
    }
};

class EventTimer {
public:
    EventTimer() {
        OCT_CUDA_CHECK(cudaEventCreate(&start_));
        OCT_CUDA_CHECK(cudaEventCreate(&stop_));
    }
    ~EventTimer() {
        cudaEventDestroy(start_);
        cudaEventDestroy(stop_);
    }
    void start() { OCT_CUDA_CHECK(cudaEventRecord(start_)); }
    double stopSeconds() {
        OCT_CUDA_CHECK(cudaEventRecord(stop_));
        OCT_CUDA_CHECK(cudaEventSynchronize(stop_));
        float ms = 0.0f;
        OCT_CUDA_CHECK(cudaEventElapsedTime(&ms, start_, stop_));
        return ms * 1e-3;
    }

private:
    cudaEvent_t start_, stop_;
};

}  // namespace

namespace {

// Under a launcher (mpirun, srun) each rank takes the GPU of its rank on the node, so K ranks on
// a node of G GPUs share them round robin (core/system/launcher.h); device 0 otherwise. Returns
// the device, or -1 when none can be selected (the caller's checks report why).
int selectLocalDevice() {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0) {
        cudaGetLastError();
        return -1;
    }
    const LauncherPlacement place = launcherPlacement();
    if (!place.launched || place.size == 1) return 0;  // the default device, no context made
    const int device = place.localRank % count;
    if (cudaSetDevice(device) != cudaSuccess) {
        cudaGetLastError();
        return -1;
    }
    return device;
}

}  // namespace

bool cudaDevicePresent(std::string& why) {
    int count = 0;
    cudaError_t e = cudaGetDeviceCount(&count);
    if (e != cudaSuccess) {
        why = std::string("no usable CUDA device: ") + cudaGetErrorName(e) + " (" +
              cudaGetErrorString(e) + ")";
        cudaGetLastError();  // reset the last-error state, so later calls do not report this one
        return false;
    }
    if (count == 0) {
        why = "no CUDA device found";
        return false;
    }
    const LauncherPlacement place = launcherPlacement();
    const int device = selectLocalDevice();
    if (device < 0) {
        why = "cannot select a CUDA device";
        return false;
    }
    cudaDeviceProp prop;
    if (cudaGetDeviceProperties(&prop, device) != cudaSuccess) {
        why = "cannot query CUDA device " + std::to_string(device);
        return false;
    }
    why = std::string(prop.name) + ", compute capability " + std::to_string(prop.major) + "." +
          std::to_string(prop.minor) +
          (place.launched && place.size > 1
               ? ", device " + std::to_string(device) + " of the node's " + std::to_string(count) +
                     " (local rank " + std::to_string(place.localRank) + ")"
               : "");
    return true;
}

namespace {

// The CUDA backend prepared for one scene: uploaded once, then any number of frames and ray
// batches.
class CudaSceneTracer : public SceneTracer {
public:
    explicit CudaSceneTracer(const BuiltScene& b) {
        auto t0 = std::chrono::steady_clock::now();
        scene_ = std::make_unique<DeviceScene>(b);
        uploadSeconds_ = secondsSince(t0);
    }
    double prepareSeconds() const override { return uploadSeconds_; }

    std::vector<double> render(const FrameParams& p, Film& film, int warmup, int repeats) override {
        const int rows = frameRows(p);
        film = Film(p.width, rows);
        DeviceFilm dfilm(film.pixelCount());
        dim3 block(16, kBlockThreads / 16);
        dim3 grid((p.width + block.x - 1) / block.x, (rows + block.y - 1) / block.y);
        FilmView fv = dfilm.view(p.width, rows);
        std::vector<double> times;
        EventTimer timer;
        const PrimitivesView prims = scene_->prims;
        scene_->visit([&](auto view) {
            for (int i = 0; i < warmup; ++i) {
                renderKernel<<<grid, block>>>(p, view, prims, fv);
                OCT_CUDA_CHECK_LAUNCH();
            }
            for (int i = 0; i < std::max(1, repeats); ++i) {
                timer.start();
                renderKernel<<<grid, block>>>(p, view, prims, fv);
                OCT_CUDA_CHECK(cudaGetLastError());
                times.push_back(timer.stopSeconds());
                OCT_CUDA_CHECK_LAUNCH();
            }
        });
        dfilm.download(film);
        return times;
    }

    double trace(RayBatchView batch) override {
        DeviceBuffer<float> rays, t;
        DeviceBuffer<int32_t> prim;
        DeviceBuffer<uint32_t> nodes, primsTested;  // only when the caller asks for the cost
        rays.upload(batch.rays, 8 * batch.count, "the rays");
        t.allocate(batch.count, "the hit distances");
        prim.allocate(batch.count, "the primitive ids");
        RayBatchView dev{rays.get(), t.get(), prim.get(), batch.count};
        if (batch.nodes) {
            nodes.allocate(batch.count, "the boxes tested per ray");
            dev.nodes = nodes.get();
        }
        if (batch.primsTested) {
            primsTested.allocate(batch.count, "the primitives tested per ray");
            dev.primsTested = primsTested.get();
        }
        double seconds = 0.0;
        if (batch.count > 0) {
            unsigned block = kBlockThreads;
            unsigned grid = unsigned((batch.count + block - 1) / block);
            EventTimer timer;
            scene_->visit([&](auto view) {
                timer.start();
                traceKernel<<<grid, block>>>(view, dev);
                OCT_CUDA_CHECK(cudaGetLastError());
                seconds = timer.stopSeconds();
                OCT_CUDA_CHECK_LAUNCH();
            });
        }
        t.download(batch.t, batch.count);
        prim.download(batch.prim, batch.count);
        if (batch.nodes) nodes.download(batch.nodes, batch.count);
        if (batch.primsTested) primsTested.download(batch.primsTested, batch.count);
        return seconds;
    }

private:
    std::unique_ptr<DeviceScene> scene_;
    double uploadSeconds_ = 0.0;
};

std::unique_ptr<SceneTracer> prepareCuda(const BuiltScene& b) {
    selectLocalDevice();
    return std::make_unique<CudaSceneTracer>(b);
}

}  // namespace

BackendDesc cudaBackend() {
    BackendDesc d;
    d.name = "cuda";
    d.summary = "the core kernel on the GPU, one thread per pixel or ray";
    d.usesLayouts = true;
    d.device = true;
    d.available = &cudaDevicePresent;
    d.prepare = &prepareCuda;
    return d;
}

}  // namespace oct
