// keepSolverThreadsSerial (solver_threads.h): OpenMP's regions inside CHOLMOD run serially.
#include "param/solver_threads.h"

#ifdef LODBAKE_HAVE_OPENMP
#include <omp.h>
#endif

namespace lodbake {

void keepSolverThreadsSerial() {
#ifdef LODBAKE_HAVE_OPENMP
    thread_local bool done = false;
    if (done) return;
    // A parallel region at nesting level 0 is active only below max-active-levels: with 0 every
    // region, whatever its num_threads clause, gets a team of one (no thread woken).
    omp_set_max_active_levels(0);
    done = true;
#endif
}

}  // namespace lodbake
