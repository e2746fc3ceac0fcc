// Readers of a scene file's body after its header, shared by the PLY and OFF loaders: the check
// of a declared count against the file's bytes, a buffered binary reader, and the ASCII walker
// that checks every value the way OpenMesh's reader would parse it.
#pragma once

#include <cstdint>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace oct::scene_detail {

// Declared counts against the file's bytes. Every count a header declares is checked against
// what the rest of the file could possibly hold before any reader runs (and so before anything
// is sized from it): an element that needs at least `minBytes` bytes cannot occur more than
// `available / minBytes` times. Overflow-safe: it divides instead of multiplying. On success
// the bytes those items need are taken off `available`.
[[noreturn]] void refuseCount(const std::string& path, uint64_t count, const std::string& what,
                              uint64_t available, uint64_t minBytes);
void checkCountFits(const std::string& path, uint64_t count, const std::string& what,
                    uint64_t& available, uint64_t minBytes);

// Buffered forward reader over a binary body; read() and skip() return false at the end.
class ByteReader {
public:
    ByteReader(const std::string& path, uint64_t start);
    bool read(void* out, size_t n);
    bool skip(uint64_t n);
    bool copy(uint64_t n, std::ostream& out);  // read() n bytes into out
    uint64_t position() const { return pos_; }

private:
    bool fill(size_t n);

    std::ifstream in_;
    std::vector<char> buffer_;
    size_t head_ = 0;
    uint64_t pos_;
};

// How an ASCII body is read, and what a refused value's message says.
struct AsciiSyntax {
    std::string reader;         // who needs the value: "OpenMesh's ASCII PLY reader"
    std::string refusalNote;    // why such a value is refused, appended to the message
    bool hashComments = false;  // '#' starts a comment that runs to the end of the line
};

// Walks the body of an ASCII PLY or OFF file token by token and checks every value: it must be
// a number of the kind read there (an integer where an int is read, within 32 bits), and the
// file must hold every declared element. For PLY it checks what OpenMesh's reader, which then
// reads the file, does not: after a token it cannot parse (nan, inf, 1e39, 0x10, a '#'
// comment), or at the end of a short file, its stream fails and every later value silently
// repeats the last one read; a truncated face list ends in copies of its last face. For OFF,
// which octrace reads itself, it is the reader. Such files are refused, naming the line.
class AsciiBody {
public:
    AsciiBody(std::istream& in, uint64_t linesBefore, const std::string& path, AsciiSyntax syntax)
        : in_(in), lineNo_(linesBefore), path_(path), syntax_(std::move(syntax)) {}

    // A value read with `>> float`: only the characters that parser accepts, all of them
    // consumed, finite and within float range (it fails on overflow). Returns what `>> float`
    // gives (strtof).
    float number();
    // A value read with `>> int` (signedInt) or `>> unsigned int`: decimal digits with an
    // optional sign, within what that type's parser accepts.
    long long integer(bool signedInt = false);
    // A list length read with `>> unsigned int`: OpenMesh would take -1 as about 4 billion.
    uint64_t count();
    void anyToken() { next(); }  // read with `>> std::string`: anything goes
    void skipRestOfLine() {
        line_.str(std::string());
        line_.clear();
    }
    // The tokens left on the current line, up to a comment; the line is done after it.
    std::vector<std::string> restOfLine();
    // Makes `text` the rest of the current line (the header line of an OFF file, whose counts
    // may follow the keyword).
    void setRestOfLine(const std::string& text);
    uint64_t lineNo() const { return lineNo_; }
    // Writes every token read from now on, each followed by a space, to *out (nullptr: none).
    void echoTo(std::ostream* out) { echo_ = out; }

private:
    std::string next();
    [[noreturn]] void refuse(const std::string& token, const char* expected) const;

    std::istream& in_;
    uint64_t lineNo_;
    std::istringstream line_;
    std::string path_;
    AsciiSyntax syntax_;
    std::ostream* echo_ = nullptr;
};

}  // namespace oct::scene_detail
