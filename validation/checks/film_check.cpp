// The per-pixel check (policy/hit_validation.h): each tracer's frame against Embree's, primary
// and shadow rays, and the same on the inside view when ValidateOptions::lightInside.
#include "validation/checks/check.h"
#include "validation/report/report.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using namespace report_detail;

class FilmCheck : public RunCheck {
public:
    const char* name() const override { return "film"; }

    void run(const CheckInputs& in, const TracerAnswers& ours, RunReport& out) const override {
        out.film =
            validateFilm(in.classifier, in.frame, ours.film, in.reference, in.referenceOccluded);
        if (!in.options.lightInside) return;
        Film inside;
        ours.tracer.render(in.frameInside, inside);
        out.lightInside = validateFilm(in.classifier, in.frameInside, inside, in.referenceInside,
                                       in.referenceOccluded);
    }

    CheckResult result(const RunReport& run, double maxAmbiguousRate) const override {
        CheckResult r;
        r.pass = run.film.passes(maxAmbiguousRate) &&
                 (!run.lightInside || run.lightInside->passes(maxAmbiguousRate));
        auto complete = [](const FilmValidation& f) {
            return f.primary.complete() && f.shadow.complete();
        };
        r.complete = complete(run.film) && (!run.lightInside || complete(*run.lightInside));
        r.json = jsonOf(run);
        r.summary = summaryOf(run);
        return r;
    }

private:
    static json jsonOf(const RunReport& run) {
        json shadow = toJson(run.film.shadow);
        shadow["resolved_by_rerun"] = run.film.shadowResolvedByRerun;
        shadow["not_compared"] = run.film.shadowNotCompared;
        json wp = json::array(), ws = json::array();
        for (const Finding& f : run.film.worstPixels) wp.push_back(findingJson(f, true));
        for (const ShadowFinding& f : run.film.worstShadows) ws.push_back(shadowJson(f));
        json inside = nullptr;
        if (run.lightInside)
            inside = {{"primary", toJson(run.lightInside->primary)},
                      {"shadow", toJson(run.lightInside->shadow)}};
        return {{"primary", toJson(run.film.primary)},
                {"shadow", shadow},
                {"inside_view", inside},
                {"worst_pixels", wp},
                {"worst_shadow_rays", ws}};
    }

    static std::string summaryOf(const RunReport& run) {
        std::string s =
            "  check     compared     agree    ties ambiguous   wrong  amb. rate  max|dt|/ext\n";
        s += countsLine("primary", run.film.primary);
        s += countsLine("shadow", run.film.shadow);
        if (run.lightInside) {
            s += countsLine("in-prim", run.lightInside->primary);
            s += countsLine("in-shad", run.lightInside->shadow);
        }
        std::string reasons = reasonsText(run.film.primary);
        if (!reasons.empty()) s += "  primary ambiguous by reason:" + reasons + "\n";
        reasons = reasonsText(run.film.shadow);
        if (!reasons.empty()) s += "  shadow ambiguous by reason:" + reasons + "\n";
        if (run.film.shadowResolvedByRerun || run.film.shadowNotCompared)
            s +=
                fmt("  shadow: %llu differing states reproduced by Embree on our shadow ray "
                    "(agree); %llu pixels not compared (primary mismatch)\n",
                    (unsigned long long)run.film.shadowResolvedByRerun,
                    (unsigned long long)run.film.shadowNotCompared);
        // Pixels: the mismatches and ties, or else the largest |dt| that still agreed.
        int shown = 0;
        for (const Finding& f : run.film.worstPixels) {
            bool notable = f.cls != HitClass::Agree;
            if (shown == 8 || (!notable && shown > 0)) break;
            if (shown++ == 0)
                s += notable ? "  worst pixels (x,y: class [reasons] ours | embree | truth)\n"
                             : "  largest |dt| (x,y: class ours | embree)\n";
            s += fmt("    %4d,%-4d %-9s %-16s %s | %s", f.x, f.y, hitClassName(f.cls),
                     ("[" + reasonNames(f.reasons) + "]").c_str(), hitText(f.ours).c_str(),
                     hitText(f.reference).c_str());
            s += f.rechecked ? " | " + hitText(f.truth) + "\n" : std::string("\n");
        }
        shown = 0;
        for (const ShadowFinding& f : run.film.worstShadows) {
            if (f.cls == HitClass::Agree) continue;
            if (shown++ == 8) break;
            if (shown == 1)
                s += "  shadow rays (x,y: class [reasons] ours | embree | embree on our ray | "
                     "truth)\n";
            s += fmt("    %4d,%-4d %-9s %-16s %s | %s | %s | %s\n", f.x, f.y, hitClassName(f.cls),
                     ("[" + reasonNames(f.reasons) + "]").c_str(), shadowState(f.ours),
                     shadowState(f.reference),
                     f.referenceOnOurRay < 0 ? "-" : (f.referenceOnOurRay ? "occluded" : "lit"),
                     f.truthOccluded < 0 ? "-" : (f.truthOccluded ? "occluded" : "lit"));
        }
        return s;
    }
};

}  // namespace

const RunCheck& filmCheck() {
    static const FilmCheck check;
    return check;
}

}  // namespace oct
