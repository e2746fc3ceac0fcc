#include "core/io/ray_file.h"

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "core/geometry/numeric_range.h"
#include "core/io/input_file.h"

namespace oct {
namespace {

// The data are read straight into floats: '<f4' is the host's own layout.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "ray files are read on little-endian hosts");

[[noreturn]] void bad(const std::string& path, const std::string& why) {
    throw IoError("'" + path + "' is not a valid .npy file: " + why);
}

// The header is a Python dict literal, e.g. {'descr': '<f4', 'fortran_order': False,
// 'shape': (3, 8), } (numpy.lib.format). Keys and string values may use either quote; values
// are kept as written (a string without its quotes, a tuple without its parentheses).
std::map<std::string, std::string> parseHeader(const std::string& h, const std::string& path) {
    size_t i = 0;
    auto space = [&] {
        while (i < h.size() && (h[i] == ' ' || h[i] == '\t' || h[i] == '\n' || h[i] == '\r')) ++i;
    };
    auto malformed = [&]() { bad(path, "malformed header dict at byte " + std::to_string(i)); };
    auto quoted = [&] {
        char q = h[i];
        size_t end = h.find(q, i + 1);
        if (end == std::string::npos) malformed();
        std::string s = h.substr(i + 1, end - i - 1);
        i = end + 1;
        return s;
    };
    std::map<std::string, std::string> out;
    space();
    if (i >= h.size() || h[i] != '{') malformed();
    ++i;
    for (;;) {
        space();
        if (i < h.size() && h[i] == '}') break;
        if (i >= h.size() || (h[i] != '\'' && h[i] != '"')) malformed();
        std::string key = quoted();
        space();
        if (i >= h.size() || h[i] != ':') malformed();
        ++i;
        space();
        if (i >= h.size()) malformed();
        std::string value;
        if (h[i] == '\'' || h[i] == '"') {
            value = quoted();
        } else if (h[i] == '(') {
            size_t end = h.find(')', i);
            if (end == std::string::npos) malformed();
            value = h.substr(i + 1, end - i - 1);
            i = end + 1;
        } else {
            size_t end = h.find_first_of(",} \t\n", i);
            if (end == std::string::npos) malformed();
            value = h.substr(i, end - i);
            i = end;
        }
        out[key] = value;
        space();
        if (i < h.size() && h[i] == ',') {
            ++i;
            continue;
        }
        if (i < h.size() && h[i] == '}') break;
        malformed();
    }
    return out;
}

std::vector<uint64_t> parseShape(const std::string& s, const std::string& path) {
    std::vector<uint64_t> shape;
    std::istringstream in(s);
    std::string token;
    while (std::getline(in, token, ',')) {
        size_t a = token.find_first_not_of(" \t");
        if (a == std::string::npos) continue;  // the trailing comma of a 1-tuple
        size_t b = token.find_last_not_of(" \t");
        token = token.substr(a, b - a + 1);
        if (token.find_first_not_of("0123456789") != std::string::npos || token.size() > 19)
            bad(path, "bad shape entry '" + token + "'");
        shape.push_back(std::stoull(token));
    }
    return shape;
}

std::string pythonShape(const std::vector<uint64_t>& shape) {
    std::string s = "(";
    for (size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

std::string number(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

}  // namespace

std::string rayRowProblem(const float* r) {
    // The bounds as float32, the type of the file: 1e-19 written by numpy is float(1e-19).
    const float maxOrigin = float(kMaxRayOrigin);
    const float minDirection = float(kMinRayDirection), maxDirection = float(kMaxRayDirection);
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(r[k]) || std::fabs(r[k]) > maxOrigin)
            return "origin component " + number(r[k]) + " is not finite or beyond +-" +
                   number(kMaxRayOrigin) +
                   ", where float32 tracing stops being exact enough (docs/ROBUSTNESS.md, "
                   "numeric range); move the origin closer to the scene";
    float largest = 0.0f;
    for (int k = 3; k < 6; ++k) {
        if (!std::isfinite(r[k])) return "direction component " + number(r[k]) + " is not finite";
        largest = std::max(largest, std::fabs(r[k]));
    }
    if (largest == 0.0f) return "the direction is zero";
    if (largest < minDirection || largest > maxDirection)
        return "the direction's largest component " + number(largest) + " is outside [" +
               number(kMinRayDirection) + ", " + number(kMaxRayDirection) +
               "]; scale the direction (t is measured in its units)";
    if (!std::isfinite(r[6]) || r[6] < 0.0f)
        return "tmin " + number(r[6]) +
               " must be finite and >= 0 (Embree, the ground truth, traces no negative tmin); "
               "move the origin to o + tmin * d and trace [0, tmax - tmin]";
    if (std::isnan(r[7]) || r[7] < r[6])
        return "tmax " + number(r[7]) + " must be >= tmin " + number(r[6]) + " (+inf allowed)";
    return "";
}

namespace {

// The lowest row index that breaks the rule, or rows when none does. The rows are checked in
// parallel (a file holds millions); the answer is the lowest index, as a sequential scan gives.
uint64_t firstBadRow(const float* rays, uint64_t rows) {
    uint64_t first = rows;
    const int64_t n = int64_t(rows);
#pragma omp parallel for schedule(static) reduction(min : first)
    for (int64_t i = 0; i < n; ++i)
        if (uint64_t(i) < first && !rayRowProblem(rays + 8 * i).empty()) first = uint64_t(i);
    return first;
}

}  // namespace

uint64_t readRayFileInto(const std::string& path, const std::function<float*(uint64_t)>& allocate) {
    InputFile in(path, "the ray file", "save the rays with numpy.save and give that file");
    const uint64_t fileSize = in.size();

    // Preamble: magic "\x93NUMPY", major, minor, header length (uint16 LE in 1.0, uint32 LE in
    // 2.0 and 3.0), then the header, then the data.
    unsigned char pre[12];
    if (fileSize < 10 || in.read(pre, 10) != 10) bad(path, "shorter than the 10-byte preamble");
    if (std::memcmp(pre, "\x93NUMPY", 6) != 0) bad(path, "missing the \\x93NUMPY magic");
    const int major = pre[6];
    uint64_t headerLen = pre[8] | uint64_t(pre[9]) << 8;
    uint64_t dataStart = 10;
    if (major == 2 || major == 3) {
        if (in.read(pre + 10, 2) != 2) bad(path, "shorter than its preamble");
        headerLen |= uint64_t(pre[10]) << 16 | uint64_t(pre[11]) << 24;
        dataStart = 12;
    } else if (major != 1) {
        bad(path, "unsupported format version " + std::to_string(major));
    }
    if (headerLen > fileSize - dataStart) bad(path, "header runs past the end of the file");
    std::string header(headerLen, '\0');
    if (in.read(&header[0], headerLen) != headerLen)
        bad(path, "the file changed while it was read");
    dataStart += headerLen;

    std::map<std::string, std::string> dict = parseHeader(header, path);
    for (const char* key : {"descr", "fortran_order", "shape"})
        if (!dict.count(key)) bad(path, std::string("header has no '") + key + "'");
    if (dict["fortran_order"] != "False")
        bad(path, "Fortran-ordered arrays are not supported; save with numpy.ascontiguousarray");
    const std::vector<uint64_t> shape = parseShape(dict["shape"], path);
    if (dict["descr"] != "<f4" || shape.size() != 2 || shape[1] != 8)
        throw IoError("'" + path +
                      "' must be a float32 array of shape (N, 8): ox oy oz dx dy dz tmin tmax; "
                      "it holds dtype " +
                      dict["descr"] + ", shape " + pythonShape(shape));
    const uint64_t available = fileSize - dataStart;
    const uint64_t rows = shape[0];
    if (rows > available / 32 || rows * 32 != available)
        bad(path, "shape " + pythonShape(shape) + " needs " +
                      (rows > available / 32 ? std::string("more") : std::to_string(rows * 32)) +
                      " data bytes but the file has " + std::to_string(available) +
                      " (truncated or wrong header)");

    float* rays = allocate(rows);  // the final buffer: read into directly, one pass
    if (in.read(rays, available) != available || !in.atEnd())
        bad(path, "the file changed while it was read");
    const uint64_t first = firstBadRow(rays, rows);
    if (first < rows)
        throw IoError("'" + path + "' row " + std::to_string(first) + ": " +
                      rayRowProblem(&rays[8 * first]));
    return rows;
}

std::vector<float> readRayFile(const std::string& path) {
    std::vector<float> rays;
    readRayFileInto(path, [&rays](uint64_t rows) {
        rays.resize(rows * 8);
        return rays.data();
    });
    return rays;
}

}  // namespace oct
