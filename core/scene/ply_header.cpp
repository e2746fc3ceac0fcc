// The PLY header parser of ply_header.h.
#include "core/scene/ply_header.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <utility>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {
namespace {

// OpenMesh's get_property_type: the first of these names found in either token wins.
PlyType plyTypeOf(const std::string& a, const std::string& b) {
    static const std::pair<const char*, PlyType> kNames[] = {
        {"float32", PlyType::Float32}, {"float64", PlyType::Float64}, {"float", PlyType::Float32},
        {"double", PlyType::Float64},  {"int8", PlyType::Int8},       {"uint8", PlyType::UInt8},
        {"char", PlyType::Int8},       {"uchar", PlyType::UInt8},     {"int32", PlyType::Int32},
        {"uint32", PlyType::UInt32},   {"int", PlyType::Int32},       {"uint", PlyType::UInt32},
        {"int16", PlyType::Int16},     {"uint16", PlyType::UInt16},   {"short", PlyType::Int16},
        {"ushort", PlyType::UInt16}};
    for (const auto& [name, type] : kNames)
        if (a == name || b == name) return type;
    return PlyType::None;
}

PlyRead plyReadOf(const std::string& element, const std::string& name, PlyType type) {
    static const char* kVertexFloats[] = {"x", "y", "z", "nx", "ny", "nz", "u", "s", "v", "t"};
    static const char* kColours[] = {"red",         "green",         "blue",        "alpha",
                                     "diffuse_red", "diffuse_green", "diffuse_blue"};
    const bool isVertex = element == "vertex", isFace = element == "face";
    if (isVertex)
        for (const char* n : kVertexFloats)
            if (name == n) return PlyRead::Float;
    for (size_t i = 0; i < std::size(kColours); ++i)
        if (name == kColours[i] && (isVertex || (isFace && i < 4)))
            return type == PlyType::Float32 ? PlyRead::Float : PlyRead::Int;
    return PlyRead::Skip;
}

class PlyHeaderParser {
public:
    explicit PlyHeaderParser(const std::string& path)
        : path_(path), in_(openOrThrow(path, std::ios::in | std::ios::binary)) {}

    PlyHeader parse() {
        std::string first;
        std::getline(in_, first);
        PlyHeader h;
        h.bomBytes = stripUtf8Bom(first);
        h.rewriteForOpenMesh = h.bomBytes > 0;  // its reader would not find "ply"
        trimLine(first);
        if (first != "ply" && first != "PLY")
            refuse("its first line is not 'ply'; check that it is a PLY file");
        std::string keyword = token("the format line"), format = token("the format line");
        if (keyword != "format")
            refuse(
                "its second line must be 'format ascii|binary_little_endian|"
                "binary_big_endian 1.0'");
        if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
            refuse("format " + inQuotes(format) +
                   " is not ascii, binary_little_endian or binary_big_endian");
        h.ascii = format == "ascii";
        h.bigEndian = format == "binary_big_endian";
        const std::string version = token("the format line");
        if (!isStrictNumber(version))
            refuse("its format version " + inQuotes(version) + " is not a number");
        std::streamoff beforeKeyword = in_.tellg();
        for (keyword = token("an 'end_header' line"); keyword != "end_header";
             keyword = token("an 'end_header' line")) {
            if (keyword == "comment") {
                std::string rest;
                std::getline(in_, rest);
            } else if (keyword == "element") {
                addElement(h);
            } else if (keyword == "property") {
                addProperty(h, uint64_t(beforeKeyword));
            }  // any other token is skipped alone, as OpenMesh skips it
            beforeKeyword = in_.tellg();
        }
        checkElements(h);
        findBody(h, beforeKeyword);
        return h;
    }

private:
    static bool isStrictNumber(const std::string& s) {
        char* end = nullptr;
        std::strtod(s.c_str(), &end);
        return !s.empty() && s.find_first_not_of("0123456789+-.eE") == std::string::npos &&
               *end == '\0';
    }

    std::string token(const char* what) {
        std::string t;
        if (!(in_ >> t))
            refuse(std::string("the header ends before ") + what +
                   " (OpenMesh's reader would loop forever); check that it is a PLY file");
        return t;
    }

    void addElement(PlyHeader& h) {
        PlyElement e;
        e.name = token("the element's name");
        const std::string count = token("the element's count");
        errno = 0;
        const unsigned long long value = std::strtoull(count.c_str(), nullptr, 10);
        if (count.find_first_not_of("0123456789") != std::string::npos || count.size() > 10 ||
            errno != 0 || value > UINT32_MAX)
            refuse("element " + inQuotes(e.name) + " has count " + inQuotes(count) +
                   ", not a whole number from 0 to 4294967295");
        e.count = value;
        for (const PlyElement& other : h.elements)
            if (other.name == e.name && (e.name == "vertex" || e.name == "face"))
                refuse("it declares element " + inQuotes(e.name) + " twice");
        h.elements.push_back(e);
    }

    void addProperty(PlyHeader& h, uint64_t declarationStart) {
        if (h.elements.empty())
            refuse("a 'property' comes before any 'element' (OpenMesh's reader would crash)");
        PlyElement& e = h.elements.back();
        PlyProperty p;
        const std::string first = token("the property's type");
        if (first == "list") {
            const std::string countType = token("the list's count type");
            const std::string entryType = token("the list's entry type");
            p.name = token("the list's name");
            if (e.name != "face")
                refuse("list property " + inQuotes(p.name) + " of element " + inQuotes(e.name) +
                       " is not supported by OpenMesh's PLY reader; remove it from the file");
            if (p.name != "vertex_indices" && p.name != "vertex_index") {
                addOtherFaceList(h, p, countType, entryType);
            } else {
                addIndexList(h, p, countType, entryType);
            }
        } else {
            const std::string second = token("the property's name");
            p.type = plyTypeOf(first, second);
            if (p.type == PlyType::None)
                refuse("property " + inQuotes(first + " " + second) + " of element " +
                       inQuotes(e.name) + " has no type OpenMesh knows (e.g. float, uchar, int)");
            p.name = plyTypeOf(first, first) != PlyType::None ? second : first;
            p.read = plyReadOf(e.name, p.name, p.type);
        }
        p.declarationStart = declarationStart;
        p.declarationEnd = uint64_t(in_.tellg());
        e.properties.push_back(p);
    }

    // A face's list of vertex indices: what OpenMesh reads, so only the types it reads.
    // OpenMesh forgets the face properties declared before it ("Custom face Properties defined,
    // before 'vertex_indices' property was defined. They will be skipped") but not their
    // values, which it then reads as the list: such a file is rewritten without them.
    void addIndexList(PlyHeader& h, PlyProperty& p, const std::string& countType,
                      const std::string& entryType) {
        PlyElement& e = h.elements.back();
        if (countType != "uint8" && countType != "uchar" && countType != "uint16" &&
            countType != "int")
            refuse("the count type " + inQuotes(countType) + " of list " + inQuotes(p.name) +
                   " is not one OpenMesh reads (uchar, uint8, uint16, int)");
        p.countType = plyTypeOf(countType, countType);
        p.type = plyTypeOf(entryType, entryType);
        if (p.type == PlyType::None || plyIsFloat(p.type))
            refuse("the entry type " + inQuotes(entryType) + " of list " + inQuotes(p.name) +
                   " is not an integer type");
        p.read = PlyRead::Indices;
        for (const PlyProperty& other : e.properties)
            if (other.read == PlyRead::Indices) refuse("element 'face' has two index lists");
        if (!e.properties.empty()) h.rewriteForOpenMesh = true;
    }

    // Any other list of a face (texture coordinates, as MeshLab and Blender write them): octrace
    // does not use it, and OpenMesh's reader cannot skip it (it reads one value for the whole
    // list, or refuses the header for some count types), so it is checked here and left out of
    // what OpenMesh reads.
    void addOtherFaceList(PlyHeader& h, PlyProperty& p, const std::string& countType,
                          const std::string& entryType) {
        p.countType = plyTypeOf(countType, countType);
        if (p.countType == PlyType::None || plyIsFloat(p.countType))
            refuse("the count type " + inQuotes(countType) + " of list " + inQuotes(p.name) +
                   " is not an integer type");
        p.type = plyTypeOf(entryType, entryType);
        if (p.type == PlyType::None)
            refuse("the entry type " + inQuotes(entryType) + " of list " + inQuotes(p.name) +
                   " is not a PLY type (e.g. float, uchar, int)");
        p.read = PlyRead::Other;
        h.rewriteForOpenMesh = true;
    }

    void checkElements(const PlyHeader& h) {
        const PlyElement* vertex = nullptr;
        for (const PlyElement& e : h.elements) {
            if (e.name == "vertex") vertex = &e;
            if (e.count > 0 && e.properties.empty())
                refuse("element " + inQuotes(e.name) + " declares " + std::to_string(e.count) +
                       " items but no properties");
            if (e.name == "face" && e.count > 0 &&
                std::none_of(e.properties.begin(), e.properties.end(),
                             [](const PlyProperty& p) { return p.read == PlyRead::Indices; }))
                refuse("element 'face' has no 'vertex_indices' list");
            if (e.name == "face") break;  // OpenMesh reads nothing after the faces
        }
        int axes[3] = {0, 0, 0};
        if (vertex)
            for (const PlyProperty& p : vertex->properties)
                for (int a = 0; a < 3; ++a) axes[a] += p.name == std::string(1, char('x' + a));
        if (!vertex || axes[0] != 1 || axes[1] != 1 || axes[2] != 1)
            refuse(
                "it needs an 'element vertex', before any 'element face', with one each of "
                "the properties x, y and z");
        if (h.ascii) return;
        // Binary bodies: OpenMesh reads these properties only from the types named here and
        // reads any other type as zero bytes.
        for (const PlyElement& e : h.elements)
            for (const PlyProperty& p : e.properties) {
                const bool ok = p.read == PlyRead::Float ? plyIsFloat(p.type)
                                : p.read == PlyRead::Int ? !plyIsFloat(p.type)
                                                         : true;
                if (!ok)
                    refuse("property " + inQuotes(p.name) + " of element " + inQuotes(e.name) +
                           " has a type OpenMesh's binary reader cannot read there (it would "
                           "misread every later value); use " +
                           (p.read == PlyRead::Float ? "float or double" : "an integer type"));
            }
    }

    // OpenMesh starts a binary body 12 bytes (14 after "\r\n") past the end of the token
    // before "end_header", which is right only when exactly one line break separates them
    // and one line break follows end_header. A comment line or trailing blanks before it put
    // every value a few bytes off.
    void findBody(PlyHeader& h, std::streamoff beforeKeyword) {
        std::streamoff afterKeyword = in_.tellg();
        if (afterKeyword < 0) {  // "end_header" is the file's last token
            in_.clear();
            afterKeyword = std::streamoff(fileSize(path_));
        }
        std::string rest;
        std::getline(in_, rest);
        const std::streamoff nextLine = in_.tellg();
        h.dataStart = nextLine < 0 ? fileSize(path_) : uint64_t(nextLine);
        in_.clear();
        std::string headerText(size_t(afterKeyword), '\0');
        in_.seekg(0);
        in_.read(headerText.data(), afterKeyword);
        h.headerLines = uint64_t(std::count(headerText.begin(), headerText.end(), '\n')) + 1;
        if (h.ascii) {
            trimLine(rest);
            if (!rest.empty()) refuse("values follow 'end_header' on its line");
            in_.clear();
            in_.seekg(std::streamoff(h.dataStart));
            return;
        }
        const char c1 = headerText[size_t(beforeKeyword)];
        const char c2 = size_t(beforeKeyword) + 1 < headerText.size()
                            ? headerText[size_t(beforeKeyword) + 1]
                            : '\0';
        const uint64_t openMeshStart =
            uint64_t(beforeKeyword) + (c1 == '\r' && c2 == '\n' ? 14 : 12);
        if ((rest != "" && rest != "\r") || openMeshStart != h.dataStart)
            refuse("OpenMesh's binary PLY reader would start reading the data at byte " +
                   std::to_string(openMeshStart) + " instead of " + std::to_string(h.dataStart) +
                   " (a comment or blanks just before 'end_header', or after it); put "
                   "'end_header' on its own line right after the last property");
    }

    [[noreturn]] void refuse(const std::string& why) const {
        throw SceneError("cannot read " + inQuotes(path_) + " as PLY: " + why);
    }

    std::string path_;
    std::ifstream in_;
};

}  // namespace

size_t plyTypeBytes(PlyType t) {
    switch (t) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
        default:
            return 0;
    }
}

bool plyIsFloat(PlyType t) { return t == PlyType::Float32 || t == PlyType::Float64; }

// Bytes of one item of an element without lists (a face's lists counted as their lengths).
uint64_t plyMinItemBytes(const PlyElement& e) {
    uint64_t bytes = 0;
    for (const PlyProperty& p : e.properties)
        bytes += plyTypeBytes(p.countType != PlyType::None ? p.countType : p.type);
    return bytes;
}

PlyHeader parsePlyHeader(const std::string& path) { return PlyHeaderParser(path).parse(); }

}  // namespace oct::scene_detail
