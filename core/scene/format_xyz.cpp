// XYZ point clouds: one point per line, "x y z" and any further columns (ignored); blank lines,
// lines starting with '#' and a UTF-8 byte-order mark are skipped. Each point becomes a sphere
// (sphereScene).
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <utility>
#include <vector>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

// Reads "x y z [more columns]" from one XYZ line; false when it is blank or a comment.
bool parseXyzLine(const std::string& line, uint64_t lineNo, const std::string& path, Vec3& p) {
    if (line.find('\0') != std::string::npos)
        throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                         " holds a NUL byte; an .xyz file is text, x y z on every point line");
    const char* s = line.c_str();
    while (std::isspace(static_cast<unsigned char>(*s))) ++s;
    if (*s == '\0' || *s == '#') return false;
    double c[3];
    for (double& v : c) {
        char* end = nullptr;
        v = std::strtod(s, &end);
        if (end == s || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end)))) {
            std::string text = line;
            trimLine(text);
            throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                             " (" + inQuotes(text.substr(0, 60)) +
                             ") does not start with 3 numbers; write x y z on every point line");
        }
        s = end;
    }
    p = {float(c[0]), float(c[1]), float(c[2])};  // beyond float range becomes inf: dropped
    return true;
}

}  // namespace

Scene loadXyz(const std::string& path, const LoadOptions& opts) {
    std::ifstream in = openOrThrow(path);
    LoadReport report;
    report.format = "xyz";
    std::vector<Vec3> points;
    std::string line;
    uint64_t lineNo = 0;
    Vec3 p;
    while (std::getline(in, line)) {
        if (lineNo == 0) stripUtf8Bom(line);
        if (parseXyzLine(line, ++lineNo, path, p)) points.push_back(p);
    }
    if (in.bad()) throw SceneError("cannot read " + inQuotes(path) + ": " + std::strerror(errno));
    report.verticesRead = points.size();
    std::vector<Vec3> kept = finitePoints(points, report);
    return sphereScene(path, kept, std::move(report), opts);
}

}  // namespace oct::scene_detail
