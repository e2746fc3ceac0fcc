// Reading a text scene file at speed: the whole file in one read, split into line-aligned
// chunks that OpenMP threads parse at once, and the number parsers those chunks use. The
// fast readers built on these (obj_fast_reader.cpp, ply_fast_reader.cpp) accept only input
// whose every value parses here exactly as the reference path parses it, and hand everything
// else back to that path (loader_detail.h).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace oct::scene_detail {

// A file's bytes, read at once into an uninitialised buffer on huge pages (adviseHugePages),
// with openOrThrow's error when it cannot be opened. Not mapped: a file truncated by someone
// else while mapped would end the process with SIGBUS, and octrace answers every input with a
// line, never a signal.
class FileText {
public:
    explicit FileText(const std::string& path);
    std::string_view text() const { return {bytes_.get(), size_}; }

private:
    struct Free {
        void operator()(char* p) const { std::free(p); }
    };
    std::unique_ptr<char[], Free> bytes_;
    size_t size_ = 0;
};

// [begin, end) offsets of `pieces` chunks of text[from..] that each end after a '\n' (the last
// one at the end of the text); fewer when the text is short. Empty chunks are left out.
std::vector<std::pair<size_t, size_t>> lineAlignedChunks(std::string_view text, size_t from,
                                                         size_t pieces);

// The blanks std::isspace knows in the C locale (operator>> stops at them)...
inline bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}
// ... and the ones OpenMesh's trimString and octrace's trimLine remove from a line's ends.
inline bool isTrimmed(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// The next blank-separated token of [p, end), advancing p past it; empty at the end.
inline std::string_view nextToken(const char*& p, const char* end) {
    while (p < end && isBlank(*p)) ++p;
    const char* start = p;
    while (p < end && !isBlank(*p)) ++p;
    return {start, size_t(p - start)};
}

// A token that `>> float` (libstdc++'s num_get, then strtof) reads whole and to this value:
// only the characters of a decimal number, all consumed by from_chars, in float's range.
// from_chars rounds correctly to nearest, as strtof does, so the values are the same bits.
// false for anything else (inf, nan, hex, garbage, overflow, a trailing word): the caller then
// leaves the file to the reference path, which decides what such a value means.
inline bool plainFloat(std::string_view token, float& value) {
    if (token.empty()) return false;
    for (char c : token)
        if (!((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-'))
            return false;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && ptr == token.data() + token.size();
}

// A token that `>> int` reads whole: an optional '-' and decimal digits within int's range.
inline bool plainInt(std::string_view token, int& value) {
    if (token.empty()) return false;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && ptr == token.data() + token.size();
}

}  // namespace oct::scene_detail
