// The machine a sweep ran on, recorded beside its results: CPU, cores, OpenMP threads, memory,
// OS, compiler and build flags, Embree version, CUDA device, date, and the load averages that
// skew timings on a shared machine.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace oct {

// `cudaDevice` is the device's one-line description, empty when none was used.
nlohmann::ordered_json machineJson(const std::string& cudaDevice);
// The 1, 5 and 15 minute load averages, or null when /proc/loadavg cannot be read.
nlohmann::ordered_json loadAverage();

}  // namespace oct
