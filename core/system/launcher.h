// Where a parallel launcher placed this process, as its environment says: mpirun (Open MPI),
// MPICH's Hydra or Slurm's srun each set a rank, a world size and a rank on the node before the
// program starts. The MPI layer (dist/ranks.h) starts MPI only when a launcher placed the
// process, so a plain `octrace ...` never touches MPI; the CUDA backend picks the device of the
// local rank from the same reading (gpu/).
#pragma once

namespace oct {

struct LauncherPlacement {
    bool launched = false;  // a launcher's variables were found
    int rank = 0, size = 1, localRank = 0;
};

// Open MPI's OMPI_COMM_WORLD_{RANK,SIZE,LOCAL_RANK}, then PMI_RANK/PMI_SIZE with
// MPI_LOCALRANKID (Hydra), then SLURM_PROCID/SLURM_STEP_NUM_TASKS/SLURM_LOCALID
// (srun). A variable that
// is not a number in range is ignored, as if absent.
LauncherPlacement launcherPlacement();

}  // namespace oct
