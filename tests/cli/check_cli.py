#!/usr/bin/env python3
"""CLI checks that read numbers, not patterns: every command's exit code is checked
and its figures are parsed and compared with what the README states.

    check_cli.py TMPC CONFIG SCRATCH CHECK    (CHECK: openloop-el | openloop-mujoco |
                                               unknown-plant | crosscheck | devices | batch |
                                               preflight | second-system | best-case |
                                               best-case-gust | robustness-sweep)
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys

tmpc, config, scratch, check = sys.argv[1:5]
os.makedirs(scratch, exist_ok=True)
failures = []


def run(*args, expect_rc=0):
    p = subprocess.run([tmpc, *args], capture_output=True, text=True, timeout=600)
    if expect_rc is not None and p.returncode != expect_rc:
        sys.exit(f"tmpc {' '.join(args)}: exit code {p.returncode}, expected {expect_rc}\n{p.stdout}{p.stderr}")
    return p


def need(ok, what):
    if not ok:
        failures.append(what)


def number(pattern, text):
    m = re.search(pattern, text)
    if not m:
        sys.exit(f"'{pattern}' not in:\n{text}")
    return float(m.group(1))


scenarios = os.path.join(os.path.dirname(os.path.abspath(config)), "scenarios/")


def design_quick(*extra):
    """The default config designed without the gain comparison and with fewer
    verification directions (the same controller, a shorter design; the envelope's
    scenario paths made absolute for the copy); its artifact."""
    text = open(config).read().replace("compare_gains: true", "compare_gains: false")
    text = text.replace("verify_directions: 2000", "verify_directions: 100")
    text = re.sub(r"(?<=[\[\s,])scenarios/", lambda _: scenarios, text)
    quick = os.path.join(scratch, "quick.yaml")
    open(quick, "w").write(text)
    art = os.path.join(scratch, "c.tmpc")
    run("design", "--config", quick, "--out", art, *extra)
    return art


if check.startswith("openloop-"):
    plant = check.split("-", 1)[1]
    out = run("openloop", "--config", config, "--plant", plant, "--duration", "2").stdout
    drift = number(r"load within ([0-9.e+-]+) m of the reference", out)
    # README: the trimmed reference keeps the open-loop plant within 1 cm for 2 s.
    need(0.0 <= drift < 0.01, f"open-loop drift {drift} m (README: within 1 cm for 2 s)")
elif check == "unknown-plant":
    p = run("openloop", "--config", config, "--plant", "gazebo", expect_rc=None)
    need(0 < p.returncode < 128, f"exit code {p.returncode}: an error, not a crash, was expected")
    need("gazebo" in p.stderr, f"the message does not name the bad plant: {p.stderr}")
    # Contradicting step options are refused before anything is loaded, naming both.
    # The same on the commands that fly the serial loop (they take simulate's estimator flags).
    for cmd in (["simulate", "--controller", "none.tmpc"], ["hil", "--controller", config],
                ["controller", "--controller", config, "--port", "/dev/null"]):
        for flag in ("--step-keeps-lift", "--no-actuator-step", "--reopen-late-steps"):
            p = run(*cmd, "--no-step-detection", flag, expect_rc=None)
            need(0 < p.returncode < 128, f"{cmd[0]}: exit code {p.returncode}: an error, not a crash, was expected")
            need(f"--no-step-detection excludes {flag}" in p.stdout + p.stderr,
                 f"{cmd[0]} {flag}: the message does not name the two options: {p.stdout}{p.stderr}")
elif check == "crosscheck":
    j = json.loads(run("crosscheck", "--config", config, "--states", "1000", "--json").stdout)
    fd = j["forward_dynamics"]["max_relative_error"]
    helix = j["open_loop"]["helix_2s"]["position_m"]
    servo = j["open_loop"]["servo_step_0p5s"]["position_m"]
    # README: forward dynamics agree to 2.4e-11 relative, open loop to 9e-14 m along the
    # helix and 3.6e-7 m for a servo-torque step (two independent engines: near, not equal).
    need(fd < 5e-11, f"forward dynamics differ by {fd} (README: 2.4e-11)")
    need(helix < 2e-13, f"helix open loop differs by {helix} m (README: 9e-14 m)")
    need(1e-7 < servo < 7e-7, f"servo step differs by {servo} m (README: 3.6e-7 m)")
    need(j["hover_max_abs_acceleration"] < 1e-12, f"hover acceleration {j['hover_max_abs_acceleration']}")
elif check == "devices":
    out = run("devices").stdout
    need(re.search(r"built without CUDA|built with CUDA runtime \d+", out) is not None, f"no build line: {out}")
    if "built with CUDA runtime" in out:
        need(re.search(r"no usable CUDA device: .+|no CUDA device found|device 0: .+, sm_\d+", out) is not None,
             f"neither a device nor the reason for none: {out}")
elif check == "batch":
    # A quick design, then five states solved one by one (--json) and all at once
    # (--batch): the batch rows are the single solves.
    art = design_quick("--report", os.path.join(scratch, "r.json"))
    states = [[0.002 * (k + 1) * (1 if i % 2 else -1) for i in range(24)] for k in range(5)]
    batch = os.path.join(scratch, "states.txt")
    with open(batch, "w") as f:
        f.write("# five states\n")
        for s in states:
            f.write(" ".join(f"{v:.17g}" for v in s) + "\n")
    csv = os.path.join(scratch, "batch.csv")
    p = run("solve", "--controller", art, "--batch", batch, "--out", csv)
    out = p.stdout + p.stderr
    need("5 QPs" in out and "5 converged" in out, f"batch summary: {out}")
    rows = [line.split(",") for line in open(csv).read().strip().splitlines()]
    header, rows = rows[0], rows[1:]
    need(len(rows) == 5, f"{len(rows)} rows for 5 states")
    for k, s in enumerate(states):
        single = json.loads(run("solve", "--controller", art, "--x0", ",".join(f"{v:.17g}" for v in s), "--json").stdout)
        row = dict(zip(header, rows[k]))
        need(row["status"] == single["status"] == "converged", f"state {k}: {row['status']} / {single['status']}")
        for i in range(4):
            d = abs(float(row[f"u{i}"]) - single["u_bar0"][i])
            need(d < 1e-8, f"state {k}: u{i} differs by {d} between batch and single solve")
    bad = os.path.join(scratch, "bad.txt")
    open(bad, "w").write("1 2 3\n")
    p = run("solve", "--controller", art, "--batch", bad, expect_rc=None)
    need(p.returncode != 0 and "bad.txt" in p.stderr, f"a short batch line was accepted: {p.returncode} {p.stderr}")
elif check == "preflight":
    # `tmpc check`: the shipped scenarios are flyable with a design of the default
    # config (exit 0); a scenario outside the envelope is refused (exit 1) with the time
    # and the numbers; `simulate` refuses it before take-off (an error, no output).
    art = design_quick()
    for name in ["thesis_helix", "figure_eight", "waypoints", "lissajous_csv"]:
        j = json.loads(run("check", "--controller", art, "--scenario", scenarios + name + ".yaml", "--json").stdout)
        need(j["ok"] and j["scenario"] == name, f"{name}: {j}")
    # The forces against the box: a warning, not a refusal (exit 0), with the windows.
    p = run("check", "--controller", art, "--scenario", scenarios + "sustained_force_4n.yaml")
    need(re.search(r"WARNING: forces on the load: .* 8 disjoint window\(s\) .* for every controller", p.stdout)
         is not None, f"4 N: no warning: {p.stdout}")
    j = json.loads(run("check", "--controller", art, "--scenario", scenarios + "sustained_force_4n.yaml",
                       "--json").stdout)
    need(j["ok"] and len(j["forces"]["certified_windows"]) == 8 and j["forces"]["static_peak_state"] == "theta",
         f"4 N: {j}")
    # The best yaw: 4 N stays outside the box even with the vehicle turned (README).
    need(abs(j["forces"]["static_peak_best_yaw"] - 1.249) < 2e-3 and j["forces"]["static_outside_best_yaw_s"] > 69.9
         and j["forces"]["static_peak_best_yaw"] <= j["forces"]["static_peak"], f"4 N, best yaw: {j}")
    need(j["forces"]["yaw_window"]["width"] == 0.0, f"4 N: a yaw that holds it inside: {j}")
    j = json.loads(run("check", "--controller", art, "--scenario", scenarios + "gusts.yaml", "--json").stdout)
    w = j["forces"].get("yaw_window", {})
    need(abs(w.get("width", -1) - 0.1415) < 2e-3 and abs(w["first"] - 0.254) < 2e-3 and abs(w["last"] - 0.395) < 2e-3
         and abs(w["time"] - 70.97) < 0.05, f"gusts: the yaw window (README: 0.254 to 0.395 rad at 70.97 s): {j}")
    j = json.loads(run("check", "--controller", art, "--scenario", scenarios + "thesis_helix.yaml", "--json").stdout)
    need("yaw_window" not in j["forces"], f"helix: a yaw window where the tilt stays inside: {j}")
    p = run("check", "--controller", art, "--scenario", scenarios + "thesis_helix.yaml")
    need("\nforces on the load: static tilt up to 0.50" in p.stdout and "WARNING" not in p.stdout, f"helix: {p.stdout}")
    fast = os.path.join(scratch, "fast_eight.yaml")
    open(fast, "w").write("duration: 60\ntrajectory: {type: figure_eight, center: [0, 0, 3], amplitude: [8, 3], "
                          "angular_rate: 0.11}\n")
    p = run("check", "--controller", art, "--scenario", fast, expect_rc=1)
    need(re.search(r"REFUSED: .*t = [0-9.]+ s: acceleration [xyz] = -?[0-9.]+ m/s\^2 outside the envelope", p.stdout)
         is not None, f"refusal without the time and the numbers: {p.stdout}")
    p = run("simulate", "--controller", art, "--scenario", fast, "--out", os.path.join(scratch, "fast"), expect_rc=None)
    need(p.returncode != 0 and "refused before take-off" in p.stderr, f"simulate flew it: {p.returncode} {p.stderr}")
    need(not os.path.exists(os.path.join(scratch, "fast", "metrics.json")), "a refused flight left metrics")
    # The law's reversion bounds (--revert-beyond, --revert-within) are checked before
    # take-off, naming the bound and its range.
    for flags, what in ((["--revert-beyond", "0.5"], "revert_beyond must be 0 (off) or above 1"),
                        (["--revert-within", "5"], "revert_within must be in [1, revert_beyond = 4")):
        out = os.path.join(scratch, "revert")
        p = run("simulate", "--controller", art, "--duration", "0.1", "--out", out, *flags, expect_rc=None)
        need(0 < p.returncode < 128 and what in p.stderr, f"{flags}: {p.returncode} {p.stderr}")
        need(not os.path.exists(os.path.join(out, "metrics.json")), f"{flags}: a refused flight left metrics")
elif check == "best-case":
    # scripts/best_case_peak.py: the smallest peak any controller reaches after the
    # thesis' 1 N x step, on the linearized plant of a Monte Carlo draw (README "Mass
    # errors"). Oracles: the free pendulum's swing speed F / (m_L sqrt(g / l)), which
    # the vehicle barely improves on; and the shipped controller's flown peaks, which no
    # controller beats.
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "best_case_peak.py")
    masses = scenarios + "masses_30.yaml"
    # (seed, run): best case (README); seed None is the scenario's (1), run None the nominal plant.
    expected = {(None, None): 0.7687, (None, 1): 0.8912, (None, 2): 1.0266, (None, 9): 1.0402,
                (2, 2): 1.0522, (2, 3): 1.0379, (2, 4): 0.9993, (2, 5): 1.0639}
    p = run("model", "--config", config, "--run", "1", "--json", expect_rc=None)
    need(p.returncode != 0 and "--run needs --scenario" in p.stderr, f"--run without a scenario: {p.stderr}")
    p = run("model", "--config", config, "--scenario", scenarios + "figure_eight.yaml", "--run", "1", "--json",
            expect_rc=None)
    need(p.returncode != 0 and "figure_eight.yaml draws no vehicles (plant.random.fraction is 0)" in p.stderr,
         f"--run on a scenario without draws: {p.stderr}")
    p = run("model", "--config", config, "--matrices", expect_rc=None)
    need(p.returncode != 0 and "--matrices needs --json" in p.stderr, f"--matrices without --json: {p.stderr}")
    p = run("model", "--config", config, "--seed", "2", expect_rc=None)
    need(p.returncode != 0 and "--seed needs --run" in p.stderr, f"--seed without --run: {p.stderr}")
    art = design_quick()
    # A single flight of a scenario with draws flies the nominal plant, and says so.
    p = run("simulate", "--controller", art, "--scenario", masses, "--duration", "0.5", "--out",
            os.path.join(scratch, "nominal"))
    need("this flight flies the nominal plant" in p.stderr, f"simulate without --run: {p.stderr}")
    p = run("simulate", "--controller", art, "--scenario", masses, "--run", "1", "--duration", "0.5", "--out",
            os.path.join(scratch, "drawn"))
    need("nominal plant" not in p.stderr and "Monte Carlo run 1" in p.stdout, f"simulate --run 1: {p.stdout}{p.stderr}")
    for (seed, k), peak in expected.items():
        model = os.path.join(scratch, f"model_{seed}_{k}.json")
        extra = [] if k is None else ["--scenario", masses, "--run", str(k)]
        extra += [] if seed is None else ["--seed", str(seed)]
        with open(model, "w") as fh:
            fh.write(run("model", "--config", config, *extra, "--json", "--matrices").stdout)
        p = subprocess.run([sys.executable, script, model, "--force", "1", "0", "0", "--horizon", "1.0", "--json"],
                           capture_output=True, text=True, timeout=600)
        need(p.returncode == 0, f"run {k}: best_case_peak.py failed: {p.stderr}")
        if p.returncode != 0:
            continue
        r = json.loads(p.stdout)
        m_load = json.load(open(model))["vehicle"]["load_mass"]
        swing = 1.0 / (m_load * (9.81 / 0.5) ** 0.5) / 0.6  # free pendulum's peak speed / the d_x bound
        k_name = k if seed is None else f"{k} of seed {seed}"
        print(f"run {k_name}: load {m_load:.3f} kg, best case {r['peak']:.4f} ({r['binding_state']} at "
              f"{r['binding_time']:.3f} s), free swing {swing:.4f}")
        need(abs(r["peak"] - peak) < 2e-3 * peak, f"run {k}: best case {r['peak']}, README states {peak}")
        need(r["binding_state"] == "d_x" and abs(r["binding_time"] - 0.372) < 0.013, f"run {k}: binds {r}")
        need(1.01 <= r["peak"] / swing <= 1.035, f"run {k}: best case {r['peak']} against the free swing {swing}")
        loads = {(None, None): 0.5, (None, 2): 0.372, (None, 9): 0.366, (2, 4): 0.382}  # README
        need((seed, k) not in loads or abs(m_load - loads[(seed, k)]) < 1e-3, f"run {k_name}: load {m_load}")
        if k is None:
            continue
        out = os.path.join(scratch, f"fly_{seed}_{k}")
        run("simulate", "--controller", art, "--scenario", masses, "--run", str(k), "--duration", "25", "--out", out,
            *([] if seed is None else ["--seed", str(seed)]))
        flown = max(json.load(open(os.path.join(out, "metrics.json")))["box_peak_ratio"].values())
        print(f"run {k_name}: flown peak {flown:.4f}")
        need(flown >= 0.99 * r["peak"], f"run {k_name}: flown {flown} below the best case {r['peak']}")
        # Run 1: no violation where 0.89 is possible (1.05, a servo-rate spike, with the tube
        # gain of lambda's input weights).
        need(seed is not None or k != 1 or abs(flown - 0.912) < 0.005, f"run 1: flown peak {flown}, README states 0.91")
        need(seed != 2 or k != 4 or abs(flown - 1.13) < 0.01, f"run 4 of seed 2: flown peak {flown}, README states 1.13")
        # README's masses row: d_x up to 1.03 (run 2), servo rates up to 1.13 (run 9).
        worst = max(json.load(open(os.path.join(out, "metrics.json")))["box_peak_ratio"].items(), key=lambda kv: kv[1])[0]
        need(seed is not None or k != 2 or (abs(flown - 1.033) < 0.005 and worst == "d_x"), f"run 2: {worst} {flown}")
        need(seed is not None or k != 9 or (abs(flown - 1.131) < 0.005 and worst.startswith("d_alpha")),
             f"run 9: {worst} {flown}")
    # README's derived figures: the lightest load the 0.6 m/s bound allows after 1 N
    # (F / (m_L sqrt(g / l)) = 0.6); the chance that ten uniform +-30 % draws of the
    # 0.5 kg load hold a lighter one; and the nonlinear pendulum's swing against the
    # linearized one's, v^2 = 2 g l (1 - cos a) / cos a against g l tan^2 a (a the
    # static tilt), which takes 0.9 % off the best cases of runs 2 and 9.
    light = 1.0 / (0.6 * (9.81 / 0.5) ** 0.5)
    need(abs(light - 0.376) < 5e-4, f"lightest load {light}")
    chance = 1.0 - (1.0 - (light - 0.35) / 0.30) ** 10
    need(abs(chance - 0.60) < 0.005, f"ten draws: {chance}")
    for m_load, best, corrected in [(0.372, 1.0266, 1.017), (0.366, 1.0402, 1.030)]:
        a = math.atan(1.0 / (m_load * 9.81))
        ratio = (2 * (1 - math.cos(a)) / math.cos(a)) ** 0.5 / math.tan(a)
        need(abs(ratio - 0.991) < 1e-3 and abs(best * ratio - corrected) < 1e-3,
             f"nonlinear swing at {m_load} kg: {ratio}")
    # A model without its matrices is refused, naming the file and what to do.
    bare = os.path.join(scratch, "bare.json")
    with open(bare, "w") as fh:
        fh.write(run("model", "--config", config, "--json").stdout)
    p = subprocess.run([sys.executable, script, bare], capture_output=True, text=True, timeout=60)
    need(p.returncode != 0 and "bare.json: no matrices" in p.stderr, f"a model without matrices: {p.stderr}")
    # A force series (tmpc check --forces) over a window: a constant 2 N along world x
    # from t = 0 on the vehicle hovering at yaw 0.3 rad. Oracles, none from the LP: the
    # rod's static tilt F / (m_L g) (linear model) or atan(F / (m_L g)) (--static-tilt)
    # of the force's larger component in the reference's heading frame (F cos 0.3),
    # against theta's 0.5 rad bound; with the yaw free within psi's 0.5 rad the force
    # can be turned onto the diagonal (-pi/4 is within -0.3 -+ 0.5): F cos(pi/4) on
    # both, less the relaxation's chord (1 %). The window's start is free, so the LP
    # may let the load accelerate along the force: over W seconds its mean acceleration
    # is at most 2 dv_max / W (the speed bound, widened by the turn with the yaw free),
    # which takes at most that / g rad off the tilt.
    hover = os.path.join(scratch, "push.yaml")
    with open(hover, "w") as fh:
        fh.write("name: push\nduration: 6.0\ntrajectory: {type: hover, position: [0.0, 0.0, 3.0], yaw: 0.3}\n"
                 "disturbances:\n  - {type: step, time: 0.0, force: [2.0, 0.0, 0.0]}\n")
    series = os.path.join(scratch, "push.csv")
    run("check", "--controller", art, "--scenario", hover, "--forces", series)
    rows = [line.split(",") for line in open(series).read().splitlines()]
    need(rows[0] == ["t", "f_x", "f_y", "f_z", "psi_ref"], f"--forces header {rows[0]}")
    need(len(rows) == 1 + 501, f"--forces: {len(rows) - 1} rows for 6 s at 12 ms")
    need(all(abs(float(r[0]) - 0.012 * k) < 1e-9 and [float(v) for v in r[1:]] == [2.0, 0.0, 0.0, 0.3]
             for k, r in enumerate(rows[1:])), f"--forces rows: {rows[1:3]} ...")
    p = run("check", "--controller", art, "--scenario", hover, "--forces", os.path.join(scratch, "no", "x.csv"),
            expect_rc=None)
    need(p.returncode != 0 and "--forces " in p.stderr and "cannot open" in p.stderr, f"--forces unwritable: {p.stderr}")
    nominal = os.path.join(scratch, "model_None_None.json")
    mg, window = 0.5 * 9.81, 4.0
    widened = 0.6 * math.sin(0.5) + 1.0 * math.cos(0.5)  # d_y's bound seen from a frame turned by 0.5 rad
    # --yaw-coupled: the turn is the model's yaw error, which psi's own bound (0.5 rad)
    # counts: the vehicle at rest turned by psi has the peak max(psi / 0.5, the static
    # tilt's larger component at -(0.3 + psi)), a point of the relaxation (its upper
    # bound), balanced by bisection; the free arc's relaxation contains the coupled
    # one (its lower bound, the free arc's oracle).
    lo_psi, hi_psi = 0.0, 0.5
    for _ in range(60):
        mid = 0.5 * (lo_psi + hi_psi)
        lo_psi, hi_psi = (mid, hi_psi) if mid / 0.5 < 2.0 / mg * math.cos(0.3 + mid) / 0.5 else (lo_psi, mid)
    balanced = lo_psi  # psi / 0.5 * 0.5: the balanced peak, in radians of the 0.5 rad bound
    for extra, static, relax, dv in [([], 2.0 * math.cos(0.3) / mg, 0.0, 0.6),
                                      (["--static-tilt"], math.atan(2.0 / mg) * math.cos(0.3), 0.0, 0.6),
                                      (["--yaw-free"], 2.0 * math.cos(math.pi / 4) / mg, 0.01, widened),
                                      (["--yaw-coupled"], balanced, 0.01, widened)]:
        p = subprocess.run([sys.executable, script, nominal, "--forces", series, "--window", "1", str(1 + window),
                            "--json", *extra], capture_output=True, text=True, timeout=600)
        need(p.returncode == 0, f"--forces {extra}: {p.stderr}")
        if p.returncode != 0:
            continue
        r = json.loads(p.stdout)
        # (the coupled relaxation's lower bounds are the free arc's)
        floor = 2.0 * math.cos(math.pi / 4) / mg if "--yaw-coupled" in extra else static
        lo = (floor * (1 - relax) - 2 * dv / window / 9.81) / 0.5
        print(f"2 N along x {extra}: best case {r['peak']:.4f} ({r['binding_state']}), static {static / 0.5:.4f}, "
              f"at least {lo:.4f}")
        need(lo <= r["peak"] <= static / 0.5 + 1e-3, f"--forces {extra}: {r['peak']} outside [{lo}, {static / 0.5}]")
        # --at-rest: the window starts at rest under the force before it (the same 2 N),
        # so its first period's tilt is the static one (the box holds there: the peak is
        # at least that) and staying at rest reaches it: the static tilt itself (with the
        # yaw free, less at most the chord's 1 %).
        p = subprocess.run([sys.executable, script, nominal, "--forces", series, "--window", "1", str(1 + window),
                            "--json", "--at-rest", *extra], capture_output=True, text=True, timeout=600)
        need(p.returncode == 0, f"--forces --at-rest {extra}: {p.stderr}")
        if p.returncode == 0:
            rest = json.loads(p.stdout)["peak"]
            print(f"2 N along x {extra}, from rest: best case {rest:.4f}")
            need(floor * (1 - relax) / 0.5 - 1e-3 <= rest <= static / 0.5 + 1e-3,
                 f"--forces --at-rest {extra}: {rest}, static {static / 0.5}")
    # --bound: the best case when a state must stay within a given half-width. The load
    # kept at its reference (x, y within 1 cm) from rest under the constant 2 N: the
    # static tilt needs no position error, so the peak is that tilt; the speeds held
    # within 1 cm/s from a free start: the load cannot accelerate along the force, and
    # the bound on what that takes off the tilt (above) shrinks to 2 * 0.01 / W / g.
    static = math.atan(2.0 / mg) * math.cos(0.3) / 0.5
    for extra, lo in [(["--at-rest", "--bound", "x", "0.01", "--bound", "y", "0.01"], static - 1e-3),
                      (["--bound", "d_x", "0.01", "--bound", "d_y", "0.01"], static - 2 * 0.01 / window / 9.81 / 0.5)]:
        p = subprocess.run([sys.executable, script, nominal, "--forces", series, "--window", "1", str(1 + window),
                            "--static-tilt", "--json", *extra], capture_output=True, text=True, timeout=600)
        need(p.returncode == 0, f"--bound {extra}: {p.stderr}")
        if p.returncode == 0:
            r = json.loads(p.stdout)
            print(f"2 N along x {extra}: best case {r['peak']:.4f} ({r['binding_state']}), static {static:.4f}")
            need(lo <= r["peak"] <= static + 1e-3 and len(r["bounds"]) == 2, f"--bound {extra}: {r}")
    # --yaw-coupled ties the force's direction to the model's yaw, so a turn takes the
    # time the yaw's dynamics need. 2.4 N at +0.2 rad from the heading, then from 1 s at
    # -0.2: the best yaw moves the force toward the nearer diagonal, -0.5 rad (psi's
    # bound) before the switch and +0.5 after it, a 1 rad turn. From rest at the switch:
    # holding the yaw is the static tilt of the larger component (the rest state itself
    # binds), the free arc turns at once, the coupled turn must take time. Oracles: the
    # relaxations' order (coupled inside the free arc's hull, the held yaw a coupled
    # trajectory) and the held static tilt; the gap of the turn's time (README: 0.892,
    # 0.721, 0.769).
    switch = os.path.join(scratch, "switch.csv")
    with open(switch, "w") as fh:
        fh.write("t,f_x,f_y,f_z,psi_ref\n")
        for k in range(400):
            a = 0.2 if k < 84 else -0.2
            fh.write(f"{0.012 * k},{2.4 * math.cos(a)},{2.4 * math.sin(a)},0,0\n")
    peaks = {}
    for how in ("held", "--yaw-free", "--yaw-coupled"):
        p = subprocess.run([sys.executable, script, nominal, "--forces", switch, "--window", "1.0", "4.0",
                            "--static-tilt", "--at-rest", "--json", *([] if how == "held" else [how])],
                           capture_output=True, text=True, timeout=600)
        need(p.returncode == 0, f"switch {how}: {p.stderr}")
        if p.returncode == 0:
            peaks[how] = json.loads(p.stdout)["peak"]
            print(f"2.4 N switching from +0.2 to -0.2 rad, from rest, {how}: best case {peaks[how]:.4f}")
    if len(peaks) == 3:
        held = math.atan(2.4 / mg) * math.cos(0.2) / 0.5
        need(abs(peaks["held"] - held) < 2e-3, f"switch, yaw held: {peaks['held']}, static {held}")
        need(peaks["--yaw-free"] + 0.03 <= peaks["--yaw-coupled"] <= peaks["held"] - 0.05, f"switch: {peaks}")
        for how, value in (("held", 0.892), ("--yaw-free", 0.721), ("--yaw-coupled", 0.769)):
            need(abs(peaks[how] - value) < 2e-3, f"switch {how}: {peaks[how]}, README states {value}")
    lifting = os.path.join(scratch, "lift.csv")  # 5 N up on a 0.5 kg load: no static tilt exists
    with open(lifting, "w") as fh:
        fh.write("t,f_x,f_y,f_z,psi_ref\n" + "".join(f"{0.012 * k},1,0,5,0\n" for k in range(100)))
    for args, what in [(["--forces", series, "--window", "5", "9"], "outside the series"),
                       (["--forces", lifting, "--window", "0", "1", "--static-tilt"], "lifts the load"),
                       (["--forces", series, "--window", "3", "2"], "or empty"),
                       (["--window", "1", "2"], "--forces and --window go together"),
                       (["--yaw-free"], "--static-tilt and --at-rest need --forces"),
                       (["--at-rest"], "--static-tilt and --at-rest need --forces"),
                       (["--yaw-coupled"], "--yaw-coupled, --static-tilt and --at-rest need --forces"),
                       (["--bound", "int_x", "1"], "--bound int_x: no such state of the box"),
                       (["--bound", "x", "0"], "--bound x 0.0: a half-width must be positive"),
                       (["--bound", "x", "wide"], "--bound x wide: not a number"),
                       (["--forces", series, "--window", "1", "2", "--yaw-free", "--yaw-coupled"],
                        "--yaw-free and --yaw-coupled exclude each other"),
                       (["--forces", hover, "--window", "1", "2"], "expected t,f_x,f_y,f_z,psi_ref")]:
        p = subprocess.run([sys.executable, script, nominal, *args], capture_output=True, text=True, timeout=60)
        need(p.returncode != 0 and what in p.stderr, f"best_case_peak.py {args}: {p.returncode} {p.stderr}")
elif check == "second-system":
    # The mass-spring pair (config/mass_spring.yaml): designed, flown on the virtual
    # clock and in real time over a pseudo-terminal pair by the same commands.
    cfg = os.path.join(os.path.dirname(os.path.abspath(config)), "mass_spring.yaml")
    scen = os.path.join(os.path.dirname(os.path.abspath(config)), "scenarios", "mass_spring_steps.yaml")
    art = os.path.join(scratch, "ms.tmpc")
    run("design", "--config", cfg, "--out", art)
    info = run("inspect", art).stdout
    need("model linear: 6 states (4 measured), 2 inputs" in info, f"inspect: {info}")
    run("simulate", "--controller", art, "--scenario", scen, "--out", os.path.join(scratch, "sim"))
    m = json.load(open(os.path.join(scratch, "sim", "metrics.json")))
    need(m["state_constraint_violations"] == 0 and m["fallback_periods"] == 0 and not m["diverged"], f"simulate: {m}")
    need(abs(m["rmse"]["p1"] - 0.0415) < 0.02 * 0.0415, f"RMSE p1 {m['rmse']['p1']} (tests: 0.0415)")
    p = run("hil", "--controller", art, "--scenario", scen, "--duration", "3", "--out", os.path.join(scratch, "hil"))
    out = p.stdout + p.stderr
    need(re.search(r"states \d+ accepted, 0 rejected", out) is not None, f"hil link: {out}")
    need(re.search(r"telemetry \d+ records, 0 dropped", out) is not None, f"hil telemetry: {out}")
    with open(os.path.join(scratch, "hil", "telemetry.csv")) as f:
        first, header = f.readline(), f.readline()
    # --solver auto (the default) says which solver flies and why in the first line.
    need(re.match(r"# solver active-set: .*(no GPU solver in this build|admm-cuda unavailable)", first) is not None,
         f"telemetry's first line: {first}")
    need(header.startswith("period,t,e_p1,e_p2,e_v1,e_v2,e_int_p1,e_int_p2,"), f"telemetry header: {header}")
    hj = json.load(open(os.path.join(scratch, "hil", "metrics.json")))
    need(hj["solver"]["name"] == "active-set" and hj["solver"]["why"] != "", f"hil metrics solver: {hj.get('solver')}")
elif check == "doctor":
    # Fake procfs/sysfs trees: a board set up per the README passes (exit 0), a missing
    # serial device fails (exit 1), each finding printed with what to do.
    def tree(name, files):
        root = os.path.join(scratch, name)
        for rel, text in files.items():
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            open(path, "w").write(text)
        return ["--proc", os.path.join(root, "proc"), "--sys", os.path.join(root, "sys")]
    good = tree("good", {
        "proc/version": "Linux version 5.15.148-rt-tegra #1 SMP PREEMPT_RT\n",
        "proc/sys/kernel/sched_rt_runtime_us": "-1\n",
        "sys/devices/system/cpu/cpu0/cpufreq/scaling_governor": "performance\n",
        "sys/devices/system/cpu/isolated": "0\n",
        "proc/self/limits": "Max locked memory  unlimited  unlimited  bytes\nMax realtime priority  99  99\n",
    })
    out = run("doctor", *good, "--cpu", "0", "--port", "/dev/null", "--seconds", "0").stdout
    for line in ("kernel           ok    PREEMPT_RT", "cpu governor     ok    performance on all 1 CPUs",
                 "serial device    ok    /dev/null", "verdict: the controller can run here"):
        need(line in out, f"doctor (good board) lacks '{line}': {out}")
    bad = tree("bad", {"proc/version": "Linux version 6.1.0 #1 SMP PREEMPT_DYNAMIC\n",
                       "sys/devices/system/cpu/isolated": "\n"})
    p = run("doctor", *bad, "--port", os.path.join(scratch, "ttyNONE"), "--seconds", "0", expect_rc=1)
    for line in ("kernel           warn  preemptible (PREEMPT), not PREEMPT_RT", "-> install a PREEMPT_RT kernel",
                 "isolated cpus    warn  none", "serial device    FAIL", "verdict: the controller cannot"):
        need(line in p.stdout, f"doctor (bad board) lacks '{line}': {p.stdout}")
    # A short real latency run: measured and judged (this VM is not real-time: either verdict).
    p = run("doctor", "--seconds", "0.2", expect_rc=None)
    need(p.returncode in (0, 1) and re.search(r"wake-up latency +(ok|warn|FAIL) +200 wake-ups: p50 \d+ us, p99 \d+ us", p.stdout)
         is not None, f"doctor latency run: rc {p.returncode}: {p.stdout}{p.stderr}")
elif check == "service":
    # scripts/install_service.sh into a staging root: the unit runs the controller with
    # the artifact, port, priority, CPU, memlock, restart and telemetry asked for.
    repo = os.path.dirname(os.path.dirname(os.path.abspath(config)))
    script = os.path.join(repo, "scripts", "install_service.sh")
    art = os.path.join(scratch, "c.tmpc")
    open(art, "w").write("stand-in: the script does not read it\n")
    stage = os.path.join(scratch, "root")
    def install(*args, rc=0):
        p = subprocess.run(["bash", script, "--bin", tmpc, "--root", stage, *args], capture_output=True, text=True, timeout=60)
        need(p.returncode == rc, f"install_service {' '.join(args)}: exit {p.returncode}, expected {rc}: {p.stderr}")
        return p
    install("--controller", art, "--port", "/dev/ttyTHS0", "--rt-priority", "85", "--cpu", "3", "--telemetry-dir", "/var/log/tmpc")
    unit = open(os.path.join(stage, "etc/systemd/system/tmpc-controller.service")).read()
    need("@" not in unit.split("[Unit]", 1)[1], f"unfilled fields in the unit: {unit}")
    keys = dict(l.split("=", 1) for l in unit.splitlines() if "=" in l and not l.startswith("#"))
    start = keys.get("ExecStart", "")
    for part in (f"{tmpc} controller --controller {art} --port /dev/ttyTHS0", "--rt-priority 85 --cpu 3", "--solver auto",
                 "--telemetry /var/log/tmpc/telemetry-$$(date +%%Y%%m%%d-%%H%%M%%S).csv"):
        need(part in start, f"ExecStart lacks '{part}': {start}")
    for k, v in (("Restart", "on-failure"), ("LimitRTPRIO", "85"), ("LimitMEMLOCK", "infinity"), ("CPUAffinity", "3"),
                 ("WantedBy", "multi-user.target")):
        need(keys.get(k) == v, f"{k}={keys.get(k)}, expected {v}")
    need(keys.get("ExecStartPre", "").startswith(f"-{tmpc} doctor --port /dev/ttyTHS0"), f"ExecStartPre: {keys.get('ExecStartPre')}")
    need(os.path.isdir(os.path.join(stage, "var/log/tmpc")), "telemetry directory not made")
    if shutil.which("systemd-analyze"):
        p = subprocess.run(["systemd-analyze", "verify", "--root", stage, "tmpc-controller.service"], capture_output=True, text=True)
        print(f"systemd-analyze verify: exit {p.returncode} {p.stderr.strip()}")
    # Bad input: named.
    need("--port DEV is required" in install("--controller", art, rc=2).stderr, "no port: not named")
    need("--rt-priority must be 1..99" in install("--controller", art, "--port", "/dev/x", "--rt-priority", "0", rc=2).stderr,
         "priority 0: not named")
    need("no such controller artifact" in install("--controller", art + ".missing", "--port", "/dev/x", rc=2).stderr,
         "missing artifact: not named")
elif check == "robustness-sweep":
    # scripts/robustness_sweep.py (README "Flights no test was tuned to"): it writes
    # scenario files tmpc takes, flies them and reports every flight; bad counts are named.
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "robustness_sweep.py")
    art = design_quick()
    out = os.path.join(scratch, "sweep")
    sweep = [sys.executable, script, "--tmpc", tmpc, "--controller", art, "--out", out, "--jobs", "1"]
    p = subprocess.run(sweep + ["--count", "3", "--duration", "6"], capture_output=True, text=True, timeout=600)
    need(p.returncode == 0, f"robustness_sweep.py failed: {p.stdout}{p.stderr}")
    rows = [line for line in p.stdout.splitlines() if line.startswith("| s0")]
    need(len(rows) == 3, f"3 flights, {len(rows)} rows:\n{p.stdout}")
    need(re.search(r"^3 flights: \d+ without a violation", p.stdout, re.M) is not None, f"no totals:\n{p.stdout}")
    # The per-class table: its classes partition the flights and their violations.
    classes = {c: (int(n), int(v)) for c, n, v in re.findall(
        r"^\| (no noise|noise, no fault|noise and the rotor fault|all) \((\d+)\) \| \d+ \| (\d+) \|", p.stdout, re.M)}
    total = re.search(r"^3 flights: \d+ without a violation, (\d+) violations", p.stdout, re.M)
    need("all" in classes and classes["all"][0] == 3, f"no 'all' row of 3 flights:\n{p.stdout}")
    parts = [v for c, v in classes.items() if c != "all"]
    need(sum(n for n, _ in parts) == 3, f"the classes do not partition the 3 flights: {classes}")
    need(total is not None and sum(v for _, v in parts) == classes.get("all", (0, -1))[1] == int(total.group(1)),
         f"the classes' violations do not add up to the total: {classes}\n{p.stdout}")
    files = sorted(os.listdir(os.path.join(out, "scenarios")))
    need(len(files) == 3, f"scenario files {files}")
    for f in files:  # each file is a scenario tmpc reads on its own
        q = run("check", "--controller", art, "--scenario", os.path.join(out, "scenarios", f), expect_rc=None)
        need("error" not in (q.stdout + q.stderr).lower(), f"tmpc check {f}: {q.stdout}{q.stderr}")
    p = subprocess.run(sweep + ["--count", "0"], capture_output=True, text=True, timeout=60)
    need(p.returncode != 0 and "--count must be in [1, 360], got 0" in p.stderr, f"--count 0: {p.stderr}")
elif check == "best-case-gust":
    # README "What this does not reach": the shipped gusts scenario (seed 3) over 66 to
    # 72 s, where its static tilt leaves the box at the reference's yaw. Even knowing the
    # gust in advance, a controller that holds the yaw leaves the box (1.10); for one that
    # may turn the lower bound stays inside (0.795). Without the preview, from rest at the
    # gust's redraw at 64 s (over 64 to 70 s, the yaw free): 0.770. On the linear model
    # calibrated to the static tilt.
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "best_case_peak.py")
    art = design_quick()
    series = os.path.join(scratch, "gusts.csv")
    run("check", "--controller", art, "--scenario", scenarios + "gusts.yaml", "--forces", series)
    model = os.path.join(scratch, "model.json")
    with open(model, "w") as fh:
        fh.write(run("model", "--config", config, "--json", "--matrices").stdout)
    for extra, window, peak in [([], ("66", "72"), 1.1048), (["--yaw-free"], ("66", "72"), 0.7952),
                                (["--yaw-free", "--at-rest"], ("64", "70"), 0.7695),
                                (["--yaw-coupled", "--at-rest"], ("64", "70"), 0.7705)]:
        p = subprocess.run([sys.executable, script, model, "--forces", series, "--window", *window, "--static-tilt",
                            "--json", *extra], capture_output=True, text=True, timeout=900)
        need(p.returncode == 0, f"gusts {extra}: {p.stderr}")
        if p.returncode == 0:
            r = json.loads(p.stdout)
            print(f"gusts seed 3, {window[0]} to {window[1]} s {extra}: best case {r['peak']:.4f} ({r['binding_state']})")
            need(abs(r["peak"] - peak) < 2e-3, f"gusts {extra}: best case {r['peak']}, README states {peak}")
else:
    sys.exit(f"unknown check {check}")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"{check}: ok")
