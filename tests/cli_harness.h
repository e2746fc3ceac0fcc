// The one harness of the tests that run the real `octrace` binary as a user does: arguments as
// a vector (no shell), stdin from /dev/null, stdout and stderr captured to files, a time limit
// after which the process is killed, and the way it ended (exit status, signal, time-out). A
// test can also send it a signal mid-run (SIGINT, SIGTERM) and check what it left behind.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace octtest {

namespace fs = std::filesystem;

inline const std::string& octraceBinary() {
    static const std::string path = std::string(OCT_BINARY_DIR) + "/octrace";
    return path;
}

inline std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline bool writeFile(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return out.good();
}

// Single-quotes a word for a shell-style command string (splitWords undoes it).
inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Splits "render 'a b.obj' --out x" into words: spaces separate, single quotes group, a
// backslash outside quotes escapes the next character (what quote() produces, nothing more).
inline std::vector<std::string> splitWords(const std::string& text) {
    std::vector<std::string> words;
    std::string w;
    bool inWord = false, inQuote = false;
    for (size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (inQuote) {
            if (c == '\'')
                inQuote = false;
            else
                w += c;
        } else if (c == '\'') {
            inQuote = inWord = true;
        } else if (c == '\\' && i + 1 < text.size()) {
            w += text[++i];
            inWord = true;
        } else if (c == ' ' || c == '\t' || c == '\n') {
            if (inWord) words.push_back(w);
            w.clear();
            inWord = false;
        } else {
            w += c;
            inWord = true;
        }
    }
    if (inWord) words.push_back(w);
    return words;
}

struct RunResult {
    bool timedOut = false;
    int status = -1;  // the exit status; -1 when the process did not exit normally
    int signal = 0;   // when a signal ended it
    double seconds = 0;
    // The process's peak resident memory (wait4's ru_maxrss), for tests of what a command
    // keeps in memory at once: a copy of a large array shows as its size.
    uint64_t peakRssBytes = 0;
    std::string out, err;
};

struct RunOptions {
    double timeoutSeconds = 300.0;
    std::string workingDir;  // empty: the test's own
    // Called every 5 ms while the process runs, with its pid and the seconds so far; may send
    // it a signal (the process is still reaped and reported as usual).
    std::function<void(pid_t, double)> whileRunning;
    // Where the process's stdout goes instead of the capture file (e.g. "/dev/full").
    std::string stdoutPath;
    // > 0: the process runs under RLIMIT_FSIZE of this many bytes (a write past it fails, as on
    // a full disk), with SIGXFSZ ignored so that the write returns EFBIG instead of killing it.
    uint64_t fileSizeLimit = 0;
    // > 0: the process runs under RLIMIT_AS of this many bytes (allocations past it fail).
    uint64_t addressSpaceLimit = 0;
    // Not empty: run by /bin/sh just before octrace, which then replaces the shell (exec), so
    // octrace has the shell's pid: `$$` in these commands is octrace's pid (a test plants a file
    // at a name octrace would derive from its pid). A failing command ends the run
    // before octrace starts (sh -e: its exit status, not 0).
    std::string shellBefore;
    // Not empty: the words that start the command before octrace (or the shell above), e.g.
    // {"/usr/bin/mpirun", "-np", "3"}: the first is the program run, by its path.
    std::vector<std::string> launcher;
};

// Runs octrace with `args`; stdout and stderr go to files in `captureDir` (created if needed).
inline RunResult runOctrace(const std::vector<std::string>& args, const fs::path& captureDir,
                            const RunOptions& opt = {}) {
    static std::atomic<int> counter{0};
    fs::create_directories(captureDir);
    const std::string tag = std::to_string(::getpid()) + "." + std::to_string(counter++);
    const std::string outPath = (captureDir / ("stdout." + tag)).string();
    const std::string errPath = (captureDir / ("stderr." + tag)).string();
    std::vector<std::string> argv = {octraceBinary()};
    if (!opt.shellBefore.empty())
        argv = {"/bin/sh", "-c", "set -e\n" + opt.shellBefore + "\nexec \"$0\" \"$@\"",
                octraceBinary()};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.begin(), opt.launcher.begin(), opt.launcher.end());
    std::vector<char*> cargv;
    for (std::string& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(
        &actions, 1, opt.stdoutPath.empty() ? outPath.c_str() : opt.stdoutPath.c_str(),
        O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    std::string oldDir;
    if (!opt.workingDir.empty()) {
        oldDir = fs::current_path().string();
        fs::current_path(opt.workingDir);  // posix_spawn_file_actions_addchdir_np is glibc 2.29+
    }
    // The terminating signals start at their default action, as in a user's terminal, even when
    // the test runs as a background job (which ignores SIGINT) or under a harness that ignores
    // SIGHUP: the signal tests rely on it.
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t defaults;
    sigemptyset(&defaults);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGXFSZ}) sigaddset(&defaults, sig);
    struct rlimit oldLimit = {0, 0};
    struct sigaction oldXfsz;
    if (opt.fileSizeLimit > 0) {
        // Inherited through posix_spawn: set in this process for the moment of the spawn.
        getrlimit(RLIMIT_FSIZE, &oldLimit);
        struct rlimit lim = {rlim_t(opt.fileSizeLimit), oldLimit.rlim_max};
        setrlimit(RLIMIT_FSIZE, &lim);
        struct sigaction ign;
        std::memset(&ign, 0, sizeof ign);
        ign.sa_handler = SIG_IGN;
        sigaction(SIGXFSZ, &ign, &oldXfsz);
        sigdelset(&defaults, SIGXFSZ);
    }
    struct rlimit oldAs = {0, 0};
    if (opt.addressSpaceLimit > 0) {
        getrlimit(RLIMIT_AS, &oldAs);
        struct rlimit lim = {rlim_t(opt.addressSpaceLimit), oldAs.rlim_max};
        setrlimit(RLIMIT_AS, &lim);
    }
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
    RunResult r;
    pid_t pid = 0;
    const auto start = std::chrono::steady_clock::now();
    const int rc = posix_spawn(&pid, argv[0].c_str(), &actions, &attr, cargv.data(), environ);
    if (opt.fileSizeLimit > 0) {
        setrlimit(RLIMIT_FSIZE, &oldLimit);
        sigaction(SIGXFSZ, &oldXfsz, nullptr);
    }
    if (opt.addressSpaceLimit > 0) setrlimit(RLIMIT_AS, &oldAs);
    posix_spawnattr_destroy(&attr);
    posix_spawn_file_actions_destroy(&actions);
    if (!oldDir.empty()) fs::current_path(oldDir);
    if (rc != 0) {
        r.err = "posix_spawn failed: " + std::string(std::strerror(rc));
        return r;
    }
    int status = 0;
    struct rusage usage;
    std::memset(&usage, 0, sizeof usage);
    for (;;) {
        const pid_t done = wait4(pid, &status, WNOHANG, &usage);
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (done == pid) break;
        if (r.seconds > opt.timeoutSeconds) {
            kill(pid, SIGKILL);
            wait4(pid, &status, 0, &usage);
            r.timedOut = true;
            break;
        }
        if (opt.whileRunning) opt.whileRunning(pid, r.seconds);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    r.peakRssBytes = uint64_t(usage.ru_maxrss) * 1024;  // KiB on Linux
    if (!r.timedOut && WIFEXITED(status)) r.status = WEXITSTATUS(status);
    if (!r.timedOut && WIFSIGNALED(status)) r.signal = WTERMSIG(status);
    r.out = readFile(outPath);
    r.err = readFile(errPath);
    fs::remove(outPath);
    fs::remove(errPath);
    return r;
}

// The same with a shell-style argument string (words split by splitWords).
inline RunResult runOctrace(const std::string& args, const fs::path& captureDir,
                            const RunOptions& opt = {}) {
    return runOctrace(splitWords(args), captureDir, opt);
}

inline std::string show(const RunResult& r) {
    std::string how = r.timedOut ? "killed after " + std::to_string(r.seconds) + " s"
                      : r.signal ? "ended by signal " + std::to_string(r.signal)
                                 : "exit " + std::to_string(r.status);
    return how + "\n--- stdout ---\n" + r.out + "--- stderr ---\n" + r.err;
}

// A failed run as the CLI promises: a non-zero exit, exactly one line on stderr, and it is
// octrace's error line.
inline ::testing::AssertionResult isOneLineError(const RunResult& r) {
    if (r.timedOut || r.signal)
        return ::testing::AssertionFailure() << "did not exit normally\n" << show(r);
    if (r.status == 0) return ::testing::AssertionFailure() << "exit 0\n" << show(r);
    size_t lines = size_t(std::count(r.err.begin(), r.err.end(), '\n'));
    if (lines != 1 || r.err.back() != '\n')
        return ::testing::AssertionFailure() << lines << " lines on stderr\n" << show(r);
    if (r.err.rfind("octrace: error:", 0) != 0)
        return ::testing::AssertionFailure() << "stderr does not start with the error\n" << show(r);
    return ::testing::AssertionSuccess();
}

// A verdict other than PASS (validate, certify): exit status `status` (1 FAIL, 3 INCOMPLETE) and
// one line on stderr, "octrace: certification FAIL ..." or "octrace: validation FAILED ...".
inline ::testing::AssertionResult isOneLineVerdict(const RunResult& r, int status) {
    if (r.timedOut || r.signal)
        return ::testing::AssertionFailure() << "did not exit normally\n" << show(r);
    if (r.status != status)
        return ::testing::AssertionFailure() << "exit " << r.status << ", not " << status << "\n"
                                             << show(r);
    size_t lines = size_t(std::count(r.err.begin(), r.err.end(), '\n'));
    if (lines != 1 || r.err.back() != '\n')
        return ::testing::AssertionFailure() << lines << " lines on stderr\n" << show(r);
    if (r.err.rfind("octrace: certification ", 0) != 0 &&
        r.err.rfind("octrace: validation ", 0) != 0)
        return ::testing::AssertionFailure() << "stderr does not start with the verdict\n"
                                             << show(r);
    return ::testing::AssertionSuccess();
}

// A fresh folder under the system's temporary folder, removed with everything in it.
class TempDir {
public:
    explicit TempDir(const std::string& tag) {
        static std::atomic<int> counter{0};
        path_ = fs::temp_directory_path() / ("octrace_" + tag + "_" + std::to_string(::getpid()) +
                                             "_" + std::to_string(counter++));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const fs::path& path() const { return path_; }
    std::string str(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

}  // namespace octtest
