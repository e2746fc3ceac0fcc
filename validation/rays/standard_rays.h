// `octrace rays` without the files: the sets a --set list names on a scene, and the standard
// rays and manifest they make (the shadow set's camera hits from the backend list's reference,
// Embree). The command line and the Python module (octrace.rays) both call these, so the same
// spec gives the same bytes through either.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "validation/rays/ray_manifest.h"
#include "validation/rays/ray_sets.h"

namespace oct {

// The sets `octrace rays` and octrace.rays make when none are named.
constexpr const char* kDefaultRaySets = "all";

// A --set list that names no set, an unknown set, one twice, or a set the scene cannot make.
class RaySetChoiceError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// The sets of a list of names or "all" (comma-separated, spaces around items ignored): "all" is
// every set the scene can make (raySetsUnavailable), each one left out named in `notes`; a set
// named explicitly that the scene cannot make is refused with the reason.
std::vector<const RaySetDesc*> chooseRaySets(const std::string& text, const Scene& scene,
                                             std::vector<std::string>& notes);

struct StandardRays {
    RaySet rays;
    RayManifest manifest;
};

// Checks the sets' memory against the machine's (raySetPeakBytes; `what` names the request in
// the message and `advice` says what to ask for instead, in the caller's spelling), then draws
// the rows, measures octrace's own kernel on them (RaySet::baseline: each set's expected
// ambiguous count, measureAmbiguityBaseline) and describes them.
StandardRays makeStandardRays(const Scene& scene, const RaySetSpec& spec, const std::string& what,
                              const std::string& advice);

}  // namespace oct
