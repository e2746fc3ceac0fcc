// validate across MPI ranks (docs/DISTRIBUTED.md): the WorkShare that splits every film by image
// rows and every ray batch and the per-ray rechecks by ray rows (dist/split_work.h), so that each
// rank holds the same films and answers and computes the same report.
#pragma once

#include "validation/validate.h"

namespace oct {

// The share of the run's ranks (Ranks::world()).
WorkShare rankShare();

// The tracer's render and trace calls made through `share`.
void shareTracer(TracerUnderTest& tracer, const WorkShare& share);

}  // namespace oct
