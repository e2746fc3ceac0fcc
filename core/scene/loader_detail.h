// Internal to the scene loader: what its files (load_scene.cpp, the format_*.cpp loaders and
// their helpers) share. Not octrace's interface; that is load_scene.h and scene_formats.h.
//
// How an OBJ, PLY or STL mesh is loaded (OFF and XYZ are read by their loaders themselves):
// OpenMesh's reader hands everything over to RawMeshImporter (openmesh_reader.cpp), which
// records it without building a halfedge mesh (an OpenMesh mesh would reject non-manifold
// faces). Because OpenMesh's readers silently skip or misread some input before any importer
// sees it, each format is first surveyed by its loader: the survey counts the file's faces,
// predicts which of them the reader will hand over (so sourceFace stays a file face index and
// the skipped ones are counted), and refuses, with a SceneError, input that a reader would
// silently misread, hang on, crash or abort on, or size from an impossible header count
// (body_readers.h). Valid input the reader would misread as it is (a byte-order mark, OBJ line
// continuations, some PLY face properties) is handed to it as a rewritten copy instead.
// Plain OBJ files and plain ASCII PLY bodies skip all of that: octrace's fast readers
// (obj_fast_reader.cpp, ply_fast_reader.cpp) parse them once, in parallel, into the same
// RawMesh (and Survey) and leave every other file to the path above.
// docs/ROBUSTNESS.md lists the cases; tests/data/bad/ holds one malformed file for each,
// tests/data/odd/ the odd but valid ones, and fuzz/ fuzzes this whole path.
#pragma once

#include <cstdint>
#include <fstream>
#include <istream>
#include <string>
#include <vector>

#include "core/scene/load_scene.h"
#include "core/scene/scene.h"
#include "core/system/resources.h"

namespace oct::scene_detail {

// ---------------------------------------------------------------------------------------------
// Small helpers (loader_detail.cpp)

std::string inQuotes(const std::string& s);
std::string toLower(std::string s);
std::string lowerExtension(const std::string& path);  // "" when the path has none
void trimLine(std::string& s);                        // the same trim as OpenMesh's OBJ/STL readers
std::ifstream openOrThrow(const std::string& path, std::ios::openmode mode = std::ios::in);
uint64_t fileSize(const std::string& path);
// "a, b or c" for lastJoin " or ": the help text's and messages' lists.
std::string joinList(const std::vector<std::string>& items, const std::string& lastJoin);

// Text files may begin with a UTF-8 byte-order mark (Windows editors write one). It is not
// part of the first line's text: stripUtf8Bom removes it from the start of `firstLine` and
// returns how many bytes it removed (3 or 0).
constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";
size_t stripUtf8Bom(std::string& firstLine);

// ---------------------------------------------------------------------------------------------
// What OpenMesh's reader hands over, recorded without interpretation (openmesh_reader.cpp).

struct RawMesh {
    std::vector<Vec3> vertices;
    std::vector<int> faceIndices;         // all faces' vertex indices, as the reader gave them
    std::vector<size_t> faceStart = {0};  // face f is faceIndices[faceStart[f], faceStart[f+1])
    size_t faceCount() const { return faceStart.size() - 1; }
};

// Reads `path` with OpenMesh's reader for its extension; `format` names it in messages. Reads
// are serialised (OpenMesh's readers are process-wide singletons with per-read state) and the
// reader's console output is captured into the SceneError of a failed read.
RawMesh readWithOpenMesh(const std::string& path, const std::string& format);
// The same from a stream holding the file's bytes as the reader for `extension` should see them
// (a copy rewritten where the file itself would be misread); `path` names it in messages. The
// stream must be seekable: OpenMesh's OBJ and PLY readers seek in it.
RawMesh readWithOpenMesh(std::istream& in, const std::string& extension, const std::string& path,
                         const std::string& format);

// ---------------------------------------------------------------------------------------------
// Surveys: what the file holds and which faces OpenMesh's reader will hand over.

struct Survey {
    bool surveyed = false;  // facesInFile and handedOver are known (OBJ, STL); PLY and OFF
                            // readers hand over every face, which the header count checks
    uint64_t facesInFile = 0;
    std::vector<uint32_t> handedOver;  // file face index of each face the reader hands over
    uint64_t skippedTooFew = 0;        // faces the reader skipped: fewer than 3 vertices
    uint64_t skippedDegenerate = 0;    // faces the reader skipped: repeated vertices
    uint64_t skippedInvalidIndex = 0;  // faces the reader skipped: an index beyond int range
    // OBJ: per handed-over face, whether the reader silently left out a corner whose index
    // does not fit an int (it hands over the rest): such a face is dropped as an invalid index.
    std::vector<bool> lostCorner;
    // OBJ: OpenMesh drops a "v" line whose coordinates do not parse (nan, inf, overflow, garbage)
    // while face indices still count it, so later vertices shift. One flag per "v" line lets the
    // file's vertex numbers be mapped back to the reader's.
    bool isObj = false;
    std::vector<bool> vertexLineOk;
};

// Element counts a PLY or OFF header declares.
struct ElementCounts {
    uint64_t vertices = 0;
    uint64_t faces = 0;
};

// ---------------------------------------------------------------------------------------------
// Scenes from what was read (mesh_scene.cpp, point_scene.cpp)

// PLY and OFF readers hand over every face; fewer than declared means a truncated file.
void checkDeclaredCounts(const std::string& path, const ElementCounts& declared,
                         const RawMesh& raw);

// Triangles in file face order (polygons fanned), every unusable face dropped and counted;
// a SceneError when none is left.
Scene buildMeshScene(const std::string& path, const std::string& format, const RawMesh& raw,
                     Survey survey);

// Exact zero-area test: the edges' cross product in double is the zero vector.
bool isDegenerate(const Triangle& t);

// The finite points; the others counted in report.droppedNonFinite.
std::vector<Vec3> finitePoints(const std::vector<Vec3>& points, LoadReport& report);

// One sphere per point, of radius opts.radius or defaultPointRadius(); a SceneError when there
// is no point.
Scene sphereScene(const std::string& path, const std::vector<Vec3>& points, LoadReport report,
                  const LoadOptions& opts);

// ---------------------------------------------------------------------------------------------
// One loader per format (format_*.cpp), each listed once in scene_formats.cpp.

Scene loadObj(const std::string& path, const LoadOptions& opts);
// OBJ's two readers. readObjFast reads the whole file once, in parallel chunks, into the RawMesh
// and Survey the reference path would produce, and lists its "mtllib" names; it returns false,
// having decided nothing, for a file outside the plain part of the format it takes
// (obj_fast_reader.cpp). loadObjWithOpenMesh is the reference path: survey, then OpenMesh's
// reader (format_obj.cpp). loadObj tries the first and falls back to the second.
bool readObjFast(const std::string& path, RawMesh& raw, Survey& survey,
                 std::vector<std::string>& materialLibraries);
Scene loadObjWithOpenMesh(const std::string& path);
Scene loadPly(const std::string& path, const LoadOptions& opts);
// PLY's two body readers, after the same header parse and count checks: readPlyFast reads a
// plain ASCII body in parallel chunks into the RawMesh OpenMesh's reader would hand over, or
// returns false, having decided nothing (ply_fast_reader.cpp); loadPlyWithOpenMesh loads with
// the reference path only (format_ply.cpp). loadPly tries the first and falls back.
struct PlyHeader;
bool readPlyFast(const std::string& path, const PlyHeader& header, RawMesh& raw);
Scene loadPlyWithOpenMesh(const std::string& path, const LoadOptions& opts);
Scene loadOff(const std::string& path, const LoadOptions& opts);
Scene loadStl(const std::string& path, const LoadOptions& opts);
Scene loadXyz(const std::string& path, const LoadOptions& opts);

}  // namespace oct::scene_detail
