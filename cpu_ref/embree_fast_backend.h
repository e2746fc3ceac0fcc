// The embree-fast backend: Embree in its default mode (no RTC_SCENE_FLAG_ROBUST), the way most
// applications call it. Not a reference: a third-party tracer whose hits `octrace certify`
// judges (docs/CERTIFY.md). Embree builds its own BVH; shading is the core kernel's.
#pragma once

#include "core/backend/backend.h"

namespace oct {

BackendDesc embreeFastBackend();

}  // namespace oct
