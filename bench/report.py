#!/usr/bin/env python3
"""Speed-up table from one Google Benchmark JSON run (bench/run.sh): each lowpair result against the
MuJoCo and KDL results of the same area and robot (BM_<Area>_<Impl>_<Robot>; a user's robot file,
BENCH_ROBOT, as any bundled robot), and against the previous lowpair (the kernel before issue 29,
BM_<Area>_<Impl>Baseline_<Robot>, bench/chain_baseline.cpp), from the same run's medians (or the single
iteration runs in smoke mode). Exits 1 if any benchmark reported an error (e.g. a peer disagreed)."""
import json
import sys


def main(path):
    with open(path) as f:
        data = json.load(f)
    runs = {}
    errors = []
    for b in data["benchmarks"]:
        name = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            errors.append(f"{name}: {b.get('error_message', '')}")
            continue
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        name = name.split("/")[0]
        scale = 1.0
        if "items_per_second" in b and b["name"].startswith(("BM_FkBatch_", "BM_JacobianBatch_")):
            # per pose: time per call / items per call
            per_call_items = b["items_per_second"] * b["real_time"] * 1e-9 if b["time_unit"] == "ns" else None
            scale = 1.0 / per_call_items if per_call_items else 1.0
        unit = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b["time_unit"]]
        runs[name] = (b["real_time"] * unit * scale, b["cpu_time"] * unit * scale)

    if "lowpair_robot" in data["context"]:
        print(f"robot file: {data['context']['lowpair_robot']}")
    runs = dict(sorted(runs.items(), key=lambda kv: (kv[0].split("_")[1], kv[0].split("_")[-1], kv[0])))
    w = max([36] + [len(name) for name in runs])
    print(f"{'benchmark (median)':<{w}} {'real ns':>10} {'cpu ns':>10} {'x MuJoCo':>9} {'x KDL':>9} {'x prev':>9}")
    for name, (real, cpu) in runs.items():
        parts = name.split("_")  # BM, Area, Impl, Robot
        if len(parts) != 4 or parts[2] in ("Mujoco", "Kdl"):
            if not (len(parts) == 4 and parts[2] in ("Mujoco", "Kdl")):
                print(f"{name:<{w}} {real:>10.1f} {cpu:>10.1f}")
            continue
        area, robot = parts[1], parts[3]
        peer_area = "Fk" if area == "FkBatch" else area
        cols = []
        for peer in ("Mujoco", "Kdl"):
            ref = runs.get(f"BM_{peer_area}_{peer}_{robot}")
            cols.append(f"{ref[0] / real:>8.2f}x" if ref else f"{'-':>9}")
        previous = runs.get(f"BM_{area}_{parts[2]}Baseline_{robot}")
        cols.append(f"{previous[0] / real:>8.2f}x" if previous else f"{'-':>9}")
        print(f"{name:<{w}} {real:>10.1f} {cpu:>10.1f} {cols[0]} {cols[1]} {cols[2]}")
    for peer in ("Mujoco", "Kdl"):
        for name, (real, cpu) in runs.items():
            if f"_{peer}_" in name:
                print(f"{name:<{w}} {real:>10.1f} {cpu:>10.1f}")
    print("(FkBatch and JacobianBatch rows are per pose; ratios use real-time medians: peer time / lowpair time;\n"
          " x prev: the same benchmark of the kernel before issue 29 (the *Baseline rows) / this one)")
    if errors:
        print("errors:\n  " + "\n  ".join(errors), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "build/bench.json"))
