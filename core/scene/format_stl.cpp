// STL, ASCII and binary: a triangle soup that OpenMesh's STL reader welds into a mesh, surveyed
// first to predict the facets it skips and to refuse what it would misread (loader_detail.h).
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

namespace fs = std::filesystem;

// OpenMesh's STL reader merges vertices whose coordinates all differ by at most FLT_MIN and
// skips a facet whose merged corners repeat. This is its comparator's equivalence.
bool stlMerged(const Vec3& a, const Vec3& b) {
    const float eps = FLT_MIN;
    return std::fabs(a.x - b.x) <= eps && std::fabs(a.y - b.y) <= eps && !(a.z < b.z - eps) &&
           !(b.z < a.z - eps);
}

void surveyStlFacet(const Vec3 (&v)[3], Survey& s) {
    const uint32_t face = uint32_t(s.facesInFile++);
    if (stlMerged(v[0], v[1]) || stlMerged(v[0], v[2]) || stlMerged(v[1], v[2]))
        ++s.skippedDegenerate;
    else
        s.handedOver.push_back(face);
}

// OpenMesh's rule: binary when the size is exactly 84 + 50 x (count at byte 80).
bool stlIsBinary(const std::string& path, uint32_t& facetCount) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    char header[84];
    if (!in.read(header, 84)) return false;
    std::memcpy(&facetCount, header + 80, 4);  // little-endian hosts, as the reader assumes
    std::error_code ec;
    return fs::file_size(path, ec) == 84 + 50 * uint64_t(facetCount);
}

Survey surveyBinaryStl(const std::string& path, uint32_t facetCount) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    in.seekg(84);
    Survey s;
    s.surveyed = true;
    char record[50];
    for (uint32_t f = 0; f < facetCount && in.read(record, 50); ++f) {
        Vec3 v[3];
        std::memcpy(v, record + 12, sizeof v);
        // inf compares consistently and is dropped later; NaN breaks the reader's vertex map.
        for (const Vec3& p : v)
            if (std::isnan(p.x) || std::isnan(p.y) || std::isnan(p.z))
                throw SceneError("cannot load " + inQuotes(path) + ": facet " + std::to_string(f) +
                                 " has a NaN coordinate, which corrupts OpenMesh's vertex merging "
                                 "for the whole file; remove or repair that facet");
        surveyStlFacet(v, s);
    }
    return s;
}

float parseStlCoordinate(std::istringstream& in, const std::string& path, uint64_t lineNo) {
    float value;
    if (!(in >> value))
        throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                         " needs 'vertex x y z' with finite numbers; OpenMesh's STL reader would "
                         "silently misplace that vertex, so fix it");
    return value;
}

Survey surveyAsciiStl(const std::string& path) {
    std::ifstream in = openOrThrow(path);
    Survey s;
    s.surveyed = true;
    std::string line, keyword;
    uint64_t lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.find("outer") == std::string::npos && line.find("OUTER") == std::string::npos)
            continue;
        Vec3 v[3];
        for (Vec3& corner : v) {  // the reader takes the next three lines as "vertex x y z"
            std::getline(in, line);
            ++lineNo;
            std::istringstream stream(line);
            stream >> keyword;
            corner.x = parseStlCoordinate(stream, path, lineNo);
            corner.y = parseStlCoordinate(stream, path, lineNo);
            corner.z = parseStlCoordinate(stream, path, lineNo);
        }
        surveyStlFacet(v, s);
    }
    return s;
}

// True when the file's first non-blank characters are "solid", as an ASCII STL must begin.
bool stlLooksAscii(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    char head[512];
    in.read(head, sizeof head);
    std::string text(head, size_t(in.gcount()));
    stripUtf8Bom(text);
    size_t begin = text.find_first_not_of(" \t\r\n");
    return begin != std::string::npos && toLower(text.substr(begin, 5)) == "solid";
}

// True when the file holds a byte no text file holds (a control character other than blanks).
bool hasBinaryBytes(const std::string& path) {
    std::ifstream in = openOrThrow(path, std::ios::in | std::ios::binary);
    char chunk[1 << 14];
    while (in.read(chunk, sizeof chunk) || in.gcount() > 0)
        for (std::streamsize i = 0; i < in.gcount(); ++i) {
            const unsigned char c = static_cast<unsigned char>(chunk[i]);
            if ((c < 0x20 && !std::isspace(c)) || c == 0x7f) return true;
        }
    return false;
}

Survey surveyStl(const std::string& path) {
    uint32_t facetCount = 0;
    if (stlIsBinary(path, facetCount)) return surveyBinaryStl(path, facetCount);
    // OpenMesh reads every file whose size is not exactly that of a binary STL as ASCII, so a
    // truncated or padded binary STL, or any other bytes, would load as an empty mesh.
    if (!stlLooksAscii(path)) {
        const uint64_t size = fileSize(path);
        throw SceneError("cannot load " + inQuotes(path) +
                         ": it is neither an ASCII STL (which starts with "
                         "'solid') nor a binary STL of the size its header declares" +
                         (size >= 84 ? " (" + std::to_string(facetCount) + " facets need " +
                                           std::to_string(84 + 50 * uint64_t(facetCount)) +
                                           " bytes, the file has " + std::to_string(size) + ")"
                                     : " (the file has " + std::to_string(size) +
                                           " bytes, fewer than a binary "
                                           "STL's 84-byte header)") +
                         "; the file is truncated, padded or not an STL file");
    }
    Survey s = surveyAsciiStl(path);
    // Many programs start a binary STL's 80-byte header with "solid" too. With a facet count
    // that does not match its size, such a file reads as an ASCII STL without a single facet.
    const uint64_t size = fileSize(path);
    if (s.facesInFile == 0 && size >= 84 && hasBinaryBytes(path))
        throw SceneError("cannot load " + inQuotes(path) +
                         ": it starts with 'solid' but is not text, so it is a binary STL, whose "
                         "header declares " +
                         std::to_string(facetCount) + " facets (" +
                         std::to_string(84 + 50 * uint64_t(facetCount)) +
                         " bytes) while the file has " + std::to_string(size) +
                         " bytes; the facet count is wrong or the file is truncated or padded");
    return s;
}

}  // namespace

Scene loadStl(const std::string& path, const LoadOptions&) {
    Survey survey = surveyStl(path);
    return buildMeshScene(path, "stl", readWithOpenMesh(path, "STL"), std::move(survey));
}

}  // namespace oct::scene_detail
