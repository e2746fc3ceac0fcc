#include "core/io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace oct {
namespace {

std::string named(const std::string& what, const std::string& path) {
    return what + " '" + path + "'";
}

std::string withHint(const std::string& hint) { return hint.empty() ? "" : "; " + hint; }

[[noreturn]] void notRegular(const std::string& path, const std::string& what, mode_t m,
                             const std::string& hint) {
    throw IoError("cannot read " + named(what, path) + ": it is " + fileKind(m) +
                  ", not a regular file" +
                  withHint(hint.empty() ? "copy it into a regular file and give that" : hint));
}

}  // namespace

InputFile::InputFile(const std::string& path, const std::string& what, const std::string& hint)
    : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
        const int err = errno;
        struct stat st;
        if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
            notRegular(path, what, st.st_mode, hint);
        throw IoError("cannot open " + named(what, path) + ": " + std::strerror(err) +
                      withHint(!hint.empty()   ? hint
                               : err == ENOENT ? "check the path"
                                               : ""));
    }
    struct stat st;
    if (::fstat(fd_, &st) != 0) {
        const int err = errno;
        ::close(fd_);
        throw IoError("cannot read " + named(what, path) + ": " + std::strerror(err));
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd_);
        notRegular(path, what, st.st_mode, hint);
    }
    size_ = uint64_t(st.st_size);
}

InputFile::~InputFile() {
    if (fd_ >= 0) ::close(fd_);
}

size_t InputFile::read(void* into, size_t n) {
    auto* p = static_cast<char*>(into);
    size_t done = 0;
    while (done < n) {
        const ssize_t got = ::read(fd_, p + done, n - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw IoError("cannot read '" + path_ + "': " + std::strerror(errno));
        if (got == 0) break;
        done += size_t(got);
    }
    return done;
}

void InputFile::readExactly(void* into, size_t n) {
    if (read(into, n) != n)
        throw IoError("cannot read '" + path_ + "': the file changed while it was read");
}

void InputFile::seekTo(uint64_t offset) {
    if (::lseek(fd_, off_t(offset), SEEK_SET) != off_t(offset))
        throw IoError("cannot seek to byte " + std::to_string(offset) + " of '" + path_ +
                      "': " + std::strerror(errno));
}

bool InputFile::atEnd() {
    char extra;
    return read(&extra, 1) == 0;
}

std::string readSmallInput(const std::string& path, const std::string& what, uint64_t maxBytes,
                           const std::string& hint) {
    InputFile in(path, what, hint);
    if (in.size() > maxBytes)
        throw IoError("cannot read " + named(what, path) + ": it is " + std::to_string(in.size()) +
                      " bytes, more than the " + std::to_string(maxBytes) + " such a file can be" +
                      withHint(hint));
    std::string bytes(size_t(in.size()), '\0');
    in.readExactly(&bytes[0], bytes.size());
    if (!in.atEnd())
        throw IoError("cannot read '" + path + "': the file changed while it was read");
    return bytes;
}

}  // namespace oct
