// Work split by rows across the ranks (dist/ranks.h, RowDeal). A frame by image rows: each rank
// renders its band (FrameParams::bandBegin .. bandStride: its blocks of rows) and the bands are
// gathered into the whole Film. A ray batch by ray rows: each rank traces its rows and the
// answers are gathered. A pixel's rays
// depend on its (x, y) and the frame only, a ray's answer on its row only, so what is gathered
// equals, byte for byte, what a single process computes (tests/dist/).
#pragma once

#include <functional>

#include "core/backend/backend.h"
#include "core/render/film.h"
#include "core/render/frame.h"

namespace oct {

// Fills and sizes a Film for a frame (or its band): a backend's render, a tracer under test's.
using RenderFn = std::function<void(const FrameParams&, Film&)>;

// Renders `frame` by bands: afterwards `film` holds the whole frame on rank 0, or on every rank
// when `everywhere` (validate's ranks each judge the whole Film). A rank whose band is empty
// (more ranks than rows) renders nothing. Collective (every rank calls it).
void renderByRows(const FrameParams& frame, const RenderFn& render, Film& film, bool everywhere);

// Traces `batch` by rows: each rank traces its rows (packed, in one call) with `trace`, then the
// t and prim arrays (and nodes and primsTested when given) hold every row's on rank 0, or on
// every rank when `everywhere`. Collective.
void traceByRows(RayBatchView batch, const std::function<void(RayBatchView)>& trace,
                 bool everywhere);

// renderWith by bands: the run's seconds are the slowest rank's, its ray counts the sum.
FrameRun renderWithByRows(const BackendDesc& backend, const BuiltScene& scene,
                          const FrameParams& frame, Film& film);

}  // namespace oct
