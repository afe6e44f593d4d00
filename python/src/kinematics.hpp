// Forward kinematics, Jacobians, the D-H table and singularities of a Robot (lowpair.Robot's methods,
// kinematics.cpp; the batched FK's kernel is fk_batch.cpp).
#pragma once

#include <optional>
#include <string>

#include "common.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/singularity.hpp"
#include "robot.hpp"

namespace lowpair::python {

// Robot.fk: T_base_tool of one configuration (n,) -> (4, 4), or of (N, n) -> (N, 4, 4) batched (fk_batch.hpp).
py::object fk(const Robot& r, const py::object& q_arg, const std::optional<std::string>& model,
              const std::optional<py::array>& out_arg);

// Robot.jacobian: the spatial, body or geometric Jacobian at q (n,), (6, n); or at each row of (N, n), (N, 6, n)
// batched (fk_batch.hpp).
// out: an optional preallocated array of the result's shape, as fk's.
py::object jacobian(const Robot& r, const InArray& q, const std::string& frame, const std::optional<py::array>& out);

// ----- the D-H table -----------------------------------------------------------------------------------

struct DhTable {
  DhConversion conversion;
  FkCheck check;
  json j;
};

DhTable dhTable(const Robot& r, double parallel_threshold, bool modified);

// ----- singularities (io/singularity_output.hpp) ----------

struct Singularity {
  SingularityReport report;
  json j;
};

// The rank rule of Singularity at each row of an (N, n) q (Robot.singular(Q)): arrays with a row per configuration.
struct SingularityBatch {
  py::array_t<long long> rank;
  py::array_t<bool> singular;
  py::array_t<double> sigma_min, manipulability, condition, tolerance;
  py::array_t<double> singular_values;  // (N, min(6, n))
};

// Robot.singular: the Singularity at q (n,), or the SingularityBatch of (N, n).
py::object singular(const Robot& r, const InArray& q);
SingularityBatch singularBatch(const Robot& r, const CArray& Q);

}  // namespace lowpair::python
