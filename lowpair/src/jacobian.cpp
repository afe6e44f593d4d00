#include "lowpair/jacobian.hpp"

#include "lowpair/check.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

namespace {

void checkSizes(int dof, const Eigen::Ref<const VecX>& q, Eigen::Index cols) {
  LP_CHECK(q.size() == dof, "expected " << dof << " joint values, got " << q.size());
  LP_CHECK(cols == dof, "Jacobian output has " << cols << " columns, expected " << dof);
}

// Spatial column of a joint whose axis has unit direction z through point o (base frame).
void axisColumn(JointType type, const Vec3& z, const Vec3& o, double pitch, double scale,
                Eigen::Ref<Mat6X>::ColXpr column) {
  if (type == JointType::Prismatic) {
    column.head<3>().setZero();
    column.tail<3>() = scale * z;
  } else {
    column.head<3>() = scale * z;
    column.tail<3>() = scale * (o.cross(z) + pitch * z);
  }
}

}  // namespace

void spatialToBody(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial, Eigen::Ref<Mat6X> J_body) {
  LP_ASSERT(J_spatial.cols() == J_body.cols());
  const Pose T_tool_base = T_base_tool.inverse();
  for (Eigen::Index i = 0; i < J_spatial.cols(); ++i) {
    const Vec6 xi = J_spatial.col(i);
    J_body.col(i) = adjointApply(T_tool_base, xi);
  }
}

void bodyToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_body, Eigen::Ref<Mat6X> J_spatial) {
  LP_ASSERT(J_spatial.cols() == J_body.cols());
  for (Eigen::Index i = 0; i < J_body.cols(); ++i) {
    const Vec6 xi = J_body.col(i);
    J_spatial.col(i) = adjointApply(T_base_tool, xi);
  }
}

void spatialToGeometric(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial,
                        Eigen::Ref<Mat6X> J_geometric) {
  LP_ASSERT(J_spatial.cols() == J_geometric.cols());
  for (Eigen::Index i = 0; i < J_spatial.cols(); ++i) {
    const Vec3 w = J_spatial.col(i).head<3>();
    const Vec3 v = J_spatial.col(i).tail<3>();
    // velocity of the body point at the tool origin: v + w x p_tool (eq. 3.13 up to the axis point)
    J_geometric.col(i).head<3>() = v + w.cross(T_base_tool.p);
    J_geometric.col(i).tail<3>() = w;
  }
}

void geometricToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_geometric,
                        Eigen::Ref<Mat6X> J_spatial) {
  LP_ASSERT(J_spatial.cols() == J_geometric.cols());
  for (Eigen::Index i = 0; i < J_geometric.cols(); ++i) {
    const Vec3 v = J_geometric.col(i).head<3>();
    const Vec3 w = J_geometric.col(i).tail<3>();
    J_spatial.col(i).head<3>() = w;
    J_spatial.col(i).tail<3>() = v - w.cross(T_base_tool.p);
  }
}

// --- POE -----------------------------------------------------------------------------------------

void spatialJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q,
                     Eigen::Ref<Mat6X> J_spatial) {
  checkSizes(model.dof(), q, J_spatial.cols());
  forwardKinematics(model, data, q);
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    if (i == 0) {
      J_spatial.col(0) = joint.scale * joint.twist;  // Ad(identity)
    } else {
      J_spatial.col(i) = joint.scale * adjointApply(data.T_base_joint[static_cast<size_t>(i - 1)], joint.twist);
    }
  }
}

void bodyJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q, Eigen::Ref<Mat6X> J_body) {
  spatialJacobian(model, data, q, J_body);
  spatialToBody(data.T_base_tool, J_body, J_body);
}

void geometricJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<Mat6X> J_geometric) {
  spatialJacobian(model, data, q, J_geometric);
  spatialToGeometric(data.T_base_tool, J_geometric, J_geometric);
}

// --- D-H -----------------------------------------------------------------------------------------

void spatialJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q,
                     Eigen::Ref<Mat6X> J_spatial) {
  checkSizes(model.dof(), q, J_spatial.cols());
  forwardKinematics(model, data, q);
  for (int i = 0; i < model.dof(); ++i) {
    const DhJoint& joint = model.joint(i);
    const Pose& F = data.T_base_frame[static_cast<size_t>(i)];  // z = joint i's axis (eq. 10)
    axisColumn(joint.type, F.R.col(2), F.p, joint.pitch, joint.scale, J_spatial.col(i));
  }
}

void bodyJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q, Eigen::Ref<Mat6X> J_body) {
  spatialJacobian(model, data, q, J_body);
  spatialToBody(data.T_base_tool, J_body, J_body);
}

void geometricJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<Mat6X> J_geometric) {
  spatialJacobian(model, data, q, J_geometric);
  spatialToGeometric(data.T_base_tool, J_geometric, J_geometric);
}

}  // namespace lowpair
