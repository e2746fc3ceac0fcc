#include "validation/rays/ray_manifest.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/io/input_file.h"
#include "core/io/output_file.h"

#ifndef OCT_VERSION
#define OCT_VERSION "unknown"
#endif

namespace oct {
namespace {

using nlohmann::json;

json vec(Vec3 v) { return json::array({v.x, v.y, v.z}); }
json optVec(const std::optional<Vec3>& v) { return v ? vec(*v) : json(nullptr); }

const char* kRewrite =
    "write it again with octrace rays, or remove it to certify the rays as one set";

[[noreturn]] void bad(const std::string& path, const std::string& why) {
    throw IoError("ray manifest '" + path + "': " + why + " (" + kRewrite + ")");
}

std::string num(uint64_t v) { return std::to_string(v); }

const json& field(const json& j, const char* key, const std::string& path) {
    if (!j.is_object() || !j.contains(key)) bad(path, std::string("no field '") + key + "'");
    return j.at(key);
}

uint64_t count(const json& j, const char* key, const std::string& path) {
    const json& v = field(j, key, path);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
        bad(path, std::string("'") + key + "' is not a non-negative integer");
    return v.get<uint64_t>();
}

std::string text(const json& j, const char* key, const std::string& path) {
    const json& v = field(j, key, path);
    if (!v.is_string()) bad(path, std::string("'") + key + "' is not a string");
    return v.get<std::string>();
}

// A count of at most `most` (the manifest's own range: nothing is built from it first).
uint64_t countAtMost(const json& j, const char* key, uint64_t most, const std::string& path,
                     const char* within = "") {
    const uint64_t v = count(j, key, path);
    if (v > most)
        bad(path, std::string(within) + "'" + key + "' " + num(v) + " is more than " + num(most));
    return v;
}

// A number that is finite as a float (1e300 would become inf).
float finiteFloat(const json& v, const std::string& what, const std::string& path) {
    if (!v.is_number()) bad(path, what + " is not a number");
    const double d = v.get<double>();
    if (!std::isfinite(float(d))) bad(path, what + " " + v.dump() + " is not a finite float");
    return float(d);
}

std::optional<Vec3> optionalVec(const json& j, const char* key, const std::string& path) {
    const json& v = field(j, key, path);
    if (v.is_null()) return std::nullopt;
    if (!v.is_array() || v.size() != 3)
        bad(path, std::string("camera '") + key + "' is not null or three numbers");
    const std::string what = std::string("camera '") + key + "'";
    return Vec3{finiteFloat(v[0], what, path), finiteFloat(v[1], what, path),
                finiteFloat(v[2], what, path)};
}

// The file's rows of one set, as bytes.
bool sameRows(const std::vector<float>& file, const RaySetRange& f, const RaySet& rebuilt,
              const RaySetRange& r) {
    if (f.count != r.count) return false;
    return f.count == 0 || std::memcmp(&file[8 * f.begin], &rebuilt.rays[8 * r.begin],
                                       size_t(8 * f.count) * sizeof(float)) == 0;
}

json baselineJson(const AmbiguityBaseline& b, const std::vector<RaySetRange>& sets) {
    json bySet = json::object();
    for (size_t i = 0; i < sets.size() && i < b.ambiguous.size(); ++i)
        bySet[sets[i].name] = b.ambiguous[i];
    return {{"tracer", b.tracer},
            {"policy",
             {{"t_tolerance", b.tTolerance},
              {"edge_tolerance", b.edgeTolerance},
              {"grazing_cos", b.grazingCos}}},
            {"by_set", bySet}};
}

// A tolerance of the baseline's policy: a finite number in [0, 1], as certify's options.
double tolerance(const json& p, const char* key, const std::string& path) {
    const json& v = field(p, key, path);
    const double d = v.is_number() ? v.get<double>() : NAN;
    if (!(d >= 0.0 && d <= 1.0))
        bad(path, std::string("expected_ambiguous policy '") + key + "' is not a number in [0, 1]");
    return d;
}

// expected_ambiguous: a count for every set of `sets` (by name, none other), each at most the
// set's rows.
AmbiguityBaseline baselineFromJson(const json& j, const std::vector<RaySetRange>& sets,
                                   const std::string& path) {
    if (!j.is_object()) bad(path, "'expected_ambiguous' is not an object");
    AmbiguityBaseline b;
    b.tracer = text(j, "tracer", path);
    const json& p = field(j, "policy", path);
    b.tTolerance = tolerance(p, "t_tolerance", path);
    b.edgeTolerance = tolerance(p, "edge_tolerance", path);
    b.grazingCos = tolerance(p, "grazing_cos", path);
    const json& bySet = field(j, "by_set", path);
    if (!bySet.is_object() || bySet.size() != sets.size())
        bad(path, "expected_ambiguous 'by_set' does not name each set once");
    for (const RaySetRange& r : sets) {
        if (!bySet.contains(r.name))
            bad(path, "expected_ambiguous 'by_set' has no count for set '" + r.name + "'");
        b.ambiguous.push_back(
            countAtMost(bySet, r.name.c_str(), r.count, path, "expected_ambiguous 'by_set' "));
    }
    return b;
}

}  // namespace

const char* octraceVersion() { return OCT_VERSION; }

std::string manifestPathFor(const std::string& raysPath) {
    const std::string ext = ".npy";
    if (raysPath.size() > ext.size() &&
        raysPath.compare(raysPath.size() - ext.size(), ext.size(), ext) == 0)
        return raysPath.substr(0, raysPath.size() - ext.size()) + ".json";
    return raysPath + ".json";
}

RayManifest describeRaySet(const Scene& scene, const RaySetSpec& spec, const RaySet& rays) {
    RayManifest m;
    m.octrace = octraceVersion();
    m.scene = scene.name;
    m.kind = primKindName(scene.kind);
    m.primitives = scene.primitiveCount();
    m.fingerprint = sceneFingerprint(scene);
    // The radius a point cloud file was loaded with, so that certify loads the same spheres. A
    // generated grid cloud's radius is fixed by its spec (and the loader refuses one): none.
    if (scene.kind == PrimKind::Spheres && !scene.spheres.empty() && scene.gridDepth < 0)
        m.radius = scene.spheres[0].radius;
    m.seed = spec.seed;
    m.count = spec.count;
    m.rows = rays.count();
    m.checksum = hex64(fnv1a64(rays.rays.data(), rays.rays.size() * sizeof(float)));
    m.sets = rays.sets;
    if (rays.frame) {
        m.camera = spec.camera;
        m.frame = rays.frame;
    }
    m.baseline = rays.baseline;
    return m;
}

json toJson(const RayManifest& m) {
    json sets = json::array();
    for (const RaySetRange& r : m.sets)
        sets.push_back({{"name", r.name}, {"begin", r.begin}, {"count", r.count}});
    json j = {{"format", "octrace-rays"},
              {"version", 1},
              {"octrace", m.octrace},
              {"scene",
               {{"name", m.scene},
                {"kind", m.kind},
                {"primitives", m.primitives},
                {"radius", m.radius ? json(*m.radius) : json(nullptr)},
                {"fnv1a64", m.fingerprint}}},
              {"seed", m.seed},
              {"count", m.count},
              {"rows", m.rows},
              {"fnv1a64", m.checksum},
              {"sets", sets}};
    if (m.camera) {
        const CameraOptions& c = *m.camera;
        json cam = {{"width", c.width},        {"height", c.height},         {"fov", c.fovDegrees},
                    {"eye", optVec(c.eye)},    {"target", optVec(c.target)}, {"up", optVec(c.up)},
                    {"light", optVec(c.light)}};
        if (m.frame) {
            const FrameParams& f = *m.frame;
            cam["frame"] = {{"eye", vec(f.camera.eye)},      {"forward", vec(f.camera.forward)},
                            {"right", vec(f.camera.right)},  {"up", vec(f.camera.up)},
                            {"light", vec(f.shading.light)}, {"shadow_bias", f.shading.shadowBias}};
        }
        j["camera"] = cam;
    }
    if (m.baseline) j["expected_ambiguous"] = baselineJson(*m.baseline, m.sets);
    return j;
}

RayManifest manifestFromJson(const json& j, const std::string& path) {
    if (text(j, "format", path) != "octrace-rays") bad(path, "'format' is not \"octrace-rays\"");
    if (count(j, "version", path) != 1) bad(path, "'version' is not 1");
    RayManifest m;
    m.octrace =
        j.contains("octrace") && j["octrace"].is_string() ? j["octrace"].get<std::string>() : "";
    const json& s = field(j, "scene", path);
    m.scene = text(s, "name", path);
    m.kind = text(s, "kind", path);
    if (m.kind != "triangles" && m.kind != "spheres")
        bad(path, "scene 'kind' is \"" + m.kind + "\", not \"triangles\" or \"spheres\"");
    // The loader refuses 2^32 - 1 primitives and more (32-bit ids): a larger count wrapped.
    m.primitives = uint32_t(countAtMost(s, "primitives", UINT32_MAX - 1, path, "scene "));
    if (s.contains("radius") && !s["radius"].is_null()) {
        m.radius = finiteFloat(s["radius"], "scene 'radius'", path);
        if (!(*m.radius > 0.0f)) bad(path, "scene 'radius' is not positive");
    }
    if (s.contains("fnv1a64")) m.fingerprint = text(s, "fnv1a64", path);
    m.seed = count(j, "seed", path);
    m.count = countAtMost(j, "count", kMaxSeededRays, path);
    m.rows = count(j, "rows", path);
    m.checksum = text(j, "fnv1a64", path);
    const json& sets = field(j, "sets", path);
    if (!sets.is_array()) bad(path, "'sets' is not a list");
    for (const json& r : sets)
        m.sets.push_back({text(r, "name", path), count(r, "begin", path), count(r, "count", path)});
    if (j.contains("camera") && !j["camera"].is_null()) {
        const json& c = j["camera"];
        CameraOptions o;
        o.width = int(countAtMost(c, "width", uint64_t(kMaxImageSide), path, "camera "));
        o.height = int(countAtMost(c, "height", uint64_t(kMaxImageSide), path, "camera "));
        if (o.width < 1 || o.height < 1) bad(path, "camera 'width' and 'height' must be >= 1");
        o.fovDegrees = finiteFloat(field(c, "fov", path), "camera 'fov'", path);
        if (!(o.fovDegrees > 0.0f && o.fovDegrees < 180.0f))
            bad(path, "camera 'fov' " + c["fov"].dump() + " is not between 0 and 180 degrees");
        o.eye = optionalVec(c, "eye", path);
        o.target = optionalVec(c, "target", path);
        o.up = optionalVec(c, "up", path);
        o.light = optionalVec(c, "light", path);
        m.camera = o;
    }
    if (j.contains("expected_ambiguous"))
        m.baseline = baselineFromJson(j["expected_ambiguous"], m.sets, path);
    return m;
}

RayManifest readManifest(const std::string& path) {
    const std::string bytes = readSmallInput(path, "the ray manifest", kMaxManifestBytes, kRewrite);
    json j = json::parse(bytes, nullptr, false);
    if (j.is_discarded()) bad(path, "not JSON");
    return manifestFromJson(j, path);
}

std::string sceneFingerprint(const Scene& scene) {
    static_assert(sizeof(Triangle) == 36 && sizeof(Sphere) == 16, "packed floats");
    uint64_t h = 0xcbf29ce484222325ull;  // fnv1a64, continued over both arrays
    auto feed = [&h](const void* data, size_t bytes) {
        const auto* p = static_cast<const uint8_t*>(data);
        for (size_t i = 0; i < bytes; ++i) {
            h ^= p[i];
            h *= 0x100000001b3ull;
        }
    };
    feed(scene.triangles.data(), scene.triangles.size() * sizeof(Triangle));
    feed(scene.spheres.data(), scene.spheres.size() * sizeof(Sphere));
    return hex64(h);
}

void checkManifestRows(const RayManifest& m, uint64_t n, const std::string& raysPath) {
    const std::string mp = manifestPathFor(raysPath);
    // The sets must cover the rows in order, without gap or overlap.
    uint64_t next = 0;
    for (const RaySetRange& r : m.sets) {
        if (r.begin != next || r.count > n - std::min(n, r.begin))
            throw IoError("ray manifest '" + mp + "': set '" + r.name + "' rows " + num(r.begin) +
                          "+" + num(r.count) + " do not follow row " + num(next) + " within the " +
                          num(n) + " rows of '" + raysPath + "' (" + kRewrite + ")");
        next = r.begin + r.count;
    }
    if (next != n || m.rows != n)
        throw IoError("ray manifest '" + mp + "' describes " + num(m.rows) +
                      " rows in sets covering " + num(next) + ", but '" + raysPath + "' has " +
                      num(n) + " (write the rays and their manifest again with octrace rays)");
    // The standard sets' own counts, from which they are rebuilt: the camera's image and the
    // seeded sets' shares of `count` (shadow depends on a reference's hits: any count).
    RaySetSpec spec;
    spec.count = m.count;
    for (const RaySetRange& r : m.sets)
        if (const RaySetDesc* k = findRaySet(r.name)) spec.sets.push_back(k);
    for (const RaySetRange& r : m.sets) {
        const RaySetDesc* k = findRaySet(r.name);
        if (!k || k->needsReference) continue;
        uint64_t expected = 0;
        std::string why;
        if (!k->seeded) {
            if (!m.camera)
                throw IoError("ray manifest '" + mp + "' has a camera set but no 'camera' (" +
                              kRewrite + ")");
            expected = uint64_t(m.camera->width) * uint64_t(m.camera->height);
            why = "its camera 'width' x 'height' " + num(uint64_t(m.camera->width)) + "x" +
                  num(uint64_t(m.camera->height));
        } else {
            expected = seededShare(spec, *k);
            why = "its share of 'count' " + num(m.count);
        }
        if (r.count != expected)
            throw IoError("ray manifest '" + mp + "': set '" + r.name + "' has " + num(r.count) +
                          " rows, but " + why + " makes " + num(expected) + " (" + kRewrite + ")");
    }
}

void checkSameScene(const RayManifest& m, const Scene& scene, const std::string& raysPath) {
    const std::string kind = primKindName(scene.kind);
    const std::string fingerprint = m.fingerprint.empty() ? "" : sceneFingerprint(scene);
    if (m.kind == kind && m.primitives == scene.primitiveCount() && m.fingerprint == fingerprint)
        return;
    auto describe = [](const std::string& k, uint64_t prims, const std::string& f) {
        return num(prims) + " " + k + (f.empty() ? "" : ", geometry " + f);
    };
    throw IoError("these rays were made for '" + m.scene + "' (" +
                  describe(m.kind, m.primitives, m.fingerprint) + "; ray manifest '" +
                  manifestPathFor(raysPath) + "'), and '" + scene.name + "' is another scene (" +
                  describe(kind, scene.primitiveCount(), fingerprint) +
                  "): certify them against that scene");
}

RaySet raySetFromFile(const Scene& scene, std::vector<float> rays,
                      const std::optional<RayManifest>& manifest, const std::string& raysPath,
                      std::vector<std::string>& notes, const DoubleTracer* truth) {
    RaySet out;
    out.rays = std::move(rays);
    const uint64_t n = out.count();
    if (!manifest) {
        out.sets.push_back({"all", 0, n});
        return out;
    }
    const RayManifest& m = *manifest;
    const std::string mp = manifestPathFor(raysPath);
    // Everything that can be checked without building, first: no manifest makes this build
    // more rows than the file has, nor rebuild the sets on another scene.
    checkManifestRows(m, n, raysPath);
    const std::string sum = hex64(fnv1a64(out.rays.data(), out.rays.size() * sizeof(float)));
    if (sum != m.checksum)
        throw IoError("'" + raysPath + "' is not the file its manifest '" + mp +
                      "' describes (FNV-1a " + sum + ", manifest " + m.checksum +
                      "): the rays were changed; write them again with octrace rays");
    checkSameScene(m, scene, raysPath);
    out.sets = m.sets;
    out.baseline = m.baseline;

    // Rebuild the standard sets (all but shadow, which needs the reference's camera hits) and
    // compare: this proves the rows are the sets they claim to be, on this scene.
    RaySetSpec spec;
    spec.seed = m.seed;
    spec.count = m.count;
    for (const RaySetRange& r : m.sets) {
        const RaySetDesc* k = findRaySet(r.name);
        if (!k) {
            notes.push_back("set '" + r.name + "' is not a standard set: rows only");
            continue;
        }
        spec.sets.push_back(k);  // shadow is kept for the seeded sets' split, then skipped
    }
    bool needCamera = false;
    for (const RaySetDesc* k : spec.sets) needCamera = needCamera || !k->seeded;
    if (needCamera) {
        if (!m.camera)
            throw IoError("ray manifest '" + mp + "' has a camera or shadow set but no 'camera' (" +
                          kRewrite + ")");
        spec.camera = *m.camera;
        out.frame = makeFrame(scene.bounds(), spec.camera);
    }
    RaySetSpec rebuildSpec = spec;
    rebuildSpec.sets.clear();
    for (const RaySetDesc* k : spec.sets)
        if (!k->needsReference) rebuildSpec.sets.push_back(k);
    // Rebuilt in one call (the sets in parallel), sharing the mesh's targets and the truth.
    // Leaving out the sets made from the reference (shadow, not seeded) keeps every seeded set's
    // share, which follows the seeded sets alone.
    rebuildSpec.truth = truth;
    const RaySet rebuilt = makeRaySet(scene, rebuildSpec);
    for (const RaySetRange& f : out.sets) {
        const RaySetDesc* k = findRaySet(f.name);
        if (k && k->needsReference) {
            notes.push_back("set '" + f.name +
                            "' depends on the reference's camera hits: taken as given");
            continue;
        }
        const RaySetRange* r = rebuilt.find(f.name);
        if (!r) continue;
        if (!sameRows(out.rays, f, rebuilt, *r))
            throw IoError("'" + raysPath + "' rows " + std::to_string(f.begin) + ".." +
                          std::to_string(f.begin + f.count) + " (set '" + f.name +
                          "') are not the set its manifest describes on '" + scene.name +
                          "': the file was edited, another version of octrace wrote "
                          "it, or it was made for another scene; write the rays "
                          "again with octrace rays");
        if (f.name == "camera")
            out.cameraRows =
                checkCameraRows(scene.bounds(), spec.camera, &out.rays[8 * f.begin], f.count);
        for (RayTarget t : rebuilt.targets)
            if (t.row >= r->begin && t.row < r->begin + r->count) {
                t.row = t.row - r->begin + f.begin;
                out.targets.push_back(t);
            }
    }
    std::sort(out.targets.begin(), out.targets.end(),
              [](const RayTarget& a, const RayTarget& b) { return a.row < b.row; });
    out.mesh = rebuilt.mesh;
    return out;
}

}  // namespace oct
