// The solver libraries stay off the console (param/solver_output.h): after silenceSolverOutput a
// glog warning (how Ceres reports a failed linear solve) writes nothing to stderr, and CHOLMOD's
// "not positive definite" warning (printed to stdout through SuiteSparse's printf) is not printed.
// The CLI side (no foreign stderr line from a whole chain) is tests/cli/test_lodbake.py.
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <glog/logging.h>

#include "param/solver_output.h"

using namespace lodbake;

TEST(SolverOutput, GlogAndCholmodWarningsAreSilent) {
    silenceSolverOutput();
    silenceSolverOutput();  // once per process: a second call changes nothing
    ::testing::internal::CaptureStderr();
    ::testing::internal::CaptureStdout();
    LOG(WARNING) << "Linear solver failure (as Ceres logs it)";
    //  A = diag(-1, -2): not positive definite, so the supernodal Cholesky fails.
    Eigen::SparseMatrix<double> A(2, 2);
    A.insert(0, 0) = -1;
    A.insert(1, 1) = -2;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> llt;
    llt.compute(A);
    const std::string out = ::testing::internal::GetCapturedStdout();
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(llt.info(), Eigen::Success);
    EXPECT_EQ(out, "");
    EXPECT_EQ(err, "");
}
