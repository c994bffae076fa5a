#!/usr/bin/env python3
"""Independent oracle: the QPs exported by `tmpc export-qp` solved by cvxopt
(Debian python3-cvxopt), compared with tmpc's reference solver and its default
exact ADMM (`tmpc solve --solver NAME --json`): relative objective gap below 1e-10
and u_bar(0) within 1e-9 for the reference, 1e-9 and 1e-7 for admm (README).

usage: check_cvxopt.py TMPC CONFIG WORKDIR"""
import json
import os
import random
import re
import subprocess
import sys

import numpy as np
from cvxopt import matrix, solvers

tmpc, config, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
# A quick design (no LMI comparison) of the default config.
text = open(config).read()
text = text.replace("compare_gains: true", "compare_gains: false").replace("verify_directions: 2000", "verify_directions: 100")
scenarios = os.path.join(os.path.dirname(os.path.abspath(config)), "scenarios/")  # the envelope's, from the copy
text = re.sub(r"(?<=[\[\s,])scenarios/", lambda _: scenarios, text)
quick = os.path.join(work, "quick.yaml")
open(quick, "w").write(text)
ctrl = os.path.join(work, "c.tmpc")
subprocess.run([tmpc, "design", "--config", quick, "--out", ctrl], check=True, capture_output=True)
# The tightened state half-widths, for x0 inside the tightened set.
inspect = subprocess.run([tmpc, "inspect", ctrl], check=True, capture_output=True, text=True).stdout

solvers.options["show_progress"] = False
solvers.options["abstol"] = 1e-10
solvers.options["reltol"] = 1e-10
solvers.options["feastol"] = 1e-10
rng = random.Random(5)
worst_gap, worst_du, cases = {"reference": 0.0, "admm": 0.0}, {"reference": 0.0, "admm": 0.0}, 0
for case in range(20):
    x0 = [0.03 * rng.uniform(-0.95, 0.95) for _ in range(24)]
    arg = ",".join(f"{v:.17g}" for v in x0)
    path = os.path.join(work, f"qp{case}.json")
    subprocess.run([tmpc, "export-qp", "--controller", ctrl, "--x0", arg, "--out", path], check=True, capture_output=True)
    qp = json.load(open(path))
    H, f, A = np.array(qp["H"]), np.array(qp["f"]), np.array(qp["A"])
    lo, hi = np.array(qp["lo"]), np.array(qp["hi"])
    # lo <= A z <= hi  as  G z <= h
    G = np.vstack([A, -A])
    h = np.concatenate([hi, -lo])
    sol = solvers.qp(matrix(H), matrix(f), matrix(G), matrix(h))
    if sol["status"] != "optimal":
        print(f"case {case}: cvxopt status {sol['status']}")
        sys.exit(1)
    z = np.array(sol["x"]).ravel()
    obj_cvx = 0.5 * z @ H @ z + f @ z
    full = abs(obj_cvx + qp["constant"])  # the full cost V >= 0 sets the scale
    for name in ("reference", "admm"):
        got = json.loads(subprocess.run([tmpc, "solve", "--controller", ctrl, "--solver", name, "--x0", arg, "--json"],
                                        check=True, capture_output=True, text=True).stdout)
        if got["status"] != "converged":
            print(f"case {case}: {name} status {got['status']}")
            sys.exit(1)
        gap = abs(got["objective"] - obj_cvx) / max(full, 1e-12)
        du = float(np.max(np.abs(np.array(got["u_bar0"]) - z[:4])))
        worst_gap[name], worst_du[name] = max(worst_gap[name], gap), max(worst_du[name], du)
    cases += 1
bounds = {"reference": (1e-10, 1e-9), "admm": (1e-9, 1e-7)}
failed = False
for name, (gap_max, du_max) in bounds.items():
    print(f"{cases} exported QPs: cvxopt vs tmpc {name}, worst relative objective gap {worst_gap[name]:.3e} "
          f"(bound {gap_max:g}), worst |u_bar(0) difference| {worst_du[name]:.3e} (bound {du_max:g})")
    failed = failed or worst_gap[name] > gap_max or worst_du[name] > du_max
if failed:
    sys.exit(1)
