#include "lowpair/singularity.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>


#include "check.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {

using JointSet = std::vector<int>;  // 0-based, sorted

// The rank of a Jacobian is at most 6, the dimension of the twist space se(3).
constexpr int kTwistDim = 6;

// Lines of one Paden-Sastry family span a space of zero-pitch screws of one dimension less than these
// counts, so this many distinct lines of the family are linearly dependent (examples 2-5).
constexpr size_t kParallelCoplanarLines = 3;  // C2: parallel lines in one plane span 2 dimensions
constexpr size_t kConcurrentLines = 4;        // C3: lines through one point span 3
constexpr size_t kParallelLines = 4;          // C4: parallel lines span 3
constexpr size_t kCoplanarLines = 4;          // C5: lines in one plane span 3

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

SingularClass& add(std::vector<SingularClass>& out, const std::string& id, const JointSet& joints) {
  SingularClass c;
  c.id = id;
  for (int j : joints) c.joints.push_back(j + 1);
  out.push_back(std::move(c));
  return out.back();
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
        add(out, "C1", {i, j});
      }
    }
  }
  const std::vector<JointSet> families = parallelFamilies(lines);
  // C2 (example 2): three parallel coplanar revolute axes (maximal sets).
  std::set<JointSet> c2;
  for (const JointSet& f : families) {
    if (f.size() < kParallelCoplanarLines) continue;
    for (size_t a = 0; a < f.size(); ++a) {
      for (size_t b = a + 1; b < f.size(); ++b) {
        Vec3 normal;
        if (!lines.plane(f[a], f[b], normal)) continue;
        JointSet members;
        for (int k : f) {
          if (lines.inPlane(k, normal, lines[f[a]].point)) addDistinct(lines, members, k);
        }
        if (members.size() >= kParallelCoplanarLines) c2.insert(members);
      }
    }
  }
  for (const JointSet& s : c2) add(out, "C2", s);
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
      if (members.size() >= kConcurrentLines && c3.insert(members).second) {
        add(out, "C3", members).point = p;
      }
    }
  }
  // C4 (example 4): four parallel revolute axes.
  for (const JointSet& f : families) {
    JointSet distinct;
    for (int k : f) addDistinct(lines, distinct, k);
    if (distinct.size() >= kParallelLines) add(out, "C4", distinct);
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
      if (members.size() >= kCoplanarLines) c5.insert(members);
    }
  }
  for (const JointSet& s : c5) add(out, "C5", s);
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
          add(out, "C7", s).prismatic_joint = k + 1;
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
      SingularClass& c = add(out, "C6", all);
      c.at_infinity = true;
      c.direction = uw.normalized();
      return;
    }
    if (std::abs(uv.dot(uw)) <= kWrenchPitchTolerance * uv.squaredNorm()) {
      const Vec3 f = uv / size;
      SingularClass& c = add(out, "C6", all);
      c.point = p_tool + f.cross(uw) / f.squaredNorm();
      c.direction = f.normalized();
      return;
    }
  }
}

// Rows of the arm block of eq. 5.2 (the linear velocity of the wrist point): its full rank.
constexpr int kArmBlockRows = 3;

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
    d.arm_singular = numericalRank(s, tol) < std::min<int>(kArmBlockRows, static_cast<int>(A.cols()));
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
  LP_CHECK(J.cols() == model.dof(),
           "dimensionlessJacobian: the Jacobian has " << J.cols() << " columns, the model has " << model.dof() << " joints");
  const double L = model.lengthScale();
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    J.col(i) *= (joint.type == JointType::Prismatic ? L : 1.0) / joint.scale;
  }
  J.topRows(3) /= L;
}

double rankTolerance(double sigma_max, int dof) { return numericalRankTolerance(sigma_max, std::max(kTwistDim, dof)); }

int numericalRank(const Eigen::Ref<const VecX>& sigma, double tolerance) {
  return static_cast<int>((sigma.array() > tolerance).count());
}

JacobianRank jacobianRank(const PoeModel& model, const Eigen::Ref<const Mat6X>& J_geometric) {
  LP_CHECK(J_geometric.cols() == model.dof(),
           "jacobianRank: the Jacobian has " << J_geometric.cols() << " columns for " << model.dof() << " joints");
  Mat6X Jn = J_geometric;
  dimensionlessJacobian(model, Jn);
  JacobianRank r;
  const int m = std::min(kTwistDim, model.dof());
  r.singular_values = Eigen::JacobiSVD<MatX>(Jn).singularValues().head(m);
  r.tolerance = rankTolerance(m > 0 ? r.singular_values(0) : 0.0, model.dof());
  r.rank = numericalRank(r.singular_values, r.tolerance);
  return r;
}

std::vector<JointLine> jointLines(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  checkJointVector(q, model.dof());
  Data data(model);
  computeJacobians(model, data, q);
  return linesFromSpatial(model, data.J_spatial);
}

namespace {
// The null-space vectors k = rank .. rank + count - 1 of a chain too long for the full V (n x n): the
// columns rank..m-1 of the thin V, then columns m.. of the Householder Q of J_n^T = Q R, which span the
// orthogonal complement of J_n's row space (the same construction JacobiSVD uses for its full V).
std::vector<VecX> largeChainNullSpace(const MatX& Jn, const Eigen::JacobiSVD<MatX>& svd, int rank, int count) {
  const int n = static_cast<int>(Jn.cols());
  const int m = static_cast<int>(svd.matrixV().cols());
  std::vector<VecX> out;
  for (int k = rank; k < m && static_cast<int>(out.size()) < count; ++k) out.push_back(svd.matrixV().col(k));
  const int rest = std::min(count - static_cast<int>(out.size()), n - std::max(m, rank));
  if (rest <= 0) return out;
  const int first = std::max(m, rank);
  const Eigen::ColPivHouseholderQR<MatX> qr(Jn.transpose());
  MatX E = MatX::Zero(n, rest);
  for (int c = 0; c < rest; ++c) E(first + c, c) = 1.0;
  qr.householderQ().applyThisOnTheLeft(E);
  for (int c = 0; c < rest; ++c) out.push_back(E.col(c));
  return out;
}
}  // namespace

void SingularityOptions::validate() const {
  LP_CHECK(max_null_vectors >= 0, "analyzeSingularity: max_null_vectors must be >= 0, got " << max_null_vectors);
}

SingularityReport analyzeSingularity(const PoeModel& model, const Eigen::Ref<const VecX>& q,
                                     const SingularityOptions& options) {
  checkJointVector(q, model.dof());
  options.validate();
  const int n = model.dof();
  const double L = model.lengthScale();
  SingularityReport r;
  r.dof = n;
  r.length_scale = L;
  r.classes_searched = n <= kClassSearchMaxJoints;

  // one FK: the spatial Jacobian gives the joint lines, its geometric form the dimensionless J_n
  Data data(model);
  computeJacobians(model, data, q);
  r.lines = linesFromSpatial(model, data.J_spatial);
  Mat6X Jn(6, n);
  getGeometricJacobian(data, Jn);
  dimensionlessJacobian(model, Jn);
  const Vec3 p_tool = data.T_base_tool.p;

  // a chain within the class-search limit gets the full U and V (every null vector, for `other` and C6);
  // a longer one the thin V (n x 6): the full V alone would be n^2 numbers
  const int m = std::min(kTwistDim, n);
  const Eigen::JacobiSVD<MatX> svd(Jn, r.classes_searched ? Eigen::ComputeFullU | Eigen::ComputeFullV
                                                          : Eigen::ComputeThinV);
  r.singular_values = svd.singularValues().head(m);
  const double sigma_max = m > 0 ? r.singular_values(0) : 0.0;
  r.tolerance = rankTolerance(sigma_max, n);
  r.rank = numericalRank(r.singular_values, r.tolerance);
  r.singular = r.rank < m;
  r.sigma_min = m > 0 ? r.singular_values(m - 1) : 0.0;
  r.manipulability = r.singular_values.prod();
  r.condition = r.sigma_min > 0.0 ? sigma_max / r.sigma_min : std::numeric_limits<double>::infinity();
  if (n > 0) {
    r.rank_linear = numericalRank(Eigen::JacobiSVD<MatX>(Jn.topRows(3)).singularValues(), r.tolerance);
    r.rank_angular = numericalRank(Eigen::JacobiSVD<MatX>(Jn.bottomRows(3)).singularValues(), r.tolerance);
  }
  // every direction of joint motion that moves nothing: n - rank of them (self-motion included for n > 6)
  r.nullity = n - r.rank;
  const int kept = std::min(r.nullity, options.max_null_vectors);
  if (r.classes_searched) {
    for (int k = r.rank; k < r.rank + kept; ++k) r.null_space.push_back(svd.matrixV().col(k));
  } else {
    r.null_space = largeChainNullSpace(Jn, svd, r.rank, kept);
  }

  const Lines lines(r.lines, L, r.singular ? kLineToleranceSingular : kLineTolerance);
  if (r.classes_searched) {
    // Classes explain a rank deficiency at the tolerance that detected it (tolerances.hpp): tight on a
    // regular pose (a class there would contradict the rank), loose on a singular one.
    lineClasses(lines, r.classes);
    const bool all_revolute = std::all_of(r.lines.begin(), r.lines.end(),
                                          [](const JointLine& l) { return l.type == JointType::Revolute; });
    if (all_revolute && n >= kTwistDim && r.rank < kTwistDim) {
      lineClassC6(svd.matrixU().rightCols(kTwistDim - r.rank), p_tool, L, n, r.classes);
    }
    if (r.singular && r.classes.empty()) {
      JointSet dependent;
      for (int i = 0; i < n; ++i) {
        bool in = false;
        for (int k = r.rank; k < n; ++k) in = in || std::abs(svd.matrixV()(i, k)) > kNullCoefficient;
        if (in) dependent.push_back(i);
      }
      add(r.classes, "other", dependent);
    }
  }
  r.decoupled = decouple(lines, L, r.tolerance);
  return r;
}

}  // namespace lowpair
