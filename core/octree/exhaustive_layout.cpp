#include "core/octree/exhaustive_layout.h"

#include <cstdio>

namespace oct {

LayoutReport ExhaustiveLayout::report(const Scene&, const Octree& tree, const LayoutOptions&) {
    const uint64_t primBytes =
        uint64_t(tree.primitiveCount) *
        (tree.kind == PrimKind::Triangles ? sizeof(Triangle) : sizeof(Sphere));
    LayoutReport r;
    r.facts = {countFact("primitive_bytes", primBytes)};
    char line[96];
    std::snprintf(line, sizeof line, "%.2f MiB of primitives, no tree",
                  double(primBytes) / 1048576.0);
    r.summary = line;
    return r;
}

}  // namespace oct
