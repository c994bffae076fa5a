#!/usr/bin/env python3
"""Independent oracle: the QPs exported by `tmpc export-qp` solved by cvxopt
(Debian python3-cvxopt), compared with tmpc's reference solver (`tmpc solve
--solver reference --json`): relative objective gap below 1e-6 and the same u_bar(0).

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
worst_gap, worst_du, cases = 0.0, 0.0, 0
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
    ref = json.loads(subprocess.run([tmpc, "solve", "--controller", ctrl, "--solver", "reference", "--x0", arg, "--json"],
                                    check=True, capture_output=True, text=True).stdout)
    full = abs(obj_cvx + qp["constant"])  # the full cost V >= 0 sets the scale
    gap = abs(ref["objective"] - obj_cvx) / max(full, 1e-12)
    du = float(np.max(np.abs(np.array(ref["u_bar0"]) - z[:4])))
    worst_gap, worst_du = max(worst_gap, gap), max(worst_du, du)
    cases += 1
print(f"{cases} exported QPs: cvxopt vs tmpc reference, worst relative objective gap {worst_gap:.3e}, "
      f"worst |u_bar(0) difference| {worst_du:.3e}")
if worst_gap > 1e-6 or worst_du > 1e-5:
    sys.exit(1)
