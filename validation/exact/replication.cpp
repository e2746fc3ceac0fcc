#include "validation/exact/replication.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/octree/morton.h"
#include "validation/exact/exact_overlap.h"

namespace oct {
namespace {

constexpr size_t kKeepEntries = 1024;  // per thread, before the final sort and cut

struct Accumulator {
    uint64_t exactOverlaps = 0, falseNegatives = 0, falsePositives = 0, exactTests = 0;
    uint64_t wideFalsePositives = 0;
    std::array<uint64_t, 5> gaps{};
    double maxGap = 0.0;
    ReferenceAgreement dp, bvd;
    std::vector<ReplicationEntry> fn, fp;
};

int gapBucket(double g) {
    if (g <= 1e-12) return 0;
    if (g <= 1e-9) return 1;
    if (g <= 1e-6) return 2;
    if (g <= 1e-3) return 3;
    return 4;
}

struct LeafTest {
    uint32_t node;
    bool exact, dbl;
};

constexpr size_t kKeepMessages = 32;

// Why node k's ranges cannot be read (a message naming the node), or "" when they can. The
// check exists to diagnose broken trees, so it must not read out of bounds through one.
std::string rangeError(const Octree& tree, uint32_t k) {
    const OctreeNode& nd = tree.nodes[k];
    const std::string name = "node " + std::to_string(k) + " (key " + std::to_string(nd.key) +
                             ", depth " + std::to_string(nd.depth) + ")";
    if (nd.nodeType() == NodeType::Internal) {
        const uint64_t first = tree.firstChild[k];
        if (first <= k || first + 8 > tree.nodes.size())
            return name + ": children [" + std::to_string(first) + ", " +
                   std::to_string(first + 8) + ") lie outside nodes [" + std::to_string(k + 1) +
                   ", " + std::to_string(tree.nodes.size()) + ")";
        return "";
    }
    const uint64_t end = uint64_t(nd.primOffset) + nd.primCount;
    if (end > tree.primIndices.size())
        return name + ": leaf list [" + std::to_string(nd.primOffset) + ", " + std::to_string(end) +
               ") lies outside the " + std::to_string(tree.primIndices.size()) +
               " primitive indices";
    return "";
}

// Leaf k's list, sorted; empty for a node whose range is broken.
std::vector<uint32_t> sortedList(const Octree& tree, uint32_t k, bool brokenRange) {
    if (brokenRange) return {};
    const OctreeNode& nd = tree.nodes[k];
    std::vector<uint32_t> list(tree.primIndices.begin() + nd.primOffset,
                               tree.primIndices.begin() + nd.primOffset + nd.primCount);
    std::sort(list.begin(), list.end());
    return list;
}

}  // namespace

ReplicationReport checkReplication(const Scene& scene, const Octree& tree) {
    if (tree.kind != scene.kind || tree.primitiveCount != scene.primitiveCount() ||
        tree.nodes.empty() || tree.firstChild.size() != tree.nodes.size())
        throw std::invalid_argument("checkReplication: the octree (" +
                                    std::to_string(tree.primitiveCount) +
                                    " primitives) was not built over scene '" + scene.name + "' (" +
                                    std::to_string(scene.primitiveCount()) + ")");
    auto start = std::chrono::steady_clock::now();
    const bool tris = scene.kind == PrimKind::Triangles;
    const uint32_t nPrims = scene.primitiveCount();
    ReplicationReport rep;
    rep.primitives = nPrims;
    rep.octreeFaces = tree.referenceCount();

    std::vector<uint8_t> broken(tree.nodes.size(), 0);  // 1: a range error, not read through
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
        std::string why = rangeError(tree, k);
        if (why.empty()) continue;
        broken[k] = 1;
        ++rep.rangeErrors;
        if (rep.structuralErrors.size() < kKeepMessages) rep.structuralErrors.push_back(why);
    }

    // Tiling: every stored box, key and depth is the subdivision's (the builder's childBox).
    auto tilingError = [&](uint32_t k, const std::string& why) {
        ++rep.tilingErrors;
        if (rep.structuralErrors.size() < kKeepMessages)
            rep.structuralErrors.push_back("node " + std::to_string(k) + " (key " +
                                           std::to_string(tree.nodes[k].key) + ", depth " +
                                           std::to_string(tree.nodes[k].depth) + "): " + why);
    };
    auto sameBox = [](const Aabb& a, const Aabb& b) {
        return std::memcmp(&a, &b, sizeof(Aabb)) == 0;
    };
    if (!sameBox(tree.nodes[0].box, tree.root) || tree.nodes[0].key != kRootKey)
        tilingError(0, "the root is not the tree's root cube with key 1");
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
        const OctreeNode& nd = tree.nodes[k];
        if (nd.nodeType() != NodeType::Internal || broken[k]) continue;
        for (int i = 0; i < 8; ++i) {
            const uint32_t c = tree.firstChild[k] + uint32_t(i);
            const OctreeNode& ch = tree.nodes[c];
            if (!sameBox(ch.box, childBox(nd.box, i)))
                tilingError(c, "its box is not octant " + std::to_string(i) + " of its parent's");
            else if (ch.key != childKey(nd.key, i) || ch.depth != nd.depth + 1)
                tilingError(c, "its key or depth is not its parent's child " + std::to_string(i));
        }
    }

    // Inverse index of the leaf lists (CSR): leaves listing each primitive, ascending node.
    std::vector<uint64_t> offset(size_t(nPrims) + 1, 0);
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
        const OctreeNode& nd = tree.nodes[k];
        if (nd.nodeType() == NodeType::Internal) continue;
        ++rep.leaves;
        std::vector<uint32_t> list = sortedList(tree, k, broken[k]);
        for (size_t j = 0; j < list.size(); ++j) {
            if (list[j] >= nPrims) {
                ++rep.indexOutOfRange;
                continue;
            }
            if (j > 0 && list[j] == list[j - 1]) {
                ++rep.duplicateEntries;
                continue;
            }
            ++offset[list[j] + 1];
        }
    }
    for (size_t i = 0; i < nPrims; ++i) offset[i + 1] += offset[i];
    std::vector<uint32_t> listedNode(offset[nPrims]);
    {
        std::vector<uint64_t> fill(offset.begin(), offset.end() - 1);
        for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
            const OctreeNode& nd = tree.nodes[k];
            if (nd.nodeType() == NodeType::Internal) continue;
            std::vector<uint32_t> list = sortedList(tree, k, broken[k]);
            list.erase(std::unique(list.begin(), list.end()), list.end());
            for (uint32_t p : list)
                if (p < nPrims) listedNode[fill[p]++] = k;
        }
    }

    auto exactTest = [&](uint32_t p, const Aabb& b) {
        return tris ? exactTriangleBoxOverlap(scene.triangles[p], b)
                    : exactSphereBoxOverlap(scene.spheres[p], b);
    };
    auto doubleTest = [&](uint32_t p, const Aabb& b) {
        return tris ? doubleTriangleBoxOverlap(scene.triangles[p], b)
                    : doubleSphereBoxOverlap(scene.spheres[p], b);
    };
    auto gapOf = [&](uint32_t p, const Aabb& b) {
        Vec3 e = b.extent();
        double edge = std::max({double(e.x), double(e.y), double(e.z)});
        double g = tris ? triangleBoxGap(scene.triangles[p], b) : sphereBoxGap(scene.spheres[p], b);
        return edge > 0.0 ? g / edge : g;
    };
    auto entry = [&](uint32_t p, uint32_t k, double gap) {
        const OctreeNode& nd = tree.nodes[k];
        return ReplicationEntry{p, k, nd.key, int(nd.depth), gap};
    };

    std::vector<Accumulator> acc(static_cast<size_t>(omp_get_max_threads()));
#pragma omp parallel
    {
        Accumulator& a = acc[size_t(omp_get_thread_num())];
        std::vector<uint32_t> stack;
        std::vector<LeafTest> reached;
#pragma omp for schedule(dynamic, 64)
        for (int64_t pi = 0; pi < int64_t(nPrims); ++pi) {
            const uint32_t p = uint32_t(pi);
            reached.clear();
            stack.assign(1, 0u);
            while (!stack.empty()) {
                uint32_t k = stack.back();
                stack.pop_back();
                const OctreeNode& nd = tree.nodes[k];
                bool ex = exactTest(p, nd.box);
                ++a.exactTests;
                bool db = doubleTest(p, nd.box);
                if (!ex && !db) continue;
                if (nd.nodeType() == NodeType::Internal) {
                    if (broken[k]) continue;  // counted above; its children are unknown
                    for (uint32_t c = 0; c < 8; ++c) stack.push_back(tree.firstChild[k] + c);
                } else {
                    reached.push_back({k, ex, db});
                }
            }
            std::sort(reached.begin(), reached.end(),
                      [](const LeafTest& x, const LeafTest& y) { return x.node < y.node; });
            // Merge the reached leaves with the listed ones (both ascending by node).
            const uint32_t* L = listedNode.data() + offset[p];
            const size_t nL = size_t(offset[p + 1] - offset[p]);
            size_t i = 0, j = 0;
            while (i < reached.size() || j < nL) {
                LeafTest t;
                bool listed;
                if (j >= nL || (i < reached.size() && reached[i].node < L[j])) {
                    t = reached[i++];
                    listed = false;
                } else if (i >= reached.size() || L[j] < reached[i].node) {
                    uint32_t k = L[j++];
                    t = {k, exactTest(p, tree.nodes[k].box), doubleTest(p, tree.nodes[k].box)};
                    ++a.exactTests;
                    listed = true;
                } else {
                    t = reached[i++];
                    ++j;
                    listed = true;
                }
                a.exactOverlaps += t.exact;
                a.dp.overlaps += t.dbl;
                a.bvd.overlaps += listed;
                if (t.exact && !listed) {
                    ++a.falseNegatives;
                    if (a.fn.size() < kKeepEntries) a.fn.push_back(entry(p, t.node, 0.0));
                }
                if (listed && !t.exact) {
                    ++a.falsePositives;
                    double g = gapOf(p, tree.nodes[t.node].box);
                    ++a.gaps[gapBucket(g)];
                    // Written as !(<=) so that a NaN gap fails too.
                    a.wideFalsePositives += !(g <= kMaxFalsePositiveGap);
                    a.maxGap = std::max(a.maxGap, g);
                    a.fp.push_back(entry(p, t.node, g));
                    if (a.fp.size() > 2 * kKeepEntries) {
                        std::sort(a.fp.begin(), a.fp.end(),
                                  [](const ReplicationEntry& x, const ReplicationEntry& y) {
                                      return x.gap > y.gap;
                                  });
                        a.fp.resize(kKeepEntries);
                    }
                }
                a.dp.falseNegatives += t.exact && !t.dbl;
                a.dp.falsePositives += t.dbl && !t.exact;
                a.bvd.falseNegatives += t.dbl && !listed;
                a.bvd.falsePositives += listed && !t.dbl;
            }
        }
    }

    for (const Accumulator& a : acc) {
        rep.exactOverlaps += a.exactOverlaps;
        rep.falseNegatives += a.falseNegatives;
        rep.falsePositives += a.falsePositives;
        rep.wideFalsePositives += a.wideFalsePositives;
        rep.exactTests += a.exactTests;
        for (int b = 0; b < 5; ++b) rep.falsePositiveGaps[b] += a.gaps[b];
        rep.maxFalsePositiveGap = std::max(rep.maxFalsePositiveGap, a.maxGap);
        rep.doublePrecision.overlaps += a.dp.overlaps;
        rep.doublePrecision.falseNegatives += a.dp.falseNegatives;
        rep.doublePrecision.falsePositives += a.dp.falsePositives;
        rep.builderVsDouble.overlaps += a.bvd.overlaps;
        rep.builderVsDouble.falseNegatives += a.bvd.falseNegatives;
        rep.builderVsDouble.falsePositives += a.bvd.falsePositives;
        rep.falseNegativeList.insert(rep.falseNegativeList.end(), a.fn.begin(), a.fn.end());
        rep.falsePositiveList.insert(rep.falsePositiveList.end(), a.fp.begin(), a.fp.end());
    }
    std::sort(rep.falseNegativeList.begin(), rep.falseNegativeList.end(),
              [](const ReplicationEntry& x, const ReplicationEntry& y) {
                  return x.prim != y.prim ? x.prim < y.prim : x.node < y.node;
              });
    if (rep.falseNegativeList.size() > 32) rep.falseNegativeList.resize(32);
    std::sort(rep.falsePositiveList.begin(), rep.falsePositiveList.end(),
              [](const ReplicationEntry& x, const ReplicationEntry& y) { return x.gap > y.gap; });
    if (rep.falsePositiveList.size() > 16) rep.falsePositiveList.resize(16);

    uint64_t total = 0;
    for (uint32_t p = 0; p < nPrims; ++p) {
        uint32_t count = uint32_t(offset[p + 1] - offset[p]);
        ++rep.distribution[count];
        rep.maxReplication = std::max(rep.maxReplication, count);
        rep.unlistedPrimitives += count == 0;
        total += count;
    }
    rep.meanReplication = nPrims ? double(total) / double(nPrims) : 0.0;
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return rep;
}

}  // namespace oct
