// The linear solver of lodbake's Ceres problems, whose Jacobians are very sparse (a residual
// touches a few vertices): sparse Cholesky of the normal equations with whichever sparse library
// Ceres was built with. Included only by the translation units that include Ceres
// (param/ceres_energy.cpp).
#pragma once

#include <cstddef>

#include <ceres/ceres.h>

namespace lodbake {

// Without a sparse library: dense Cholesky up to `denseUpTo` unknowns, else CGNR.
inline void chooseSparseSolver(ceres::Solver::Options& so, size_t unknowns, size_t denseUpTo) {
    if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
        so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
        so.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
    } else if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE)) {
        so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
        so.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    } else {
        so.linear_solver_type = unknowns <= denseUpTo ? ceres::DENSE_NORMAL_CHOLESKY : ceres::CGNR;
    }
}

}  // namespace lodbake
