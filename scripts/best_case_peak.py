#!/usr/bin/python3
"""The smallest peak of the state errors (as a fraction of their bounds) that ANY
controller could reach under a force on the load, on the linear error model: a lower
bound to compare a flight's violations against.

    tmpc model --config C [--scenario S --run K] --json --matrices > model.json
    scripts/best_case_peak.py model.json --force 1 0 0 [--horizon 2.0]
    tmpc check --controller A --scenario S --forces forces.csv
    scripts/best_case_peak.py model.json --forces forces.csv --window 62 80 [--yaw-free | --yaw-coupled]
                              [--static-tilt] [--at-rest] [--bound STATE VALUE ...]

A step (--force): from zero error, the force F (N, on the load) acts from period 0 on;
the inputs over the horizon are free within the actuator limits (u_eq + u in
[u_min, u_max]) and know the force exactly from the step on (a clairvoyant controller:
no estimation delay). The linear program

    min t  s.t.  x(k+1) = A x(k) + B u(k) + D F(k),  x(0) = 0,
                 |x_i(k)| <= t * b_i  (the measured states, k = 1..H),  u in U

(GLPK's simplex through cvxopt, independent of tmpc's solvers) gives t*: when t* > 1 no
controller keeps the linearized plant inside the box after this step; below 1, t* is
how far inside the best one stays. Prints t* and the bound that forces it (the box row
of the largest multiplier: its state and time), JSON with --json.

A force series (--forces, written by `tmpc check --forces`: the scenario's force on the
load every period, world frame, and the reference's yaw) over a window [T0, T1]: the
same program with F(k) the series seen in the reference's heading frame, known over the
whole window in advance (perfect preview), and x(0) free inside the scaled box (the
best state any controller could have reached by T0), so t* bounds the peak over the
window from below for every controller whose errors stay inside the box before it.
  --yaw-free   the vehicle may turn by up to psi's bound from the reference's yaw: each
               period's horizontal force may point anywhere on its arc of directions
               (its convex hull, by tangents: a relaxation, still a lower bound), the
               horizontal position and speed bounds taken in the turned frame at their
               largest over the arc (also a relaxation). The yaw's own dynamics and the
               second-order terms of turning are not modelled.
  --yaw-coupled  as --yaw-free, but the force's direction is tied to the model's own yaw
               error psi(k) (its dynamics, driven by the inputs, bound how fast the
               vehicle turns): the vehicle turned by psi sees the force f at -psi from
               where it lies, (along, across) = |f| (cos psi, -sin psi), and each period's
               (psi, along, across) is held inside that helix's convex hull: the slab
               |across + |f| psi| <= |f| (psi_max - sin psi_max), the tangents of the
               concave along = |f| cos psi (9 points; other counts where GLPK's simplex
               ends "unknown") and its chord. Still a relaxation
               (a lower bound), tighter than --yaw-free: at psi = 0 the force may shrink
               by the chord's 1 - cos psi_max (12 % at 0.5 rad) but not turn.
  --bound STATE VALUE  (repeatable) that state's half-width in the program instead of the
               box's: what the best controller reaches when it must also keep STATE
               within VALUE (e.g. the load within 0.3 m of its reference: --bound x 0.3
               --bound y 0.3); t* is then relative to VALUE for that state.
  --static-tilt  the linear model tilts the rod by F_h / (m_L g) statically, the load
               by atan(F_h / (m_L g - F_z)); with this flag the horizontal force is
               scaled so that the linear static tilt is the rod's true one (an upward
               force then tilts more: the linear model misses it). Near the box's edge
               the uncalibrated model is optimistic by about 10 %, the calibrated one is
               an estimate, not a bound: it is exact only statically.
  --at-rest    x(0) at rest under the force of the period before the window (its first
               period's when the window starts the series), the best such equilibrium
               (its positions and, with --yaw-free, its yaw free): a controller that
               had settled and learns the force only from T0 on. For a window that
               starts at an event (a step, a gust's redraw: from then on the gust follows
               its first-order lag to the new command, which a controller that knows the
               gust's model reads within a period or two), t* is the best case without
               preview of the event.
"""
import argparse
import json
import sys

import numpy as np
from cvxopt import matrix, solvers, spmatrix


def _lqr_gain(A, B, iterations=20000, tol=1e-10):
    """u = K x of the discrete LQR with Q = I, R = I (the Riccati recursion to its fixed point)."""
    P = np.eye(A.shape[0])
    R = np.eye(B.shape[1])
    for _ in range(iterations):
        K = -np.linalg.solve(R + B.T @ P @ B, B.T @ P @ A)
        P_next = np.eye(A.shape[0]) + A.T @ P @ (A + B @ K)
        P_next = 0.5 * (P_next + P_next.T)
        if np.max(np.abs(P_next - P)) <= tol * np.max(np.abs(P_next)):
            P = P_next
            break
        P = P_next
    K = -np.linalg.solve(R + B.T @ P @ B, B.T @ P @ A)
    if np.max(np.abs(np.linalg.eigvals(A + B @ K))) >= 1.0:
        raise RuntimeError("the scaled model's LQR gain does not stabilize it")
    return K


def _solve(cost, G, h, A, b):
    """min cost'z s.t. G z <= h, A z = b (G, A as (values, rows, cols, shape)) by GLPK's
    simplex: z and the multipliers of G's rows (>= 0); None where the simplex ends
    "unknown" (a basis it cannot factor well: the caller retries with other tangents)."""
    sp = lambda m: spmatrix([float(x) for x in m[0]], [int(x) for x in m[1]], [int(x) for x in m[2]], m[3])
    col = lambda v: matrix([float(x) for x in v])
    solvers.options["glpk"] = {"msg_lev": "GLP_MSG_OFF"}
    sol = solvers.lp(col(cost), sp(G), col(h), sp(A), col(b), solver="glpk")
    if sol["status"] == "unknown":
        return None
    if sol["status"] != "optimal":
        raise RuntimeError(f"LP: {sol['status']} (GLPK's simplex)")
    return np.array(sol["x"]).ravel(), np.array(sol["z"]).ravel()


# The arc's and the helix's tangents: 9 points, and where GLPK's simplex ends "unknown" on
# that program (it does on some long windows) the same relaxation with the tangents at
# other points (each an outer hull of the same curve, all within 1e-6 of each other
# where more than one solves; measured once).
TANGENTS = (9, 5, 17, 10)


def _lp(model, force_z, horizontal, free_start, yaw_arc, static_tilt, rest=None, yaw_coupled=False, bounds=None):
    last = None
    for tangents in TANGENTS if yaw_arc is not None else TANGENTS[:1]:
        last = _lp_once(model, force_z, horizontal, free_start, yaw_arc, static_tilt, rest, yaw_coupled, bounds,
                        tangents)
        if last is not None:
            return last
    raise RuntimeError(f"LP: unknown (GLPK's simplex, with the tangents at {', '.join(map(str, TANGENTS))} points)")


def _lp_once(model, force_z, horizontal, free_start, yaw_arc, static_tilt, rest, yaw_coupled, bounds, tangents):
    """min t over the window; horizontal: per period the (2,) force in the reference's
    heading frame; yaw_arc None or psi_max (the force's direction free on its arc);
    rest None or (horizontal (2,), force_z): x(0) at rest under that force (free start);
    yaw_coupled (with yaw_arc): the direction tied to the state psi(k) (the helix's hull);
    bounds: {state name: half-width} in place of the box's."""
    m = model["matrices"]
    A, B, D = (np.array(m[k]) for k in ("A", "B", "D"))
    T = model["discrete"]["sample_time"]
    names = m["state_names"]
    p = int(m["measured"])
    # The states past the measured ones (the integrals of the position errors) are the
    # controller's: they never act on the plant's, and the box does not bound them.
    A, B, D = A[:p, :p], B[:p], D[:p]
    n, nu = B.shape
    H = len(force_z)
    assert rest is None or free_start, "a start at rest is a free start's special case"
    assert not yaw_coupled or (yaw_arc is not None and free_start), "the coupling turns a free start's force"
    r0 = 0 if rest is None else 1  # the rest force is the force row before the window's first
    if rest is not None:
        horizontal = np.vstack([np.reshape(rest[0], (1, 2)), np.reshape(horizontal, (H, 2))])
        force_z = np.concatenate([[rest[1]], force_z])
    bound = np.array(m["state_error_max"], dtype=float)[:p]
    i_psi = names.index("psi")
    for name, value in (bounds or {}).items():
        if name not in names[:p]:
            raise ValueError(f"--bound {name}: no such state of the box (the states: {', '.join(names[:p])})")
        if not value > 0.0:
            raise ValueError(f"--bound {name} {value}: a half-width must be positive")
        bound[names.index(name)] = float(value)
    if yaw_arc is not None:  # the reference-frame box seen from a frame turned by up to psi_max:
        # |v_x'| <= max over |psi| <= psi_max of b_x cos psi + b_y |sin psi| (and v_y' alike)
        def widest(b_along, b_across):
            if np.arctan2(b_across, b_along) <= yaw_arc:
                return float(np.hypot(b_along, b_across))
            return float(b_along * np.cos(yaw_arc) + b_across * np.sin(yaw_arc))
        for a_, b_ in (("x", "y"), ("d_x", "d_y")):
            i, j = names.index(a_), names.index(b_)
            bound[i], bound[j] = widest(bound[i], bound[j]), widest(bound[j], bound[i])
    u_lo = np.array(m["input_min"]) - np.array(m["u_eq"])
    u_hi = np.array(m["input_max"]) - np.array(m["u_eq"])
    fh = np.array(horizontal, dtype=float).reshape(H + r0, 2)
    fz = np.asarray(force_z, dtype=float)
    if static_tilt:
        mg = model["vehicle"]["load_mass"] * model["vehicle"]["gravity"]
        mag = np.linalg.norm(fh, axis=1)
        if np.any(fz >= mg):
            raise ValueError("--static-tilt: the vertical force lifts the load (F_z >= m_L g)")
        scale = np.where(mag > 1e-12, mg * np.arctan(mag / (mg - fz)) / np.maximum(mag, 1e-12), 1.0)
        fh = fh * scale[:, None]
    # Variables: x(k0..H) (n each; k0 = 0 with a free start, else x(0) = 0 is no variable),
    # u(0..H-1), w(0..H-1) (the horizontal force, 2 each; w(-1) the rest force's, then
    # the rest input ve), t; the dynamics as sparse
    # equalities (the open-loop model has unstable modes: powers of A condition badly).
    k0 = 0 if free_start else 1
    nx = n * (H + 1 - k0)
    xi = lambda k: n * (k - k0)
    ui = lambda k: nx + nu * k
    wi = lambda k: nx + nu * H + 2 * (k + r0)
    nz = nx + nu * H + 2 * (H + r0) + r0 * nu + 1
    ei = nz - 1 - nu  # rest: the equilibrium's input ve (us = K xs(0) + ve)
    Ai, Aj, Av, b = [], [], [], []
    # Scaled: the states in units of their bounds (x = S_x xs), the inputs of their
    # largest excursion (u = S_u us), each dynamics row divided by its state's bound:
    # the simplex stalls on the raw model, whose entries span eight decades.
    u_scale = np.maximum(np.abs(u_lo), np.abs(u_hi))
    As = A * bound[None, :] / bound[:, None]
    Bs = B * u_scale[None, :] / bound[:, None]
    Ds = D / bound[:, None]
    # Pre-stabilized: us = K xs + v with K the LQR gain of the scaled model, the
    # variables v (a change of variables, the same feasible set): the chain of
    # equalities then follows a stable A + B K, and the simplex's bases stay well
    # conditioned over long windows (with the open-loop A they turn singular).
    K = _lqr_gain(As, Bs)
    Acl = As + Bs @ K
    for k in range(H):  # xs(k+1) - (As + Bs K) xs(k) - Bs v(k) - Ds_h w(k) = Ds_z F_z(k)
        for r in range(n):
            row = k * n + r
            Ai.append(row); Aj.append(xi(k + 1) + r); Av.append(1.0)
            if k >= k0:
                for q in np.nonzero(Acl[r])[0]:
                    Ai.append(row); Aj.append(xi(k) + q); Av.append(-Acl[r, q])
            for q in np.nonzero(Bs[r])[0]:
                Ai.append(row); Aj.append(ui(k) + q); Av.append(-Bs[r, q])
            for q in (0, 1):
                if Ds[r, q] != 0.0:
                    Ai.append(row); Aj.append(wi(k) + q); Av.append(-Ds[r, q])
            b.append(Ds[r, 2] * fz[k + r0])
    n_eq = n * H
    if rest is not None:  # xs(0) = Acl xs(0) + Bs ve + Ds w(-1): at rest under the force before
        for r in range(n):
            for q in range(n):
                v = (1.0 if q == r else 0.0) - Acl[r, q]
                if v != 0.0:
                    Ai.append(n_eq + r); Aj.append(xi(0) + q); Av.append(v)
            for q in np.nonzero(Bs[r])[0]:
                Ai.append(n_eq + r); Aj.append(ei + q); Av.append(-Bs[r, q])
            for q in (0, 1):
                if Ds[r, q] != 0.0:
                    Ai.append(n_eq + r); Aj.append(wi(-1) + q); Av.append(-Ds[r, q])
            b.append(Ds[r, 2] * fz[0])
        n_eq += n
    Gi, Gj, Gv, h = [], [], [], []
    row = 0
    for k in range(k0, H + 1):  # +-xs_i(k) - t <= 0
        for i in range(p):
            for sign in (1.0, -1.0):
                Gi += [row, row]; Gj += [xi(k) + i, nz - 1]; Gv += [sign, -1.0]; h.append(0.0)
                row += 1
    n_box = row
    for k in range(H):  # u_lo <= S_u (K xs(k) + v(k)) <= u_hi
        for q in range(nu):
            for sign, lim in ((1.0, u_hi[q]), (-1.0, -u_lo[q])):
                Gi.append(row); Gj.append(ui(k) + q); Gv.append(sign)
                if k >= k0:
                    for c in np.nonzero(K[q])[0]:
                        Gi.append(row); Gj.append(xi(k) + c); Gv.append(sign * K[q, c])
                h.append(lim / u_scale[q]); row += 1
    if rest is not None:  # the equilibrium's input S_u (K xs(0) + ve) within the actuator limits
        for q in range(nu):
            for sign, lim in ((1.0, u_hi[q]), (-1.0, -u_lo[q])):
                Gi.append(row); Gj.append(ei + q); Gv.append(sign)
                for c in np.nonzero(K[q])[0]:
                    Gi.append(row); Gj.append(xi(0) + c); Gv.append(sign * K[q, c])
                h.append(lim / u_scale[q]); row += 1
    for k in range(-r0, H):
        r_k = float(np.hypot(*fh[k + r0]))
        if yaw_arc is None or r_k < 1e-12:  # w(k) = the force (as two inequalities)
            for q in (0, 1):
                Gi.append(row); Gj.append(wi(k) + q); Gv.append(1.0); h.append(fh[k + r0, q]); row += 1
                Gi.append(row); Gj.append(wi(k) + q); Gv.append(-1.0); h.append(-fh[k + r0, q]); row += 1
            continue
        a = float(np.arctan2(fh[k + r0, 1], fh[k + r0, 0]))
        if yaw_coupled:  # (psi, along, across) in the hull of r (., cos psi, -sin psi), psi = b_psi xs_psi
            j_psi, b_psi = xi(max(k, 0)) + i_psi, bound[i_psi]  # w(-1), the rest force, with psi(0)
            along, across = (np.cos(a), np.sin(a)), (-np.sin(a), np.cos(a))
            slab = r_k * (yaw_arc - np.sin(yaw_arc))
            for sign in (1.0, -1.0):  # +-(across + r psi) <= slab
                Gi += [row] * 3; Gj += [wi(k), wi(k) + 1, j_psi]
                Gv += [sign * across[0], sign * across[1], sign * r_k * b_psi]; h.append(slab); row += 1
            for th in np.linspace(-yaw_arc, yaw_arc, tangents):  # along <= r cos th - r sin th (psi - th)
                Gi += [row] * 3; Gj += [wi(k), wi(k) + 1, j_psi]
                Gv += [along[0], along[1], r_k * np.sin(th) * b_psi]
                h.append(r_k * (np.cos(th) + th * np.sin(th))); row += 1
            Gi += [row, row]; Gj += [wi(k), wi(k) + 1]; Gv += [-along[0], -along[1]]
            h.append(-r_k * np.cos(yaw_arc)); row += 1
            continue
        # The arc {r (cos th, sin th): |th - a| <= psi_max} (the vehicle turned by -+psi:
        # the force turns the other way in its frame, the same arc): inside the tangents
        # at `tangents` points of it (TANGENTS) and beyond its chord.
        for th in np.linspace(a - yaw_arc, a + yaw_arc, tangents):
            Gi += [row, row]; Gj += [wi(k), wi(k) + 1]; Gv += [np.cos(th), np.sin(th)]; h.append(r_k); row += 1
        Gi += [row, row]; Gj += [wi(k), wi(k) + 1]; Gv += [-np.cos(a), -np.sin(a)]
        h.append(-r_k * np.cos(yaw_arc)); row += 1
    cost = np.zeros(nz)
    cost[-1] = 1.0
    solved = _solve(cost, (Gv, Gi, Gj, (row, nz)), h, (Av, Ai, Aj, (n_eq, nz)), b)
    if solved is None:
        return None
    z, duals = solved
    # The binding bound: the box row of the largest multiplier (the optimum reaches t*
    # in many places, most of them free; the multipliers say which ones force it).
    j = int(np.argmax(duals[:n_box]))
    k, i = j // (2 * p) + k0, (j % (2 * p)) // 2
    return float(z[-1]), names[i], k * T


def best_case_peak(model, force, horizon_s, bounds=None):
    """After a step F from zero error over horizon_s (the period after the step first)."""
    T = model["discrete"]["sample_time"]
    H = int(round(horizon_s / T))
    f = np.asarray(force, dtype=float)
    t, state, when = _lp(model, np.full(H, f[2]), np.tile(f[:2], (H, 1)), False, None, False, bounds=bounds)
    return {"peak": t, "binding_state": state, "binding_time": when, "horizon_s": H * T,
            "force": list(map(float, force)), "vehicle": model.get("vehicle", {})}


def read_forces(path):
    """`tmpc check --forces` CSV: t, f_x, f_y, f_z, psi_ref per row."""
    with open(path) as fh:
        header = fh.readline().strip().split(",")
    if header != ["t", "f_x", "f_y", "f_z", "psi_ref"]:
        raise ValueError(f"{path}: header {header}, expected t,f_x,f_y,f_z,psi_ref (tmpc check --forces)")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    if data.shape[0] < 2 or data.shape[1] != 5:
        raise ValueError(f"{path}: {data.shape[0]} rows of {data.shape[1]} columns, expected at least 2 of 5")
    return data


def best_case_window(model, forces, window, yaw_free=False, static_tilt=False, at_rest=False, yaw_coupled=False,
                     bounds=None):
    """Over [T0, T1) of a force series, x(T0) free in the scaled box (at_rest: at rest under
    the force of the period before T0): the peak's lower bound."""
    T = model["discrete"]["sample_time"]
    step = forces[1, 0] - forces[0, 0]
    if abs(step - T) > 1e-9 * T:
        raise ValueError(f"forces: rows {step} s apart, the model's sample time is {T} s")
    k0, k1 = (int(round((w - forces[0, 0]) / T)) for w in window)
    if not (0 <= k0 < k1 <= forces.shape[0]):
        raise ValueError(f"--window {window[0]} {window[1]}: outside the series' "
                         f"{forces[0, 0]} to {forces[-1, 0] + T} s, or empty")
    before = max(k0 - 1, 0)  # at rest: under the force of the period before the window
    seg = forces[before:k1]
    c, s = np.cos(seg[:, 4]), np.sin(seg[:, 4])  # world -> the reference's heading frame
    horizontal = np.column_stack([c * seg[:, 1] + s * seg[:, 2], -s * seg[:, 1] + c * seg[:, 2]])
    rest = (horizontal[0], seg[0, 3]) if at_rest else None
    horizontal, seg = horizontal[k0 - before:], seg[k0 - before:]
    psi_max = None
    if yaw_free or yaw_coupled:
        psi_max = float(model["matrices"]["state_error_max"][model["matrices"]["state_names"].index("psi")])
    t, state, when = _lp(model, seg[:, 3], horizontal, True, psi_max, static_tilt, rest, yaw_coupled, bounds)
    return {"peak": t, "binding_state": state, "binding_time": forces[k0, 0] + when, "window": list(window),
            "yaw_free": yaw_free, "yaw_coupled": yaw_coupled, "static_tilt": static_tilt, "at_rest": at_rest,
            "vehicle": model.get("vehicle", {})}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", help="tmpc model --json --matrices output")
    ap.add_argument("--force", nargs=3, type=float, default=[1.0, 0.0, 0.0], help="N on the load (default 1 0 0)")
    ap.add_argument("--horizon", type=float, default=2.0, help="s (default 2)")
    ap.add_argument("--forces", help="a force series (tmpc check --forces) instead of the step")
    ap.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"), help="s of the series (with --forces)")
    ap.add_argument("--yaw-free", action="store_true", help="with --forces: the vehicle may turn within psi's bound")
    ap.add_argument("--yaw-coupled", action="store_true",
                    help="with --forces: as --yaw-free, the force's direction tied to the model's yaw error")
    ap.add_argument("--static-tilt", action="store_true", help="with --forces: the force scaled to the true static tilt")
    ap.add_argument("--at-rest", action="store_true",
                    help="with --forces: the window starts at rest under the force before it")
    ap.add_argument("--bound", nargs=2, action="append", metavar=("STATE", "VALUE"), default=[],
                    help="that state's half-width instead of the box's (repeatable)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if (a.forces is None) != (a.window is None):
        sys.exit("--forces and --window go together")
    if a.forces is None and (a.yaw_free or a.yaw_coupled or a.static_tilt or a.at_rest):
        sys.exit("--yaw-free, --yaw-coupled, --static-tilt and --at-rest need --forces")
    if a.yaw_free and a.yaw_coupled:
        sys.exit("--yaw-free and --yaw-coupled exclude each other (the coupling is the tighter form)")
    with open(a.model) as fh:
        model = json.load(fh)
    if "matrices" not in model:
        sys.exit(f"{a.model}: no matrices (run tmpc model with --json --matrices)")
    bounds = {}
    for name, value in a.bound:
        try:
            bounds[name] = float(value)
        except ValueError:
            sys.exit(f"--bound {name} {value}: not a number")
    try:
        if a.forces is None:
            r = best_case_peak(model, a.force, a.horizon, bounds)
        else:
            r = best_case_window(model, read_forces(a.forces), a.window, a.yaw_free, a.static_tilt, a.at_rest,
                                 a.yaw_coupled, bounds)
        r["bounds"] = bounds
    except (ValueError, RuntimeError) as e:
        sys.exit(str(e))
    if a.json:
        print(json.dumps(r))
    elif a.forces is None:
        print(f"best case after a {r['force']} N step over {r['horizon_s']:.2f} s"
              f"{''.join(f', {k} within {v:g}' for k, v in bounds.items())}: peak {r['peak']:.4f} of the "
              f"bounds (binding: {r['binding_state']} at {r['binding_time']:.3f} s)")
    else:
        how = ("yaw free" if a.yaw_free else "yaw coupled" if a.yaw_coupled else "yaw held") + \
            (", static tilt calibrated" if a.static_tilt else "") + (", from rest" if a.at_rest else "") + \
            "".join(f", {k} within {v:g}" for k, v in bounds.items())
        print(f"best case over {a.window[0]} to {a.window[1]} s ({how}): peak {r['peak']:.4f} of the bounds "
              f"(binding: {r['binding_state']} at {r['binding_time']:.3f} s)")


if __name__ == "__main__":
    main()
