#include "lowpair/singularity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "lowpair/check.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {

using JointSet = std::vector<int>;  // 0-based, sorted

// "4 and 6", "2, 3 and 5" (1-based).
std::string jointList(const JointSet& joints) {
  std::ostringstream out;
  for (size_t k = 0; k < joints.size(); ++k) {
    if (k > 0) out << (k + 1 == joints.size() ? " and " : ", ");
    out << joints[k] + 1;
  }
  return out.str();
}

std::string vec3Text(const Vec3& v) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

int countAbove(const VecX& sigma, double tol) {
  return static_cast<int>((sigma.array() > tol).count());
}

// Line geometry with the tolerances of the header: angles in rad, lengths relative to L.
class Lines {
 public:
  /// @param tolerance angle (rad) and distance (times size) within which lines count as parallel, meeting...
  Lines(const std::vector<JointLine>& lines, double size, double tolerance)
      : lines_(lines), size_(size), tol_(tolerance) {}
  double tolerance() const { return tol_; }

  int count() const { return static_cast<int>(lines_.size()); }
  const JointLine& operator[](int i) const { return lines_[static_cast<size_t>(i)]; }
  bool revolute(int i) const { return (*this)[i].type == JointType::Revolute; }
  bool parallel(int i, int j) const { return dir(i).cross(dir(j)).norm() <= tol_; }
  bool onLine(const Vec3& p, int i) const { return (p - pt(i)).cross(dir(i)).norm() <= tol_ * size_; }
  bool collinear(int i, int j) const { return parallel(i, j) && onLine(pt(j), i); }

  // The point where two non-parallel lines meet (midpoint of the common perpendicular), if they meet.
  bool meet(int i, int j, Vec3& point) const {
    const Vec3 n = dir(i).cross(dir(j));
    const double s = n.norm();
    if (s <= tol_) return false;
    const Vec3 d = pt(j) - pt(i);
    if (std::abs(d.dot(n)) / s > tol_ * size_) return false;  // skew
    // o_i + t z_i = o_j + u z_j (least squares)
    const double t = d.cross(dir(j)).dot(n) / (s * s);
    const double u = d.cross(dir(i)).dot(n) / (s * s);
    point = 0.5 * (pt(i) + t * dir(i) + pt(j) + u * dir(j));
    return true;
  }

  // Unit normal of the plane spanned by two distinct coplanar lines, if they span one.
  bool plane(int i, int j, Vec3& normal) const {
    if (parallel(i, j)) {
      if (collinear(i, j)) return false;
      normal = dir(i).cross(pt(j) - pt(i)).normalized();
      return true;
    }
    Vec3 p;
    if (!meet(i, j, p)) return false;
    normal = dir(i).cross(dir(j)).normalized();
    return true;
  }
  bool inPlane(int k, const Vec3& normal, const Vec3& origin) const {
    return std::abs(normal.dot(dir(k))) <= tol_ && std::abs(normal.dot(pt(k) - origin)) <= tol_ * size_;
  }

 private:
  const Vec3& dir(int i) const { return (*this)[i].direction; }
  const Vec3& pt(int i) const { return (*this)[i].point; }
  const std::vector<JointLine>& lines_;
  double size_;
  double tol_;
};

// Adds k to a set of lines unless it is collinear with a member: C2-C5 count distinct lines (a
// collinear pair is C1, and a duplicate line adds nothing to a plane, a point or a direction).
void addDistinct(const Lines& lines, JointSet& members, int k) {
  for (int m : members) {
    if (lines.collinear(m, k)) return;
  }
  members.push_back(k);
}

void add(std::vector<SingularClass>& out, const std::string& id, const JointSet& joints, const std::string& text) {
  SingularClass c;
  c.id = id;
  for (int j : joints) c.joints.push_back(j + 1);
  c.description = text;
  out.push_back(std::move(c));
}

// Revolute lines grouped into parallel families (each family sorted).
std::vector<JointSet> parallelFamilies(const Lines& lines) {
  std::vector<JointSet> families;
  for (int i = 0; i < lines.count(); ++i) {
    if (!lines.revolute(i)) continue;
    bool placed = false;
    for (JointSet& f : families) {
      if (lines.parallel(f.front(), i)) {
        f.push_back(i);
        placed = true;
        break;
      }
    }
    if (!placed) families.push_back({i});
  }
  return families;
}

// C1..C5, C7 (Paden–Sastry §4, examples 1-5 and 7).
void lineClasses(const Lines& lines, std::vector<SingularClass>& out) {
  const int n = lines.count();
  // C1 (example 1): two collinear revolute axes.
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (lines.revolute(i) && lines.revolute(j) && lines.collinear(i, j)) {
        add(out, "C1", {i, j}, "joint axes " + jointList({i, j}) + " are collinear");
      }
    }
  }
  const std::vector<JointSet> families = parallelFamilies(lines);
  // C2 (example 2): three parallel coplanar revolute axes (maximal sets).
  std::set<JointSet> c2;
  for (const JointSet& f : families) {
    if (f.size() < 3) continue;
    for (size_t a = 0; a < f.size(); ++a) {
      for (size_t b = a + 1; b < f.size(); ++b) {
        Vec3 normal;
        if (!lines.plane(f[a], f[b], normal)) continue;
        JointSet members;
        for (int k : f) {
          if (lines.inPlane(k, normal, lines[f[a]].point)) addDistinct(lines, members, k);
        }
        if (members.size() >= 3) c2.insert(members);
      }
    }
  }
  for (const JointSet& s : c2) add(out, "C2", s, "joint axes " + jointList(s) + " are parallel and coplanar");
  // C3 (example 3): four revolute axes through one point.
  std::set<JointSet> c3;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      Vec3 p;
      if (!lines.revolute(i) || !lines.revolute(j) || !lines.meet(i, j, p)) continue;
      JointSet members;
      for (int k = 0; k < n; ++k) {
        if (lines.revolute(k) && lines.onLine(p, k)) addDistinct(lines, members, k);
      }
      if (members.size() >= 4 && c3.insert(members).second) {
        add(out, "C3", members, "joint axes " + jointList(members) + " pass through one point " + vec3Text(p));
      }
    }
  }
  // C4 (example 4): four parallel revolute axes.
  for (const JointSet& f : families) {
    JointSet distinct;
    for (int k : f) addDistinct(lines, distinct, k);
    if (distinct.size() >= 4) add(out, "C4", distinct, "joint axes " + jointList(distinct) + " are parallel");
  }
  // C5 (example 5): four coplanar revolute axes.
  std::set<JointSet> c5;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      Vec3 normal;
      if (!lines.revolute(i) || !lines.revolute(j) || !lines.plane(i, j, normal)) continue;
      JointSet members;
      for (int k = 0; k < n; ++k) {
        if (lines.revolute(k) && lines.inPlane(k, normal, lines[i].point)) addDistinct(lines, members, k);
      }
      if (members.size() >= 4) c5.insert(members);
    }
  }
  for (const JointSet& s : c5) add(out, "C5", s, "joint axes " + jointList(s) + " lie in one plane");
  // C7 (example 7): a prismatic axis normal to the plane of two parallel revolute axes.
  for (int k = 0; k < n; ++k) {
    if (lines[k].type != JointType::Prismatic) continue;
    for (const JointSet& f : families) {
      for (size_t a = 0; a < f.size(); ++a) {
        for (size_t b = a + 1; b < f.size(); ++b) {
          Vec3 normal;
          if (!lines.plane(f[a], f[b], normal)) continue;  // members of a family are parallel
          if (lines[k].direction.cross(normal).norm() > lines.tolerance()) continue;
          JointSet s = {f[a], f[b], k};
          std::sort(s.begin(), s.end());
          add(out, "C7", s,
              "prismatic joint " + std::to_string(k + 1) + " is normal to the plane of the parallel joint axes " +
                  jointList({f[a], f[b]}));
        }
      }
    }
  }
}

// C6 (example 6): every axis meets one line <=> a zero-pitch wrench (a force along that line) is
// reciprocal to every joint screw, i.e. lies in the left null space of J (eq. 4.18). With u^T J_n = 0,
// u = [u_v; u_w]: force f = u_v / L, moment about the tool origin m = u_w; pitch f.m/|f|^2 = L u_v.u_w/|u_v|^2.
// A pure couple (u_v = 0) is the line at infinity: every axis is perpendicular to u_w.
void lineClassC6(const MatX& left_null, const Vec3& p_tool, double size, int n, std::vector<SingularClass>& out) {
  const int k = static_cast<int>(left_null.cols());
  if (k == 0) return;
  const MatX Uv = left_null.topRows(3), Uw = left_null.bottomRows(3);
  const MatX S = 0.5 * (Uv.transpose() * Uw + Uw.transpose() * Uv);  // pitch quadratic form
  Eigen::SelfAdjointEigenSolver<MatX> eig(S);
  std::vector<VecX> candidates;
  for (int e = 0; e < k; ++e) candidates.push_back(eig.eigenvectors().col(e));
  const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(k - 1);
  if (lo < 0.0 && hi > 0.0) {
    candidates.push_back(std::sqrt(hi) * eig.eigenvectors().col(0) + std::sqrt(-lo) * eig.eigenvectors().col(k - 1));
  }
  for (const VecX& a : candidates) {
    const Vec6 u = left_null * a.normalized();
    const Vec3 uv = u.head<3>(), uw = u.tail<3>();
    JointSet all(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) all[static_cast<size_t>(i)] = i;
    if (uv.norm() <= kWrenchPitchTolerance) {
      add(out, "C6", all, "all " + std::to_string(n) + " joint axes meet one line at infinity: all are perpendicular to " +
                              vec3Text(uw.normalized()));
      return;
    }
    if (std::abs(uv.dot(uw)) <= kWrenchPitchTolerance * uv.squaredNorm()) {
      const Vec3 f = uv / size;
      const Vec3 point = p_tool + f.cross(uw) / f.squaredNorm();
      add(out, "C6", all,
          "all " + std::to_string(n) + " joint axes meet the line through " + vec3Text(point) + " along " +
              vec3Text(f.normalized()));
      return;
    }
  }
}

// Paden–Sastry §5: the last three consecutive revolute axes that meet in one point.
DecoupledAnalysis decouple(const Lines& lines, double size, double tol) {
  DecoupledAnalysis d;
  const int n = lines.count();
  for (int i = n - 3; i >= 0 && !d.applies; --i) {
    if (!lines.revolute(i) || !lines.revolute(i + 1) || !lines.revolute(i + 2)) continue;
    Vec3 p;
    if (!lines.meet(i, i + 1, p) && !lines.meet(i + 1, i + 2, p) && !lines.meet(i, i + 2, p)) continue;
    if (!lines.onLine(p, i) || !lines.onLine(p, i + 1) || !lines.onLine(p, i + 2)) continue;
    d.applies = true;
    d.wrist_joints = {i + 1, i + 2, i + 3};
    d.wrist_point = p;
  }
  if (!d.applies) return d;
  Mat3 W;
  for (int c = 0; c < 3; ++c) W.col(c) = lines[d.wrist_joints[static_cast<size_t>(c)] - 1].direction;
  MatX A(3, n - 3);
  int col = 0;
  for (int k = 0; k < n; ++k) {
    if (k + 1 >= d.wrist_joints[0] && k + 1 <= d.wrist_joints[2]) continue;
    d.arm_joints.push_back(k + 1);
    const JointLine& l = lines[k];
    // eq. 5.2: arm vector z x (P - o) (+ h z), in units of L; prismatic: z (J_n's linear entry)
    A.col(col++) = l.type == JointType::Prismatic
                       ? Vec3(l.direction)
                       : Vec3((l.direction.cross(d.wrist_point - l.point) + l.pitch * l.direction) / size);
  }
  const Eigen::JacobiSVD<MatX> w_svd{MatX(W)};
  d.wrist_sigma_min = w_svd.singularValues()(2);
  d.wrist_singular = d.wrist_sigma_min <= tol;
  if (A.cols() > 0) {
    const Eigen::JacobiSVD<MatX> a_svd(A);
    const VecX& s = a_svd.singularValues();
    d.arm_sigma_min = s(s.size() - 1);
    d.arm_singular = numericalRank(s, tol) < std::min<int>(3, static_cast<int>(A.cols()));
  }
  return d;
}

}  // namespace

namespace {
// The joint lines from the spatial Jacobian: column i / scale_i is joint i's current unit twist [w; v].
std::vector<JointLine> linesFromSpatial(const PoeModel& model, const Mat6X& J_spatial) {
  std::vector<JointLine> lines(static_cast<size_t>(model.dof()));
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    const Vec6 xi = J_spatial.col(i) / joint.scale;
    JointLine& l = lines[static_cast<size_t>(i)];
    l.type = joint.type;
    l.pitch = joint.pitch;
    if (joint.type == JointType::Prismatic) {
      l.direction = xi.tail<3>();
    } else {
      l.direction = xi.head<3>();
      l.point = l.direction.cross(Vec3(xi.tail<3>()));  // w x (o x w + h w): the foot point from the origin
    }
  }
  return lines;
}
}  // namespace

void dimensionlessJacobian(const PoeModel& model, Eigen::Ref<Mat6X> J) {
  const double L = model.size();
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    J.col(i) *= (joint.type == JointType::Prismatic ? L : 1.0) / joint.scale;
  }
  J.topRows(3) /= L;
}

double rankTolerance(double sigma_max, int dof) { return kRankFactor * std::max(6, dof) * kEps * sigma_max; }

int numericalRank(const Eigen::Ref<const VecX>& sigma, double tolerance) { return countAbove(sigma, tolerance); }

JacobianRank jacobianRank(const PoeModel& model, const Eigen::Ref<const Mat6X>& J_geometric) {
  LP_CHECK(J_geometric.cols() == model.dof(),
           "jacobianRank: the Jacobian has " << J_geometric.cols() << " columns for " << model.dof() << " joints");
  Mat6X Jn = J_geometric;
  dimensionlessJacobian(model, Jn);
  JacobianRank r;
  const int m = std::min(6, model.dof());
  r.singular_values = Eigen::JacobiSVD<MatX>(Jn).singularValues().head(m);
  r.tolerance = rankTolerance(m > 0 ? r.singular_values(0) : 0.0, model.dof());
  r.rank = countAbove(r.singular_values, r.tolerance);
  return r;
}

std::vector<JointLine> jointLines(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  checkJointVector(q, model.dof());
  Data data(model);
  computeJacobians(model, data, q);
  return linesFromSpatial(model, data.J_spatial);
}

SingularityReport analyzeSingularity(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  checkJointVector(q, model.dof());
  const int n = model.dof();
  const double L = model.size();
  SingularityReport r;
  r.dof = n;
  r.size = L;

  // one FK: the spatial Jacobian gives the joint lines, its geometric form the dimensionless J_n
  Data data(model);
  computeJacobians(model, data, q);
  r.lines = linesFromSpatial(model, data.J_spatial);
  Mat6X Jn(6, n);
  getGeometricJacobian(data, Jn);
  dimensionlessJacobian(model, Jn);
  const Vec3 p_tool = data.T_base_tool.p;

  const int m = std::min(6, n);
  Eigen::JacobiSVD<MatX> svd(Jn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  r.singular_values = svd.singularValues().head(m);
  const double sigma_max = m > 0 ? r.singular_values(0) : 0.0;
  r.tolerance = rankTolerance(sigma_max, n);
  r.rank = countAbove(r.singular_values, r.tolerance);
  r.singular = r.rank < m;
  r.sigma_min = m > 0 ? r.singular_values(m - 1) : 0.0;
  r.manipulability = r.singular_values.prod();
  r.condition = r.sigma_min > 0.0 ? sigma_max / r.sigma_min : std::numeric_limits<double>::infinity();
  if (n > 0) {
    r.rank_linear = countAbove(Eigen::JacobiSVD<MatX>(Jn.topRows(3)).singularValues(), r.tolerance);
    r.rank_angular = countAbove(Eigen::JacobiSVD<MatX>(Jn.bottomRows(3)).singularValues(), r.tolerance);
  }
  // every direction of joint motion that moves nothing: n - rank of them (self-motion included for n > 6)
  for (int k = r.rank; k < n; ++k) r.null_space.push_back(svd.matrixV().col(k));

  // Classes explain a rank deficiency at the tolerance that detected it (tolerances.hpp): tight on a
  // regular pose (a class there would contradict the rank), loose on a singular one.
  const Lines lines(r.lines, L, r.singular ? kLineToleranceSingular : kLineTolerance);
  lineClasses(lines, r.classes);
  const bool all_revolute = std::all_of(r.lines.begin(), r.lines.end(),
                                        [](const JointLine& l) { return l.type == JointType::Revolute; });
  if (all_revolute && n >= 6 && r.rank < 6) {
    lineClassC6(svd.matrixU().rightCols(6 - r.rank), p_tool, L, n, r.classes);
  }
  if (r.singular && r.classes.empty()) {
    JointSet dependent;
    for (int i = 0; i < n; ++i) {
      bool in = false;
      for (const VecX& x : r.null_space) in = in || std::abs(x(i)) > kNullCoefficient;
      if (in) dependent.push_back(i);
    }
    add(r.classes, "other", dependent,
        "the screws of joints " + jointList(dependent) + " are linearly dependent (no listed class)");
  }
  r.decoupled = decouple(lines, L, r.tolerance);
  return r;
}

}  // namespace lowpair
