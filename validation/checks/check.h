// The checks of `octrace validate`, one list (checks.cpp) that validateScene runs, its reports
// print and its failure message names. A check reads what validateScene prepared once for the
// scene, writes its typed result into the report (validate.h, where tests and callers read it)
// and describes that result as a CheckResult. Adding a check: a file here with its class, a
// field for its result in validate.h, and one line in checks.cpp.
#pragma once

#include <vector>

#include "validation/report/check_result.h"
#include "validation/validate.h"

namespace oct {

// What validateScene prepares once per scene: the frames, the ray sets, Embree's answers.
struct CheckInputs {
    CheckInputs(const Scene& s, const Octree* tree, const ValidateOptions& o,
                const HitClassifier& c)
        : scene(s), canonical(tree), options(o), classifier(c) {}
    const Scene& scene;
    const Octree* canonical;  // null without one
    const ValidateOptions& options;
    const HitClassifier& classifier;
    FrameParams frame, frameInside;  // the default view; the inside view (validate.h)
    Film reference, referenceInside;
    RaySet rays;
    HitArrays referenceHits;
    OcclusionQuery referenceOccluded;
};

// One tracer's answers to the shared inputs, made once for every run check.
struct TracerAnswers {
    const TracerUnderTest& tracer;
    const Film& film;       // of CheckInputs::frame
    const HitArrays& hits;  // of CheckInputs::rays
};

// A check of each tracer under test.
class RunCheck {
public:
    virtual ~RunCheck() = default;
    virtual const char* name() const = 0;
    virtual void run(const CheckInputs& in, const TracerAnswers& ours, RunReport& out) const = 0;
    virtual CheckResult result(const RunReport& run, double maxAmbiguousRate) const = 0;
};

// A check of the scene (its canonical octree), once.
class SceneCheck {
public:
    virtual ~SceneCheck() = default;
    virtual const char* name() const = 0;
    virtual void run(const CheckInputs& in, ValidationReport& out) const = 0;
    virtual CheckResult result(const ValidationReport& rep) const = 0;
};

const std::vector<const RunCheck*>& runChecks();  // film, structure, rays
// replication, box contract, and the kernel's rays against their definitions: camera, shadow
// ray, ray scaling
const std::vector<const SceneCheck*>& sceneChecks();

}  // namespace oct
