// The one list of backends: every launcher this build has (cpu_ref/: OpenMP, Embree, the
// scalar binary BVH; gpu/: CUDA), behind the interface of core/backend/backend.h. render, trace,
// validate, bench and the regression checks choose a launcher only through this list.
#pragma once

#include <string>
#include <vector>

#include "core/backend/backend.h"

namespace oct {

// Every backend this build has, in list order.
const std::vector<BackendDesc>& backends();
// "cpu, embree, embree-fast, bvh, cuda" (those this build has).
std::string backendNames();
// The backend called `name` in this build's list, or null.
const BackendDesc* findBackend(const std::string& name);
// The host launcher of our kernel (OpenMP): what `auto` falls back to, what validate and the
// regression checks trace with unless told otherwise.
const BackendDesc& hostBackend();
// The ground truth (BackendDesc::reference): Embree in robust mode.
const BackendDesc& referenceBackend();
// The backend called `name`, or for "auto" the CUDA one when a device answers, else the CPU;
// `note` receives what auto chose and why. Throws std::runtime_error naming the value and the
// choices for an unknown name, and the reason for a backend that cannot run here.
const BackendDesc& resolveBackend(const std::string& name, std::string& note);

}  // namespace oct
