#include "core/system/launcher.h"

#include <cstdlib>
#include <string>

namespace oct {
namespace {

// The variable as an int in [lo, hi], or -1.
int envInt(const char* name, int lo, int hi) {
    const char* v = std::getenv(name);
    if (!v || !*v) return -1;
    char* end = nullptr;
    const long x = std::strtol(v, &end, 10);
    if (*end != '\0' || x < lo || x > hi) return -1;
    return int(x);
}

bool read(const char* rank, const char* size, const char* local, LauncherPlacement& p) {
    constexpr int kMax = 1 << 24;
    const int s = envInt(size, 1, kMax), r = envInt(rank, 0, kMax - 1);
    if (s < 0 || r < 0 || r >= s) return false;
    const int l = envInt(local, 0, s - 1);
    p = {true, r, s, l < 0 ? 0 : l};
    return true;
}

}  // namespace

LauncherPlacement launcherPlacement() {
    LauncherPlacement p;
    if (read("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_LOCAL_RANK", p))
        return p;
    if (read("PMI_RANK", "PMI_SIZE", "MPI_LOCALRANKID", p)) return p;
    // srun's step variables (a batch script's own shell has SLURM_NTASKS but no step of tasks).
    if (read("SLURM_PROCID", "SLURM_STEP_NUM_TASKS", "SLURM_LOCALID", p)) return p;
    return {};
}

}  // namespace oct
