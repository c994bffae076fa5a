#!/usr/bin/env python3
"""Oracle for `tmpc model --json`: stable keys present, the thesis equilibrium
reproduced to 3 significant digits (thesis 6.2), and physically sane summaries."""
import json
import math
import subprocess
import sys

tmpc, config = sys.argv[1], sys.argv[2]
out = subprocess.run([tmpc, "model", "--config", config, "--json"], check=True, capture_output=True, text=True)
j = json.loads(out.stdout)


def key(path):
    node = j
    for part in path.split("."):
        node = node[part]
    return node


def sig3(x):
    return float(f"{x:.3g}")


failures = []
thesis = {"equilibrium.gamma_1": 1.3170e-4, "equilibrium.gamma_2": 0.01396,
          "equilibrium.alpha_r": 0.0140, "equilibrium.alpha_l": 0.0138,
          "equilibrium.f_r": 11.732257, "equilibrium.f_l": 11.767602}
for k, v in thesis.items():
    got = key(k)
    if sig3(got) != sig3(v):
        failures.append(f"{k}: {got} does not round to {sig3(v)}")
if key("lpv.vertices") != 8:
    failures.append(f"lpv.vertices = {key('lpv.vertices')}, expected 8")
rho = key("discrete.spectral_radius")
# Integrators and the x-theta / y-phi chains give eigenvalues at 1; eigenvalues of such
# Jordan chains are computed to about sqrt(eps) ~ 1e-5 only.
if not (0.999 <= rho <= 1.0 + 1e-4):
    failures.append(f"discrete.spectral_radius = {rho}: expected 1 (integrators) to within 1e-4")
evs = key("continuous.eigenvalues")
if len(evs) != 24:
    failures.append(f"{len(evs)} continuous eigenvalues, expected 24")
if not math.isfinite(key("lpv.affinity_residual")):
    failures.append("lpv.affinity_residual not finite")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print("tmpc model --json: equilibrium", {k: key(k) for k in thesis}, "spectral radius", rho)
