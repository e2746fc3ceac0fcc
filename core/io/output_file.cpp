#include "core/io/output_file.h"

#include <signal.h>
#include <stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>

namespace oct {

const char* fileKind(mode_t m) {
    if (S_ISDIR(m)) return "a directory";
    if (S_ISFIFO(m)) return "a FIFO";
    if (S_ISSOCK(m)) return "a socket";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    return "not a regular file";
}

namespace {

namespace fs = std::filesystem;

// ---- Temporaries the signal handler removes ---------------------------------------------------
//
// The handler may run at any instruction of any thread, so everything it reads is static
// storage written before it can be seen (no allocation, no locks in the handler): a table of
// kMaxTemps paths of at most kMaxTempPath bytes, each with a flag saying whether it names a
// temporary to remove. The table is changed only inside a "held" section (gState 1); a handler
// finding gState 1 records the signal in gPendingSignal and returns, and the section acts on it
// when it ends. A handler finding gState 0 sets it to 2 for good, unlinks every registered
// temporary, restores the default action and re-raises: the process ends by the signal.

constexpr int kMaxTemps = 64;
constexpr size_t kMaxTempPath = 4096;  // Linux PATH_MAX, the terminating NUL included
constexpr int kHandledSignals[] = {SIGINT, SIGTERM, SIGHUP};
static_assert(std::atomic<int>::is_always_lock_free, "the handler needs lock-free atomics");

char gTempPath[kMaxTemps][kMaxTempPath];
std::atomic<int> gTempUsed[kMaxTemps];
std::atomic<int> gState{0};  // 0 idle, 1 held (table changing or commit renaming), 2 dying
std::atomic<int> gPendingSignal{0};
std::mutex gHeldMutex;  // one held section at a time among threads (never taken by the handler)

void removeTempsAndReraise(int sig) {  // async-signal-safe: unlink, sigaction, raise only
    for (int i = 0; i < kMaxTemps; ++i)
        if (gTempUsed[i].load()) ::unlink(gTempPath[i]);
    struct sigaction dfl;
    std::memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(sig, &dfl, nullptr);
    ::raise(sig);  // blocked while this handler runs; delivered, with the default action, on return
}

void onTerminatingSignal(int sig) {
    int expected = 0;
    if (gState.compare_exchange_strong(expected, 2)) {
        removeTempsAndReraise(sig);
    } else if (expected == 1) {
        gPendingSignal.store(sig);  // the held section acts on it when it ends
    }
    // expected == 2: another thread is already removing the temporaries and ending the process.
}

void installHandlersOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (int sig : kHandledSignals) {
            struct sigaction old;
            if (::sigaction(sig, nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
            struct sigaction sa;
            std::memset(&sa, 0, sizeof sa);
            sa.sa_handler = onTerminatingSignal;
            sigemptyset(&sa.sa_mask);
            for (int s : kHandledSignals) sigaddset(&sa.sa_mask, s);
            sa.sa_flags = SA_RESTART;  // a held-back signal must not fail the I/O it interrupted
            ::sigaction(sig, &sa, nullptr);
        }
    });
}

// Runs f with the handler held back; a signal that arrived meanwhile is acted on at the end.
template <class F>
void held(F&& f) {
    std::lock_guard<std::mutex> lock(gHeldMutex);
    int expected = 0;
    if (!gState.compare_exchange_strong(expected, 1))
        for (;;) ::pause();  // 2: a handler is removing the temporaries and ending the process
    auto leave = [] {
        gState.store(0);
        if (int sig = gPendingSignal.exchange(0)) onTerminatingSignal(sig);
    };
    try {
        f();
    } catch (...) {
        leave();
        throw;
    }
    leave();
}

int registerTemp(const std::string& tmp) {
    installHandlersOnce();
    if (tmp.size() >= kMaxTempPath)
        throw IoError("cannot write '" + tmp + "': the path is longer than " +
                      std::to_string(kMaxTempPath - 1) + " bytes");
    int slot = -1;
    held([&] {
        for (int i = 0; i < kMaxTemps && slot < 0; ++i)
            if (!gTempUsed[i].load()) slot = i;
        if (slot < 0) return;
        std::memcpy(gTempPath[slot], tmp.c_str(), tmp.size() + 1);
        gTempUsed[slot].store(1);
    });
    if (slot < 0)
        throw IoError("cannot write '" + tmp + "': more than " + std::to_string(kMaxTemps) +
                      " outputs are being written at once");
    return slot;
}

void releaseTempHeld(int slot) {  // inside a held section
    if (slot >= 0) gTempUsed[slot].store(0);
}

// Removes a registered temporary (a failure or an abandoned set).
void discardTemp(const std::string& tmp, int slot) {
    held([&] {
        std::remove(tmp.c_str());
        releaseTempHeld(slot);
    });
}

// ---- Writing ------------------------------------------------------------------------------------

std::string tempNameFor(const std::string& path) {
    return path + ".tmp." + std::to_string(::getpid());
}

// An output is replaced by renaming a complete file onto it: onto a device node (as root) that
// would replace the node itself (/dev/null), onto a directory it fails late. Refused up front.
// A symlink is replaced by the file, its target left alone.
void refuseSpecialTarget(const std::string& path) {
    struct stat st;
    if (::lstat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)) return;
    throw IoError("cannot write '" + path + "': it is " + fileKind(st.st_mode) +
                  ", and octrace replaces an output by renaming a complete file onto it; "
                  "name a regular file");
}

// Writes bytes to tmp (registered as `slot`); on failure removes it and throws naming the
// target path.
void writeTemp(const std::string& path, const std::string& tmp, int slot,
               const std::vector<OutputSet::Piece>& pieces) {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        int err = errno;
        discardTemp(tmp, slot);
        throw IoError("cannot write '" + path + "': " + std::strerror(err) +
                      " (check that the folder exists and is writable)");
    }
    errno = 0;
    bool ok = true;
    for (const OutputSet::Piece& p : pieces)
        ok = ok && (p.bytes == 0 || std::fwrite(p.data, 1, p.bytes, f) == p.bytes);
    int err = errno;
    if (std::fflush(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (std::fclose(f) != 0 && ok) {
        ok = false;
        err = errno;
    }
    if (!ok) {
        discardTemp(tmp, slot);
        throw IoError("cannot write '" + path + "': " + std::strerror(err ? err : EIO) +
                      " (nothing was written; free space or choose another folder)");
    }
}

void renameInto(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int err = errno;
        std::remove(tmp.c_str());
        throw IoError("cannot replace '" + path + "': " + std::strerror(err));
    }
}

// ---- Identity of paths --------------------------------------------------------------------------

struct FileId {
    bool exists = false;
    dev_t dev = 0;
    ino_t ino = 0;
    std::string path;  // absolute and normalised, for a path that does not exist
};

FileId identify(const std::string& p) {
    FileId id;
    struct stat st;
    if (::stat(p.c_str(), &st) == 0) {
        id.exists = true;
        id.dev = st.st_dev;
        id.ino = st.st_ino;
        return id;
    }
    std::error_code ec;
    fs::path abs = fs::absolute(p, ec);
    fs::path w = ec ? fs::path(p) : fs::weakly_canonical(abs, ec);
    if (ec) w = abs;
    id.path = w.lexically_normal().string();
    return id;
}

bool sameFile(const FileId& a, const FileId& b) {
    if (a.exists != b.exists) return false;
    return a.exists ? a.dev == b.dev && a.ino == b.ino : a.path == b.path;
}

}  // namespace

void writeFileAtomic(const std::string& path, const void* data, size_t bytes) {
    OutputSet out;
    out.stage(path, data, bytes);
    out.commit();
}

OutputSet::~OutputSet() {
    for (const Staged& s : staged_) discardTemp(s.tmp, s.slot);
}

void OutputSet::stage(const std::string& path, const void* data, size_t bytes) {
    stage(path, std::vector<Piece>{{data, bytes}});
}

void OutputSet::stage(const std::string& path, const std::vector<Piece>& pieces) {
    const FileId id = identify(path);
    for (const Staged& s : staged_)
        if (sameFile(identify(s.path), id))
            throw IoError("outputs '" + s.path + "' and '" + path +
                          "' are the same file; give each output its own path");
    refuseSpecialTarget(path);
    std::string tmp = tempNameFor(path);
    int slot = registerTemp(tmp);
    writeTemp(path, tmp, slot, pieces);
    staged_.push_back({path, tmp, slot});
}

void OutputSet::commit() {
    // Renames cannot fail for lack of space; what can fail (a vanished folder) is reported, and
    // the temporaries not yet renamed are removed by the destructor. SIGINT, SIGTERM and SIGHUP
    // wait until the renames are done (held), so the set is replaced all at once or not at all.
    held([&] {
        while (!staged_.empty()) {
            Staged s = staged_.front();
            staged_.erase(staged_.begin());
            try {
                renameInto(s.tmp, s.path);
            } catch (...) {
                releaseTempHeld(s.slot);
                throw;
            }
            releaseTempHeld(s.slot);
        }
    });
}

void checkWritable(const std::string& path) {
    refuseSpecialTarget(path);
    std::string tmp = tempNameFor(path);
    int slot = registerTemp(tmp);
    writeTemp(path, tmp, slot, {});
    discardTemp(tmp, slot);
}

void checkOutputPaths(const std::vector<std::string>& outputs,
                      const std::vector<std::string>& inputs) {
    std::vector<std::pair<std::string, FileId>> seen;
    for (const std::string& in : inputs)
        if (!in.empty()) seen.push_back({in, identify(in)});
    const size_t inputCount = seen.size();
    for (const std::string& out : outputs) {
        if (out.empty()) continue;
        refuseSpecialTarget(out);
        FileId id = identify(out);
        for (size_t i = 0; i < seen.size(); ++i) {
            if (!sameFile(seen[i].second, id)) continue;
            if (i < inputCount)
                throw IoError("output '" + out + "' is the input '" + seen[i].first +
                              "' (the same file): writing it would replace the input; choose "
                              "another output path");
            throw IoError("outputs '" + seen[i].first + "' and '" + out +
                          "' are the same file; give each output its own path");
        }
        seen.push_back({out, id});
    }
}

namespace {

void appendBytes(void* context, void* data, int size) {
    auto* out = static_cast<std::vector<uint8_t>*>(context);
    auto* p = static_cast<uint8_t*>(data);
    out->insert(out->end(), p, p + size);
}
}  // namespace

std::vector<uint8_t> encodePng(const std::string& path, int width, int height,
                               const std::vector<uint8_t>& rgb) {
    std::vector<uint8_t> png;
    if (!stbi_write_png_to_func(appendBytes, &png, width, height, 3, rgb.data(), width * 3))
        throw IoError("cannot encode the PNG for '" + path + "'");
    return png;
}

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb) {
    writeFileAtomic(path, encodePng(path, width, height, rgb));
}

}  // namespace oct
