#include "core/scene/mesh_topology.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace oct {
namespace {

// A vertex position as its three float bit patterns, -0 folded onto +0 (equal positions).
struct PositionKey {
    uint32_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

uint32_t bits(float f) {
    if (f == 0.0f) f = 0.0f;  // -0 == +0
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

struct PositionHash {
    size_t operator()(const PositionKey& k) const {
        uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
        h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
        return size_t(h ^ (h >> 32));
    }
};

}  // namespace

const MeshEdge* MeshTopology::findEdge(uint32_t a, uint32_t b) const {
    if (a > b) std::swap(a, b);
    auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(a, b),
                               [](const MeshEdge& e, const std::pair<uint32_t, uint32_t>& k) {
                                   return std::tie(e.a, e.b) < std::tie(k.first, k.second);
                               });
    return it != edges.end() && it->a == a && it->b == b ? &*it : nullptr;
}

MeshTopology meshTopology(const Scene& scene) {
    if (scene.kind != PrimKind::Triangles)
        throw std::invalid_argument("meshTopology: '" + scene.name + "' is a point cloud");
    MeshTopology t;
    const size_t n = scene.triangles.size();
    std::unordered_map<PositionKey, uint32_t, PositionHash> ids;
    ids.reserve(n);
    t.corners.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const Triangle& tri = scene.triangles[i];
        const Vec3 v[3] = {tri.v0, tri.v1, tri.v2};
        for (int k = 0; k < 3; ++k) {
            PositionKey key = {bits(v[k].x), bits(v[k].y), bits(v[k].z)};
            auto [it, added] = ids.emplace(key, uint32_t(t.vertices.size()));
            if (added) t.vertices.push_back(v[k]);
            t.corners[i][k] = it->second;
        }
    }
    // Edges: (a, b, triangle) for the three sides of every triangle, sorted, then grouped. The
    // sort is by a counting pass over a (the smaller vertex id), which leaves each a's sides in
    // triangle order, then by (b, triangle) within each a: the lexicographic order of a sort of
    // them all, in linear time plus a few sides per vertex.
    std::vector<std::array<uint32_t, 3>> sides(3 * n);
    {
        std::vector<uint32_t> start(t.vertices.size() + 1, 0);
        auto side = [&](size_t i, int k) {
            uint32_t a = t.corners[i][k], b = t.corners[i][(k + 1) % 3];
            return a < b ? std::array<uint32_t, 3>{a, b, uint32_t(i)}
                         : std::array<uint32_t, 3>{b, a, uint32_t(i)};
        };
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) ++start[side(i, k)[0] + 1];
        for (size_t v = 0; v < t.vertices.size(); ++v) start[v + 1] += start[v];
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                const std::array<uint32_t, 3> s = side(i, k);
                sides[fill[s[0]]++] = s;
            }
        for (size_t v = 0; v < t.vertices.size(); ++v)
            std::sort(sides.begin() + start[v], sides.begin() + start[v + 1]);
    }
    for (size_t i = 0; i < sides.size();) {
        size_t j = i;
        MeshEdge e{sides[i][0], sides[i][1], 0, {0, 0}};
        while (j < sides.size() && sides[j][0] == e.a && sides[j][1] == e.b) {
            if (e.triangles < 2) e.tri[e.triangles] = sides[j][2];
            ++e.triangles;
            ++j;
        }
        if (e.triangles == 1) ++t.boundaryEdges;
        if (e.triangles > 2) ++t.nonManifoldEdges;
        t.edges.push_back(e);
        i = j;
    }
    // Triangles around each vertex (CSR).
    t.vertexStart.assign(t.vertices.size() + 1, 0);
    for (const auto& c : t.corners)
        for (uint32_t v : c) ++t.vertexStart[v + 1];
    for (size_t v = 0; v < t.vertices.size(); ++v) t.vertexStart[v + 1] += t.vertexStart[v];
    t.vertexTriangles.resize(3 * n);
    std::vector<uint32_t> fill(t.vertexStart.begin(), t.vertexStart.end() - 1);
    for (size_t i = 0; i < n; ++i)
        for (uint32_t v : t.corners[i]) t.vertexTriangles[fill[v]++] = uint32_t(i);
    return t;
}

std::vector<uint32_t> vertexLink(const MeshTopology& topo, uint32_t v) {
    if (v + 1 >= topo.vertexStart.size()) return {};
    const uint32_t begin = topo.vertexStart[v], end = topo.vertexStart[v + 1];
    if (end - begin < 3) return {};
    // The far edge (u, w) of each triangle around v; in a manifold interior vertex they form one
    // cycle in which every neighbour appears in exactly two far edges.
    std::vector<std::pair<uint32_t, uint32_t>> far;
    for (uint32_t k = begin; k < end; ++k) {
        const auto& c = topo.corners[topo.vertexTriangles[k]];
        int i = c[0] == v ? 0 : (c[1] == v ? 1 : 2);
        far.push_back({c[(i + 1) % 3], c[(i + 2) % 3]});
    }
    std::vector<bool> used(far.size(), false);
    std::vector<uint32_t> cycle = {far[0].first, far[0].second};
    used[0] = true;
    for (size_t step = 1; step < far.size(); ++step) {
        const uint32_t last = cycle.back();
        size_t next = far.size();
        for (size_t k = 0; k < far.size(); ++k) {
            if (used[k] || (far[k].first != last && far[k].second != last)) continue;
            if (next != far.size()) return {};  // three far edges meet at `last`: not manifold
            next = k;
        }
        if (next == far.size()) return {};  // the chain ends: a boundary vertex
        used[next] = true;
        cycle.push_back(far[next].first == last ? far[next].second : far[next].first);
    }
    // Closed: back at the start, and no neighbour twice (a pinch of two fans).
    if (cycle.back() != cycle.front()) return {};
    cycle.pop_back();
    std::vector<uint32_t> sorted = cycle;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return {};
    return cycle;
}

}  // namespace oct
