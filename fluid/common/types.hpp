#pragma once
// Shared numeric types of sphib.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sphib {
using Vec = Eigen::VectorXd;
using Mat2 = Eigen::Matrix<double, Eigen::Dynamic, 2>;     // N x 2 fields: positions, velocities, forces
using SpMat = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;  // operators (row-major: fast products)
using Triplet = Eigen::Triplet<double, int>;
}  // namespace sphib
