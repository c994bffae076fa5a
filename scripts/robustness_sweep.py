#!/usr/bin/python3
"""Flights no test was tuned to: a seeded random sweep over tracks, forces, noise and faults.

Usage: scripts/robustness_sweep.py --controller out/tiltrotor.tmpc [--tmpc build/tmpc]
                                   [--out out/sweep] [--count 80] [--seed 7] [--duration 60]
                                   [--jobs 2] [--args=--no-step-detection]

Draws --count combinations (without repeats, in a seeded order) of
  track:       the thesis helix; a faster, lower helix at yaw 0.3 rad; the figure eight;
               the waypoint box; the nose-first helix (a CSV track with a turning yaw)
  steps:       the thesis' 1 N steps at 20/40/60 s; two diagonal steps (15 s, 45 s); none
  noise:       0, 0.5, 1, 1.5 times the noisy_sensors scenario's white noise (5 mm,
               0.3 deg, 0.031 m/s, 0.033 rad/s)
  gusts:       none, 1.0 N, 1.5 N on the load (time constant 1 s, redrawn every 8 s)
  fault:       none, or the left rotor at 90 % of its thrust from 25 s (halfway through a shorter one)
writes each as a scenario file into OUT/scenarios, flies it with `tmpc simulate` (the
arguments of --args appended) and prints one row per flight: violations, the worst state
over its bound, the servo-rate peak, fallbacks, softened periods, RMSE, steps read by the
filter (in brackets those that re-opened the lift), aborted; then the totals per class (no
noise, noise without the fault, noise and the fault) and over all. The seeds of the gusts and the noise follow the row.
Exit status 0 when every flight ran (aborted flights are reported, not errors).
"""
import argparse
import concurrent.futures
import itertools
import json
import os
import random
import shlex
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TRACKS = {
    "helix": "{type: helix, center: [0.0, 0.0, 4.0], radius: 5.0, z_amplitude: 3.0, "
             "angular_rate: 0.07853981633974483, yaw: 0.0}",
    "helix_fast": "{type: helix, center: [0.0, 0.0, 4.0], radius: 4.0, z_amplitude: 2.0, "
                  "angular_rate: 0.12, yaw: 0.3}",
    "eight": "{type: figure_eight, center: [0.0, 0.0, 3.0], amplitude: [8.0, 3.0], "
             "angular_rate: 0.085, yaw: 0.0}",
    "waypoints": "{type: waypoints, points: [[0.0, 0.0, 1.0], [4.0, 0.0, 2.0], [4.0, 4.0, 3.0], "
                 "[0.0, 4.0, 2.0], [0.0, 0.0, 1.0]], max_speed: 0.6, max_acceleration: 0.05, yaw: 0.0}",
    "nose": "{type: csv, file: %s}" % os.path.join(REPO, "config/scenarios/tracks/helix_nose_first.csv"),
}
STEPS = {
    "steps": [(20, (1, 0, 0)), (40, (0, 1, 0)), (60, (0, 0, 1))],
    "diag": [(15, (0.7, 0.7, 0)), (45, (-0.7, 0.5, -0.5))],
    "none": [],
}
NOISE = [0.0, 0.5, 1.0, 1.5]
NOISE_1 = {"position": 0.005, "angle": 0.00524, "velocity": 0.031, "angular_rate": 0.033}
GUSTS = [0.0, 1.0, 1.5]
FAULTS = {"none": None, "rotor90": "{type: efficiency, input: 1, factor: 0.9, start: %g}"}
SERVO_RATES = ["d_alpha_r", "d_alpha_l"]


def scenario(name, track, steps, noise, gust, fault, seed, duration):
    lines = [f"name: {name}", f"duration: {duration}", f"trajectory: {TRACKS[track]}", "disturbances:"]
    events = [f"  - {{type: step, time: {t}.0, force: [{f[0]}, {f[1]}, {f[2]}], on: load}}"
              for t, f in STEPS[steps] if t < duration]
    if gust > 0.0:
        events.append(f"  - {{type: gust, start: 0.0, magnitude: {gust}, time_constant: 1.0, "
                      f"redraw: 8.0, seed: {seed}, on: load}}")
    lines = lines[:-1] + ["disturbances: []"] if not events else lines + events
    if noise > 0.0:
        lines += ["noise:", f"  seed: {seed + 10}"]
        lines += [f"  {group}: {{white: {noise * level:.6g}}}" for group, level in NOISE_1.items()]
    if FAULTS[fault]:
        lines += ["faults:", "  - " + FAULTS[fault] % min(25.0, 0.5 * duration)]
    return "\n".join(lines) + "\n"


def fly(tmpc, controller, path, out, extra):
    cmd = [tmpc, "simulate", "--controller", controller, "--scenario", path, "--out", out] + extra
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stdout}")
    with open(os.path.join(out, "metrics.json")) as f:
        return json.load(f)


def new_totals():
    return {"flights": 0, "violations": 0, "fallbacks": 0, "softened": 0, "aborted": 0, "clean": 0,
            "worst": 0.0, "worst_state": ""}


def add(t, m):
    """One flight's metrics into a class's totals (its worst state over its bound too)."""
    t["flights"] += 1
    t["violations"] += m["state_constraint_violations"]
    t["fallbacks"] += m["fallback_periods"]
    t["softened"] += m["softened"]["periods"]
    t["aborted"] += bool(m["diverged"])
    t["clean"] += m["state_constraint_violations"] == 0 and not m["diverged"]
    if m["state_constraint_violations"] > 0 and m["violation"]["max_ratio"] > t["worst"]:
        t["worst"] = m["violation"]["max_ratio"]
        t["worst_state"] = m["violation"]["worst_state"]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--controller", required=True)
    p.add_argument("--tmpc", default=os.path.join(REPO, "build", "tmpc"))
    p.add_argument("--out", default="out/sweep")
    p.add_argument("--count", type=int, default=80)
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--duration", type=float, default=60.0)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--args", default="", help="more arguments for tmpc simulate")
    a = p.parse_args()
    combos = list(itertools.product(TRACKS, STEPS, NOISE, GUSTS, FAULTS))
    random.Random(a.seed).shuffle(combos)
    if not 0 < a.count <= len(combos):
        raise SystemExit(f"--count must be in [1, {len(combos)}], got {a.count}")
    os.makedirs(os.path.join(a.out, "scenarios"), exist_ok=True)
    flights = []
    for i, (track, steps, noise, gust, fault) in enumerate(combos[:a.count]):
        name = f"s{i:03d}_{track}_{steps}_n{noise:g}_g{gust:g}_{fault}"
        path = os.path.join(a.out, "scenarios", name + ".yaml")
        with open(path, "w") as f:
            f.write(scenario(name, track, steps, noise, gust, fault, 1 + i % 11, a.duration))
        flights.append((name, path))
    extra = shlex.split(a.args)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        results = list(pool.map(lambda nf: fly(a.tmpc, a.controller, nf[1], os.path.join(a.out, nf[0]), extra),
                                flights))
    print("| flight | violations | worst state (x bound) | servo-rate peak | fallbacks | softened | "
          "RMSE x, y, z (m) | steps read (lift re-opened) | aborted |")
    print("|---|---|---|---|---|---|---|---|---|")
    classes = {}  # the README's classes: no noise, noise without the fault, noise and the fault
    for (name, _), (_, _, noise, _, fault), m in zip(flights, combos, results):
        servo = max(m["box_peak_ratio"].get(s, 0.0) for s in SERVO_RATES)
        worst = m["violation"]
        r = m["rmse"]
        print(f"| {name} | {m['state_constraint_violations']} | {worst['worst_state'] or '-'} "
              f"{worst['max_ratio']:.2f} | {servo:.2f} | {m['fallback_periods']} | {m['softened']['periods']} | "
              f"{r['x']:.3f}, {r['y']:.3f}, {r['z']:.3f} | {m['observer']['step_detections']} "
              f"({m['observer'].get('step_lift_reopenings', 0)}) | "
              f"{'yes' if m['diverged'] else 'no'} |")
        label = "no noise" if noise == 0.0 else "noise, no fault" if FAULTS[fault] is None else "noise and the rotor fault"
        for key in (label, "all"):
            add(classes.setdefault(key, new_totals()), m)
    print("\n| flights | without a violation | violations | worst state (x bound) | fallbacks | softened | aborted |")
    print("|---|---|---|---|---|---|---|")
    for label in ("no noise", "noise, no fault", "noise and the rotor fault", "all"):
        if label not in classes:
            continue
        t = classes[label]
        worst = f"{t['worst']:.2f} ({t['worst_state']})" if t["worst_state"] else "-"
        print(f"| {label} ({t['flights']}) | {t['clean']} | {t['violations']} | {worst} | {t['fallbacks']} | "
              f"{t['softened']} | {t['aborted']} |")
    t = classes["all"]
    print(f"\n{len(flights)} flights: {t['clean']} without a violation, {t['violations']} violations, "
          f"{t['fallbacks']} fallback and {t['softened']} softened periods, {t['aborted']} aborted")
    return 0


if __name__ == "__main__":
    sys.exit(main())
