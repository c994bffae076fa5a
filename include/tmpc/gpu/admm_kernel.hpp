// The ADMM iterations of both variants written once for a "team" of cooperating
// threads: a CUDA thread block on the device (one solve per block, the whole loop in
// one kernel launch), or host threads in the tests that check this code without a
// GPU. C++14, no library headers, so nvcc of every JetPack compiles it.
//
// A Team provides: int rank, size; void sync() (barrier, memory visible after it);
// R sum(R), R max(R) (all-reduce, every member gets the result);
// long long now_ns() (the same clock for every member).
//
// exact (E3, the CPU "admm" with fixed rho and no polish; dense_admm.hpp):
//   x~ = Kinv (sigma x - f + A'(R z^ - y^))
//   y_1/2 = y^ + r R (A x~ - z^)                                  (4.21)
//   z = clip(A x~ + R^-1 y_1/2, lo, hi),  y = y_1/2 + s R (A x~ - z)   (4.23)
//   Nesterov (4.29)-(4.31) on (z, y) with the restart of Algorithm 4.2 (optional)
//   stop: ||Ax - z|| <= eps_abs + eps_rel max(||Ax||, ||z||) and
//         ||Hx + f + A'y|| <= eps_abs + eps_rel max(||Hx||, ||A'y||, ||f||)
// thesis (Algorithm 4.3 with E2 fixed; the CPU "admm-thesis"): see admm_problem.hpp.
#pragma once

#include "tmpc/gpu/admm_problem.hpp"
#include "tmpc/gpu/nesterov_restart.hpp"  // also defines TMPC_TEAM_FN

namespace tmpc {
namespace gpu {

/// A row-major matrix view (leading dimension ld >= cols; padded in shared memory).
/// The condensed constraint matrix A = [I; P] and the prediction matrix P may instead
/// be given by their repeating blocks (G != nullptr, p unused): with move blocking,
///   P(k, j) = G_(k-j) for j < M-1, j <= k;  P(k, M-1) = S_(k-M+1) for k >= M-1; else 0
/// where G_l = A^l B and S_l = G_0 + ... + G_l (n x m each, row-major), after `eye`
/// leading identity rows: 2 N n m numbers instead of (eye + N n) M m.
template <class R>
struct MatView {
  const R* p;
  int rows, cols, ld;
  const R* G = nullptr;
  const R* S = nullptr;
  int eye = 0, bn = 0, bm = 0, bN = 0, bM = 0;
};

/// Pointers to one problem's data (global or shared memory).
template <class R>
struct ProblemView {
  int nz, nc, nx, m, M, n, N;
  R rho, rho_thesis;
  MatView<R> H, F, A, E, Kinv;
  const R *f0, *lo0, *hi0, *rho_vec;
  MatView<R> P, Q, H1inv, H2last;
  const R *H2diag, *xlo, *xhi, *ulo, *uhi;
};

/// Per-slot memory kept between solves (warm start) and the per-solve result.
template <class R>
struct SlotView {
  R* state;      ///< previous solution: exact [x (nz), z (nc)], thesis [u (nz), x (Nn), lam (Nn)]
  int* have_previous;
  AdmmOutcome* outcome;
  R* z_out;      ///< nz: the solution u_hat
  R* y_out;      ///< nc multipliers (exact variant) or nullptr
};

/// The view of a problem whose arrays `where(vector)` places (host: the vectors' own
/// data; device: their device copies), every matrix with ld = cols; A and P in their
/// block form when `block_form` and the problem has it.
template <class R, class Where>
ProblemView<R> view_of(const BasicAdmmProblem<R>& p, Where where, bool block_form = false) {
  ProblemView<R> v;
  v.nz = p.nz;
  v.nc = p.nc;
  v.nx = p.nx;
  v.m = p.m;
  v.M = p.M;
  v.n = p.n;
  v.N = p.N;
  v.rho = p.rho;
  v.rho_thesis = p.rho_thesis;
  const int L = p.N * p.n;
  v.H = MatView<R>{where(p.H), p.nz, p.nz, p.nz};
  v.F = MatView<R>{where(p.F), p.nz, p.nx, p.nx};
  v.A = MatView<R>{where(p.A), p.nc, p.nz, p.nz};
  v.E = MatView<R>{where(p.E), p.nc, p.nx, p.nx};
  v.Kinv = MatView<R>{where(p.Kinv), p.nz, p.nz, p.nz};
  v.f0 = where(p.f0);
  v.lo0 = where(p.lo0);
  v.hi0 = where(p.hi0);
  v.rho_vec = where(p.rho_vec);
  v.P = MatView<R>{where(p.P), L, p.nz, p.nz};
  if (block_form && !p.Gblk.empty()) {  // the block forms of A = [I; P] and P
    v.A.G = v.P.G = where(p.Gblk);
    v.A.S = v.P.S = where(p.Sblk);
    v.A.eye = p.nz;
    v.A.bn = v.P.bn = p.n;
    v.A.bm = v.P.bm = p.m;
    v.A.bN = v.P.bN = p.N;
    v.A.bM = v.P.bM = p.M;
  }
  v.Q = MatView<R>{where(p.Q), L, p.nx, p.nx};
  v.H1inv = MatView<R>{where(p.H1inv), p.nz, p.nz, p.nz};
  v.H2last = MatView<R>{where(p.H2last), p.n, p.n, p.n};
  v.H2diag = where(p.H2diag);
  v.xlo = where(p.xlo);
  v.xhi = where(p.xhi);
  v.ulo = where(p.ulo);
  v.uhi = where(p.uhi);
  return v;
}

inline int state_floats(int nz, int nc, int N, int n) {
  const int a = nz + nc, b = nz + 2 * N * n;
  return a > b ? a : b;
}
/// Workspace Rs a solve needs for a team of `size` members (plus 0 for reductions).
inline int workspace_floats(int nz, int nc, int N, int n, int size) {
  const int L = N * n;
  const int exact = 7 * nz + 11 * nc;
  const int thesis = 2 * nz + 10 * L;
  const int scratch = (nz > size ? nz : size) + 1;
  return (exact > thesis ? exact : thesis) + scratch;
}

namespace detail {

template <class R>
TMPC_TEAM_FN R clampf(R v, R lo, R hi) { return v < lo ? lo : (v > hi ? hi : v); }
/// max that keeps a NaN (fmaxf drops it, and a NaN must end the solve).
template <class R>
TMPC_TEAM_FN R nan_max(R a, R b) { return (a != a || a > b) ? a : b; }
template <class R>
TMPC_TEAM_FN R absf(R v) { return v < 0.0f ? -v : v; }
template <class R>
TMPC_TEAM_FN bool finite(R v) { return v - v == 0.0f; }
template <class R>
TMPC_TEAM_FN R dot_row(const MatView<R>& A, int i, const R* x) {
  if (A.G != nullptr) {  // block form
    if (i < A.eye) return x[i];
    const int r = i - A.eye, k = r / A.bn, s = r % A.bn, bsz = A.bn * A.bm;
    R acc = 0.0f;
    for (int j = 0; j < A.bM; ++j) {
      const R* blk = nullptr;
      if (j < A.bM - 1) {
        if (j <= k) blk = A.G + (k - j) * bsz;
      } else if (k >= A.bM - 1) {
        blk = A.S + (k - A.bM + 1) * bsz;
      }
      if (blk == nullptr) continue;
      const R* row = blk + s * A.bm;
      const R* xj = x + j * A.bm;
      for (int c = 0; c < A.bm; ++c) acc += row[c] * xj[c];
    }
    return acc;
  }
  const R* r = A.p + static_cast<long>(i) * A.ld;
  R s = 0.0f;
  for (int j = 0; j < A.cols; ++j) s += r[j] * x[j];
  return s;
}

/// Column c of the block form times the rows [eye + k n, eye + (k+1) n) of v,
/// summed over k = first, first + step, ... (the part of (A'v)_c those rows give).
template <class R>
TMPC_TEAM_FN R block_column_dot(const MatView<R>& A, int c, const R* v, int first, int step) {
  const int j = c / A.bm, col = c % A.bm, bsz = A.bn * A.bm;
  R acc = 0.0f;
  for (int k = first; k < A.bN; k += step) {
    const R* blk = nullptr;
    if (j < A.bM - 1) {
      if (j <= k) blk = A.G + (k - j) * bsz;
    } else if (k >= A.bM - 1) {
      blk = A.S + (k - A.bM + 1) * bsz;
    }
    if (blk == nullptr) continue;
    const R* vk = v + A.eye + k * A.bn;
    for (int s = 0; s < A.bn; ++s) acc += blk[s * A.bm + col] * vk[s];
  }
  return acc;
}

/// out = A' v: members split (column, row chunk) pairs, partial sums in scratch.
template <class Team, class R>
TMPC_TEAM_FN void gemv_t(Team& t, const MatView<R>& A, const R* v, R* out, R* scratch) {
  const int cols = A.cols;
  int chunks = t.size / cols;
  if (chunks < 1) chunks = 1;
  for (int p = t.rank; p < cols * chunks; p += t.size) {
    const int j = p % cols, c = p / cols;
    R s = 0.0f;
    if (A.G != nullptr) {  // block form: chunks split the block rows; chunk 0 adds the identity rows
      s = block_column_dot(A, j, v, c, chunks);
      if (c == 0 && j < A.eye) s += v[j];
    } else {
      for (int i = c; i < A.rows; i += chunks) s += A.p[static_cast<long>(i) * A.ld + j] * v[i];
    }
    scratch[p] = s;
  }
  t.sync();
  for (int j = t.rank; j < cols; j += t.size) {
    R s = 0.0f;
    for (int c = 0; c < chunks; ++c) s += scratch[c * cols + j];
    out[j] = s;
  }
  t.sync();
}

/// y = A x, a member a row.
template <class Team, class R>
TMPC_TEAM_FN void gemv(Team& t, const MatView<R>& A, const R* x, R* y) {
  for (int i = t.rank; i < A.rows; i += t.size) y[i] = dot_row(A, i, x);
  t.sync();
}

/// The previous solution shifted one step: blocks of `block` move one block forward
/// within [offset, offset + count block); the last block keeps its value.
template <class R>
TMPC_TEAM_FN R shifted(const R* old, int i, int offset, int block, int count) {
  const int k = i - offset;
  return k < (count - 1) * block ? old[i + block] : old[i];
}

/// True on every member when rank 0's clock says the budget is spent.
template <class Team>
TMPC_TEAM_FN bool over_budget(Team& t, long long t0, const AdmmSettings& s) {
  if (s.time_budget_ns <= 0) return false;
  const float over = (t.rank == 0 && t.now_ns() - t0 > s.time_budget_ns) ? 1.0f : 0.0f;
  return t.max(over) > 0.5f;
}

/// The outcome of a solve (by rank 0) and whether the next may start warm; ends with
/// a barrier.
template <class Team, class R>
TMPC_TEAM_FN void report(Team& t, const SlotView<R>& slot, const AdmmSettings& S, int status, int k, int restarts,
                         R primal, R dual) {
  if (t.rank == 0) {
    slot.outcome->status = status;
    slot.outcome->iterations = k < S.max_iterations ? k : S.max_iterations;
    slot.outcome->restarts = restarts;
    slot.outcome->primal_residual = primal;
    slot.outcome->dual_residual = dual;
    *slot.have_previous = status != kNumericalFailure ? 1 : 0;
  }
  t.sync();
}

}  // namespace detail

/// One solve of the exact variant by a team. ws: workspace_floats() Rs.
template <class Team, class R>
TMPC_TEAM_FN void admm_exact(Team& t, const ProblemView<R>& P, const AdmmSettings& S, const R* x0, R* ws,
                             const SlotView<R>& slot) {
  using namespace detail;
  const int n = P.nz, m = P.nc, rk = t.rank, sz = t.size;
  R* x = ws;
  R* xt = x + n;
  R* rhs = xt + n;
  R* f = rhs + n;
  R* Hx = f + n;
  R* Aty = Hx + n;
  R* tn = Aty + n;
  R* z = tn + n;
  R* y = z + m;
  R* zh = y + m;
  R* yh = zh + m;
  R* zp = yh + m;
  R* yp = zp + m;
  R* zt = yp + m;
  R* lo = zt + m;
  R* hi = lo + m;
  R* tm = hi + m;
  R* ychk = tm + m;  // y at the previous check (infeasibility certificate)
  R* scratch = ychk + m;
  const long long t0 = t.now_ns();

  // Instance: f = f0 + F x0, bounds lo0 - E x0, hi0 - E x0.
  R fmax = 0.0f;
  for (int i = rk; i < n; i += sz) {
    f[i] = P.f0[i] + dot_row(P.F, i, x0);
    fmax = nan_max(fmax, absf(f[i]));
  }
  for (int i = rk; i < m; i += sz) {
    const R e = dot_row(P.E, i, x0);
    lo[i] = P.lo0[i] - e;
    hi[i] = P.hi0[i] - e;
  }
  const R f_norm = t.max(fmax);  // also the barrier after the instance
  // Start: the previous solution shifted one step (duals at zero), or cold.
  const bool warm = S.warm_start != 0 && *slot.have_previous != 0;
  const R* xs = slot.state;
  const R* zs = slot.state + n;
  for (int i = rk; i < n; i += sz) x[i] = warm ? shifted(xs, i, 0, P.m, P.M) : 0.0f;
  for (int i = rk; i < m; i += sz) {
    R v = 0.0f;
    if (warm) v = i < n ? shifted(zs, i, 0, P.m, P.M) : shifted(zs, i, n, P.n, P.N);
    v = clampf(v, lo[i], hi[i]);
    z[i] = zh[i] = zp[i] = v;
    y[i] = yh[i] = yp[i] = ychk[i] = 0.0f;
  }
  t.sync();

  NesterovRestart<R> nest;
  int status = kMaxIterations, restarts = 0, k = 1;
  R r_prim = 0.0f, r_dual = 0.0f;
  for (; k <= S.max_iterations; ++k) {
    // x~ = Kinv (A'(R z^ - y^) + sigma x - f)
    for (int i = rk; i < m; i += sz) tm[i] = P.rho_vec[i] * zh[i] - yh[i];
    t.sync();
    gemv_t(t, P.A, tm, rhs, scratch);
    for (int j = rk; j < n; j += sz) rhs[j] += S.sigma * x[j] - f[j];
    t.sync();
    gemv(t, P.Kinv, rhs, xt);
    // z~ = A x~ and the symmetric dual steps around the exact projection, row by row.
    for (int i = rk; i < m; i += sz) {
      const R a = dot_row(P.A, i, xt), rho = P.rho_vec[i];
      zt[i] = a;
      const R yhalf = yh[i] + S.r * rho * (a - zh[i]);
      const R zz = clampf(a + yhalf / rho, lo[i], hi[i]);
      z[i] = zz;
      y[i] = yhalf + S.s * rho * (a - zz);
    }
    for (int j = rk; j < n; j += sz) x[j] = xt[j];
    t.sync();
    if (S.nesterov) {
      R dy = 0.0f;
      for (int i = rk; i < m; i += sz) {
        tm[i] = P.rho_vec[i] * (z[i] - zh[i]);
        const R d = (y[i] - yh[i]) / P.rho_vec[i];
        dy += d * d;
      }
      t.sync();
      gemv_t(t, P.A, tm, tn, scratch);
      R dz = 0.0f;
      for (int j = rk; j < n; j += sz) dz += tn[j] * tn[j];
      const R c = sqrt_of(t.sum(dy)) + sqrt_of(t.sum(dz));
      R beta = 0.0f;
      const bool ok = nest.accept(c, S.eta, beta);
      if (!ok) ++restarts;
      for (int i = rk; i < m; i += sz) {
        if (ok) {
          zh[i] = z[i] + beta * (z[i] - zp[i]);
          yh[i] = y[i] + beta * (y[i] - yp[i]);
        } else {
          zh[i] = zp[i];
          yh[i] = yp[i];
        }
        zp[i] = z[i];
        yp[i] = y[i];
      }
    } else {
      for (int i = rk; i < m; i += sz) {
        zh[i] = z[i];
        yh[i] = y[i];
      }
    }
    t.sync();
    if (k % S.check_every != 0 && k < S.max_iterations) {
      if (over_budget(t, t0, S)) {
        status = kTimeBudget;
        break;
      }
      continue;
    }
    // Residuals at (x, z, y).
    gemv(t, P.H, x, Hx);
    gemv_t(t, P.A, y, Aty, scratch);
    R rp = 0.0f, azt = 0.0f, az = 0.0f, rd = 0.0f, ahx = 0.0f, aty = 0.0f;
    for (int i = rk; i < m; i += sz) {
      rp = nan_max(rp, absf(zt[i] - z[i]));
      azt = nan_max(azt, absf(zt[i]));
      az = nan_max(az, absf(z[i]));
    }
    for (int j = rk; j < n; j += sz) {
      rd = nan_max(rd, absf(Hx[j] + f[j] + Aty[j]));
      ahx = nan_max(ahx, absf(Hx[j]));
      aty = nan_max(aty, absf(Aty[j]));
    }
    r_prim = t.max(rp);
    r_dual = t.max(rd);
    const R eps_p = S.eps_abs + S.eps_rel * nan_max(t.max(azt), t.max(az));
    const R eps_d = S.eps_abs + S.eps_rel * nan_max(nan_max(t.max(ahx), t.max(aty)), f_norm);
    if (!finite(r_prim) || !finite(r_dual)) {
      status = kNumericalFailure;
      break;
    }
    if (r_prim <= eps_p && r_dual <= eps_d) {
      status = kConverged;
      break;
    }
    if (S.eps_pinf > 0.0f) {
      // OSQP's primal infeasibility certificate on dy = y - y(previous check):
      // ||A'dy|| <= eps ||dy|| and hi'max(dy, 0) + lo'min(dy, 0) <= -eps ||dy||.
      R dmax = 0.0f, support = 0.0f;
      for (int i = rk; i < m; i += sz) {
        const R d = y[i] - ychk[i];
        tm[i] = d;
        ychk[i] = y[i];
        dmax = nan_max(dmax, absf(d));
        if (d > 0.0f) support += hi[i] * d;
        if (d < 0.0f) support += lo[i] * d;
      }
      t.sync();
      gemv_t(t, P.A, tm, tn, scratch);
      R atd = 0.0f;
      for (int j = rk; j < n; j += sz) atd = nan_max(atd, absf(tn[j]));
      const R dn = t.max(dmax), an = t.max(atd), sp = t.sum(support);
      if (dn > R(1e-12) && an <= S.eps_pinf * dn && sp <= -S.eps_pinf * dn) {
        status = kInfeasible;
        break;
      }
    }
    if (over_budget(t, t0, S)) {
      status = kTimeBudget;
      break;
    }
  }
  // Result and the memory of the next warm start.
  for (int j = rk; j < n; j += sz) {
    slot.z_out[j] = x[j];
    slot.state[j] = x[j];
  }
  for (int i = rk; i < m; i += sz) {
    slot.state[n + i] = z[i];
    if (slot.y_out != nullptr) slot.y_out[i] = y[i];
  }
  report(t, slot, S, status, k, restarts, r_prim, r_dual);
}

/// One solve of the thesis variant (Algorithm 4.3) by a team.
template <class Team, class R>
TMPC_TEAM_FN void admm_thesis(Team& t, const ProblemView<R>& P, const AdmmSettings& S, const R* x0, R* ws,
                              const SlotView<R>& slot) {
  using namespace detail;
  const int nz = P.nz, L = P.N * P.n, ns = P.n, rk = t.rank, sz = t.size;
  const R rho = P.rho_thesis;
  R* u = ws;
  R* tu = u + nz;
  R* Qx0 = tu + nz;
  R* x = Qx0 + L;
  R* lam = x + L;
  R* xe = lam + L;
  R* lame = xe + L;
  R* xp = lame + L;
  R* lamp = xp + L;
  R* Pu = lamp + L;
  R* g = Pu + L;
  R* scratch = g + L;
  const long long t0 = t.now_ns();
  const bool warm = S.warm_start != 0 && *slot.have_previous != 0;
  const R* us = slot.state;
  const R* xs = slot.state + nz;
  const R* ls = xs + L;
  for (int i = rk; i < nz; i += sz) u[i] = warm ? shifted(us, i, 0, P.m, P.M) : 0.0f;
  for (int i = rk; i < L; i += sz) {
    const R q = dot_row(P.Q, i, x0);
    Qx0[i] = q;
    x[i] = warm ? shifted(xs, i, 0, ns, P.N) : q;  // Algorithm 4.3: x from the prediction
    lam[i] = warm ? shifted(ls, i, 0, ns, P.N) : 0.0f;
    xe[i] = xp[i] = x[i];
    lame[i] = lamp[i] = lam[i];
  }
  t.sync();
  NesterovRestart<R> nest;
  int status = kMaxIterations, restarts = 0, k = 1;
  R primal = 0.0f, dual = 0.0f;
  for (; k <= S.max_iterations; ++k) {
    // u-step (4.32), (4.25)-(4.26): the dense H1's unconstrained minimizer, clipped.
    for (int i = rk; i < L; i += sz) g[i] = xe[i] - Qx0[i] + lame[i];
    t.sync();
    gemv_t(t, P.P, g, tu, scratch);
    for (int i = rk; i < nz; i += sz) u[i] = clampf(rho * dot_row(P.H1inv, i, tu), P.ulo[i], P.uhi[i]);
    t.sync();
    // First dual step (4.33) and the x-step (4.27)-(4.28) on the diagonal stages.
    for (int i = rk; i < L; i += sz) {
      const R pu = dot_row(P.P, i, u);
      Pu[i] = pu;
      lam[i] = lame[i] + S.r * (xe[i] - pu - Qx0[i]);
      g[i] = rho * (pu + Qx0[i] - lam[i]);
      if (i < L - ns) x[i] = clampf(P.H2diag[i % ns] * g[i], P.xlo[i], P.xhi[i]);
    }
    t.sync();
    for (int i = rk; i < ns; i += sz) {  // the dense terminal block
      const int row = L - ns + i;
      x[row] = clampf(dot_row(P.H2last, i, g + (L - ns)), P.xlo[row], P.xhi[row]);
    }
    t.sync();
    // Gamma, the second dual step (4.23) and the residual measure (4.34).
    R pr = 0.0f, dl = 0.0f;
    for (int i = rk; i < L; i += sz) {
      const R gam = x[i] - Pu[i] - Qx0[i];
      lam[i] += S.s * gam;
      pr = nan_max(pr, absf(gam));
      const R d = lam[i] - lame[i];
      dl += d * d;
      g[i] = x[i] - xe[i];
    }
    t.sync();
    gemv_t(t, P.P, g, tu, scratch);
    R tu2 = 0.0f, tumax = 0.0f;
    for (int j = rk; j < nz; j += sz) {
      tu2 += tu[j] * tu[j];
      tumax = nan_max(tumax, absf(tu[j]));
    }
    primal = t.max(pr);
    const R c = sqrt_of(t.sum(dl)) + rho * sqrt_of(t.sum(tu2));
    dual = rho * t.max(tumax);
    R beta = 0.0f;
    const bool ok = nest.accept(c, S.eta, beta);
    if (!ok) ++restarts;
    for (int i = rk; i < L; i += sz) {
      if (ok) {
        xe[i] = x[i] + beta * (x[i] - xp[i]);
        lame[i] = lam[i] + beta * (lam[i] - lamp[i]);
      } else {
        xe[i] = xp[i];
        lame[i] = lamp[i];
      }
      xp[i] = x[i];
      lamp[i] = lam[i];
    }
    t.sync();
    if (!finite(c)) {
      status = kNumericalFailure;
      break;
    }
    if (primal <= S.eps_abs) {  // E2: iterate while ||Gamma||_inf > epsilon
      status = kConverged;
      break;
    }
    if (over_budget(t, t0, S)) {
      status = kTimeBudget;
      break;
    }
  }
  for (int i = rk; i < nz; i += sz) {
    slot.z_out[i] = u[i];
    slot.state[i] = u[i];
  }
  for (int i = rk; i < L; i += sz) {
    slot.state[nz + i] = x[i];
    slot.state[nz + L + i] = lam[i];
  }
  if (slot.y_out != nullptr) {
    for (int i = rk; i < P.nc; i += sz) slot.y_out[i] = 0.0f;  // the thesis variant has no QP multipliers
  }
  report(t, slot, S, status, k, restarts, primal, dual);
}

}  // namespace gpu
}  // namespace tmpc
