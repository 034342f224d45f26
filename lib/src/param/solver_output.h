// Private to lib/src/param: the solver libraries' own console output turned off. Ceres logs through
// glog (a failed linear solve is a W... line on stderr, "Logging before InitGoogleLogging()" before
// it) and CHOLMOD prints its warnings through SuiteSparse's printf; the library never prints
// (STYLE.md practice 7): a failed solve is already handled by its caller (a rejected step, the
// Tutte start, SolverError).
#pragma once

namespace lodbake {

// Once per process (thread-safe), before the first Ceres solve or CHOLMOD factorisation: glog's
// minimum level raised to FATAL unless the host program initialised glog itself (its logging is
// then its own), and SuiteSparse's printf unset. Defined in ceres_energy.cpp.
void silenceSolverOutput();

}  // namespace lodbake
