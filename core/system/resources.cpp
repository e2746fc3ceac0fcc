#include "core/system/resources.h"

#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>

namespace oct {
namespace {

uint64_t physicalMemory() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || size <= 0) return std::numeric_limits<uint64_t>::max();  // unknown: no bound
    return saturatingMul(uint64_t(pages), uint64_t(size));
}

// The address space the process maps now (VmSize) and what of it is resident (VmRSS), or 0
// when /proc cannot tell.
struct Footprint {
    uint64_t mapped = 0, resident = 0;
};

Footprint footprint() {
    Footprint fp;
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return fp;
    unsigned long long size = 0, resident = 0;
    const bool ok = std::fscanf(f, "%llu %llu", &size, &resident) == 2;
    std::fclose(f);
    const long page = sysconf(_SC_PAGE_SIZE);
    if (!ok || page <= 0) return fp;
    return {saturatingMul(size, uint64_t(page)), saturatingMul(resident, uint64_t(page))};
}

uint64_t minus(uint64_t a, uint64_t b) { return a > b ? a - b : 0; }

}  // namespace

uint64_t saturatingMul(uint64_t a, uint64_t b) {
    if (a != 0 && b > std::numeric_limits<uint64_t>::max() / a)
        return std::numeric_limits<uint64_t>::max();
    return a * b;
}

uint64_t saturatingAdd(uint64_t a, uint64_t b) {
    return b > std::numeric_limits<uint64_t>::max() - a ? std::numeric_limits<uint64_t>::max()
                                                        : a + b;
}

MemoryLimit memoryLimit() {
    const Footprint fp = footprint();
    const uint64_t physical = physicalMemory();
    MemoryLimit m{minus(physical, fp.resident),
                  "left of the " + bytesText(physical) + " of physical memory"};
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        const uint64_t limit = uint64_t(as.rlim_cur), left = minus(limit, fp.mapped);
        if (left < m.bytes)
            m = {left,
                 "left under the address-space limit of " + bytesText(limit) + " (ulimit -v)"};
    }
    return m;
}

int onlineCores() {
    const long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? int(n) : 1;
}

std::string bytesText(uint64_t bytes) {
    const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 6) {
        v /= 1024.0;
        ++u;
    }
    char b[48];
    if (u == 0)
        std::snprintf(b, sizeof b, "%llu bytes", (unsigned long long)bytes);
    else
        std::snprintf(b, sizeof b,
                      v < 10    ? "%.2f %s"
                      : v < 100 ? "%.1f %s"
                                : "%.0f %s",
                      v, units[u]);
    return b;
}

std::string memoryShortfall(uint64_t bytes, const std::string& what, const std::string& advice) {
    return memoryShortfall(bytes, what, advice, memoryLimit());
}

std::string memoryShortfall(uint64_t bytes, const std::string& what, const std::string& advice,
                            const MemoryLimit& m) {
    if (bytes <= m.bytes) return "";
    return what + " needs about " + bytesText(bytes) + " of memory, more than the " +
           bytesText(m.bytes) + " " + m.source + "; " + advice;
}

void adviseHugePages(const void* data, size_t bytes) {
#if defined(MADV_HUGEPAGE)
    constexpr uintptr_t kPage = 4096, kHugePage = uintptr_t(2) << 20;
    // Only a whole 2 MiB-aligned page within the range can become a huge page.
    const uintptr_t firstHuge = (uintptr_t(data) + kHugePage - 1) & ~(kHugePage - 1);
    if (firstHuge + kHugePage > uintptr_t(data) + bytes) return;
    const uintptr_t begin = (uintptr_t(data) + kPage - 1) & ~(kPage - 1);
    const uintptr_t end = (uintptr_t(data) + bytes) & ~(kPage - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
    (void)data;
    (void)bytes;
#endif
}

void* allocateHuge(size_t bytes) {
    constexpr size_t kHugePage = size_t(2) << 20;
    if (bytes < kHugePage / 8) {
        void* p = std::malloc(std::max<size_t>(bytes, 1));
        if (!p) throw std::bad_alloc();
        return p;
    }
    const size_t room = (bytes + kHugePage - 1) & ~(kHugePage - 1);  // aligned_alloc's rule
    void* p = std::aligned_alloc(kHugePage, room);
    if (!p) throw std::bad_alloc();
    adviseHugePages(p, room);
    return p;
}

}  // namespace oct
