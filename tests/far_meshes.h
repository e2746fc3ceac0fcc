// Meshes far from the origin, at the float grid's own spacing or at extreme sizes, made by the
// tests and written as OBJ files (every float read back exactly): a UTM-like terrain at x = 5e5,
// y = 4e6; the teapot x 100 moved there; 8 x 8 heightfields whose vertices are 1 to 2 ulps apart
// (issue 21); the teapot scaled by any factor about the origin.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/scene/load_scene.h"
#include "core/scene/mesh_topology.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace octtest {

struct Mesh {
    std::vector<oct::Vec3> v;
    std::vector<std::array<int, 3>> f;  // 0-based
};

// Written with 9 significant digits: every float reads back exactly.
inline std::string writeObj(const TempDir& dir, const std::string& name, const Mesh& m) {
    const std::string path = dir.str(name);
    std::FILE* out = std::fopen(path.c_str(), "w");
    for (const oct::Vec3& p : m.v)
        std::fprintf(out, "v %.9g %.9g %.9g\n", double(p.x), double(p.y), double(p.z));
    for (const auto& f : m.f) std::fprintf(out, "f %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1);
    std::fclose(out);
    return path;
}

// A heightfield of n x n vertices, x and y from the given coordinate lists, z from `height`,
// each cell two triangles wound so that the normal points up (+z).
inline Mesh heightfield(const std::vector<float>& xs, const std::vector<float>& ys,
                        const std::function<float(size_t, size_t)>& height) {
    Mesh m;
    for (size_t j = 0; j < ys.size(); ++j)
        for (size_t i = 0; i < xs.size(); ++i) m.v.push_back({xs[i], ys[j], height(i, j)});
    const int n = int(xs.size());
    for (int j = 0; j + 1 < int(ys.size()); ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            m.f.push_back({a, b, d});
            m.f.push_back({a, d, c});
        }
    return m;
}

// 32 x 32 vertices 10 m apart at x = 5e5, y = 4e6 (UTM), heights 0 .. 60 m (floats: 1/32 and
// 1/4 m apart there).
inline Mesh utmTerrain() {
    std::mt19937 rng(21);
    std::vector<float> xs, ys;
    for (int i = 0; i < 32; ++i) {
        xs.push_back(float(5e5 + 10.0 * i));
        ys.push_back(float(4e6 + 10.0 * i));
    }
    std::vector<float> h(32 * 32);
    for (float& z : h) z = float(double(rng() % 6000) / 100.0);
    return heightfield(xs, ys, [&](size_t i, size_t j) { return h[j * 32 + i]; });
}

// n float steps of 1 or 2 ulps from `base` upwards.
inline std::vector<float> ulpSteps(float base, int n, std::mt19937& rng) {
    std::vector<float> out = {base};
    while (int(out.size()) < n) {
        float next = std::nextafter(out.back(), INFINITY);
        if (rng() % 2) next = std::nextafter(next, INFINITY);
        out.push_back(next);
    }
    return out;
}

inline Mesh ulpHeightfield(float base, uint32_t seed) {
    std::mt19937 rng(seed);
    const std::vector<float> xs = ulpSteps(base, 8, rng), ys = ulpSteps(base, 8, rng);
    const std::vector<float> zs = ulpSteps(base, 3, rng);
    std::vector<float> h(64);
    for (float& z : h) z = zs[rng() % 3];
    return heightfield(xs, ys, [&](size_t i, size_t j) { return h[j * 8 + i]; });
}

// The teapot x 100, moved to x = 5e5, y = 4e6 (each vertex rounded to float there).
inline Mesh farTeapot() {
    const oct::Scene t = oct::loadScene(kTeapot);
    const oct::MeshTopology topo = oct::meshTopology(t);
    Mesh m;
    for (const oct::Vec3& p : topo.vertices)
        m.v.push_back({float(5e5 + 100.0 * p.x), float(4e6 + 100.0 * p.y), float(100.0 * p.z)});
    for (const auto& c : topo.corners) m.f.push_back({int(c[0]), int(c[1]), int(c[2])});
    return m;
}

// The teapot times `factor` about the origin (each vertex rounded to float).
inline Mesh scaledTeapot(double factor) {
    const oct::Scene t = oct::loadScene(kTeapot);
    const oct::MeshTopology topo = oct::meshTopology(t);
    Mesh m;
    for (const oct::Vec3& p : topo.vertices)
        m.v.push_back({float(factor * p.x), float(factor * p.y), float(factor * p.z)});
    for (const auto& c : topo.corners) m.f.push_back({int(c[0]), int(c[1]), int(c[2])});
    return m;
}

}  // namespace octtest
