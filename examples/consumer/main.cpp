// A user's own tracer certified through octrace's package: load a mesh's triangles as octrace
// numbers them, make the standard rays, trace them with a brute-force Moller-Trumbore test in
// float (the textbook one, as a user might write it), and certify the hits. Then move one hit
// far along its ray and certify again: that must FAIL, naming that row wrong.
// Exit status 0 only when the first certification is PASS and the second FAIL; 1 otherwise,
// saying why; 2 on an error (octrace::Error) or bad usage.
//
// usage: consumer MESH        (e.g. meshes/teapot.obj)
#include <octrace/certify.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {

struct Hits {
    std::vector<float> t;       // +inf on a miss
    std::vector<int32_t> prim;  // -1 on a miss
};

float dot(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void cross(const float* a, const float* b, float* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

// Closest hit of every ray (ox oy oz dx dy dz tmin tmax) against every triangle (v0 v1 v2):
// Moller & Trumbore 1997, "Fast, minimum storage ray-triangle intersection", with its epsilon
// on the determinant and on t. Equal t keep the lower id, as octrace numbers its answers.
Hits trace(const std::vector<float>& triangles, const std::vector<float>& rays) {
    const float kEps = 1e-7f;
    const size_t m = triangles.size() / 9, n = rays.size() / 8;
    Hits h{std::vector<float>(n, INFINITY), std::vector<int32_t>(n, -1)};
    for (size_t i = 0; i < n; ++i) {
        const float* r = &rays[8 * i];
        for (size_t k = 0; k < m; ++k) {
            const float* v = &triangles[9 * k];
            float e1[3], e2[3], s[3], p[3], q[3];
            for (int a = 0; a < 3; ++a) {
                e1[a] = v[3 + a] - v[a];
                e2[a] = v[6 + a] - v[a];
                s[a] = r[a] - v[a];
            }
            cross(r + 3, e2, p);
            const float det = dot(p, e1);
            if (std::fabs(det) <= kEps) continue;  // parallel to the triangle's plane
            const float inv = 1.0f / det;
            const float u = dot(s, p) * inv;
            if (u < 0.0f || u > 1.0f) continue;
            cross(s, e1, q);
            const float w = dot(q, r + 3) * inv;
            if (w < 0.0f || u + w > 1.0f) continue;
            const float t = dot(q, e2) * inv;
            if (t > kEps && t >= r[6] && t <= r[7] && t < h.t[i]) {
                h.t[i] = t;
                h.prim[i] = int32_t(k);
            }
        }
    }
    return h;
}

void report(const char* what, const octrace::CertifyResult& c) {
    std::printf("%s: %s (correct %s, watertight %s)\n", what, c.outcome.c_str(), c.correct.c_str(),
                c.watertight.c_str());
}

int run(const std::string& mesh) {
    const std::vector<float> triangles = octrace::loadTriangles(mesh);
    octrace::RayOptions options;  // a small run: 64x64 camera and shadow rays, 2000 seeded
    options.count = 2000;
    options.width = options.height = 64;
    const octrace::StandardRays rays = octrace::makeRays(mesh, options);
    for (const std::string& note : rays.notes) std::printf("note: %s\n", note.c_str());
    std::printf("%s: %zu triangles, %llu rays\n", mesh.c_str(), triangles.size() / 9,
                (unsigned long long)rays.count());
    Hits hits = trace(triangles, rays.rays);

    // Moller-Trumbore in float is not watertight (rays through shared edges and vertices slip
    // between the triangles: docs/CERTIFY.md), so this tracer asks for correct answers only;
    // the report still gives the watertight verdict.
    octrace::CertifyPolicy policy;
    policy.require = "correct";
    auto certify = [&] {
        return octrace::certify(mesh, rays.rays.data(), rays.count(), hits.t.data(),
                                hits.prim.data(), rays.manifestJson, policy);
    };
    const octrace::CertifyResult traced = certify();
    std::fputs(traced.summary.c_str(), stdout);
    report("as traced", traced);

    // The first hit, moved half its distance further along the ray: off the surface.
    size_t row = 0;
    while (row < hits.prim.size() && hits.prim[row] < 0) ++row;
    if (row == hits.prim.size()) {
        std::printf("no ray hit %s: nothing to corrupt\n", mesh.c_str());
        return 1;
    }
    hits.t[row] *= 1.5f;
    const octrace::CertifyResult corrupted = certify();
    report(("row " + std::to_string(row) + " moved").c_str(), corrupted);

    if (!traced.pass) {
        std::printf(
            "expected PASS for the tracer's own hits, got %s (the report above says "
            "which rays and why)\n",
            traced.outcome.c_str());
        return 1;
    }
    if (corrupted.outcome != "FAIL" || corrupted.classes[row] != 3) {
        std::printf("expected FAIL with row %zu wrong (class 3), got %s with class %d\n", row,
                    corrupted.outcome.c_str(), int(corrupted.classes[row]));
        return 1;
    }
    std::printf("ok: the hits as traced PASS, and one moved hit FAILs\n");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s MESH (e.g. meshes/teapot.obj)\n", argv[0]);
        return 2;
    }
    try {
        return run(argv[1]);
    } catch (const octrace::Error& e) {
        std::fprintf(stderr, "consumer: %s\n", e.what());
        return 2;
    }
}
