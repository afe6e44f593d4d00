#!/usr/bin/env python3
"""Times lowpair's Python FK against the same FK in C++, in one process (docs/python.md, "Speed").

  PYTHONPATH=build/python python3 python/bench_fk.py [--robot models/puma560_corke.yaml] [--n 100000]
                                                     [--rounds 7] [--repeats 5] [--single 20000]

Per round, each of these is timed (the fastest of --repeats), and the medians over --rounds are printed:
- robot.fk(Q), Q of shape (N, n): one call from Python (input checks, the chunked copy into the library's
  column-major layout, forwardKinematicsBatch, the repacking into a fresh (N, 4, 4) array);
- robot.fk(Q, out=buffer): the same into a preallocated array;
- the C++ reference: forwardKinematicsBatch of all N poses in one call into a reused buffer, no Python in the loop
  (_lowpair_bench.time_batch_fk, the C++ references' module built beside the package: python/bench/timers.cpp);
- robot.fk(q), q of shape (n,): one call, and the same kinematics in C++ (_lowpair_bench.time_single_fk): their
  difference is the call's overhead; one numpy ufunc call, np.add(q, q), for comparison.
The ratios are taken per round, then their median. The load average is printed before and after: run it on a
quiet machine.
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

import lowpair
import _lowpair_bench  # build/python/_lowpair_bench*.so, built with the benchmarks or the tests


def best_of(repeats, fn, calls=1):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best / calls


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robot", default=os.path.join(here, "models", "puma560_corke.yaml"))
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--single", type=int, default=20_000, help="calls of robot.fk(q) per timing")
    args = parser.parse_args()

    robot = lowpair.load(args.robot)
    rng = np.random.default_rng(1)
    Q = rng.uniform(-np.pi, np.pi, (args.n, robot.dof))
    out = np.empty((args.n, 4, 4))
    robot.fk(Q, out=out)  # warm up (page in the code and the buffer)
    qs = list(Q[: args.single])
    q = Q[0].copy()
    fk = robot.fk
    load_before = os.getloadavg()

    rows = {key: [] for key in ("fresh", "out", "cpp", "single", "single_cpp", "ufunc")}
    for _ in range(args.rounds):
        rows["fresh"].append(best_of(args.repeats, lambda: fk(Q), args.n))
        rows["out"].append(best_of(args.repeats, lambda: fk(Q, out=out), args.n))
        rows["cpp"].append(_lowpair_bench.time_batch_fk(robot, Q, args.repeats))
        rows["single"].append(best_of(args.repeats, lambda: [fk(x) for x in qs], len(qs)))
        rows["single_cpp"].append(_lowpair_bench.time_single_fk(robot, Q[: args.single], args.repeats))
        rows["ufunc"].append(best_of(args.repeats, lambda: [np.add(x, x) for x in qs], len(qs)))
    # the loop over a list costs ~20 ns per element in both list timings; it is left in both
    median = {key: statistics.median(values) * 1e9 for key, values in rows.items()}
    ratio = statistics.median(f / c for f, c in zip(rows["fresh"], rows["cpp"]))
    ratio_out = statistics.median(o / c for o, c in zip(rows["out"], rows["cpp"]))
    overhead = statistics.median((s - c) * 1e9 for s, c in zip(rows["single"], rows["single_cpp"]))

    print(f"robot {robot.name} ({robot.dof} joints, {robot.model} model), N = {args.n}; medians of {args.rounds} "
          f"rounds, each the fastest of {args.repeats}")
    print(f"load average before {load_before[0]:.2f}, after {os.getloadavg()[0]:.2f} (1 min)")
    print(f"  robot.fk(Q), (N, n) -> (N, 4, 4):         {median['fresh']:8.1f} ns per pose")
    print(f"  robot.fk(Q, out=buffer):                  {median['out']:8.1f} ns per pose")
    print(f"  C++ forwardKinematicsBatch, one call:     {median['cpp']:8.1f} ns per pose")
    print(f"  ratio robot.fk(Q) / C++:                  {ratio:8.2f}")
    print(f"  ratio robot.fk(Q, out=) / C++:            {ratio_out:8.2f}")
    print(f"  robot.fk(q), one call, (n,) -> (4, 4):    {median['single']:8.1f} ns per call")
    print(f"  C++ forwardKinematics, one call:          {median['single_cpp']:8.1f} ns per call")
    print(f"  overhead of one robot.fk(q) call:         {overhead:8.1f} ns")
    print(f"  np.add(q, q), one numpy ufunc call:       {median['ufunc']:8.1f} ns per call")
    return 0


if __name__ == "__main__":
    sys.exit(main())
