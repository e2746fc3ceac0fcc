// The body readers of body_readers.h.
#include "core/scene/body_readers.h"

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "core/scene/loader_detail.h"

namespace oct::scene_detail {

void refuseCount(const std::string& path, uint64_t count, const std::string& what,
                 uint64_t available, uint64_t minBytes) {
    throw SceneError("cannot load " + inQuotes(path) + ": its header declares " +
                     std::to_string(count) + " " + what + ", but the " + std::to_string(available) +
                     " bytes after the header hold at most " +
                     std::to_string(minBytes ? available / minBytes : 0) +
                     "; the file is truncated or its header is wrong");
}

void checkCountFits(const std::string& path, uint64_t count, const std::string& what,
                    uint64_t& available, uint64_t minBytes) {
    if (minBytes == 0 || count == 0) return;
    if (count > available / minBytes) refuseCount(path, count, what, available, minBytes);
    available -= count * minBytes;
}

// ---------------------------------------------------------------------------------------------
// ByteReader

ByteReader::ByteReader(const std::string& path, uint64_t start)
    : in_(openOrThrow(path, std::ios::in | std::ios::binary)), pos_(start) {
    in_.seekg(std::streamoff(start));
}

bool ByteReader::read(void* out, size_t n) {
    if (!fill(n)) return false;
    std::memcpy(out, buffer_.data() + head_, n);
    head_ += n;
    pos_ += n;
    return true;
}

bool ByteReader::skip(uint64_t n) {
    uint64_t buffered = buffer_.size() - head_;
    if (n <= buffered) {
        head_ += size_t(n);
        pos_ += n;
        return true;
    }
    n -= buffered;
    pos_ += buffered;
    buffer_.clear();
    head_ = 0;
    in_.clear();
    in_.seekg(std::streamoff(n), std::ios::cur);
    char probe;  // seeking past the end succeeds; reading the last skipped byte does not
    in_.seekg(-1, std::ios::cur);
    if (!in_.get(probe)) return false;
    pos_ += n;
    return true;
}

bool ByteReader::copy(uint64_t n, std::ostream& out) {
    char chunk[1 << 14];
    while (n > 0) {
        const size_t k = size_t(std::min<uint64_t>(n, sizeof chunk));
        if (!read(chunk, k)) return false;
        out.write(chunk, std::streamsize(k));
        n -= k;
    }
    return true;
}

bool ByteReader::fill(size_t n) {
    if (buffer_.size() - head_ >= n) return true;
    buffer_.erase(buffer_.begin(), buffer_.begin() + std::ptrdiff_t(head_));
    head_ = 0;
    const size_t want = std::max<size_t>(n - buffer_.size(), 1 << 16);
    const size_t old = buffer_.size();
    buffer_.resize(old + want);
    in_.read(buffer_.data() + old, std::streamsize(want));
    buffer_.resize(old + size_t(in_.gcount()));
    return buffer_.size() >= n;
}

// ---------------------------------------------------------------------------------------------
// AsciiBody

float AsciiBody::number() {
    std::string token = next();
    char* end = nullptr;
    double value = std::strtod(token.c_str(), &end);
    if (token.find_first_not_of("0123456789+-.eE") != std::string::npos || *end != '\0' ||
        !std::isfinite(value) || std::fabs(value) > FLT_MAX)
        refuse(token, "a finite number");
    return std::strtof(token.c_str(), nullptr);
}

long long AsciiBody::integer(bool signedInt) {
    std::string token = next();
    char* end = nullptr;
    errno = 0;
    long long value = std::strtoll(token.c_str(), &end, 10);
    const long long lo = signedInt ? INT32_MIN : -(long long)UINT32_MAX;
    const long long hi = signedInt ? INT32_MAX : (long long)UINT32_MAX;
    if (token.empty() || *end != '\0' || errno != 0 || value < lo || value > hi)
        refuse(token, signedInt ? "a 32-bit integer" : "a 32-bit unsigned integer");
    return value;
}

uint64_t AsciiBody::count() {
    long long value = integer();
    if (value < 0) refuse(std::to_string(value), "a count >= 0");
    return uint64_t(value);
}

std::vector<std::string> AsciiBody::restOfLine() {
    std::vector<std::string> tokens;
    std::string token;
    while (line_ >> token && !(syntax_.hashComments && token[0] == '#')) tokens.push_back(token);
    skipRestOfLine();
    return tokens;
}

void AsciiBody::setRestOfLine(const std::string& text) {
    line_.str(text);
    line_.clear();
}

std::string AsciiBody::next() {
    std::string token;
    while (!(line_ >> token) || (syntax_.hashComments && token[0] == '#')) {
        std::string text;
        if (!std::getline(in_, text))
            throw SceneError("cannot load " + inQuotes(path_) + ": it ends at line " +
                             std::to_string(lineNo_) + " before all elements its header " +
                             "declares; the file is truncated");
        ++lineNo_;
        line_.str(text);
        line_.clear();
    }
    if (echo_) *echo_ << token << ' ';
    return token;
}

void AsciiBody::refuse(const std::string& token, const char* expected) const {
    std::string shown = token.size() > 40 ? token.substr(0, 40) + "..." : token;
    throw SceneError("cannot load " + inQuotes(path_) + ": line " + std::to_string(lineNo_) +
                     " holds " + inQuotes(shown) + " where " + syntax_.reader + " needs " +
                     expected + syntax_.refusalNote + "; fix that value");
}

}  // namespace oct::scene_detail
