"""lowpair: serial-robot POE/D-H kinematics, Jacobians, singularities, identifiability, calibration, inverse
kinematics, compensation and calibration planning.

The C++ library and the harness behind the ``lowpair`` command line, as a Python module (docs/python.md).
Arrays are numpy float64; lengths are in the robot's ``length_unit``, angles in rad. Errors raise
``lowpair.Error`` (a ValueError) with the one-line message the CLI prints.
"""
from ._lowpair import (  # noqa: F401
    Calibration,
    DhTable,
    Error,
    Identifiability,
    IkAllSolutions,
    IkSolutions,
    Measurements,
    Plan,
    Robot,
    Singularity,
    SingularityBatch,
    __version__,
    calibrate,
    compensate,
    export,
    identifiability,
    ik,
    ik_all,
    load,
    plan,
    read_measurements,
    simulate,
)

__all__ = ["Calibration", "DhTable", "Error", "Identifiability", "IkAllSolutions", "IkSolutions", "Measurements",
           "Plan", "Robot", "Singularity", "SingularityBatch", "calibrate", "compensate", "export", "identifiability",
           "ik", "ik_all", "load", "plan", "read_measurements", "simulate"]
