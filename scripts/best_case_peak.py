#!/usr/bin/python3
"""The smallest peak of the state errors (as a fraction of their bounds) that ANY
controller could reach after a force step, on the linear error model: a lower bound
to compare a flight's violations against.

    tmpc model --config C [--scenario S --run K] --json --matrices > model.json
    scripts/best_case_peak.py model.json --force 1 0 0 [--horizon 2.0]

From zero error, the force F (N, on the load) acts from period 0 on; the inputs over
the horizon are free within the actuator limits (u_eq + u in [u_min, u_max]) and known
the force exactly from the step on (a clairvoyant controller: no estimation delay).
The linear program

    min t  s.t.  x(k+1) = A x(k) + B u(k) + D F,  x(0) = 0,
                 |x_i(k)| <= t * b_i  (the measured states, k = 1..H),  u in U

(GLPK's simplex through cvxopt, independent of tmpc's solvers) gives t*: when t* > 1 no controller keeps the
linearized plant inside the box after this step; below 1, t* is how far inside the
best one stays. Prints t* and the bound that forces it (the box row of the largest
multiplier: its state and time), JSON with --json.
"""
import argparse
import json
import sys

import numpy as np
from cvxopt import matrix, solvers, spmatrix


def best_case_peak(model, force, horizon_s):
    m = model["matrices"]
    A, B, D = (np.array(m[k]) for k in ("A", "B", "D"))
    T = model["discrete"]["sample_time"]
    H = int(round(horizon_s / T))
    n, nu = B.shape
    p = int(m["measured"])
    bound = np.array(m["state_error_max"])[:p]
    u_lo = np.array(m["input_min"]) - np.array(m["u_eq"])
    u_hi = np.array(m["input_max"]) - np.array(m["u_eq"])
    f = D @ np.asarray(force, dtype=float)
    # Variables: x(1..H) (n each), u(0..H-1) (nu each), t; sparse, the dynamics as
    # equalities (the open-loop model has unstable modes: powers of A condition badly).
    nx, nuH = n * H, nu * H
    nz = nx + nuH + 1
    xi = lambda k: nx * 0 + n * (k - 1)  # column of x(k), k = 1..H
    ui = lambda k: nx + nu * k           # column of u(k), k = 0..H-1
    Ai, Aj, Av, b = [], [], [], []
    for k in range(H):  # x(k+1) - A x(k) - B u(k) = D F
        for r in range(n):
            Ai.append(k * n + r); Aj.append(xi(k + 1) + r); Av.append(1.0)
            if k > 0:
                for q in np.nonzero(A[r])[0]:
                    Ai.append(k * n + r); Aj.append(xi(k) + q); Av.append(-A[r, q])
            for q in np.nonzero(B[r])[0]:
                Ai.append(k * n + r); Aj.append(ui(k) + q); Av.append(-B[r, q])
        b.extend(f)
    Gi, Gj, Gv, h = [], [], [], []
    row = 0
    for k in range(1, H + 1):  # +-x_i(k) / b_i - t <= 0
        for i in range(p):
            for sign in (1.0, -1.0):
                Gi += [row, row]; Gj += [xi(k) + i, nz - 1]; Gv += [sign / bound[i], -1.0]; h.append(0.0)
                row += 1
    for k in range(H):  # u_lo <= u(k) <= u_hi
        for q in range(nu):
            Gi.append(row); Gj.append(ui(k) + q); Gv.append(1.0); h.append(u_hi[q]); row += 1
            Gi.append(row); Gj.append(ui(k) + q); Gv.append(-1.0); h.append(-u_lo[q]); row += 1
    cost = np.zeros(nz)
    cost[-1] = 1.0
    solvers.options["glpk"] = {"msg_lev": "GLP_MSG_OFF"}
    sp = lambda v, i, j, shape: spmatrix([float(x) for x in v], [int(x) for x in i], [int(x) for x in j], shape)
    col = lambda v: matrix([float(x) for x in v])
    sol = solvers.lp(col(cost), sp(Gv, Gi, Gj, (row, nz)), col(h), sp(Av, Ai, Aj, (n * H, nz)), col(b), solver="glpk")
    if sol["status"] != "optimal":
        raise RuntimeError(f"LP: {sol['status']}")
    z = np.array(sol["x"]).ravel()
    # The binding bound: the box row of the largest multiplier (the optimum reaches t*
    # in many places, most of them free; the multipliers say which ones force it).
    t_star = float(z[-1])
    duals = np.array(sol["z"]).ravel()[:2 * p * H]
    j = int(np.argmax(duals))
    k, i = j // (2 * p) + 1, (j % (2 * p)) // 2
    worst = (m["state_names"][i], k * T)
    return {"peak": t_star, "binding_state": worst[0], "binding_time": worst[1], "horizon_s": H * T,
            "force": list(map(float, force)), "vehicle": model.get("vehicle", {})}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", help="tmpc model --json --matrices output")
    ap.add_argument("--force", nargs=3, type=float, default=[1.0, 0.0, 0.0], help="N on the load (default 1 0 0)")
    ap.add_argument("--horizon", type=float, default=2.0, help="s (default 2)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    with open(a.model) as fh:
        model = json.load(fh)
    if "matrices" not in model:
        sys.exit(f"{a.model}: no matrices (run tmpc model with --json --matrices)")
    r = best_case_peak(model, a.force, a.horizon)
    if a.json:
        print(json.dumps(r))
    else:
        print(f"best case after a {r['force']} N step over {r['horizon_s']:.2f} s: peak {r['peak']:.4f} of the "
              f"bounds (binding: {r['binding_state']} at {r['binding_time']:.3f} s)")


if __name__ == "__main__":
    main()
