// The CUDA launcher: uploads the scene and the chosen layout as plain views, and runs the core
// per-pixel function (core/render/kernel.h) one thread per pixel. Nothing here traces or shades.
#include <algorithm>
#include <chrono>
#include <vector>

#include "core/time_spread.h"
#include "gpu/cuda_backend.h"
#include "gpu/device_buffer.h"

namespace oct {

template <class Accel>
__global__ void renderKernel(FrameParams p, Accel accel, PrimitivesView prims, FilmView film) {
    int x = blockIdx.x * blockDim.x + threadIdx.x;
    int y = blockIdx.y * blockDim.y + threadIdx.y;
    if (x < p.width && y < p.height) renderPixel(x, y, p, accel, prims, film);
}

template <class Accel>
__global__ void traceKernel(Accel accel, RayBatchView batch) {
    uint64_t i = uint64_t(blockIdx.x) * blockDim.x + threadIdx.x;
    if (i < batch.count) traceRayAt(i, accel, batch);
}

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The scene's primitives, leaf index array and the chosen layout's nodes in device memory.
struct DeviceScene {
    DeviceBuffer<Triangle> tris;
    DeviceBuffer<Sphere> spheres;
    DeviceBuffer<uint32_t> primIndices;
    DeviceBuffer<OctreeNode> nodes;  // linear array or hash slots
    PrimitivesView prims{};

    explicit DeviceScene(const BuiltScene& b) {
        const Scene& s = *b.scene;
        tris.upload(s.triangles, "the triangles");
        spheres.upload(s.spheres, "the spheres");
        primIndices.upload(b.tree.primIndices, "the leaf primitive index array");
        if (b.layout == Layout::Linear) nodes.upload(b.linear.nodes, "the linear octree");
        if (b.layout == Layout::Hash) nodes.upload(b.hash.slots, "the hash octree");
        prims = b.prims();
        prims.tris = tris.get();
        prims.spheres = spheres.get();
    }

    // Same switch as visitView (core/octree/accel.h), with device pointers.
    template <class F>
    void visit(const BuiltScene& b, F&& f) const {
        switch (b.layout) {
            case Layout::Linear:
                f(LinearOctreeView{nodes.get(), nodes.size(), primIndices.get(), prims});
                break;
            case Layout::Hash:
                f(HashOctreeView{nodes.get(), b.hash.bucketCount, b.hash.bucketSlots,
                                 primIndices.get(), prims});
                break;
            case Layout::Exhaustive:
            default:
                f(ExhaustiveView{prims});
        }
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

bool cudaDevicePresent(std::string& why) {
    int count = 0;
    cudaError_t e = cudaGetDeviceCount(&count);
    if (e != cudaSuccess) {
        why = std::string("no usable CUDA device: ") + cudaGetErrorName(e) + " (" +
              cudaGetErrorString(e) + ")";
        cudaGetLastError();  // clear the sticky-free error so later queries start clean
        return false;
    }
    if (count == 0) {
        why = "no CUDA device found";
        return false;
    }
    cudaDeviceProp prop;
    if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) {
        why = "cannot query CUDA device 0";
        return false;
    }
    why = std::string(prop.name) + ", compute capability " + std::to_string(prop.major) + "." +
          std::to_string(prop.minor);
    return true;
}

double renderCuda(const FrameParams& p, const BuiltScene& b, Film& film, CudaTiming* timing,
                  int warmup, int repeats) {
    CudaTiming tm;
    auto t0 = std::chrono::steady_clock::now();
    DeviceScene scene(b);
    film = Film(p.width, p.height);
    DeviceFilm dfilm(film.pixelCount());
    tm.uploadSeconds = secondsSince(t0);

    dim3 block(16, 8);
    dim3 grid((p.width + block.x - 1) / block.x, (p.height + block.y - 1) / block.y);
    FilmView fv = dfilm.view(p.width, p.height);
    std::vector<double> times;
    EventTimer timer;
    scene.visit(b, [&](auto view) {
        for (int i = 0; i < warmup; ++i) {
            renderKernel<<<grid, block>>>(p, view, scene.prims, fv);
            OCT_CUDA_CHECK_LAUNCH();
        }
        for (int i = 0; i < std::max(1, repeats); ++i) {
            timer.start();
            renderKernel<<<grid, block>>>(p, view, scene.prims, fv);
            OCT_CUDA_CHECK(cudaGetLastError());
            times.push_back(timer.stopSeconds());
            OCT_CUDA_CHECK_LAUNCH();
        }
    });
    t0 = std::chrono::steady_clock::now();
    dfilm.download(film);
    tm.downloadSeconds = secondsSince(t0);
    const TimeSpread spread = timeSpread(times);  // the rule octrace bench uses for the CPU
    tm.kernelSeconds = spread.median;
    tm.minKernelSeconds = spread.min;
    tm.maxKernelSeconds = spread.max;
    if (timing) *timing = tm;
    return tm.kernelSeconds;
}

double traceCuda(const BuiltScene& b, RayBatchView batch) {
    DeviceScene scene(b);
    DeviceBuffer<float> rays, t;
    DeviceBuffer<int32_t> prim;
    rays.upload(batch.rays, 8 * batch.count, "the rays");
    t.allocate(batch.count, "the hit distances");
    prim.allocate(batch.count, "the primitive ids");
    RayBatchView dev{rays.get(), t.get(), prim.get(), batch.count};
    double seconds = 0.0;
    if (batch.count > 0) {
        unsigned block = 128;
        unsigned grid = unsigned((batch.count + block - 1) / block);
        EventTimer timer;
        scene.visit(b, [&](auto view) {
            timer.start();
            traceKernel<<<grid, block>>>(view, dev);
            OCT_CUDA_CHECK(cudaGetLastError());
            seconds = timer.stopSeconds();
            OCT_CUDA_CHECK_LAUNCH();
        });
    }
    t.download(batch.t, batch.count);
    prim.download(batch.prim, batch.count);
    return seconds;
}

}  // namespace oct
