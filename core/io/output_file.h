// Output files are written to a temporary name beside the target and renamed into place only
// when complete, so a failure never leaves a partial file and an existing file is replaced
// only by a complete one (rename within one directory is atomic on POSIX).
//
// The temporary name is NAME.tmp.PID. While one exists it is registered in a fixed table that
// the handler of SIGINT, SIGTERM and SIGHUP reads: the handler unlinks every registered
// temporary (unlink is async-signal-safe) and re-raises the signal with its default action, so
// an interrupted run leaves neither a temporary nor a partial output behind and still ends "by
// the signal" for its parent. A signal arriving while OutputSet::commit() renames is held back
// until the last rename is done, so a commit is all-or-none for these signals too. A signal
// that was ignored when the first output was staged (nohup, a background job) stays ignored.
// SIGKILL cannot be caught: it can leave NAME.tmp.PID behind (never a partial NAME).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace oct {

class IoError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

void writeFileAtomic(const std::string& path, const void* data, size_t bytes);

// Several outputs of one command, all or none: stage() writes each to a temporary name,
// commit() renames them all into place once every one was written. Destroying an uncommitted
// set removes its temporaries, so a failure anywhere leaves every target as it was. Staging
// the same path twice is refused (the second would overwrite the first's temporary).
class OutputSet {
public:
    OutputSet() = default;
    ~OutputSet();
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;

    void stage(const std::string& path, const void* data, size_t bytes);
    void stage(const std::string& path, const std::vector<uint8_t>& bytes) {
        stage(path, bytes.data(), bytes.size());
    }
    // One file from several buffers one after another (a header, then the caller's data), so
    // that a large array is written from where it lies, never copied behind a header first.
    struct Piece {
        const void* data;
        size_t bytes;
    };
    void stage(const std::string& path, const std::vector<Piece>& pieces);
    void commit();

private:
    struct Staged {
        std::string path, tmp;
        int slot;  // the temporary's entry in the signal handler's table
    };
    std::vector<Staged> staged_;
};

// Fails early, before heavy work, when a file cannot be created in path's folder, or when path
// exists and is not a regular file (a device, FIFO, socket or directory: renaming onto a device
// node as root would replace /dev/null itself).
void checkWritable(const std::string& path);

// What a path that is not a regular file is, for messages: "a directory", "a FIFO", "a socket",
// "a character device", "a block device", else "not a regular file" (st_mode of stat/lstat).
const char* fileKind(mode_t m);

// Refuses, before any work, a command's outputs that would destroy a file or each other:
//  - two outputs naming the same file (the second would overwrite the first and the set would
//    no longer be all-or-none): "out.png" and "./out.png" are the same file;
//  - an output naming one of the inputs (writing it would replace the input): the same file
//    also through a symlink or a hard link;
//  - an output that exists and is not a regular file (see checkWritable).
// "The same file": the same device and inode when the path exists (stat follows symlinks),
// otherwise the same absolute, normalised path with the existing folders' symlinks resolved
// (std::filesystem::weakly_canonical). Empty strings are skipped (options not given). Throws
// IoError naming both paths and what to do.
void checkOutputPaths(const std::vector<std::string>& outputs,
                      const std::vector<std::string>& inputs);

inline void writeFileAtomic(const std::string& path, const std::vector<uint8_t>& bytes) {
    writeFileAtomic(path, bytes.data(), bytes.size());
}

// Encodes an 8-bit RGB image as PNG (stb_image_write, Debian's libstb) and writes it atomically.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb);
std::vector<uint8_t> encodePng(const std::string& path, int width, int height,
                               const std::vector<uint8_t>& rgb);

}  // namespace oct
