// The topics of the Python module, each binding its classes and functions (module.cpp calls them in this order).
#pragma once

#include "common.hpp"

namespace lowpair::python {

void exposeRobot(py::module_& m);            // robot.cpp: Robot, load
void exposeKinematics(py::module_& m);       // kinematics.cpp: DhTable, Singularity (Robot.fk and the rest: robot.cpp)
void exposeIdentifiability(py::module_& m);  // identifiability.cpp: Identifiability, identifiability
void exposeCalibration(py::module_& m);      // calibration.cpp: Calibration, calibrate
void exposeIk(py::module_& m);               // ik.cpp: IkSolutions, ik, compensate
void exposePlan(py::module_& m);             // plan.cpp: Plan, plan
void exposeFiles(py::module_& m);            // files.cpp: Measurements, read_measurements, simulate, export

}  // namespace lowpair::python
