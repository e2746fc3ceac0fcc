// The per-ray check of `octrace certify` (certify.h) on validate's seeded ray sets: each
// tracer's hits against Embree's.
#include "validation/checks/check.h"
#include "validation/report/report.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using report_detail::findingJson;

class RayCheck : public RunCheck {
public:
    const char* name() const override { return "rays"; }

    void run(const CheckInputs& in, const TracerAnswers& ours, RunReport& out) const override {
        CertifyOptions options;
        RowShare share;  // the rows whose rechecks this process does (ValidateOptions::share)
        if (in.options.share.rows) {
            share = in.options.share.rows(in.rays.count());
            options.share = &share;
        }
        out.rays = certifyRays(in.classifier, in.rays, ours.hits, in.referenceHits, options);
    }

    CheckResult result(const RunReport& run, double maxAmbiguousRate) const override {
        CheckResult r;
        const Outcome o = worse(run.rays.correct(maxAmbiguousRate), run.rays.watertight());
        r.pass = o != Outcome::Fail;
        r.complete = o != Outcome::Incomplete;
        json worst = json::array();
        for (const Finding& f : run.rays.worst) worst.push_back(findingJson(f, false));
        r.json = {{"rays", toJson(run.rays, maxAmbiguousRate)}, {"worst_rays", worst}};
        r.summary = "  rays (the per-ray check of octrace certify)\n" +
                    humanRaySets(run.rays, maxAmbiguousRate);
        return r;
    }
};

}  // namespace

const RunCheck& rayCheck() {
    static const RayCheck check;
    return check;
}

}  // namespace oct
