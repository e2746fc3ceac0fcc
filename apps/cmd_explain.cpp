// octrace explain: one pixel's (or one ray's) traversal step by step, as text, JSON, an
// interactive HTML page or figures for slides (SVG). The work is teach/explain.h (the kernel
// with a recording observer), teach/explain_page.h, teach/svg_view.h, teach/quadtree.h and
// teach/layout_figure.h; this file parses the options and prints.
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "apps/cli.h"
#include "core/io/output_file.h"
#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "teach/explain.h"
#include "teach/explain_page.h"
#include "teach/layout_figure.h"
#include "teach/quadtree.h"
#include "teach/svg_view.h"

namespace oct {
namespace {

struct ExplainOptions {
    SceneOptions scene;
    std::string accel = kDefaultLayout;
    CameraChoice camera;
    std::string pixel, ray, json, html;
    std::string svg, svgPlane, layoutsSvg;
    bool quadtree = false;
};

// The figure options' combinations, before anything is loaded.
void checkFigureOptions(const ExplainOptions& o) {
    if (o.quadtree && o.svg.empty())
        throw CLI::ValidationError("--quadtree",
                                   "draws into the --svg file: give --svg F.svg as well");
    if (!o.svgPlane.empty() && o.svg.empty())
        throw CLI::ValidationError("--svg-plane", "'" + o.svgPlane +
                                                      "' chooses the plane of the --svg figure: "
                                                      "give --svg F.svg as well");
    if (!o.svgPlane.empty()) parseAxisPlane(o.svgPlane);  // a bad name is refused here
    for (const auto& [name, path] : {std::pair{"--svg", &o.svg}, {"--layouts-svg", &o.layoutsSvg}})
        if (*path == "-") throw CLI::ValidationError(name, "needs a file name, not stdout");
}

// The --svg figure: the explained ray in a plane of the octree, or with --quadtree the
// quadtree of the flat scene and the ray in its plane.
std::string svgFigure(const ExplainOptions& o, const Explanation& e, const Scene& scene,
                      const BuiltScene& bs, std::string& what) {
    if (!o.quadtree) {
        what = "the explained ray over the octree's cells";
        return explainSvg(e, scene, bs.tree.get(), o.svgPlane);
    }
    const AxisPlane plane = quadtreePlane(scene, o.svgPlane);
    const Ray2D ray = rayInPlane(e.primary.ray, plane);
    const Quadtree q =
        buildQuadtree(scene, plane, quadRootOf(scene, plane), o.scene.layoutOptions().build);
    const QuadTrace trace = traceQuadtree(q, scene, ray);
    what = "quadtree of " + std::to_string(q.nodes.size()) + " cells in the " + plane.name() +
           " plane, " + std::to_string(trace.visits.size()) + " visited";
    return quadtreeSvg(q, trace, scene, explainFigureTitle(e), explainFigureQuery(e));
}

// The --layouts-svg figure, from the explained layout's canonical octree (or one built now for
// a layout without an octree).
std::string layoutsFigure(const ExplainOptions& o, const Explanation& e, const Scene& scene,
                          const BuiltScene& bs, std::string& what) {
    const LayoutOptions options = o.scene.layoutOptions();
    const std::shared_ptr<const Octree> tree =
        bs.tree ? bs.tree : buildSharedOctree(scene, options.build);
    const LayoutFigure f = layoutFigure(scene, tree, options, e);
    what = "one octree of " + std::to_string(f.nodes) + " nodes in three layouts";
    return layoutFigureSvg(f);
}

// "X,Y": two integers.
void parsePixel(const std::string& text, int& x, int& y) {
    std::istringstream in(text);
    long long a = 0, b = 0;
    char comma = 0;
    if (!(in >> a >> comma >> b) || comma != ',' || !in.eof() || a < INT32_MIN || a > INT32_MAX ||
        b < INT32_MIN || b > INT32_MAX)
        throw CLI::ValidationError("--pixel", "'" + text + "' is not two integers X,Y");
    x = int(a);
    y = int(b);
}

// "ox,oy,oz,dx,dy,dz[,tmin,tmax]": a row of a ray file (tmin 0 and tmax +inf when left out),
// each number read as float32 as numpy.float32 reads it (1e39 is +inf, 1e-50 is 0), so that the
// ray file's rule, checked next, meets the same floats as in a file trace reads.
std::array<float, 8> parseRay(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) parts.push_back(item);
    std::array<float, 8> row = {0, 0, 0, 0, 0, 0, 0.0f, INFINITY};
    // getline drops an empty last item ("...,-1," would pass as six); numpy reads no hex floats.
    bool ok = (parts.size() == 6 || parts.size() == 8) && text.back() != ',' &&
              text.find_first_of("xX") == std::string::npos;
    for (size_t i = 0; ok && i < parts.size(); ++i) {
        char* end = nullptr;
        row[i] = std::strtof(parts[i].c_str(), &end);
        while (end != parts[i].c_str() && std::isspace((unsigned char)*end)) ++end;
        ok = end != parts[i].c_str() && *end == '\0';
    }
    if (!ok)
        throw CLI::ValidationError(
            "--ray", "'" + text + "' is not six or eight numbers ox,oy,oz,dx,dy,dz[,tmin,tmax]");
    return row;
}

// The ray file's rule (core/io/ray_file.h), the one trace applies to every row: explain takes
// exactly the rays trace takes.
void checkRay(const std::string& text, const std::array<float, 8>& row) {
    const std::string problem = rayRowProblem(row.data());
    if (!problem.empty()) throw std::runtime_error("--ray '" + text + "': " + problem);
}

void runExplain(const ExplainOptions& o) {
    const CameraOptions cam = cameraOptions(o.camera);
    const LayoutDesc& layout = parseOneLayout(o.accel, "explain");
    if (!o.pixel.empty() && !o.ray.empty())
        throw CLI::ValidationError("--ray", "give --pixel or --ray, not both");
    // Default: the image's centre pixel.
    int x = cam.width / 2, y = cam.height / 2;
    std::array<float, 8> row{};
    if (!o.ray.empty()) {
        row = parseRay(o.ray);
        checkRay(o.ray, row);
    } else if (!o.pixel.empty())
        parsePixel(o.pixel, x, y);
    if (o.ray.empty()) checkPixelInImage(x, y, cam.width, cam.height);
    if (o.html == "-") throw CLI::ValidationError("--html", "needs a file name, not stdout");
    checkFigureOptions(o);
    checkOutputPaths({o.json == "-" ? "" : o.json, o.html, o.svg, o.layoutsSvg}, {o.scene.path});
    for (const std::string* p : {&o.json, &o.html, &o.svg, &o.layoutsSvg})
        if (!p->empty() && *p != "-") checkWritable(*p);
    const std::vector<OutputLock> locks = lockOutputs({o.json, o.html, o.svg, o.layoutsSvg});

    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    BuiltScene bs = buildScene(scene, layout, o.scene.layoutOptions());
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    const Explanation e =
        o.ray.empty() ? explainPixel(bs, frame, x, y) : explainRay(bs, frame, row.data());

    OutputSet out;  // every file or none
    PageStats page;
    if (!o.json.empty() && o.json != "-") {
        const std::string text = explainJson(e);
        out.stage(o.json, text.data(), text.size());
    }
    if (!o.html.empty()) {
        const std::string text = explainPage(e, bs, o.scene.layoutOptions(), frame, &page);
        out.stage(o.html, text.data(), text.size());
    }
    std::string svgWhat, layoutsWhat;
    if (!o.svg.empty()) {
        const std::string text = svgFigure(o, e, scene, bs, svgWhat);
        out.stage(o.svg, text.data(), text.size());
    }
    if (!o.layoutsSvg.empty()) {
        const std::string text = layoutsFigure(o, e, scene, bs, layoutsWhat);
        out.stage(o.layoutsSvg, text.data(), text.size());
    }
    out.commit();
    if (o.json == "-") {
        writeTextOutput("-", explainJson(e));
        return;  // stdout is the JSON alone
    }
    std::fputs(explainText(e).c_str(), stdout);
    if (!o.json.empty()) std::printf("wrote   %s\n", o.json.c_str());
    if (!o.html.empty())
        std::printf("wrote   %s (%.2f MB; model: %llu %s%s, %llu cells, %llu steps)\n",
                    o.html.c_str(), double(page.bytes) / 1e6,
                    (unsigned long long)page.modelPrimitives,
                    scene.kind == PrimKind::Triangles ? "triangles" : "points",
                    page.reduced ? ", reduced" : "", (unsigned long long)page.cells,
                    (unsigned long long)page.lines);
    if (!o.svg.empty()) std::printf("wrote   %s (%s)\n", o.svg.c_str(), svgWhat.c_str());
    if (!o.layoutsSvg.empty())
        std::printf("wrote   %s (%s)\n", o.layoutsSvg.c_str(), layoutsWhat.c_str());
}

}  // namespace

void registerExplain(CLI::App& app) {
    auto o = std::make_shared<ExplainOptions>();
    CLI::App* cmd = app.add_subcommand(
        "explain", "One pixel's traversal step by step (text, --json, or an --html page)");
    addSceneOptions(*cmd, o->scene);
    cmd->add_option("--accel", o->accel, "Acceleration layout: " + layoutNames())
        ->capture_default_str();
    addCameraOptions(*cmd, o->camera);
    cmd->add_option("--pixel", o->pixel,
                    "Pixel X,Y of the image render draws with the same camera options (row 0 at "
                    "the top; default: the centre)");
    cmd->add_option("--ray", o->ray,
                    "A ray of your own ox,oy,oz,dx,dy,dz[,tmin,tmax] instead of a pixel, as a row "
                    "of a trace ray file (the same rule; tmin 0 and tmax inf by default): closest "
                    "hit, then its shadow ray");
    addJsonOption(*cmd, o->json, "every step, the hits and the totals");
    cmd->add_option("--html", o->html,
                    "Write an interactive page (one self-contained file): the model, the cells "
                    "visited, the ray and the steps");
    cmd->add_option("--svg", o->svg,
                    "Write a 2D figure for a slide (SVG): the cells the ray tested cut by an axis "
                    "plane that holds it, numbered in visit order, the primitives it tested, the "
                    "ray and its hit");
    cmd->add_option("--svg-plane", o->svgPlane,
                    "The --svg figure's plane through the ray's origin: xy, xz or yz (default: "
                    "the one that drops the ray's smallest direction component)");
    cmd->add_flag("--quadtree", o->quadtree,
                  "With --svg, for a flat scene (every primitive in one axis plane): the "
                  "quadtree over that plane (the octree's split rule, --max-depth, --max-prims), "
                  "each cell's Morton key in base 4, and the ray in the plane (the paper's "
                  "Figure 1)");
    cmd->add_option("--layouts-svg", o->layoutsSvg,
                    "Write one small octree as the linear array, the hash table and the compact "
                    "records side by side (SVG), with their bytes and one hash lookup's probes");
    cmd->callback([o] { runExplain(*o); });
}

}  // namespace oct
