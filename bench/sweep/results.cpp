#include "bench/sweep/results.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "backends/backend_list.h"
#include "core/io/output_file.h"
#include "core/time_spread.h"

namespace oct {
namespace {

// Ordered, so the CSV's columns and the JSON's keys keep the order written here.
using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

template <class T>
json optJson(const std::optional<T>& v) {
    return v ? json(*v) : json(nullptr);
}

// CSV: the JSON row's fields in the same order; null is an empty cell.
std::string csvCell(const json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) {
        std::string s = v.get<std::string>();
        if (s.find_first_of(",\"\n") == std::string::npos) return s;
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    }
    if (v.is_number_float()) return fmt("%.9g", v.get<double>());
    return v.dump();
}

// Write to a temporary name and rename (core/io/output_file.h), so a reader never sees half a
// file and an interrupted or failed write leaves no temporary behind.
void writeAtomic(const fs::path& p, const std::string& text) {
    writeFileAtomic(p.string(), text.data(), text.size());
}

}  // namespace

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

json rowJson(const Row& r) {
    return {{"scene_type", r.sceneType},
            {"scene", r.scene},
            {"path", r.path},
            {"n", r.n},
            {"primitives", r.primitives},
            {"vertices", r.vertices},
            {"faces", r.faces},
            {"grid_depth", r.gridDepth < 0 ? json(nullptr) : json(r.gridDepth)},
            {"load_s", r.loadSeconds},
            {"layout", r.layout},
            {"backend", r.backend},
            {"status", r.status},
            {"reason", r.reason},
            {"tree_build_s", optJson(r.treeSeconds)},
            {"convert_s", optJson(r.convertSeconds)},
            {"build_s", optJson(r.buildSeconds)},
            {"frame_s_median", optJson(r.frameMedian)},
            {"frame_s_min", optJson(r.frameMin)},
            {"frame_s_max", optJson(r.frameMax)},
            {"upload_s", optJson(r.uploadSeconds)},
            {"mrays_per_s", optJson(r.mraysPerSecond)},
            {"ratio_to_embree", optJson(r.ratioToEmbree)},
            {"primary_rays", optJson(r.primaryRays)},
            {"shadow_rays", optJson(r.shadowRays)},
            {"layout_bytes", optJson(r.layoutBytes)},
            {"octree_nodes", optJson(r.octreeNodes)},
            {"octree_depth", optJson(r.octreeDepth)},
            {"octree_faces", optJson(r.octreeFaces)},
            // boxes tested (docs/TEACHING.md, "Words"); format 1 named them nodes_per_*.
            {"boxes_per_pixel", optJson(r.nodesPerPixel)},
            {"prims_per_pixel", optJson(r.primsPerPixel)},
            {"boxes_per_ray", optJson(r.nodesPerRay)},
            {"prims_per_ray", optJson(r.primsPerRay)},
            {"width", r.width},
            {"height", r.height},
            {"warmup", r.warmup},
            {"repeats", r.repeats}};
}

std::string csvTable(const std::vector<std::string>& keys, const json& rows) {
    std::string csv;
    for (size_t k = 0; k < keys.size(); ++k) csv += (k ? "," : "") + keys[k];
    csv += "\n";
    for (const json& row : rows) {
        for (size_t k = 0; k < keys.size(); ++k) csv += (k ? "," : "") + csvCell(row[keys[k]]);
        csv += "\n";
    }
    return csv;
}

void writeResults(const fs::path& dir, const json& machine, const json& config,
                  const std::vector<Row>& rows, bool complete) {
    json all = json::array();
    for (const Row& r : rows) all.push_back(rowJson(r));
    json doc = {{"format", "octrace-bench/2"},  // 2: boxes_per_* (1: nodes_per_*)
                {"complete", complete},
                {"machine", machine},
                {"config", config},
                {"results", all}};
    writeAtomic(dir / "bench.json", doc.dump(2) + "\n");

    const json header = rowJson(Row{});
    std::vector<std::string> keys;
    for (const auto& field : header.items()) keys.push_back(field.key());
    writeAtomic(dir / "bench.csv", csvTable(keys, all));
}

void fillFilmCounts(const Film& film, bool withCost, Row& r) {
    uint64_t primary = 0, shadow = 0;
    countRays(film, primary, shadow);
    r.primaryRays = primary;
    r.shadowRays = shadow;
    if (withCost) {
        double nodes = 0, tested = 0;
        for (size_t i = 0; i < film.pixelCount(); ++i) {
            nodes += film.nodes[i];
            tested += film.primsTested[i];
        }
        double pixels = double(film.pixelCount());
        double rays = double(film.pixelCount() + shadow);
        r.nodesPerPixel = nodes / pixels;
        r.primsPerPixel = tested / pixels;
        r.nodesPerRay = nodes / rays;
        r.primsPerRay = tested / rays;
    }
}

void fillTiming(const std::vector<double>& frames, Row& r) {
    const TimeSpread s = timeSpread(frames);
    r.frameMedian = s.median;
    r.frameMin = s.min;
    r.frameMax = s.max;
    double rays = double(r.primaryRays.value_or(0) + r.shadowRays.value_or(0));
    r.mraysPerSecond = s.median > 0 ? rays / s.median * 1e-6 : 0.0;
}

}  // namespace oct
