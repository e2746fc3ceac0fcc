#include "core/io/output_file.h"

#include <fcntl.h>
#include <signal.h>
#include <stb_image_write.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <utility>

namespace oct {

const char* fileKind(mode_t m) {
    if (S_ISDIR(m)) return "a directory";
    if (S_ISFIFO(m)) return "a FIFO";
    if (S_ISSOCK(m)) return "a socket";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISLNK(m)) return "a symbolic link";
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

int freeSlotHeld() {  // inside a held section; -1 when the table is full
    for (int i = 0; i < kMaxTemps; ++i)
        if (!gTempUsed[i].load()) return i;
    return -1;
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

// ---- Temporary names ----------------------------------------------------------------------------
//
// A temporary is NAME.tmp.XXXXXXXX beside its output (the same folder: the rename into place
// must not cross file systems), XXXXXXXX eight characters of [0-9A-Za-z] from getrandom (47
// bits), created with O_CREAT|O_EXCL|O_NOFOLLOW: whatever is at that name already (a file, a
// symlink, a dangling symlink someone planted) is never opened, followed or truncated; the
// next name is drawn instead. The name used to be NAME.tmp.PID opened with fopen("wb"): a
// symlink planted there had its target truncated and overwritten.

constexpr int kTempNameAttempts = 64;
constexpr char kSuffixAlphabet[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
constexpr size_t kSuffixLength = 8;

TempSuffixSource gSuffixSource = nullptr;  // tests only (setTempSuffixSourceForTests)

std::string randomSuffix() {
    if (gSuffixSource) return gSuffixSource();
    unsigned char bytes[kSuffixLength];
    randomBytes(bytes, sizeof bytes);
    std::string s;
    for (unsigned char b : bytes) s += kSuffixAlphabet[b % (sizeof kSuffixAlphabet - 1)];
    return s;
}

class UniqueFd {
public:
    explicit UniqueFd(int fd) : fd_(fd) {}
    ~UniqueFd() {
        if (fd_ >= 0) ::close(fd_);
    }
    UniqueFd(const UniqueFd&) = delete;
    UniqueFd& operator=(const UniqueFd&) = delete;
    int get() const { return fd_; }
    int release() { return std::exchange(fd_, -1); }
    void reset(int fd) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = fd;
    }

private:
    int fd_;
};

// An open temporary: its name, its entry in the signal handler's table, and its descriptor
// (closed on destruction unless writeTemp closed it, checking the result).
struct Temp {
    std::string path;
    int slot = -1;
    UniqueFd fd{-1};
};

// Creates a new, empty temporary for `target` (mode 0666 less the umask, as fopen gives). The
// file is created and entered in the handler's table in one held section: the table never
// names a file this process did not create (a signal would unlink it), and no file this
// process created is missing from it.
void createTemp(const std::string& target, Temp& t) {
    installHandlersOnce();
    for (int attempt = 0; attempt < kTempNameAttempts; ++attempt) {
        const std::string tmp = target + ".tmp." + randomSuffix();
        if (tmp.size() >= kMaxTempPath)
            throw IoError("cannot write '" + target + "': the path is longer than " +
                          std::to_string(kMaxTempPath - 1 - kSuffixLength - 5) + " bytes");
        int slot = -1, fd = -1, err = 0;
        held([&] {
            slot = freeSlotHeld();
            if (slot < 0) return;
            fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
            err = errno;
            if (fd < 0) return;
            std::memcpy(gTempPath[slot], tmp.c_str(), tmp.size() + 1);
            gTempUsed[slot].store(1);
        });
        if (slot < 0)
            throw IoError("cannot write '" + target + "': more than " + std::to_string(kMaxTemps) +
                          " outputs are being written at once");
        if (fd >= 0) {
            t.path = tmp;
            t.slot = slot;
            t.fd.reset(fd);
            return;
        }
        if (err != EEXIST)
            throw IoError("cannot write '" + target + "': " + std::strerror(err) +
                          " (check that the folder exists and is writable)");
    }
    throw IoError("cannot write '" + target + "': " + std::to_string(kTempNameAttempts) +
                  " temporary names beside it (" + target +
                  ".tmp.*) were all taken; remove the stale ones");
}

// write(2) until every byte is written; false with err set on a failure.
bool writeAll(int fd, const void* data, size_t bytes, int& err) {
    const char* p = static_cast<const char*>(data);
    while (bytes > 0) {
        const ssize_t n = ::write(fd, p, std::min(bytes, size_t(1) << 30));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            err = n < 0 ? errno : EIO;
            return false;
        }
        p += n;
        bytes -= size_t(n);
    }
    return true;
}

// ---- Writing ------------------------------------------------------------------------------------

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

// Writes the pieces to the open temporary t and closes it; on failure removes it and throws
// naming the target path.
void writeTemp(const std::string& path, Temp& t, const std::vector<OutputSet::Piece>& pieces) {
    int err = 0;
    bool ok = true;
    for (const OutputSet::Piece& p : pieces) ok = ok && writeAll(t.fd.get(), p.data, p.bytes, err);
    const int fd = t.fd.release();
    if (::close(fd) != 0 && ok) {  // NFS reports a failed write at close
        ok = false;
        err = errno;
    }
    if (!ok) {
        discardTemp(t.path, t.slot);
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

// ---- Locks on a run's outputs -------------------------------------------------------------------
//
// A run holds flock(LOCK_EX) on NAME.lock, a regular file beside NAME, from before its work
// until its outputs are in place; a second run finding it held is refused at once (LOCK_NB).
// Why a lock file per name rather than a lock on the output folder: runs into other prefixes of
// one folder (parallel jobs into one results folder) must not refuse each other. Why flock: the
// kernel drops it when the holder ends, even by SIGKILL, so a lock file left behind locks
// nothing and the next run takes it over.
//
// Removing the file at the end has a known race: run B opens NAME.lock, run A unlinks it and
// ends, B's flock succeeds on the unlinked file while run C creates a new NAME.lock and locks
// that: two holders. So the holder unlinks the file while still holding the lock, and a run
// that got the lock checks that NAME.lock still names the file it locked (fstat of its
// descriptor against lstat of the name); if not it closes and tries again. Whoever holds the
// lock on the file that NAME.lock names is then the only holder.
//
// Only a file octrace created is removed: a file of that name that was there before (a user's,
// or a lock a killed run left) is locked and left in place, unless it holds exactly kLockText,
// which octrace writes into the lock files it creates (a lock a killed run left: removed).
// Removed files are entered in the signal handler's table like the temporaries, so an
// interrupted run leaves no lock file either.

constexpr char kLockText[] = "octrace run lock (flock): removed when the run ends\n";
constexpr int kLockAttempts = 16;

bool sameInode(const struct stat& a, const struct stat& b) {
    return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

bool holdsLockText(int fd) {
    char buf[sizeof kLockText];
    const ssize_t n = ::pread(fd, buf, sizeof buf, 0);
    return n == ssize_t(sizeof kLockText - 1) && std::memcmp(buf, kLockText, size_t(n)) == 0;
}

void refuseSpecialLock(const std::string& lock) {
    struct stat st;
    if (::lstat(lock.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
    throw IoError("cannot lock '" + lock + "': it is " + fileKind(st.st_mode) +
                  "; octrace holds a regular file of that name while it writes the outputs "
                  "beside it: remove it, or write elsewhere");
}

}  // namespace

OutputLock::OutputLock(const std::string& name) : path_(name + ".lock") {
    installHandlersOnce();
    if (path_.size() >= kMaxTempPath)
        throw IoError("cannot lock '" + path_ + "': the path is longer than " +
                      std::to_string(kMaxTempPath - 1) + " bytes");
    for (int attempt = 0; attempt < kLockAttempts; ++attempt) {
        refuseSpecialLock(path_);
        bool locked = false;
        held([&] { locked = lockOnceHeld(name); });
        if (locked) return;
    }
    throw IoError("cannot lock '" + path_ + "': it was replaced " + std::to_string(kLockAttempts) +
                  " times while octrace tried to lock it; is another program removing it?");
}

// One try, in a held section: no signal between creating the file and entering it in the
// handler's table. False: the file was removed or replaced between open and flock (its holder
// ended), try again.
bool OutputLock::lockOnceHeld(const std::string& name) {
    const int slot = freeSlotHeld();
    if (slot < 0)
        throw IoError("cannot lock '" + path_ + "': more than " + std::to_string(kMaxTemps) +
                      " outputs are being written at once");
    bool created = true;
    UniqueFd fd(::open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666));
    if (fd.get() < 0 && errno == EEXIST) {
        // Opened to lock, never written (it may be anyone's file); for writing where allowed:
        // NFS emulates flock with byte-range locks, whose exclusive kind needs a descriptor
        // open for writing.
        created = false;
        const int flags = O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC;
        fd.reset(::open(path_.c_str(), O_RDWR | flags));
        if (fd.get() < 0 && (errno == EACCES || errno == EROFS))
            fd.reset(::open(path_.c_str(), O_RDONLY | flags));
        if (fd.get() < 0 && errno == ENOENT) return false;
    }
    if (fd.get() < 0)
        throw IoError("cannot lock '" + path_ + "': " + std::strerror(errno) +
                      " (check that the folder exists and is writable)");
    struct stat st;
    if (::fstat(fd.get(), &st) != 0 || !S_ISREG(st.st_mode)) return false;  // replaced since
    if (created) {
        // Best effort: without the text, a lock file a SIGKILL left behind is not known for
        // octrace's and stays (it is still locked, never written).
        [[maybe_unused]] const ssize_t n = ::write(fd.get(), kLockText, sizeof kLockText - 1);
    }
    if (::flock(fd.get(), LOCK_EX | LOCK_NB) != 0) {
        const int err = errno;
        if (created) ::unlink(path_.c_str());  // ours, not yet in the handler's table
        if (err == EWOULDBLOCK)
            throw IoError("another octrace run is writing '" + name + "' (it holds the lock '" +
                          path_ + "'); wait for it to end, or write elsewhere");
        if (err == ENOLCK || err == EOPNOTSUPP || err == ENOSYS) {
            // A file system without locks (NFS without a lock manager): octrace wrote such
            // folders before it locked, and still does, saying so once.
            std::fprintf(stderr,
                         "octrace: note: cannot lock '%s' (%s); going on without the lock: do "
                         "not run two octrace commands into this output at once\n",
                         path_.c_str(), std::strerror(err));
            return true;
        }
        throw IoError("cannot lock '" + path_ + "': " + std::strerror(err));
    }
    struct stat now;
    if (::lstat(path_.c_str(), &now) != 0 || !sameInode(now, st)) return false;
    if (created || holdsLockText(fd.get())) {
        std::memcpy(gTempPath[slot], path_.c_str(), path_.size() + 1);
        gTempUsed[slot].store(1);
        slot_ = slot;
    }
    fd_ = fd.release();
    return true;
}

OutputLock::OutputLock(OutputLock&& o) noexcept
    : path_(std::move(o.path_)), fd_(std::exchange(o.fd_, -1)), slot_(std::exchange(o.slot_, -1)) {}

OutputLock::~OutputLock() {
    if (fd_ < 0) return;
    if (slot_ >= 0)
        held([&] {
            // Unlinked while the lock is still held (see above), and only while the name still
            // is this file (an output renamed onto it is not removed).
            struct stat mine, named;
            if (::fstat(fd_, &mine) == 0 && ::lstat(path_.c_str(), &named) == 0 &&
                sameInode(mine, named))
                ::unlink(path_.c_str());
            releaseTempHeld(slot_);
        });
    ::close(fd_);
}

std::vector<OutputLock> lockOutputs(const std::vector<std::string>& outputs) {
    std::vector<std::string> names;
    for (const std::string& o : outputs)
        if (!o.empty() && o != "-") names.push_back(o);
    for (const std::string& a : names)
        for (const std::string& b : names)
            if (sameFile(identify(a + ".lock"), identify(b)))
                throw IoError("output '" + b + "' is the lock file of output '" + a +
                              "' (octrace holds NAME.lock while it writes NAME); give it another "
                              "name");
    // In one order, so two runs with the same outputs contend for the same lock first.
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    std::vector<OutputLock> locks;
    locks.reserve(names.size());
    for (const std::string& n : names) locks.emplace_back(n);
    return locks;
}

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
    Temp t;
    createTemp(path, t);
    writeTemp(path, t, pieces);
    staged_.push_back({path, t.path, t.slot});
}

OutputSet::Stamp OutputSet::stamp(const std::string& path) const {
    for (const Staged& s : staged_) {
        if (s.path != path) continue;
        struct stat st;
        if (::lstat(s.tmp.c_str(), &st) != 0)
            throw IoError("cannot read back '" + s.tmp + "': " + std::strerror(errno));
        return {uint64_t(st.st_ino), int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec};
    }
    throw IoError("'" + path + "' is not staged in this set of outputs");
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

// Creates a temporary as stage() would, and removes it: nothing is created or truncated at a
// name anyone could guess.
void checkWritable(const std::string& path) {
    refuseSpecialTarget(path);
    Temp t;
    createTemp(path, t);
    discardTemp(t.path, t.slot);
}

void setTempSuffixSourceForTests(TempSuffixSource source) { gSuffixSource = source; }

void randomBytes(void* out, size_t n) {
    if (::getrandom(out, n, 0) == ssize_t(n)) return;
    std::random_device device;  // getrandom missing (a kernel before 3.17): the C++ source
    unsigned char* b = static_cast<unsigned char*>(out);
    for (size_t i = 0; i < n; ++i) b[i] = static_cast<unsigned char>(device());
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
