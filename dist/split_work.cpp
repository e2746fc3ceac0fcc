#include "dist/split_work.h"

#include "dist/ranks.h"

namespace oct {
namespace {

// One channel of the band (its rows packed) into the whole Film's: `perPixel` elements of T a
// pixel, rank 0's or every rank's.
template <class T>
void gatherChannel(Ranks& ranks, const std::vector<T>& band, std::vector<T>& whole, int width,
                   int height, int perPixel, bool everywhere) {
    const size_t rowBytes = size_t(width) * size_t(perPixel) * sizeof(T);
    if (everywhere)
        ranks.allgatherRows(band.data(), whole.data(), uint64_t(height), rowBytes);
    else
        ranks.gatherRows(band.data(), whole.data(), uint64_t(height), rowBytes);
}

}  // namespace

void renderByRows(const FrameParams& frame, const RenderFn& render, Film& film, bool everywhere) {
    Ranks& ranks = Ranks::world();
    if (!ranks.distributed()) return render(frame, film);
    const RowDeal deal = ranks.deal(uint64_t(frame.height));
    const uint64_t rows = deal.countOf(ranks.rank());
    Film band(frame.width, 0);
    if (rows > 0) {  // bandRows 0 would mean the whole image
        FrameParams p = frame;
        p.bandBegin = int(uint64_t(ranks.rank()) * deal.block);
        p.bandRows = int(rows);
        p.bandBlock = int(deal.block);
        p.bandStride = int(deal.block * uint64_t(deal.ranks));
        render(p, band);
    }
    Film whole;
    if (ranks.root() || everywhere) whole = Film(frame.width, frame.height);
    const int w = frame.width, h = frame.height;
    gatherChannel(ranks, band.rgb, whole.rgb, w, h, 3, everywhere);
    gatherChannel(ranks, band.t, whole.t, w, h, 1, everywhere);
    gatherChannel(ranks, band.prim, whole.prim, w, h, 1, everywhere);
    gatherChannel(ranks, band.nodes, whole.nodes, w, h, 1, everywhere);
    gatherChannel(ranks, band.primsTested, whole.primsTested, w, h, 1, everywhere);
    gatherChannel(ranks, band.shadow, whole.shadow, w, h, 1, everywhere);
    film = std::move(whole);
}

void traceByRows(RayBatchView batch, const std::function<void(RayBatchView)>& trace,
                 bool everywhere) {
    Ranks& ranks = Ranks::world();
    if (!ranks.distributed()) return trace(batch);
    // This rank's rows packed into one batch, traced at once, the answers put back in place.
    const std::vector<RowRange> blocks = ranks.blocksOf(batch.count);
    uint64_t m = 0;
    for (const RowRange& b : blocks) m += b.count();
    std::vector<float> rays(m * 8), t(m);
    std::vector<int32_t> prim(m);
    std::vector<uint32_t> nodes(batch.nodes ? m : 0), tested(batch.primsTested ? m : 0);
    packRows(blocks, batch.rays, rays.data(), 8 * sizeof(float));
    RayBatchView mine{rays.data(), t.data(), prim.data(), m};
    if (batch.nodes) mine.nodes = nodes.data();
    if (batch.primsTested) mine.primsTested = tested.data();
    if (m > 0) trace(mine);
    auto place = [&](const auto* packed, auto* all) {
        if (!all) return;
        if (everywhere)
            ranks.allgatherRows(packed, all, batch.count, sizeof(*all));
        else
            ranks.gatherRows(packed, all, batch.count, sizeof(*all));
    };
    place(t.data(), batch.t);
    place(prim.data(), batch.prim);
    place(nodes.data(), batch.nodes);
    place(tested.data(), batch.primsTested);
}

FrameRun renderWithByRows(const BackendDesc& backend, const BuiltScene& scene,
                          const FrameParams& frame, Film& film) {
    Ranks& ranks = Ranks::world();
    if (!ranks.distributed()) return renderWith(backend, scene, frame, film);
    FrameRun run;
    renderByRows(
        frame, [&](const FrameParams& band, Film& f) { run = renderWith(backend, scene, band, f); },
        film, false);
    run.prepareSeconds = ranks.maxOver(run.prepareSeconds);
    run.buildSeconds = ranks.maxOver(run.buildSeconds);
    run.frameSeconds = {ranks.maxOver(run.frameSeconds.empty() ? 0.0 : run.frameSeconds[0])};
    if (ranks.root()) countRays(film, run.primaryRays, run.shadowRays);
    return run;
}

}  // namespace oct
