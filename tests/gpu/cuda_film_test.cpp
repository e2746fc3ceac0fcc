// The CUDA path against the OpenMP path: same kernel source, so in the certification build
// (--fmad=false, no fast math) t, primitive id and colour must agree bit for bit, per layout.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "backends/backend_list.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "gpu/cuda_backend.h"

namespace oct {
namespace {

#define OCT_REQUIRE_GPU()                                                 \
    do {                                                                  \
        std::string why_;                                                 \
        if (!cudaDevicePresent(why_)) GTEST_SKIP() << "no GPU: " << why_; \
    } while (0)

// The CUDA backend's entry in the backend list (this test binary is built only with CUDA).
const BackendDesc& cuda() { return *findBackend(cudaBackend().name); }

// The repository root: $OCT_SOURCE_DIR when set (the GPU machine runs binaries built here from
// another checkout path, scripts/gpu-run), else the path compiled in.
std::string meshPath(const std::string& name) {
    const char* root = std::getenv("OCT_SOURCE_DIR");
    return std::string(root ? root : OCT_SOURCE_DIR) + "/meshes/" + name;
}

// Counts pixels whose t, prim or colour bits differ between the two films.
size_t differingPixels(const Film& a, const Film& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.pixelCount(); ++i) {
        bool same = std::memcmp(&a.t[i], &b.t[i], sizeof(float)) == 0 && a.prim[i] == b.prim[i] &&
                    std::memcmp(&a.rgb[3 * i], &b.rgb[3 * i], 3) == 0 && a.shadow[i] == b.shadow[i];
        n += !same;
    }
    return n;
}

void expectBitEqual(const Scene& scene, int w, int h) {
    CameraOptions cam;
    cam.width = w;
    cam.height = h;
    FrameParams frame = makeFrame(scene.bounds(), cam);
    for (const LayoutDesc& layout : layouts()) {  // every layout of the registry
        BuiltScene b = buildScene(scene, layout, {});
        Film cpu, gpu;
        renderWith(hostBackend(), b, frame, cpu);
        renderWith(cuda(), b, frame, gpu);
        size_t hits = 0;
        for (int32_t p : cpu.prim) hits += p >= 0;
        EXPECT_GT(hits, 0u) << scene.name;
        EXPECT_EQ(differingPixels(cpu, gpu), 0u) << scene.name << " " << layout.name;
    }
}

TEST(CudaBackend, ReportsPresenceInOneLine) {
    std::string why;
    bool present = cudaDevicePresent(why);
    EXPECT_FALSE(why.empty());
    EXPECT_EQ(why.find('\n'), std::string::npos);
    if (!present) GTEST_SKIP() << "no GPU: " << why;
}

TEST(CudaBackend, FilmEqualsOpenMpOnCommittedMeshes) {
    OCT_REQUIRE_GPU();
    for (const char* m : {"cornell_box.obj", "teapot.obj", "spider.obj", "wuson.obj"})
        expectBitEqual(loadScene(meshPath(m)), 256, 256);
}

TEST(CudaBackend, FilmEqualsOpenMpOnBunny) {
    OCT_REQUIRE_GPU();
    std::string bunny = meshPath("cache/bunny.obj");
    if (!std::filesystem::exists(bunny)) GTEST_SKIP() << "run meshes/fetch for the bunny";
    expectBitEqual(loadScene(bunny), 512, 512);
}

TEST(CudaBackend, FilmEqualsOpenMpOnGridCloud) {
    OCT_REQUIRE_GPU();
    expectBitEqual(makeGridCloud(4096, 3), 256, 256);
}

TEST(CudaBackend, TraceEqualsOpenMp) {
    OCT_REQUIRE_GPU();
    Scene scene = loadScene(meshPath("teapot.obj"));
    Aabb bb = scene.bounds();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const uint64_t n = 20000;
    std::vector<float> rays(8 * n);
    for (uint64_t i = 0; i < n; ++i) {
        Vec3 o = bb.lo + bb.extent() * Vec3{u(rng), u(rng), u(rng)};
        Vec3 d = {u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f};
        if (i % 7 == 0) d = {0.0f, 0.0f, (i % 2) ? 1.0f : -1.0f};  // axis-parallel
        float r[8] = {o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, INFINITY};
        std::memcpy(&rays[8 * i], r, sizeof r);
    }
    for (const LayoutDesc& layout : layouts()) {
        BuiltScene b = buildScene(scene, layout, {});
        std::vector<float> tc(n), tg(n);
        std::vector<int32_t> pc(n), pg(n);
        traceWith(hostBackend(), b, {rays.data(), tc.data(), pc.data(), n});
        traceWith(cuda(), b, {rays.data(), tg.data(), pg.data(), n});
        EXPECT_EQ(std::memcmp(tc.data(), tg.data(), n * sizeof(float)), 0) << layout.name;
        EXPECT_EQ(pc, pg) << layout.name;
    }
}

}  // namespace
}  // namespace oct
