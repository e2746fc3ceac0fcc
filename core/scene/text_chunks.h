// Reading a text scene file at speed: the whole file in one read, split into line-aligned
// chunks that OpenMP threads parse at once, and the number parsers those chunks use. The
// fast readers built on these (obj_fast_reader.cpp, ply_fast_reader.cpp) accept only input
// whose every value parses here exactly as the reference path parses it, and hand everything
// else back to that path (loader_detail.h).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/system/resources.h"

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
    HugeArray<char> bytes_;
    size_t size_ = 0;
};

// [begin, end) offsets of the chunks of text[from..] that the threads parse: four a thread, so
// that a chunk of slow lines does not hold the others up, each ending after a '\n' (the last
// one at the end of the text); fewer when the text is short (at least 4 KiB each).
std::vector<std::pair<size_t, size_t>> lineAlignedChunks(std::string_view text, size_t from);

// Runs body(i) for every chunk i in [0, count) on OpenMP threads. An exception must not leave a
// parallel region (the process would end in std::terminate, not in a SceneError naming the
// file: a std::bad_alloc while parsing becomes "out of memory while loading ..." in loadScene),
// so the first one thrown is caught there and rethrown after the loop.
template <class Body>
void forEachChunk(size_t count, const Body& body) {
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t i = 0; i < int64_t(count); ++i) {
        try {
            body(size_t(i));
        } catch (...) {
#pragma omp critical(oct_for_each_chunk)
            if (!error) error = std::current_exception();
        }
    }
    if (error) std::rethrow_exception(error);
}

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
