// User-named input files, opened the one way every reader of octrace opens them (ray files,
// hit files, ray manifests, the regression files and golden PNGs): a path that is not a regular
// file (a FIFO, a character or block device, a directory, a socket; also through a symlink) is
// refused without reading, so a FIFO without a writer cannot block, /dev/zero cannot be read
// forever and a directory is named as one (it gave "basic_filebuf::underflow"). The scene
// loaders check their paths the same way before their readers open them (core/scene).
#pragma once

#include <cstdint>
#include <string>

#include "core/io/output_file.h"

namespace oct {

class InputFile {
public:
    // Opens `path` for reading, or throws IoError with one line naming the path and `what` it
    // was to be ("the ray file", "hits", "the ray manifest", ...): missing or unreadable
    // (strerror), or not a regular file (fileKind), then `hint`, what to do instead. O_NONBLOCK:
    // opening a FIFO without a writer returns at once, and is then refused.
    InputFile(const std::string& path, const std::string& what, const std::string& hint = "");
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;

    const std::string& path() const { return path_; }
    uint64_t size() const { return size_; }  // when opened (fstat)
    // Reads up to n bytes, fewer only at the end of the file; returns the bytes read. Throws
    // IoError naming the file when the read fails.
    size_t read(void* into, size_t n);
    // Reads exactly n bytes, or throws IoError "the file changed while it was read" (it shrank).
    void readExactly(void* into, size_t n);
    // True when no byte is left; a file that grew since it was opened is refused by the caller.
    bool atEnd();
    // Moves the next read to byte `offset` from the start (an MPI rank's slice of a ray file).
    // Throws IoError naming the file when the seek fails.
    void seekTo(uint64_t offset);

private:
    std::string path_;
    int fd_ = -1;
    uint64_t size_ = 0;
};

// The whole of a small input (a manifest, a JSON file, a PNG), read only when its size is at
// most maxBytes: a larger one is refused with both figures before a byte is read. Throws IoError
// as InputFile does, and when the file changes size while read.
std::string readSmallInput(const std::string& path, const std::string& what, uint64_t maxBytes,
                           const std::string& hint = "");

}  // namespace oct
