// Private to lib/src/param: the solver libraries' own thread teams kept out of lodbake's solves.
// CHOLMOD (SuiteSparse) is built with OpenMP and opens parallel regions of a fixed team size
// (4 threads, whatever the cores) inside every supernodal factorisation. On the small systems of a
// chart solve each region costs more in waking, spinning and joining its team than its work, and
// the team competes with lodbake's own workers (parallelFor), which already solve charts in
// parallel. The regions only split independent writes, so the factor is the same with one thread.
#pragma once

namespace lodbake {

// On the calling thread, before a Ceres solve or a CHOLMOD factorisation: OpenMP parallel regions
// run on the calling thread alone (max-active-levels 0, an ICV of the calling thread's data
// environment in recent libgomp, process-wide in older ones; either way set from code, not from
// the environment). Cheap after the first call on a thread; a no-op without OpenMP. Defined in
// solver_threads.cpp.
void keepSolverThreadsSerial();

}  // namespace lodbake
