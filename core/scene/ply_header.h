// The header of a PLY file (Greg Turk's PLY format, as read by OpenMesh 9.0's PLY reader):
// its elements and properties, and the parser that reads it the way that reader does.
//
// OpenMesh's PLY reader parses the header token by token with operator>> and loops until it
// reads "end_header": a header that ends early, or a token its number parser rejects, makes
// that loop spin forever; a "property" before any "element" dereferences an empty vector. It
// then reads each property as its name and type dictate, and a type it cannot read there is
// read as zero bytes, shifting every later value. The header is therefore parsed here exactly
// as that reader parses it (same stream operations on the same bytes), and everything it would
// hang on, crash on or misread is refused before it runs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace oct::scene_detail {

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64, None };

size_t plyTypeBytes(PlyType t);
bool plyIsFloat(PlyType t);

// How OpenMesh's reader consumes one property.
enum class PlyRead : uint8_t {
    Float,    // coordinates, normals, texture coordinates, float colours: `>> float`/readValue
    Int,      // colours of any other type: `>> int` / readInteger
    Skip,     // everything else: `>> std::string` / skip the type's bytes
    Indices,  // the face's vertex_indices list
    Other,    // another list of the face: checked here, never handed to OpenMesh
};

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::None;       // the value's type (a list's entry type)
    PlyType countType = PlyType::None;  // a list's length type; None when not a list
    PlyRead read = PlyRead::Skip;
    // Its declaration's bytes in the header, from the blank before "property" to the end of
    // its name: what a rewritten header leaves out.
    uint64_t declarationStart = 0, declarationEnd = 0;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    bool ascii = true;
    bool bigEndian = false;
    std::vector<PlyElement> elements;
    uint64_t dataStart = 0;  // byte offset of the body
    uint64_t headerLines = 0;
    uint64_t bomBytes = 0;  // a UTF-8 byte-order mark before "ply": 3, else 0
    // OpenMesh's reader would misread the file as it is (a byte-order mark, a face list other
    // than vertex_indices, a face property before it): it reads a rewritten copy instead, whose
    // faces hold only their vertex_indices (format_ply.cpp).
    bool rewriteForOpenMesh = false;
};

// Bytes of one item of an element without lists (the face's index list counted as its length).
uint64_t plyMinItemBytes(const PlyElement& e);

// Parses the header of the PLY file at `path` with the same stream operations on the same
// bytes as OpenMesh's reader, and refuses (SceneError) every header that reader would hang on,
// crash on or misread. ASCII bodies start at dataStart; so do binary ones, which is checked
// against where OpenMesh would start reading them.
PlyHeader parsePlyHeader(const std::string& path);

}  // namespace oct::scene_detail
