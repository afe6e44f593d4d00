// The explicit instantiations declared in linalg.hpp.
#include "linalg.hpp"

template class Eigen::JacobiSVD<Eigen::MatrixXd>;
template class Eigen::JacobiSVD<Eigen::Matrix3d>;
template class Eigen::JacobiSVD<lowpair::linalg::Small>;
template class Eigen::LLT<Eigen::MatrixXd>;
template class Eigen::LLT<lowpair::linalg::Small>;
template class Eigen::ColPivHouseholderQR<Eigen::MatrixXd>;
template class Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;
