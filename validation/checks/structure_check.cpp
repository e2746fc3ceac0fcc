// The layout's structure against the canonical octree (exact/layout_structure.h), for a tracer
// with a node lookup when there is a canonical octree.
#include "validation/checks/check.h"
#include "validation/report/report_util.h"

namespace oct {
namespace {

using nlohmann::json;
using report_detail::fmt;

class StructureCheck : public RunCheck {
public:
    const char* name() const override { return "structure"; }

    void run(const CheckInputs& in, const TracerAnswers& ours, RunReport& out) const override {
        if (ours.tracer.lookup && in.canonical)
            out.structure = checkLayoutStructure(*in.canonical, ours.tracer.lookup);
    }

    CheckResult result(const RunReport& run, double) const override {
        if (!run.structure) return notRun("structure");
        CheckResult r;
        const StructureReport& st = *run.structure;
        r.pass = st.passes();
        r.json = {{"structure",
                   {{"pass", st.passes()},
                    {"nodes", st.nodes},
                    {"missing", st.missing},
                    {"wrong_type", st.wrongType},
                    {"wrong_box", st.wrongBox},
                    {"wrong_list", st.wrongList},
                    {"broken", st.broken},
                    {"errors", st.errors}}}};
        r.summary =
            fmt("  structure %s: %llu canonical nodes looked up through the layout; %llu "
                "missing, %llu of another kind, %llu with another box, %llu with another "
                "list, %llu lookups out of its arrays\n",
                st.passes() ? "PASS" : "FAIL", (unsigned long long)st.nodes,
                (unsigned long long)st.missing, (unsigned long long)st.wrongType,
                (unsigned long long)st.wrongBox, (unsigned long long)st.wrongList,
                (unsigned long long)st.broken);
        for (const std::string& e : st.errors) r.summary += "    " + e + "\n";
        return r;
    }
};

}  // namespace

const RunCheck& structureCheck() {
    static const StructureCheck check;
    return check;
}

}  // namespace oct
