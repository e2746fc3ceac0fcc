#include "core/system/resources.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <limits>

namespace oct {
namespace {

uint64_t physicalMemory() {
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
    if (pages <= 0 || size <= 0) return std::numeric_limits<uint64_t>::max();  // unknown: no bound
    return saturatingMul(uint64_t(pages), uint64_t(size));
}

// The address space the process maps now (VmSize), or 0 when /proc cannot tell.
uint64_t mappedBytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long pages = 0;
    const bool ok = std::fscanf(f, "%llu", &pages) == 1;
    std::fclose(f);
    const long size = sysconf(_SC_PAGE_SIZE);
    return ok && size > 0 ? saturatingMul(pages, uint64_t(size)) : 0;
}

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
    MemoryLimit m{physicalMemory(), "of physical memory"};
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        const uint64_t limit = uint64_t(as.rlim_cur), mapped = mappedBytes();
        const uint64_t left = limit > mapped ? limit - mapped : 0;
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

void checkMemory(uint64_t bytes, const std::string& what, const std::string& advice) {
    const MemoryLimit m = memoryLimit();
    if (bytes <= m.bytes) return;
    throw ResourceError(what + " needs about " + bytesText(bytes) + " of memory, more than the " +
                        bytesText(m.bytes) + " " + m.source + "; " + advice);
}

}  // namespace oct
