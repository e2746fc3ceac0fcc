#include "core/io/npy.h"

#include <cstring>
#include <limits>
#include <map>
#include <sstream>

#include "core/io/input_file.h"

namespace oct {

uint64_t NpyArray::elementCount() const {
    uint64_t n = 1;
    for (uint64_t d : shape) n *= d;
    return n;
}

namespace {

size_t descrSize(const std::string& d) {
    if (d == "<f4" || d == "<i4" || d == "<u4") return 4;
    if (d == "|u1" || d == "<u1") return 1;
    if (d == "<f8" || d == "<i8" || d == "<u8") return 8;
    return 0;
}

std::string headerFor(const std::string& descr, const std::vector<uint64_t>& shape) {
    std::ostringstream h;
    h << "{'descr': '" << descr << "', 'fortran_order': False, 'shape': (";
    for (size_t i = 0; i < shape.size(); ++i) h << (i ? ", " : "") << shape[i];
    if (shape.size() == 1) h << ",";  // a Python 1-tuple
    h << "), }";
    std::string s = h.str();
    size_t total = 10 + s.size() + 1;  // magic(6) + version(2) + len(2) + dict + '\n'
    s.append((64 - total % 64) % 64, ' ');
    s.push_back('\n');
    return s;
}

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

// Version 1.0 layout: magic "\x93NUMPY", major 1, minor 0, header length (uint16 LE), the
// header (padded so data starts at a multiple of 64), then the raw little-endian data. Returns
// the header and checks the element size.
std::string checkedHeader(const std::string& descr, const std::vector<uint64_t>& shape,
                          size_t elementSize, size_t& dataBytes) {
    if (descrSize(descr) != elementSize)
        throw IoError("internal: .npy dtype " + descr + " does not match element size");
    uint64_t count = 1;
    for (uint64_t d : shape) count *= d;
    dataBytes = count * elementSize;
    return headerFor(descr, shape);
}

void writePreamble(uint8_t* out, const std::string& header) {
    std::memcpy(out, "\x93NUMPY\x01\x00", 8);
    out[8] = uint8_t(header.size() & 0xff);
    out[9] = uint8_t(header.size() >> 8);
    std::memcpy(out + 10, header.data(), header.size());
}

}  // namespace

NpyBuffer::NpyBuffer(const std::string& descr, const std::vector<uint64_t>& shape,
                     size_t elementSize) {
    size_t dataBytes = 0;
    const std::string header = checkedHeader(descr, shape, elementSize, dataBytes);
    dataOffset_ = 10 + header.size();
    size_ = dataOffset_ + dataBytes;
    bytes_ = makeHugeArray<uint8_t>(size_);  // not zeroed: the tracer writes every element
    writePreamble(bytes_.get(), header);
}

std::vector<uint8_t> encodeNpy(const std::string& descr, const std::vector<uint64_t>& shape,
                               const void* data, size_t elementSize) {
    size_t dataBytes = 0;
    const std::string header = checkedHeader(descr, shape, elementSize, dataBytes);
    // Sized once and filled with memcpy (gcc 12 misreads a chain of vector::insert calls here
    // as an overflow).
    std::vector<uint8_t> bytes(10 + header.size() + dataBytes);
    writePreamble(bytes.data(), header);
    if (dataBytes) std::memcpy(bytes.data() + 10 + header.size(), data, dataBytes);
    return bytes;
}

void stageNpy(OutputSet& out, const std::string& path, const std::string& descr,
              const std::vector<uint64_t>& shape, const void* data, size_t elementSize) {
    size_t dataBytes = 0;
    const std::string header = checkedHeader(descr, shape, elementSize, dataBytes);
    std::vector<uint8_t> preamble(10 + header.size());
    writePreamble(preamble.data(), header);
    out.stage(path, {{preamble.data(), preamble.size()}, {data, dataBytes}});
}

void writeNpy(const std::string& path, const std::string& descr, const std::vector<uint64_t>& shape,
              const void* data, size_t elementSize) {
    OutputSet out;
    stageNpy(out, path, descr, shape, data, elementSize);
    out.commit();
}

std::string npyShapeText(const std::vector<uint64_t>& shape) {
    std::string s = "(";
    for (size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

NpyHeader readNpyHeader(InputFile& in, const std::string& path) {
    const uint64_t fileSize = in.size();
    // Preamble: magic "\x93NUMPY", major, minor, header length (uint16 LE in 1.0, uint32 LE in
    // 2.0 and 3.0), then the header, then the data.
    unsigned char pre[12];
    if (fileSize < 10) bad(path, "shorter than the 10-byte preamble");
    in.readExactly(pre, 10);
    if (std::memcmp(pre, "\x93NUMPY", 6) != 0) bad(path, "missing the \\x93NUMPY magic");
    const int major = pre[6];
    uint64_t headerLen = pre[8] | uint64_t(pre[9]) << 8;
    NpyHeader h;
    h.dataStart = 10;
    if (major == 2 || major == 3) {
        if (fileSize < 12) bad(path, "shorter than its preamble");
        in.readExactly(pre + 10, 2);
        headerLen |= uint64_t(pre[10]) << 16 | uint64_t(pre[11]) << 24;
        h.dataStart = 12;
    } else if (major != 1) {
        bad(path, "unsupported format version " + std::to_string(major));
    }
    if (headerLen > fileSize - h.dataStart) bad(path, "header runs past the end of the file");
    std::string header(headerLen, '\0');
    in.readExactly(&header[0], header.size());
    h.dataStart += headerLen;

    std::map<std::string, std::string> dict = parseHeader(header, path);
    for (const char* key : {"descr", "fortran_order", "shape"})
        if (!dict.count(key)) bad(path, std::string("header has no '") + key + "'");
    if (dict["fortran_order"] != "False")
        bad(path, "Fortran-ordered arrays are not supported; save with numpy.ascontiguousarray");
    h.descr = dict["descr"];
    h.shape = parseShape(dict["shape"], path);
    return h;
}

NpyArray readNpy(const std::string& path, const std::string& what,
                 const std::function<void(const NpyArray&)>& check) {
    InputFile in(path, what);
    const uint64_t fileSize = in.size();
    const NpyHeader h = readNpyHeader(in, path);
    NpyArray a;
    a.descr = h.descr;
    a.shape = h.shape;
    size_t elem = descrSize(a.descr);
    if (elem == 0) bad(path, "unsupported dtype '" + a.descr + "'");
    uint64_t count = 1;
    for (uint64_t d : a.shape) {
        if (d != 0 && count > std::numeric_limits<uint64_t>::max() / d / elem)
            bad(path, "shape is too large");
        count *= d;
    }
    uint64_t available = fileSize - h.dataStart;
    if (count * elem != available)
        bad(path, "shape needs " + std::to_string(count * elem) + " data bytes but the file has " +
                      std::to_string(available) + " (truncated or wrong header)");
    if (check) check(a);  // before the data: a wrong shape is refused unread
    a.data.resize(count * elem);
    in.readExactly(a.data.data(), a.data.size());
    if (!in.atEnd()) bad(path, "the file changed while it was read");
    return a;
}

}  // namespace oct
