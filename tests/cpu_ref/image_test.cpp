// Known pixels of a Cornell box frame, checked against what geometry says they must be rather
// than against a stored checksum: a background corner, a lit point of the back wall (colour
// from an independent double-precision Phong evaluation), and a floor point in the shadow of
// the short block (colour exactly the ambient term). The pixels are found by projecting chosen
// world points, the surfaces by their coordinates in the loaded file, and every outcome is
// also confirmed with Embree as an independent tracer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/geometry/vec3t.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"

namespace oct {
namespace {

constexpr int kSide = 128;
// Just under the ceiling (y = 548.8), over the middle of the floor.
const Vec3 kLight = {278.0f, 540.0f, 279.0f};

// Round-to-nearest conversion of a colour channel, as an image writer would do it.
int byteOf(double c) { return int(std::floor(std::min(std::max(c, 0.0), 1.0) * 255.0 + 0.5)); }

class CornellImage : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        scene_ = new Scene(loadScene(std::string(OCT_SOURCE_DIR) + "/meshes/cornell_box.obj"));
        CameraOptions opt;
        opt.width = kSide;
        opt.height = kSide;
        opt.eye = Vec3{278.0f, 273.0f, -800.0f};
        opt.target = Vec3{278.0f, 273.0f, 0.0f};
        opt.fovDegrees = 40.0f;
        opt.light = kLight;
        frame_ = makeFrame(scene_->bounds(), opt);
        BuiltScene built = buildScene(*scene_, findLayout("linear"), LayoutOptions{});
        film_ = new Film;
        renderWith(hostBackend(), built, frame_, *film_);
        EmbreeTracer embree(*scene_);
        embreeFilm_ = new Film(kSide, kSide);
        renderFrameCpu(frame_, embree.accel(), primitivesView(*scene_), embreeFilm_->view());
    }
    static void TearDownTestSuite() {
        delete scene_;
        delete film_;
        delete embreeFilm_;
    }

    // Triangles whose three vertices all satisfy pred: a wall or floor found by coordinates.
    template <class Pred>
    static std::vector<int32_t> trianglesWhere(Pred pred) {
        std::vector<int32_t> ids;
        for (size_t i = 0; i < scene_->triangles.size(); ++i) {
            const Triangle& t = scene_->triangles[i];
            if (pred(t.v0) && pred(t.v1) && pred(t.v2)) ids.push_back(int32_t(i));
        }
        return ids;
    }

    // The pixel through which the camera sees p (inverse of primaryRay).
    static void pixelOf(Vec3 p, int& x, int& y) {
        const Camera& c = frame_.camera;
        DVec3 d = toDouble(p) - toDouble(c.eye);
        double f = dot(d, toDouble(c.forward));
        double sx = dot(d, toDouble(c.right)) / (dot(toDouble(c.right), toDouble(c.right)) * f);
        double sy = dot(d, toDouble(c.up)) / (dot(toDouble(c.up), toDouble(c.up)) * f);
        x = int(std::floor((sx + 1.0) * 0.5 * kSide));
        y = int(std::floor((1.0 - sy) * 0.5 * kSide));
        ASSERT_TRUE(x >= 0 && x < kSide && y >= 0 && y < kSide) << "point outside the frame";
    }

    static size_t index(int x, int y) { return size_t(y) * kSide + size_t(x); }

    // Hit point of pixel (x, y) from the film's t, in double.
    static DVec3 hitPoint(int x, int y) {
        Ray r = primaryRay(frame_.camera, x, y, kSide, kSide);
        return toDouble(r.org) + toDouble(r.dir) * double(film_->t[index(x, y)]);
    }

    static bool contains(const std::vector<int32_t>& ids, int32_t id) {
        return std::find(ids.begin(), ids.end(), id) != ids.end();
    }

    static Scene* scene_;
    static FrameParams frame_;
    static Film* film_;
    static Film* embreeFilm_;
};

Scene* CornellImage::scene_ = nullptr;
FrameParams CornellImage::frame_;
Film* CornellImage::film_ = nullptr;
Film* CornellImage::embreeFilm_ = nullptr;

TEST_F(CornellImage, CornerPixelIsExactlyTheBackground) {
    // With a 40 degree field of view from z = -800 the frame is ~582 units wide at the open
    // face (z = 0), a little more than the box: the top-left corner ray passes left of and
    // above the box where the geometry begins and diverges from it, so it can hit nothing.
    const int x = 0, y = 0;
    Aabb b = scene_->bounds();
    Ray r = primaryRay(frame_.camera, x, y, kSide, kSide);
    ASSERT_GT(r.dir.z, 0.0f);
    double tFront = (double(b.lo.z) - r.org.z) / r.dir.z;
    DVec3 entry = toDouble(r.org) + toDouble(r.dir) * tFront;
    bool leftAndLeaving = entry.x < b.lo.x && r.dir.x <= 0.0f;
    bool aboveAndLeaving = entry.y > b.hi.y && r.dir.y >= 0.0f;
    ASSERT_TRUE(leftAndLeaving || aboveAndLeaving)
        << "the corner ray enters the scene's z range at " << entry.x << "," << entry.y;

    size_t i = index(x, y);
    EXPECT_EQ(film_->prim[i], -1);
    EXPECT_TRUE(std::isinf(film_->t[i]) && film_->t[i] > 0.0f);
    EXPECT_EQ(film_->shadow[i], kNoShadowRay);
    const Vec3 bg = frame_.shading.background;
    EXPECT_EQ(int(film_->rgb[3 * i + 0]), byteOf(bg.x));
    EXPECT_EQ(int(film_->rgb[3 * i + 1]), byteOf(bg.y));
    EXPECT_EQ(int(film_->rgb[3 * i + 2]), byteOf(bg.z));
    EXPECT_EQ(embreeFilm_->prim[i], -1);
}

TEST_F(CornellImage, BackWallPointIsLitWithPhongColour) {
    // A point high on the back wall (z = 559.2), left of the blocks. Its segment to the light
    // stays at y in [450, 540]: above both blocks (tops at 165 and 330) and below the ceiling
    // (548.8), inside the walls, so nothing can shadow it.
    const float wallZ = 559.2f;
    std::vector<int32_t> backWall = trianglesWhere([&](Vec3 v) { return v.z == wallZ; });
    ASSERT_EQ(backWall.size(), 2u) << "the back wall quad, fan-triangulated";

    int x = 0, y = 0;
    ASSERT_NO_FATAL_FAILURE(pixelOf({100.0f, 450.0f, wallZ}, x, y));
    size_t i = index(x, y);
    ASSERT_TRUE(contains(backWall, film_->prim[i]))
        << "pixel " << x << "," << y << " hit primitive " << film_->prim[i];
    DVec3 h = hitPoint(x, y);
    EXPECT_NEAR(h.z, wallZ, 1e-2);
    ASSERT_GT(h.y, 340.0);  // the premise of "nothing can shadow it"
    EXPECT_EQ(film_->shadow[i], kLit);
    EXPECT_EQ(embreeFilm_->shadow[i], kLit);
    EXPECT_TRUE(contains(backWall, embreeFilm_->prim[i]));

    // Phong in double: normal -z (towards the camera), light direction from the hit point.
    const ShadingParams& s = frame_.shading;
    Ray r = primaryRay(frame_.camera, x, y, kSide, kSide);
    DVec3 n = {0.0, 0.0, -1.0};
    DVec3 toLight = normalize(toDouble(s.light) - h);
    double nl = dot(n, toLight);
    ASSERT_GT(nl, 0.0);
    DVec3 reflected = n * (2.0 * nl) - toLight;
    double rv = std::max(0.0, -dot(reflected, toDouble(r.dir)));
    double spec = s.specular * std::pow(rv, 32.0);
    const double albedo[3] = {s.surfaceColour.x, s.surfaceColour.y, s.surfaceColour.z};
    for (int k = 0; k < 3; ++k) {
        double c = albedo[k] * s.ambient + albedo[k] * s.diffuse * nl + spec;
        int got = film_->rgb[3 * i + k];
        EXPECT_NEAR(got, byteOf(c), 1) << "channel " << k;
        EXPECT_GT(got, byteOf(albedo[k] * s.ambient)) << "channel " << k << " not above ambient";
    }
}

TEST_F(CornellImage, FloorPointInFrontOfShortBlockIsInItsShadow) {
    // The light is behind the short block as seen from the camera, so the block's shadow
    // falls forwards onto the floor in front of it, in plain view. Chosen point: (210, 0, 45),
    // 20 units in front of the block's front face, which runs from (130, 65) to (290, 114) in
    // x-z and is 165 high. The segment to the light crosses that face's plane at about
    // x = 226, y = 110: well inside the face in both directions.
    std::vector<int32_t> floor = trianglesWhere([](Vec3 v) { return v.y == 0.0f; });
    ASSERT_GE(floor.size(), 2u);

    int x = 0, y = 0;
    ASSERT_NO_FATAL_FAILURE(pixelOf({210.0f, 0.0f, 45.0f}, x, y));
    size_t i = index(x, y);
    ASSERT_TRUE(contains(floor, film_->prim[i]))
        << "pixel " << x << "," << y << " hit primitive " << film_->prim[i];
    DVec3 h = hitPoint(x, y);
    EXPECT_NEAR(h.y, 0.0, 1e-2);

    // Independent occlusion check for the actual hit point: where does its segment to the
    // light cross the vertical plane of the block's front face?
    const DVec3 a = {130.0, 0.0, 65.0}, b = {290.0, 0.0, 114.0};
    const DVec3 l = toDouble(frame_.shading.light);
    auto side = [&](DVec3 p) { return (b.x - a.x) * (p.z - a.z) - (b.z - a.z) * (p.x - a.x); };
    double s0 = side(h), s1 = side(l);
    ASSERT_LT(s0 * s1, 0.0) << "hit point and light must lie on opposite sides of the face";
    double u = s0 / (s0 - s1);
    DVec3 cross = h + (l - h) * u;
    double along = dot(cross - a, b - a) / dot(b - a, b - a);
    ASSERT_GT(cross.y, 10.0);
    ASSERT_LT(cross.y, 155.0);
    ASSERT_GT(along, 0.05);
    ASSERT_LT(along, 0.95);

    EXPECT_EQ(film_->shadow[i], kOccluded);
    EXPECT_EQ(embreeFilm_->shadow[i], kOccluded);
    EXPECT_TRUE(contains(floor, embreeFilm_->prim[i]));
    const ShadingParams& s = frame_.shading;
    // The shadowed colour is the ambient term exactly, as the kernel computes it in float.
    const float albedo[3] = {s.surfaceColour.x, s.surfaceColour.y, s.surfaceColour.z};
    for (int k = 0; k < 3; ++k) {
        float c = albedo[k] * s.ambient;
        int expected = int(c * 255.0f + 0.5f);
        EXPECT_EQ(int(film_->rgb[3 * i + k]), expected) << "channel " << k;
        EXPECT_NEAR(expected, byteOf(double(albedo[k]) * s.ambient), 1);
    }
}

TEST_F(CornellImage, LinearFrameMatchesEmbreeShadowsAlmostEverywhere) {
    // Whole-frame sanity for the image above: the hit/miss and shadow outcomes of the linear
    // layout and Embree agree on all but a handful of edge pixels.
    uint64_t hitMiss = 0, shadow = 0, hits = 0;
    for (size_t i = 0; i < film_->pixelCount(); ++i) {
        hitMiss += (film_->prim[i] < 0) != (embreeFilm_->prim[i] < 0);
        shadow += film_->shadow[i] != kNoShadowRay && embreeFilm_->shadow[i] != kNoShadowRay &&
                  film_->shadow[i] != embreeFilm_->shadow[i];
        hits += film_->prim[i] >= 0;
    }
    EXPECT_GT(hits, film_->pixelCount() / 2);
    EXPECT_LE(hitMiss, 8u);
    EXPECT_LE(shadow, 8u);
}

}  // namespace
}  // namespace oct
