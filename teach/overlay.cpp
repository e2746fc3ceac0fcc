#include "teach/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/geometry/vec3t.h"
#include "teach/legend.h"
#include "teach/teach_error.h"

namespace oct {
namespace {

// Camera-space coordinates of p: depth along forward and the image-plane coordinates sx, sy in
// [-1, 1] across the image (primaryRay's parametrisation: dir ~ forward + sx right + sy up).
struct CamPoint {
    double depth, sx, sy;
};
CamPoint toCamera(const Camera& c, DVec3 p) {
    const DVec3 d = p - toDouble(c.eye);
    const DVec3 r = toDouble(c.right), u = toDouble(c.up);
    const double z = dot(d, toDouble(c.forward));
    return {z, dot(d, r) / dot(r, r) / z, dot(d, u) / dot(u, u) / z};
}

// Pixel coordinates (continuous; pixel i covers [i, i + 1)) of image-plane coordinates.
void toPixel(const FrameParams& f, double sx, double sy, double& x, double& y) {
    x = (sx + 1.0) * 0.5 * f.width;
    y = (1.0 - sy) * 0.5 * f.height;
}

struct EdgeStyle {
    Rgb8 colour;
    float alpha;
};

// The strongest edge sample of each pixel: edges are composited once per pixel, so where many
// small cells crowd together their edges do not add up to a solid colour.
struct EdgeLayer {
    int width;
    std::vector<EdgeStyle> px;
    EdgeLayer(int w, int h) : width(w), px(size_t(w) * h, EdgeStyle{{0, 0, 0}, 0.0f}) {}
    void put(int x, int y, EdgeStyle s) {
        EdgeStyle& p = px[size_t(y) * width + x];
        if (s.alpha > p.alpha) p = s;
    }
};

// Draws the segment a-b: samples about two per pixel of its projected length, each depth-tested
// against the Film. The part behind the eye's near plane is clipped first.
void drawEdge(EdgeLayer& img, const Film& film, const FrameParams& f, DVec3 a, DVec3 b,
              EdgeStyle st, OverlayStats& stats) {
    const Camera& c = f.camera;
    const double za = dot(a - toDouble(c.eye), toDouble(c.forward)),
                 zb = dot(b - toDouble(c.eye), toDouble(c.forward));
    const double nearZ = 1e-6 * std::max(std::fabs(za), std::fabs(zb));
    if (za <= nearZ && zb <= nearZ) return;
    if (za <= nearZ) a = a + (b - a) * ((nearZ - za) / (zb - za));
    if (zb <= nearZ) b = b + (a - b) * ((nearZ - zb) / (za - zb));
    CamPoint pa = toCamera(c, a), pb = toCamera(c, b);
    double xa, ya, xb, yb;
    toPixel(f, pa.sx, pa.sy, xa, ya);
    toPixel(f, pb.sx, pb.sy, xb, yb);
    const double span = std::max(std::fabs(xb - xa), std::fabs(yb - ya));
    // Far outside the image an edge can span millions of pixels; a few per image pixel suffice.
    const int n = int(std::min(2.0 * span, 8.0 * (f.width + f.height))) + 2;
    for (int i = 0; i <= n; ++i) {
        const DVec3 p = a + (b - a) * (double(i) / n);
        const CamPoint q = toCamera(c, p);
        if (q.depth <= 0) continue;
        double x, y;
        toPixel(f, q.sx, q.sy, x, y);
        if (!(x >= 0 && y >= 0 && x < f.width && y < f.height)) continue;
        const int px = int(x), py = int(y);
        const DVec3 d = p - toDouble(c.eye);
        const double dist = std::sqrt(dot(d, d));
        const float t = film.t[size_t(py) * film.width + px];
        // Hidden when the surface along this pixel's ray is nearer than the sample; the margin
        // keeps edges lying on the surface itself visible despite rounding.
        if (std::isfinite(t) && double(t) < dist * (1.0 - 1e-4)) {
            ++stats.samplesHidden;
            continue;
        }
        ++stats.samplesDrawn;
        img.put(px, py, st);
    }
}

void drawBox(EdgeLayer& img, const Film& film, const FrameParams& f, const Aabb& box, EdgeStyle st,
             OverlayStats& stats) {
    const DVec3 lo = toDouble(box.lo), hi = toDouble(box.hi);
    auto corner = [&](int i) {
        return DVec3{(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
    };
    // The 12 edges join corners that differ in one bit.
    for (int i = 0; i < 8; ++i)
        for (int bit : {1, 2, 4})
            if (!(i & bit)) drawEdge(img, film, f, corner(i), corner(i | bit), st, stats);
}

}  // namespace

bool projectToPixel(const FrameParams& frame, Vec3 p, double& x, double& y, double& distance) {
    const CamPoint q = toCamera(frame.camera, toDouble(p));
    if (!(q.depth > 0)) return false;
    toPixel(frame, q.sx, q.sy, x, y);
    const DVec3 d = toDouble(p) - toDouble(frame.camera.eye);
    distance = std::sqrt(dot(d, d));
    return true;
}

RgbImage overlayImage(const Film& film, const FrameParams& frame, const Octree& tree,
                      const OverlaySpec& spec, OverlayStats* statsOut) {
    if (spec.depth > tree.depth)
        throw TeachError("--overlay-depth " + std::to_string(spec.depth) +
                         ": the octree's deepest level is " + std::to_string(tree.depth) +
                         " (give 0.." + std::to_string(tree.depth) +
                         ", or leave it out for "
                         "the leaves)");
    RgbImage picture(film.width, film.height, {0, 0, 0});
    picture.rgb = film.rgb;
    EdgeLayer edges(film.width, film.height);
    OverlayStats stats;
    // Radians a pixel spans at the image centre (up is scaled by tan(fov / 2), see camera.h).
    const double pixelAngle = 2.0 * double(length(frame.camera.up)) / frame.height;
    const int maxDepth = std::max(tree.depth, 1);
    auto depthColour = [&](int d) {
        // Viridis from depth 1 (the root's children) to the deepest level; the root itself is
        // the bottom colour as well.
        return mapColour(ColourMap::Viridis,
                         double(std::max(d - 1, 0)) / std::max(maxDepth - 1, 1));
    };
    for (const OctreeNode& n : tree.nodes) {
        const NodeType t = n.nodeType();
        const bool leaf = t == NodeType::Leaf || t == NodeType::EmptyLeaf;
        if (spec.depth < 0 ? !leaf : int(n.depth) != spec.depth) continue;
        // Empty leaves are the octree's free space: drawn, but fainter than the leaves that
        // hold primitives. Cells a few pixels wide fade out, or the finest leaves would paint
        // the model over with their edges.
        float alpha = t == NodeType::EmptyLeaf ? 0.4f : 0.9f;
        double px, py, dist;
        if (projectToPixel(frame, n.box.center(), px, py, dist)) {
            const double pixels = double(n.box.hi.x - n.box.lo.x) / dist / pixelAngle;
            alpha *= float(std::clamp((pixels - 1.0) / 10.0, 0.12, 1.0));
        }
        const EdgeStyle st = {depthColour(n.depth), alpha};
        drawBox(edges, film, frame, n.box, st, stats);
        ++stats.cells;
    }

    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const EdgeStyle& e = edges.px[size_t(y) * film.width + x];
            if (e.alpha > 0) picture.blend(x, y, e.colour, e.alpha);
        }

    Legend legend;
    legend.title = spec.depth < 0 ? "Octree leaf cells"
                                  : "Octree cells of depth " + std::to_string(spec.depth);
    legend.subtitle.push_back(spec.layout + " | " + spec.scene + " | " +
                              std::to_string(film.width) + "x" + std::to_string(film.height) +
                              " | " + std::to_string(stats.cells) + " cells");
    if (!spec.details.empty()) legend.subtitle.push_back(spec.details);
    legend.swatchPrefix = "depth";
    if (spec.depth < 0) {
        for (int d = 1; d <= tree.depth; ++d)
            legend.swatches.push_back({depthColour(d), std::to_string(d)});
        legend.notes.push_back(
            "Edges behind the surface are hidden. Empty leaves and cells "
            "under 10 pixels wide are drawn fainter.");
    } else {
        legend.swatches.push_back({depthColour(spec.depth), std::to_string(spec.depth)});
        legend.notes.push_back(
            "Edges behind the surface are hidden. Cells under 10 pixels wide "
            "are drawn fainter.");
    }
    if (statsOut) *statsOut = stats;
    return withLegend(picture, legend);
}

}  // namespace oct
