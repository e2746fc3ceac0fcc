#include "cpu_ref/render_cpu.h"

#include <cstdlib>
#include <cstring>

namespace oct {
namespace {

bool cpuHas(HostIsa isa) {
#if defined(OCT_HOST_ISA_DISPATCH)
    if (isa == HostIsa::Avx2) return __builtin_cpu_supports("avx2");
#endif
    return isa == HostIsa::Baseline;
}

HostIsa initialIsa() {
    const char* asked = std::getenv("OCTRACE_HOST_ISA");
    if (asked && std::strcmp(asked, "baseline") == 0) return HostIsa::Baseline;
    return cpuHas(HostIsa::Avx2) ? HostIsa::Avx2 : HostIsa::Baseline;
}

HostIsa& currentIsa() {
    static HostIsa isa = initialIsa();
    return isa;
}

}  // namespace

void setCpuThreads(int threads) {
    if (threads > 0) omp_set_num_threads(threads);
}

bool availableOnHost(std::string& why) {
    why = "OpenMP on the host";
    return true;
}

HostIsa hostIsa() { return currentIsa(); }

bool setHostIsa(HostIsa isa) {
    if (!cpuHas(isa)) return false;
    currentIsa() = isa;
    return true;
}

const char* hostIsaName(HostIsa isa) { return isa == HostIsa::Avx2 ? "avx2" : "baseline"; }

}  // namespace oct
