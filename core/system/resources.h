// What this machine lends a command: memory and cores. Every count and size option whose work
// grows with its value is bounded by them (docs/ROBUSTNESS.md, "Work without bounds"): the
// memory a command needs is estimated before it is allocated and refused with the figure, so
// that too large a --size or --count is one line at once, not a bad_alloc after minutes (or the
// kernel's OOM killer, which sends SIGKILL and leaves no line at all).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace oct {

// A request beyond what the machine has: one line naming the need, the limit and what to do.
class ResourceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct MemoryLimit {
    uint64_t bytes = 0;  // what the process may still allocate
    // Where the figure comes from, after "the N": "left of the 23.5 GiB of physical memory",
    // "left under the address-space limit of 1.00 GiB (ulimit -v)".
    std::string source;
};

// What the process may still allocate: physical memory (sysconf(_SC_PHYS_PAGES) *
// sysconf(_SC_PAGE_SIZE)) less what it holds resident, or, when RLIMIT_AS is set and leaves
// less, that limit less the address space it maps (/proc/self/statm), which counts against it.
// Either way the figure is what is left now, so that a check made between two allocations
// (the builder's, level by level) counts only what comes next. Read on every call: the limit
// is the process's, and tests lower it.
MemoryLimit memoryLimit();

// Cores online (sysconf(_SC_NPROCESSORS_ONLN)), at least 1.
int onlineCores();

// The most OpenMP threads a caller may ask for (--threads, the Python module's threads=):
// kThreadsPerCore times the cores online. Threads past the cores only take turns on them, and
// each reserves a stack: `--threads 4096` under a memory limit ended in libgomp's "Thread
// creation failed", an abort with no octrace line. Eight per core leaves room to oversubscribe
// on purpose (a test of thread counts on a small machine) and keeps the stacks to a few hundred
// MiB even on large machines.
constexpr int kThreadsPerCore = 8;
inline int maxThreads() { return kThreadsPerCore * onlineCores(); }

// "512 MiB", "8.6 GiB": binary units, three significant digits.
std::string bytesText(uint64_t bytes);

// "" when `bytes` fit memoryLimit(), else why not: "<what> needs about <bytes> of memory, more
// than the <limit> <source>; <advice>". `what` names the work and its options ("octrace rays
// --size 16384x16384 --count 30000"), `advice` what to lower. For callers with an error type
// of their own (the builder's OctreeError).
std::string memoryShortfall(uint64_t bytes, const std::string& what, const std::string& advice);
// The same against a limit read before (what was left when a level began).
std::string memoryShortfall(uint64_t bytes, const std::string& what, const std::string& advice,
                            const MemoryLimit& limit);
// The same, thrown as `Error` (ResourceError, or the caller's own: OctreeError, SceneError).
template <class Error = ResourceError>
void checkMemory(uint64_t bytes, const std::string& what, const std::string& advice) {
    const std::string why = memoryShortfall(bytes, what, advice);
    if (!why.empty()) throw Error(why);
}
template <class Error>
void checkMemory(uint64_t bytes, const std::string& what, const std::string& advice,
                 const MemoryLimit& limit) {
    const std::string why = memoryShortfall(bytes, what, advice, limit);
    if (!why.empty()) throw Error(why);
}

// a * b, or UINT64_MAX when it overflows: estimates of absurd requests stay absurd, not small.
uint64_t saturatingMul(uint64_t a, uint64_t b);
uint64_t saturatingAdd(uint64_t a, uint64_t b);

// Large arrays on 2 MiB pages where the kernel offers them (transparent huge pages in "madvise"
// mode, as on Debian): on this project's virtual machines the first touch of every 4 KiB page
// is a fault of some 18 us, which made most of a 34 MB mesh's load and of a 128 MB ray file's
// read (docs/PERFORMANCE.md, "Loading meshes"). A hint only: nothing changes where the kernel
// declines. adviseHugePages takes any range (one holding no whole 2 MiB-aligned page it leaves
// alone).
void adviseHugePages(const void* data, size_t bytes);

// Reserves a vector's room for `count` T and advises it onto huge pages before anything is
// written there (the loaders' arrays, the builder's, the compact conversion's).
template <class T>
void reserveHuge(std::vector<T>& v, size_t count) {
    v.reserve(count);
    adviseHugePages(v.data(), v.capacity() * sizeof(T));
}

// An uninitialised array of `count` T, 2 MiB-aligned and advised onto huge pages from 256 KiB
// on (one huge page's first touch, 2 MiB zeroed, costs less than 64 faults of 4 KiB), plainly
// allocated below; throws std::bad_alloc when the memory is not there.
struct FreeDeleter {
    void operator()(void* p) const { std::free(p); }
};
template <class T>
using HugeArray = std::unique_ptr<T[], FreeDeleter>;
void* allocateHuge(size_t bytes);
template <class T>
HugeArray<T> makeHugeArray(size_t count) {
    return HugeArray<T>(static_cast<T*>(allocateHuge(count * sizeof(T))));
}

}  // namespace oct
