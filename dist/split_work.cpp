#include "dist/split_work.h"

#include <cstring>

#include "dist/ranks.h"

namespace oct {
namespace {

// One channel of the band into the whole Film's: `perPixel` elements of T a pixel.
template <class T>
void gatherChannel(Ranks& ranks, const std::vector<T>& band, std::vector<T>& whole, int width,
                   int height, int perPixel, bool everywhere) {
    const size_t rowBytes = size_t(width) * size_t(perPixel) * sizeof(T);
    if (everywhere) {
        const RowRange rows = ranks.rowsOf(uint64_t(height));
        if (!band.empty())
            std::memcpy(reinterpret_cast<char*>(whole.data()) + rows.begin * rowBytes, band.data(),
                        rows.count() * rowBytes);
        ranks.allgatherRows(whole.data(), uint64_t(height), rowBytes);
    } else {
        ranks.gatherRows(band.data(), whole.data(), uint64_t(height), rowBytes);
    }
}

}  // namespace

void renderByRows(const FrameParams& frame, const RenderFn& render, Film& film, bool everywhere) {
    Ranks& ranks = Ranks::world();
    if (!ranks.distributed()) return render(frame, film);
    const RowRange rows = ranks.rowsOf(uint64_t(frame.height));
    Film band(frame.width, 0);
    if (rows.count() > 0) {  // bandRows 0 would mean the whole image
        FrameParams p = frame;
        p.bandBegin = int(rows.begin);
        p.bandRows = int(rows.count());
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
    const RowRange rows = ranks.rowsOf(batch.count);
    RayBatchView mine = batch;
    mine.rays = batch.rays + 8 * rows.begin;
    mine.t = batch.t + rows.begin;
    mine.prim = batch.prim + rows.begin;
    if (batch.nodes) mine.nodes = batch.nodes + rows.begin;
    if (batch.primsTested) mine.primsTested = batch.primsTested + rows.begin;
    mine.count = rows.count();
    if (mine.count > 0) trace(mine);
    auto gather = [&](auto* all) {
        if (!all) return;
        if (everywhere)
            ranks.allgatherRows(all, batch.count, sizeof(*all));
        else
            ranks.gatherRows(all + rows.begin, all, batch.count, sizeof(*all));
    };
    gather(batch.t);
    gather(batch.prim);
    gather(batch.nodes);
    gather(batch.primsTested);
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
