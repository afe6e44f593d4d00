#include "lowpair/jacobian.hpp"

#include <stdexcept>
#include <string>

#include "chain_eval.hpp"
#include "check.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

namespace {

[[noreturn]] LP_COLD void throwOutputColumns(const char* function, Eigen::Index cols, int dof) {
  throw std::invalid_argument(std::string(function) + ": the output has " + std::to_string(cols) + " columns, data has " +
                              std::to_string(dof) + " joints");
}

[[noreturn]] LP_COLD void throwConversionColumns(const char* function, Eigen::Index in, Eigen::Index out) {
  throw std::invalid_argument(std::string(function) + ": the input has " + std::to_string(in) + " columns, the output " +
                              std::to_string(out));
}

// A getter writes data.dof columns.
inline void checkColumns(const char* function, const Data& data, Eigen::Index cols) {
  if (LP_UNLIKELY(cols != data.dof)) throwOutputColumns(function, cols, data.dof);
}

// A conversion writes column i of `out` for every column i of `in`.
inline void checkSameColumns(const char* function, Eigen::Index in, Eigen::Index out) {
  if (LP_UNLIKELY(in != out)) throwConversionColumns(function, in, out);
}

}  // namespace

void spatialToBody(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial, Eigen::Ref<Mat6X> J_body) {
  checkSameColumns("spatialToBody", J_spatial.cols(), J_body.cols());
  const Pose T_tool_base = T_base_tool.inverse();
  for (Eigen::Index i = 0; i < J_spatial.cols(); ++i) {
    const Vec6 xi = J_spatial.col(i);
    J_body.col(i) = adjointApply(T_tool_base, xi);
  }
}

void bodyToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_body, Eigen::Ref<Mat6X> J_spatial) {
  checkSameColumns("bodyToSpatial", J_body.cols(), J_spatial.cols());
  for (Eigen::Index i = 0; i < J_body.cols(); ++i) {
    const Vec6 xi = J_body.col(i);
    J_spatial.col(i) = adjointApply(T_base_tool, xi);
  }
}

void spatialToGeometric(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial,
                        Eigen::Ref<Mat6X> J_geometric) {
  checkSameColumns("spatialToGeometric", J_spatial.cols(), J_geometric.cols());
  // velocity of the body point at the tool origin: v + w x p_tool (eq. 3.13 up to the axis point); each
  // column is read whole before it is written, so J_geometric may alias J_spatial
  const double px = T_base_tool.p[0], py = T_base_tool.p[1], pz = T_base_tool.p[2];
  for (Eigen::Index i = 0; i < J_spatial.cols(); ++i) {
    const double* s = J_spatial.col(i).data();
    const double w0 = s[0], w1 = s[1], w2 = s[2], v0 = s[3], v1 = s[4], v2 = s[5];
    double* g = J_geometric.col(i).data();
    g[0] = v0 + (w1 * pz - w2 * py);
    g[1] = v1 + (w2 * px - w0 * pz);
    g[2] = v2 + (w0 * py - w1 * px);
    g[3] = w0;
    g[4] = w1;
    g[5] = w2;
  }
}

void geometricToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_geometric,
                        Eigen::Ref<Mat6X> J_spatial) {
  checkSameColumns("geometricToSpatial", J_geometric.cols(), J_spatial.cols());
  for (Eigen::Index i = 0; i < J_geometric.cols(); ++i) {
    const Vec3 v = J_geometric.col(i).head<3>();
    const Vec3 w = J_geometric.col(i).tail<3>();
    J_spatial.col(i).head<3>() = w;
    J_spatial.col(i).tail<3>() = v - w.cross(T_base_tool.p);
  }
}

void computeJacobians(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  detail::checkChainCall("computeJacobians", model.chain(), data, q.size());
  detail::chainJacobian(model.chain(), data, q.data());
}

void computeJacobians(const DhModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  detail::checkChainCall("computeJacobians", model.chain(), data, q.size());
  detail::chainJacobian(model.chain(), data, q.data());
}

void computeJacobiansBatch(const PoeModel& model, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                           Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses) {
  detail::jacobianBatch(model.chain(), q, frame, jacobians, poses);
}

void computeJacobiansBatch(const DhModel& model, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                           Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses) {
  detail::jacobianBatch(model.chain(), q, frame, jacobians, poses);
}

void getSpatialJacobian(const Data& data, Eigen::Ref<Mat6X> J_spatial) {
  checkColumns("getSpatialJacobian", data, J_spatial.cols());
  J_spatial = data.J_spatial;
}

void getBodyJacobian(const Data& data, Eigen::Ref<Mat6X> J_body) {
  checkColumns("getBodyJacobian", data, J_body.cols());
  spatialToBody(data.T_base_tool, data.J_spatial, J_body);
}

void getGeometricJacobian(const Data& data, Eigen::Ref<Mat6X> J_geometric) {
  checkColumns("getGeometricJacobian", data, J_geometric.cols());
  spatialToGeometric(data.T_base_tool, data.J_spatial, J_geometric);
}

}  // namespace lowpair
