// The OpenMP backend: our layouts, traced by the core kernel in an OpenMP loop.
#pragma once

#include "core/backend/backend.h"

namespace oct {

BackendDesc cpuBackend();

}  // namespace oct
