// One benchmark case as a result row, and the files a sweep writes: DIR/bench.json (machine,
// config, rows) and DIR/bench.csv (the rows' fields as columns, in the same order). Both are
// rewritten after every case, so a sweep that is stopped keeps what it measured.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/render/film.h"

namespace oct {

struct Row {
    std::string sceneType;  // "cloud" or "mesh"
    std::string scene;      // grid:N:seed or the mesh's file name
    std::string path;       // mesh path (empty for clouds)
    uint64_t n = 0;         // requested points, or triangles
    uint64_t primitives = 0;
    uint64_t vertices = 0;
    uint64_t faces = 0;
    int gridDepth = -1;
    double loadSeconds = 0.0;
    std::string layout;   // a layout's name, or the structure of a backend with its own
    std::string backend;  // a backend's name
    std::string status = "ok";
    std::string reason;
    std::optional<double> treeSeconds, convertSeconds, buildSeconds;
    std::optional<double> frameMedian, frameMin, frameMax, mraysPerSecond, ratioToEmbree;
    std::optional<double> uploadSeconds;  // preparing our layout on the backend (CUDA upload)
    std::optional<uint64_t> primaryRays, shadowRays, layoutBytes, octreeNodes, octreeFaces;
    std::optional<int> octreeDepth;
    std::optional<double> nodesPerPixel, primsPerPixel, nodesPerRay, primsPerRay;
    int width = 0, height = 0, warmup = 0, repeats = 0;
};

nlohmann::ordered_json rowJson(const Row& r);

// Rays and (withCost) the traversal cost per pixel and per ray, from a rendered Film.
void fillFilmCounts(const Film& film, bool withCost, Row& r);
// Median, min, max of the timed frames and the rays per second at the median.
void fillTiming(const std::vector<double>& frames, Row& r);

// Writes DIR/bench.json and DIR/bench.csv, each to a temporary name renamed when complete.
void writeResults(const std::filesystem::path& dir, const nlohmann::ordered_json& machine,
                  const nlohmann::ordered_json& config, const std::vector<Row>& rows,
                  bool complete);

// CSV of JSON rows: a header line of `keys`, then each row's fields under them (null: an empty
// cell; a string holding a comma, quote or newline quoted, RFC 4180). bench.csv and the ray
// bench's rays-bench.csv.
std::string csvTable(const std::vector<std::string>& keys, const nlohmann::ordered_json& rows);

// printf-style formatting of one number.
std::string fmt(const char* format, double v);

}  // namespace oct
