#!/usr/bin/python3
"""Plots of a closed-loop mission, like thesis Figures 6.11-6.21.

Usage: scripts/plot_mission.py DIR [DIR ...]
DIR holds telemetry.csv (tmpc simulate --out DIR); a Monte Carlo campaign directory
(with run_K/ folders) is plotted run by run. PNGs go to DIR/plots/: for the tiltrotor
the 3-D path with the reference, position errors, attitude, swing and tilt angles,
thrusts and torques; for another model (config `model: linear`) the errors of its
measured states and its inputs; and a violin plot of the solve times of every DIR
given (one violin each). The dashed lines are the scenario's disturbance events
(metrics.json's window starts).
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DISTURBANCE_TIMES = []


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    if not rows:
        raise SystemExit(f"{path}: no telemetry rows")
    cols = {k: [] for k in rows[0]}
    for r in rows:
        for k, v in r.items():
            try:
                cols[k].append(float(v))
            except ValueError:
                cols[k].append(v)
    for k in ("t", "solve_us"):
        if k not in cols:
            raise SystemExit(f"{path}: column '{k}' missing (not a tmpc telemetry.csv)")
    return cols


def event_times(d):
    """The scenario's disturbance events: the metrics' window starts after 0."""
    try:
        with open(os.path.join(d, "metrics.json")) as f:
            return [t for t in json.load(f)["tube_exits"]["window_starts"] if t > 0.0]
    except (OSError, KeyError, ValueError):
        return []


def absolute(c, name):
    return [r + e for r, e in zip(c["r_" + name], c["e_" + name])]


def mark_disturbances(ax, t_end):
    for td in DISTURBANCE_TIMES:
        if td < t_end:
            ax.axvline(td, color="0.7", lw=0.8, ls="--")


def series(c, names, ylabel, title, out, absolute_values=False):
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(8, 2.2 * len(names)))
    axes = axes if len(names) > 1 else [axes]
    for ax, (key, label) in zip(axes, names):
        y = absolute(c, key) if absolute_values else c[key]
        ax.plot(c["t"], y, lw=0.9)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        mark_disturbances(ax, c["t"][-1])
    axes[-1].set_xlabel("t [s]")
    axes[0].set_title(title)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_generic(c, out):
    """Any model: the errors of the measured states and the inputs, by column name."""
    errors = [(k, k[2:]) for k in c if k.startswith("e_")]
    inputs = [(k, k[2:]) for k in c if k.startswith("u_")]
    if errors:
        series(c, errors, "", "tracking errors", os.path.join(out, "errors.png"))
    if inputs:
        series(c, inputs, "", "inputs", os.path.join(out, "inputs.png"))


def plot_run(d):
    c = read(os.path.join(d, "telemetry.csv"))
    DISTURBANCE_TIMES[:] = event_times(d) or event_times(os.path.dirname(os.path.normpath(d)))
    out = os.path.join(d, "plots")
    os.makedirs(out, exist_ok=True)
    if not all(k in c for k in ("e_x", "r_x", "e_gamma_1", "u_f_r")):
        plot_generic(c, out)
        return c
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    ax.plot(c["r_x"], c["r_y"], c["r_z"], "k--", lw=0.8, label="reference")
    ax.plot(absolute(c, "x"), absolute(c, "y"), absolute(c, "z"), lw=1.0, label="load")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "path_3d.png"), dpi=120)
    plt.close(fig)
    series(c, [("e_x", "x err [m]"), ("e_y", "y err [m]"), ("e_z", "z err [m]")], "m", "position errors",
           os.path.join(out, "position_errors.png"))
    series(c, [("phi", "phi [rad]"), ("theta", "theta [rad]"), ("psi", "psi [rad]")], "rad", "load attitude",
           os.path.join(out, "attitude.png"), absolute_values=True)
    series(c, [("gamma_1", "gamma_1 [rad]"), ("gamma_2", "gamma_2 [rad]")], "rad", "swing angles",
           os.path.join(out, "swing.png"), absolute_values=True)
    series(c, [("alpha_r", "alpha_r [rad]"), ("alpha_l", "alpha_l [rad]")], "rad", "tilt angles",
           os.path.join(out, "tilt.png"), absolute_values=True)
    series(c, [("u_f_r", "f_r [N]"), ("u_f_l", "f_l [N]"), ("u_tau_r", "tau_r [N m]"), ("u_tau_l", "tau_l [N m]")],
           "", "thrusts and servo torques", os.path.join(out, "inputs.png"))
    if "dhat_x" in c and any(abs(v) > 0.0 for v in c["dhat_x"] + c["dhat_y"] + c["dhat_z"]):
        # Offset-free tube law: the observer's estimate of the force on the load.
        series(c, [("dhat_x", "d_x [N]"), ("dhat_y", "d_y [N]"), ("dhat_z", "d_z [N]")], "N",
               "estimated force on the load (offset-free tube law)", os.path.join(out, "disturbance_estimate.png"))
    if "tube_ratio" in c:
        series(c, [("tube_ratio", "|x~ - x_bar| / radius of Z")], "", "distance from the tube (<= 1: inside)",
               os.path.join(out, "tube_distance.png"))
    return c


def runs_of(d):
    if os.path.exists(os.path.join(d, "telemetry.csv")):
        return [d]
    runs = sorted(os.path.join(d, r) for r in os.listdir(d) if r.startswith("run_"))
    if not runs:
        raise SystemExit(f"{d}: no telemetry.csv and no run_K/ folders")
    return runs


def main(argv):
    if len(argv) < 2:
        raise SystemExit(__doc__)
    solve, labels = [], []
    for d in argv[1:]:
        times = []
        for r in runs_of(d):
            times += plot_run(r)["solve_us"]
        solve.append(times)
        labels.append(os.path.basename(os.path.normpath(d)))
    fig, ax = plt.subplots(figsize=(1.8 + 1.6 * len(solve), 4))
    ax.violinplot(solve, showmedians=True)
    ax.set_xticks(range(1, len(labels) + 1), labels)
    ax.set_yscale("log")
    ax.set_ylabel("solve time [us]")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    first = os.path.join(argv[1], "plots")
    os.makedirs(first, exist_ok=True)
    fig.savefig(os.path.join(first, "solve_times_violin.png"), dpi=120)
    plt.close(fig)
    print(f"plots written under {', '.join(os.path.join(d, 'plots') for d in argv[1:])} (violin: {first})")


if __name__ == "__main__":
    main(sys.argv)
