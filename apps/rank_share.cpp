#include "apps/rank_share.h"

#include "dist/ranks.h"
#include "dist/split_work.h"

namespace oct {

WorkShare rankShare() {
    WorkShare s;
    s.render = [](const FrameParams& p, Film& f, const WorkShare::RenderCall& call) {
        renderByRows(p, call, f, true);
    };
    s.trace = [](RayBatchView b, const WorkShare::TraceCall& call) { traceByRows(b, call, true); };
    s.rows = [](uint64_t n) {
        Ranks& ranks = Ranks::world();
        return RowShare{ranks.deal(n).block, uint32_t(ranks.rank()), uint32_t(ranks.size()),
                        [&ranks](void* data, uint64_t bytes) { ranks.combineOwned(data, bytes); }};
    };
    return s;
}

void shareTracer(TracerUnderTest& tracer, const WorkShare& share) {
    tracer.render = [share, render = tracer.render](const FrameParams& p, Film& f) {
        share.render(p, f, render);
    };
    tracer.trace = [share, trace = tracer.trace](RayBatchView b) { share.trace(b, trace); };
}

}  // namespace oct
