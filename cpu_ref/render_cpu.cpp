#include "cpu_ref/render_cpu.h"

namespace oct {

void setCpuThreads(int threads) {
    if (threads > 0) omp_set_num_threads(threads);
}

}  // namespace oct
