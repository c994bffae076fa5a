#!/usr/bin/python3
"""The noisy-sensor and disturbance report (issue 19): designs and flies every scenario.

Usage: scripts/scenario_report.py [--tmpc build/tmpc] [--out out/report]
                                  [--designs shipped,residual,noisy] [--scenarios a,b,...]
                                  [--runs 10] [--jobs 1] [--reuse]

For each design (shipped: config/tiltrotor.yaml, its switched observer; residual: the same
artifact flown with `--observer residual`, the one-step residual observer alone; noisy:
config/tiltrotor_noisy.yaml, the Kalman filter always) `tmpc design` (once per
configuration), then `tmpc simulate` of each scenario
(config/scenarios/NAME.yaml; masses_30 and masses_30_noisy as Monte Carlo campaigns of --runs runs), and
prints one markdown table row per flight with what the issue asks to report: RMSE x, y,
z; the servo-rate peak (the larger of |d_alpha_r| and |d_alpha_l| over its bound,
metrics.json box_peak_ratio) and the largest |x_i| / bound of any state; state-constraint
violations; slack use (softened periods, the largest slack and its state); fallback
periods; the solve time (median, p99, max, us); whether the flight aborted (a state past
10 times its bound). A campaign's row sums the counts over its runs, takes the largest
peaks and the runs' mean RMSE, and lists each run's violations. --jobs > 1 flies
missions side by side (the solve times then share the cores). --reuse keeps an
artifact or a flight already in OUT.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys

# name: (configuration, observer override of `tmpc simulate` or None)
DESIGNS = {
    "shipped": ("config/tiltrotor.yaml", None),
    "residual": ("config/tiltrotor.yaml", "residual"),
    "noisy": ("config/tiltrotor_noisy.yaml", None),
}
SCENARIOS = ["thesis_helix", "noisy_sensors", "gusts", "sustained_force", "masses_30",
             "masses_30_noisy", "noisy_sensors_x2", "gusts_2n"]
CAMPAIGNS = {"masses_30", "masses_30_noisy"}
SERVO_RATES = ["d_alpha_r", "d_alpha_l"]


def run(cmd):
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stdout}")


def design(tmpc, config, out, reuse):
    if not (reuse and os.path.exists(out)):
        run([tmpc, "design", "--config", config, "--out", out])
    return out


def fly(tmpc, artifact, observer, scenario, out, runs, reuse):
    metrics = os.path.join(out, "metrics.json")
    if not (reuse and os.path.exists(metrics)):
        cmd = [tmpc, "simulate", "--controller", artifact, "--scenario",
               f"config/scenarios/{scenario}.yaml", "--out", out]
        if observer:
            cmd += ["--observer", observer]
        if scenario in CAMPAIGNS:
            cmd += ["--monte-carlo", str(runs)]
        run(cmd)
    with open(metrics) as f:
        return json.load(f)


def row(design_name, scenario, m):
    """One markdown row from a flight's or a campaign's metrics.json."""
    runs = m["runs"] if "runs" in m else [m]
    rmse = [sum(r["rmse"][a] for r in runs) / len(runs) for a in ("x", "y", "z")]
    servo = max(r["box_peak_ratio"][s] for r in runs for s in SERVO_RATES)
    peak_state, peak = max(((s, v) for r in runs for s, v in r["box_peak_ratio"].items()), key=lambda p: p[1])
    violations = [r["state_constraint_violations"] for r in runs]
    softened = sum(r["softened"]["periods"] for r in runs)
    slack = max(runs, key=lambda r: r["softened"]["slack_max"])["softened"]
    fallbacks = sum(r["fallback_periods"] for r in runs)
    aborted = sum(1 for r in runs if r["diverged"])
    solve = [max(r["solve_us"][q] for r in runs) for q in ("p50", "p99", "max")]
    v = str(sum(violations)) + (f" ({', '.join(map(str, violations))})" if len(runs) > 1 else "")
    s = f"{softened}" + (f", slack {slack['slack_max']:.3g} ({slack['worst_state']})" if softened else "")
    a = "no" if aborted == 0 else (f"{aborted} of {len(runs)}" if len(runs) > 1 else f"after {runs[0]['periods']} periods")
    return (f"| {design_name} | {scenario} | {rmse[0]:.4f}, {rmse[1]:.4f}, {rmse[2]:.4f} | {servo:.2f} | "
            f"{peak:.2f} ({peak_state}) | {v} | {s} | {fallbacks} | {solve[0]:.0f}, {solve[1]:.0f}, {solve[2]:.0f} | {a} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tmpc", default="build/tmpc")
    ap.add_argument("--out", default="out/report")
    ap.add_argument("--designs", default=",".join(DESIGNS))
    ap.add_argument("--scenarios", default=",".join(SCENARIOS))
    ap.add_argument("--runs", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--reuse", action="store_true")
    o = ap.parse_args()
    designs = o.designs.split(",")
    scenarios = o.scenarios.split(",")
    for d in designs:
        if d not in DESIGNS:
            raise SystemExit(f"--designs: unknown design '{d}' (known: {', '.join(DESIGNS)})")
    for s in scenarios:
        if not os.path.exists(f"config/scenarios/{s}.yaml"):
            raise SystemExit(f"--scenarios: no config/scenarios/{s}.yaml")
    os.makedirs(o.out, exist_ok=True)
    configs = sorted({DESIGNS[d][0] for d in designs})
    made = {c: design(o.tmpc, c, os.path.join(o.out, os.path.basename(c).replace(".yaml", ".tmpc")), o.reuse)
            for c in configs}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, o.jobs)) as pool:
        flights = {(d, s): pool.submit(fly, o.tmpc, made[DESIGNS[d][0]], DESIGNS[d][1], s,
                                       os.path.join(o.out, d, s), o.runs, o.reuse)
                   for d in designs for s in scenarios}
        print("| design | scenario | RMSE x, y, z (m) | servo-rate peak (x bound) | largest state (x bound) | "
              "violations | softened periods, largest slack | fallbacks | solve us p50, p99, max | aborted |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for s in scenarios:
            for d in designs:
                print(row(d, s, flights[(d, s)].result()))
                sys.stdout.flush()


if __name__ == "__main__":
    main()
