// The box-test contract of the kernel's slab tests on the canonical octree's boxes
// (exact/box_contract.h), on ValidateOptions::boxContractRays rays (0: off).
#include "validation/checks/check.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using report_detail::fmt;

class BoxContractCheck : public SceneCheck {
public:
    const char* name() const override { return "box_contract"; }

    void run(const CheckInputs& in, ValidationReport& out) const override {
        if (in.options.boxContractRays > 0 && in.canonical)
            out.boxContract =
                checkBoxContract(*in.canonical, in.options.boxContractRays, in.options.seed);
    }

    CheckResult result(const ValidationReport& rep) const override {
        if (!rep.boxContract) return notRun("box_contract");
        CheckResult r;
        const BoxContractReport& b = *rep.boxContract;
        r.pass = b.passes();
        r.json = {{"box_contract",
                   {{"pass", b.passes()},
                    {"rays", b.rays},
                    {"tests", b.tests},
                    {"exact_meets", b.meets},
                    {"touching", b.touching},
                    {"culled", b.culled},
                    {"loose", b.loose},
                    {"slack", kBoxContractSlack},
                    {"errors", b.errors}}}};
        r.summary = fmt(
            "\nbox test   %s: %llu rays on the octree's boxes, %llu float tests (intersectBox, "
            "childIntervals) against exact rationals: %llu meet, %llu of them touching; %llu "
            "culled a meeting ray, %llu accepted a ray missing the box grown by %g (of its edge or "
            "distance)\n",
            b.passes() ? "PASS" : "FAIL", (unsigned long long)b.rays, (unsigned long long)b.tests,
            (unsigned long long)b.meets, (unsigned long long)b.touching,
            (unsigned long long)b.culled, (unsigned long long)b.loose, kBoxContractSlack);
        for (const std::string& e : b.errors) r.summary += "  " + e + "\n";
        if (!r.pass)
            r.failureText = ", box-test contract broken (" + std::to_string(b.culled) +
                            " culled, " + std::to_string(b.loose) + " loose)";
        return r;
    }
};

}  // namespace

const SceneCheck& boxContractCheck() {
    static const BoxContractCheck check;
    return check;
}

}  // namespace oct
