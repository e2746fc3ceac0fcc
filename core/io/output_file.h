// Output files are written to a temporary name beside the target and renamed into place only
// when complete, so a failure never leaves a partial file and an existing file is replaced
// only by a complete one (rename within one directory is atomic on POSIX).
//
// The temporary is NAME.tmp.XXXXXXXX, eight random characters, created exclusively
// (O_CREAT|O_EXCL|O_NOFOLLOW): a file or symlink anyone planted at a name octrace might use is
// never opened, followed or truncated. While one exists it is registered in a fixed table that
// the handler of SIGINT, SIGTERM and SIGHUP reads: the handler unlinks every registered
// temporary (unlink is async-signal-safe) and re-raises the signal with its default action, so
// an interrupted run leaves neither a temporary nor a partial output behind and still ends "by
// the signal" for its parent. A signal arriving while OutputSet::commit() renames is held back
// until the last rename is done, so a commit is all-or-none for these signals too. A signal
// that was ignored when the first output was staged (nohup, a background job) stays ignored.
// SIGKILL cannot be caught: it can leave NAME.tmp.XXXXXXXX behind (never a partial NAME).
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

    // What a staged file will be once renamed into place (a rename keeps both): its inode and
    // its modification time in ns since the epoch. Throws IoError for a path not staged.
    struct Stamp {
        uint64_t inode = 0;
        int64_t mtimeNs = 0;
    };
    Stamp stamp(const std::string& path) const;

private:
    struct Staged {
        std::string path, tmp;
        int slot;  // the temporary's entry in the signal handler's table
    };
    std::vector<Staged> staged_;
};

// Fails early, before heavy work, when a file cannot be created in path's folder (it creates a
// temporary as OutputSet::stage does and removes it), or when path exists and is not a regular
// file (a device, FIFO, socket or directory: renaming onto a device node as root would replace
// /dev/null itself).
void checkWritable(const std::string& path);

// An advisory lock (flock) on NAME.lock beside a run's outputs, held from before the work until
// the outputs are in place, so that two octrace runs never write one set of outputs at once:
// the second is refused at once (trace renames PREFIX.t.npy and PREFIX.prim.npy one after the
// other; a run finishing between the two left a pair from two runs). The file is created if
// absent (O_CREAT|O_NOFOLLOW, never written when it was there before) and removed at the end
// when octrace made it; output_file.cpp says why that is safe. `name` is what the refusal says is
// being written: trace's PREFIX, another command's output path. Throws IoError: "another
// octrace run is writing 'NAME' (it holds the lock 'NAME.lock'); ...", or NAME.lock is not a
// regular file (a symlink, a FIFO, ...), or cannot be created.
class OutputLock {
public:
    explicit OutputLock(const std::string& name);
    ~OutputLock();
    OutputLock(OutputLock&& o) noexcept;
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;
    OutputLock& operator=(OutputLock&&) = delete;
    const std::string& path() const { return path_; }

private:
    bool lockOnceHeld(const std::string& name);
    std::string path_;
    int fd_ = -1;
    int slot_ = -1;  // >= 0: octrace's file, in the signal handler's table, removed at the end
};

// An OutputLock on each output ("" and "-" skipped), for the commands that write a set of
// files: render, rays, certify, explain. Refuses an output that is another's lock file.
std::vector<OutputLock> lockOutputs(const std::vector<std::string>& outputs);

// n unpredictable bytes (getrandom; std::random_device where the kernel lacks it): the
// temporaries' names, trace's run ids.
void randomBytes(void* out, size_t n);

// Tests only: where the temporaries' random suffixes come from (nullptr: getrandom). A test
// returns a name it has taken, to see that the file there is never opened.
using TempSuffixSource = std::string (*)();
void setTempSuffixSourceForTests(TempSuffixSource source);

// What a path that is not a regular file is, for messages: "a directory", "a FIFO", "a socket",
// "a character device", "a block device", "a symbolic link" (lstat), else "not a regular file".
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
