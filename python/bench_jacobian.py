#!/usr/bin/env python3
"""Times lowpair's batched Python Jacobians and singularity analysis against the same work in C++, in one process,
on every bundled robot (docs/python.md, "Speed").

  PYTHONPATH=build/python python3 python/bench_jacobian.py [--n 20000] [--rounds 7] [--repeats 5] [robot.yaml ...]

Per robot and round, each of these is timed (the fastest of --repeats), and the medians over --rounds printed:
- robot.jacobian(Q, frame), Q of shape (N, n) -> (N, 6, n), for the three frames: the input checks, the chunked
  copy into the library's layout, computeJacobiansBatch and the repacking into a fresh array;
- the C++ reference: one computeJacobiansBatch over all N configurations into reused buffers
  (_lowpair_bench.time_batch_jacobian, python/bench/timers.cpp);
- robot.singular(Q) -> SingularityBatch, against the C++ loop a C++ user writes (computeJacobiansBatch, then
  jacobianRank per row: _lowpair_bench.time_batch_singular).
Ratios are taken per round (a first, warm-up round dropped), then their median. The load average is printed before and after: a shared machine
moves single timings by 20 % and more.
"""
import argparse
import glob
import os
import statistics

import numpy as np

import lowpair
import _lowpair_bench  # build/python/_lowpair_bench*.so, built with the benchmarks or the tests
from bench_fk import best_of  # python/bench_fk.py, beside this script


def robot_files(here):
    return sorted(glob.glob(os.path.join(here, "models", "*.yaml"))) + [
        os.path.join(here, "tests", "data", "bench", "rrpr_arm.yaml")]


def bench_robot(path, args):
    robot = lowpair.load(path)
    rng = np.random.default_rng(1)
    Q = rng.uniform(-1.0, 1.0, (args.n, robot.dof))  # within every bundled robot's joint ranges
    Qs = Q[: args.n // 10]  # the singularity analysis is ~50x the Jacobian's cost per row
    ratios = {f: [] for f in ("spatial", "body", "geometric", "singular")}
    times = {k: [] for k in ratios}
    for round_ in range(args.rounds + 1):  # round 0 warms up (pages, caches, clock) and is dropped
        if round_ == 1:
            ratios, times = ({k: [] for k in ratios} for _ in range(2))
        for frame in ("spatial", "body", "geometric"):
            py = best_of(args.repeats, lambda: robot.jacobian(Q, frame=frame), args.n)
            cpp = _lowpair_bench.time_batch_jacobian(robot, Q, frame, args.repeats)
            times[frame].append((py, cpp))
            ratios[frame].append(py / cpp)
        py = best_of(args.repeats, lambda: robot.singular(Qs), len(Qs))
        cpp = _lowpair_bench.time_batch_singular(robot, Qs, args.repeats)
        times["singular"].append((py, cpp))
        ratios["singular"].append(py / cpp)
    name = os.path.basename(path)
    for key in ratios:
        py_ns = statistics.median(t[0] for t in times[key]) * 1e9
        cpp_ns = statistics.median(t[1] for t in times[key]) * 1e9
        what = f"jacobian({key})" if key != "singular" else "singular"
        print(f"  {name:32s} {what:20s} python {py_ns:9.1f} ns/pose   C++ {cpp_ns:9.1f}   ratio "
              f"{statistics.median(ratios[key]):5.2f}")
    return max(statistics.median(r) for r in ratios.values())


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("robots", nargs="*", help="robot files (default: models/*.yaml and the 4-joint bench arm)")
    parser.add_argument("--n", type=int, default=20_000)
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    print(f"N = {args.n} (singular: {args.n // 10}); medians of {args.rounds} rounds, each the fastest of {args.repeats}")
    worst = max(bench_robot(path, args) for path in (args.robots or robot_files(here)))
    print(f"worst ratio python / C++: {worst:.2f}")
    print(f"load average before {load_before:.2f}, after {os.getloadavg()[0]:.2f} (1 min)")


if __name__ == "__main__":
    main()
