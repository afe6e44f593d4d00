#pragma once
/// @file linalg.hpp (internal, not installed)
/// The dynamic-size Eigen decompositions the library uses, instantiated once (linalg.cpp) instead of in
/// every source file that uses them: JacobiSVD<MatrixXd> alone costs 6 s of -O3 compile time per file.
/// Include this instead of <Eigen/SVD>, <Eigen/Cholesky>, <Eigen/QR>, <Eigen/Eigenvalues>.

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

namespace lowpair::linalg {
/// At most 6 x 6, on the stack (IK's normal matrices and their factors never allocate).
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
}  // namespace lowpair::linalg

extern template class Eigen::JacobiSVD<Eigen::MatrixXd>;
extern template class Eigen::JacobiSVD<Eigen::Matrix3d>;
extern template class Eigen::JacobiSVD<lowpair::linalg::Small>;
extern template class Eigen::LLT<Eigen::MatrixXd>;
extern template class Eigen::LLT<lowpair::linalg::Small>;
extern template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
extern template class Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;
