// One certification run on arrays already in memory: what `octrace certify` does after reading
// its files, and what the Python module (octrace.certify) and the C++ package's façade
// (api/octrace/certify.h) call on a user's own arrays. One code path, so the three agree.
// Order: the rows against the manifest, the scene against the manifest, the double truth, the
// ray sets rebuilt from the manifest (or one set "all"), Embree's reference, the per-ray check.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "validation/certify.h"
#include "validation/rays/ray_manifest.h"

namespace oct {

struct CertifyRun {
    CertifyReport report;
    RaySet rays;  // the sets as judged (certify's --diff-image draws the camera set)
    double truthSeconds = 0.0, setsSeconds = 0.0;
};

struct CertifyRunOptions {
    ValidationPolicy policy;
    Require require = Require::All;
    CertifyOptions query;           // how sets of one's own are judged
    std::string raysName = "rays";  // the rays as messages and the report name them
};

// Certifies `hits` (one per row; prim ids optional: HitArrays::primIds) for `rows` (N x 8 floats,
// the trace format) in `scene`. Throws std::invalid_argument (no rows, or arrays of another
// length) and IoError (the manifest disagrees with the rows or the scene) naming raysName.
CertifyRun certifyRows(const Scene& scene, std::vector<float> rows, const HitArrays& hits,
                       const std::optional<RayManifest>& manifest, const CertifyRunOptions& o);

}  // namespace oct
