#include "bench/sweep/machine.h"

#include <embree3/rtcore_config.h>
#include <omp.h>
#include <sys/utsname.h>

#include <ctime>
#include <fstream>
#include <thread>

namespace oct {
namespace {

using json = nlohmann::ordered_json;

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0 || line.rfind("Model", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos)
                return line.substr(line.find_first_not_of(" ", colon + 1));
        }
    }
    return "unknown";
}

uint64_t memoryBytes() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    while (in >> key >> kib) {
        if (key == "MemTotal:") return kib * 1024;
        in.ignore(1 << 10, '\n');
    }
    return 0;
}

std::string compilerName() {
#if defined(__clang__)
    return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
    return std::string("gcc ") + __VERSION__;
#else
    return "unknown";
#endif
}

std::string utcNow() {
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

}  // namespace

// Other work on the machine skews timings, so the results record the load at the start and
// the end of the sweep.
json loadAverage() {
    std::ifstream in("/proc/loadavg");
    double a = 0, b = 0, c = 0;
    if (!(in >> a >> b >> c)) return nullptr;
    return json::array({a, b, c});
}

json machineJson(const std::string& cudaDevice) {
    utsname u{};
    uname(&u);
#ifdef __OPTIMIZE__
    bool optimized = true;
#else
    bool optimized = false;
#endif
#ifdef NDEBUG
    bool ndebug = true;
#else
    bool ndebug = false;
#endif
#ifdef OCT_HAVE_CUDA
    bool cudaBuild = true;
#else
    bool cudaBuild = false;
#endif
    return {{"cpu_model", cpuModel()},
            {"logical_cores", std::thread::hardware_concurrency()},
            {"omp_threads", omp_get_max_threads()},
            {"memory_bytes", memoryBytes()},
            {"os", std::string(u.sysname) + " " + u.release + " " + u.machine},
            {"compiler", compilerName()},
            // "cuda": the toolkit was found at configure time. check-lists: not a name
            {"build", {{"optimized", optimized}, {"ndebug", ndebug}, {"cuda", cudaBuild}}},
            {"embree_version", RTC_VERSION_STRING},
            {"cuda_device", cudaDevice.empty() ? json(nullptr) : json(cudaDevice)},
            {"date_utc", utcNow()},
            {"load_average_start", loadAverage()},
            {"load_average_end", nullptr}};
}

}  // namespace oct
