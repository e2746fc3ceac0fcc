// Wavefront OBJ: a polygon mesh of "v" and "f" lines. Read by octrace's fast reader
// (obj_fast_reader.cpp) when the file keeps to the plain part of the format, else, the
// reference path, by OpenMesh's OBJ reader after a survey of the same lines, parsed as that
// reader parses them (loader_detail.h says why). Both give the same RawMesh and Survey.
//
// Two things of the format OpenMesh's reader does not know are settled first, by ObjLines: a
// UTF-8 byte-order mark before the first line (it would make the first keyword unknown and
// the reader drop that line, shifting every later vertex number), and statements continued
// over several lines with a final backslash. A file with either is handed to OpenMesh as a
// rewritten copy holding the same statements on one line each.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

namespace fs = std::filesystem;

// The logical lines of an OBJ file. Wavefront's OBJ specification makes '\' at the end of a
// line the line-continuation character; the backslash becomes a blank and the next line is
// joined on. A comment line is never continued, so that a comment ending in a Windows path
// ("# C:\models\") cannot swallow the statement after it. A UTF-8 byte-order mark at the start
// of the file is dropped.
class ObjLines {
public:
    explicit ObjLines(std::istream& in) : in_(in) {}

    // The next logical line, and the number of its first physical line; false at the end.
    bool next(std::string& line, uint64_t& firstLineNo) {
        if (!std::getline(in_, line)) return false;
        firstLineNo = ++lineNo_;
        if (lineNo_ == 1 && stripUtf8Bom(line) > 0) rewritten_ = true;
        const size_t start = line.find_first_not_of(" \t\r\n");
        if (start != std::string::npos && line[start] == '#') return true;
        for (size_t last = line.find_last_not_of(" \t\r\n");
             last != std::string::npos && line[last] == '\\';
             last = line.find_last_not_of(" \t\r\n")) {
            rewritten_ = true;
            line.resize(last);
            line += ' ';
            std::string more;
            if (!std::getline(in_, more)) break;
            ++lineNo_;
            line += more;
        }
        return true;
    }
    uint64_t lastLineNo() const { return lineNo_; }  // of the last physical line read
    // Whether a line so far was not what OpenMesh's reader would read there.
    bool rewritten() const { return rewritten_; }

private:
    std::istream& in_;
    uint64_t lineNo_ = 0;
    bool rewritten_ = false;
};

// One OBJ "f" line, decided as OpenMesh's OBJ reader decides it: the first component of each
// corner is the vertex (negative = relative to the "v" lines so far); repeated vertices are
// removed; fewer than 3 left and the reader skips the face without a word.
void surveyObjFace(std::istringstream& rest, size_t vertexLinesSoFar, Survey& s,
                   const std::string& path, uint64_t lineNo) {
    const uint32_t face = uint32_t(s.facesInFile++);
    std::vector<long long> corners;
    std::string token;
    bool lostCorner = false;
    while (rest >> token) {
        // A corner without '/' whose number does not parse is skipped; one with '/' is kept
        // with the value operator>> leaves behind (0 on garbage, INT_MAX/INT_MIN on overflow).
        const size_t slash = token.find('/');
        // A corner without a vertex index ("/2", "/2/3") makes Debian's OpenMesh, built with
        // assertions, abort the process (assert(!vhandles.empty()) in its OBJ reader).
        if (slash == 0)
            throw SceneError("cannot load " + inQuotes(path) + ": line " + std::to_string(lineNo) +
                             " has a face corner " + inQuotes(token) +
                             " without a vertex index; every corner needs one (v, v/vt, v//vn "
                             "or v/vt/vn)");
        std::istringstream number(token.substr(0, slash));
        int value = 0;
        if (!(number >> value) && slash == std::string::npos) {
            // A number that overflows int is an index naming no vertex, not a stray word.
            const std::string digits = token.substr(token[0] == '-' || token[0] == '+' ? 1 : 0);
            lostCorner = lostCorner || (!digits.empty() && digits.find_first_not_of("0123456789") ==
                                                               std::string::npos);
            continue;
        }
        corners.push_back(value < 0 ? (long long)vertexLinesSoFar + value : (long long)value - 1);
    }
    const size_t listed = corners.size();
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    if (corners.size() > 2) {
        s.handedOver.push_back(face);
        s.lostCorner.push_back(lostCorner);
    } else if (lostCorner)
        ++s.skippedInvalidIndex;
    else if (listed < 3)
        ++s.skippedTooFew;
    else
        ++s.skippedDegenerate;
}

// The name an "mtllib" line gives, as OpenMesh's reader takes it: the rest of the line after
// the keyword, trimmed.
std::string materialLibrary(std::istringstream& rest) {
    std::string name;
    std::getline(rest, name);
    trimLine(name);
    return name;
}

// OpenMesh's OBJ reader opens "mtllib NAME" as the OBJ's folder + NAME and reads it line by
// line to its end: a FIFO there blocks forever and a device such as /dev/zero never ends.
// `name` is the rest of the line after "mtllib", trimmed (materialLibrary).
void checkMaterialFile(const std::string& path, const std::string& name) {
    const size_t slash = path.rfind('/');
    const std::string material =
        (slash == std::string::npos ? std::string("./") : path.substr(0, slash + 1)) + name;
    std::error_code ec;
    const fs::file_status status = fs::status(material, ec);
    if (ec || !fs::exists(status) || fs::is_regular_file(status) || fs::is_directory(status))
        return;  // missing or unreadable: OpenMesh warns and goes on; a folder reads as empty
    throw SceneError("cannot load " + inQuotes(path) + ": its material library " +
                     inQuotes(material) +
                     " is not a regular file (a pipe or device would hang the reader); fix or "
                     "remove the 'mtllib' line");
}

// `rewrite` is set when OpenMesh must read the copy of rewrittenObj() instead of the file.
Survey surveyObj(const std::string& path, bool& rewrite) {
    std::ifstream in = openOrThrow(path);
    ObjLines lines(in);
    Survey s;
    s.isObj = true;
    s.surveyed = true;
    std::string line, keyword;
    uint64_t lineNo = 0;
    while (lines.next(line, lineNo)) {
        trimLine(line);
        if (line.empty() || line[0] == '#') continue;
        std::istringstream stream(line);
        stream >> keyword;
        if (keyword == "v") {
            float x, y, z;  // parsed exactly as OpenMesh parses them: operator>> into float
            stream >> x >> y >> z;
            s.vertexLineOk.push_back(!stream.fail());
        } else if (keyword == "f") {
            surveyObjFace(stream, s.vertexLineOk.size(), s, path, lineNo);
        } else if (keyword == "mtllib") {
            checkMaterialFile(path, materialLibrary(stream));
        }
    }
    rewrite = lines.rewritten();
    return s;
}

// The file's logical lines, one a line, each followed by as many empty lines as it had
// continuation lines, so that line numbers stay those of the file. Its "mtllib" lines are
// left empty: OpenMesh's reader would look for the library next to the file it read before
// (it reads a stream without knowing its folder), and octrace uses no materials.
void writeRewrittenObj(const std::string& path, std::ostream& out) {
    std::ifstream in = openOrThrow(path);
    ObjLines lines(in);
    std::string line, keyword;
    uint64_t lineNo = 0;
    while (lines.next(line, lineNo)) {
        std::istringstream stream(line);
        if (!(stream >> keyword && keyword == "mtllib")) out << line;
        out << std::string(size_t(lines.lastLineNo() - lineNo + 1), '\n');
    }
}

}  // namespace

Scene loadObjWithOpenMesh(const std::string& path) {
    bool rewrite = false;
    Survey survey = surveyObj(path, rewrite);
    if (!rewrite)
        return buildMeshScene(path, "obj", readWithOpenMesh(path, "OBJ"), std::move(survey));
    std::stringstream copy;
    writeRewrittenObj(path, copy);
    return buildMeshScene(path, "obj", readWithOpenMesh(copy, "obj", path, "OBJ"),
                          std::move(survey));
}

// The fast reader takes the files it reads exactly as the reference path would; it hands the
// others (continued lines, unparsable numbers, odd corners: docs/ROBUSTNESS.md) to that path.
Scene loadObj(const std::string& path, const LoadOptions&) {
    RawMesh raw;
    Survey survey;
    std::vector<std::string> materialLibraries;
    if (!readObjFast(path, raw, survey, materialLibraries)) return loadObjWithOpenMesh(path);
    for (const std::string& name : materialLibraries) checkMaterialFile(path, name);
    return buildMeshScene(path, "obj", raw, std::move(survey));
}

}  // namespace oct::scene_detail
