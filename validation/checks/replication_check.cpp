// The replication check of the canonical octree against the exact overlap test
// (exact/replication.h), unless ValidateOptions::replication is off.
#include "validation/checks/check.h"
#include "validation/report/report.h"

namespace oct {
namespace {

class ReplicationCheck : public SceneCheck {
public:
    const char* name() const override { return "replication"; }

    void run(const CheckInputs& in, ValidationReport& out) const override {
        if (in.options.replication && in.canonical)
            out.replication = checkReplication(in.scene, *in.canonical);
    }

    CheckResult result(const ValidationReport& rep) const override {
        if (!rep.replication) return notRun("replication");
        CheckResult r;
        const ReplicationReport& x = *rep.replication;
        r.pass = x.passes();
        r.json = {{"replication", toJson(x)}};
        r.summary = "\n" + humanSummary(x);
        r.verdict = r.pass ? ", replication ok" : ", replication FAILED";
        if (!r.pass)
            r.failureText = ", " + std::to_string(x.falseNegatives) +
                            " replication false negatives, " + std::to_string(x.rangeErrors) +
                            " broken node ranges";
        return r;
    }
};

}  // namespace

const SceneCheck& replicationCheck() {
    static const ReplicationCheck check;
    return check;
}

}  // namespace oct
