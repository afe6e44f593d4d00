#!/usr/bin/env python3
"""Times lowpair's Python FK against the same batched FK in C++ (docs/python.md, "Speed").

  PYTHONPATH=build/python python3 python/bench_fk.py [--robot models/puma560_corke.yaml] [--n 100000] [--repeats 7]

Prints, per pose: robot.fk(Q) for Q of shape (N, n) (one batched call from Python: input checks, the copy to
the library's column-major layout, forwardKinematicsBatch, the repacking into (N, 4, 4)); the C++
forwardKinematicsBatch alone (lowpair._time_batch_fk: the same call N poses at a time in C++, no Python in the
loop, the best of the repeats); their ratio; and the overhead of one robot.fk(q) call (q of shape (n,)) over the
C++ single FK estimate (the batched per-pose time is a lower bound of it). Best of --repeats runs each.
"""
import argparse
import os
import sys
import time

import numpy as np

import lowpair


def best_of(repeats, fn):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robot", default=os.path.join(here, "models", "puma560_corke.yaml"))
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--single", type=int, default=20_000, help="calls of robot.fk(q) timed for the overhead")
    args = parser.parse_args()

    robot = lowpair.load(args.robot)
    rng = np.random.default_rng(1)
    Q = rng.uniform(-np.pi, np.pi, (args.n, robot.dof))
    robot.fk(Q[:1000])  # warm up (page in the code, the allocator)

    python_batch = best_of(args.repeats, lambda: robot.fk(Q)) / args.n
    out = np.empty((args.n, 4, 4))
    python_batch_out = best_of(args.repeats, lambda: robot.fk(Q, out=out)) / args.n
    cpp_batch = lowpair._time_batch_fk(robot, Q, args.repeats)
    qs = list(Q[: args.single])
    fk = robot.fk
    single = best_of(args.repeats, lambda: [fk(q) for q in qs]) / len(qs)

    print(f"robot {robot.name} ({robot.dof} joints, {robot.model} model), N = {args.n}, best of {args.repeats}")
    print(f"  robot.fk(Q), (N, n) -> (N, 4, 4):     {python_batch * 1e9:9.1f} ns per pose")
    print(f"  robot.fk(Q, out=buffer), reused:     {python_batch_out * 1e9:9.1f} ns per pose")
    print(f"  C++ forwardKinematicsBatch:          {cpp_batch * 1e9:9.1f} ns per pose")
    print(f"  ratio Python batch / C++ batch:      {python_batch / cpp_batch:9.2f}")
    print(f"  ratio with out= / C++ batch:         {python_batch_out / cpp_batch:9.2f}")
    print(f"  robot.fk(q), one call, (n,) -> (4,4): {single * 1e9:9.1f} ns per call")
    print(f"  single-call overhead over C++ batch: {(single - cpp_batch) * 1e9:9.1f} ns per call")
    return 0


if __name__ == "__main__":
    sys.exit(main())
