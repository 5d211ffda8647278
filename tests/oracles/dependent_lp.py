# SPDX-License-Identifier: GPL-3.0-or-later
"""A second route for the consistency fuzzer's findings on dependent contact columns (proofs/README.md,
"Consistency on dependent columns"), written separately from src/fuzz/consistency_dependent.cpp.

The claim of a `kinetic` or `friction_cone` finding is that no impulse Lambda of the kind (normals
>= 0; and |Lambda_T| <= mu Lambda_N) changes the velocities by M^-1 W Lambda within t w_i of the
answer's change du in every coordinate i (w_i >= sqrt((M^-1)_ii)), for t = the tolerance. Here:
  - `box_feasible` decides that in Python fractions by Fourier-Motzkin elimination over Lambda
    (exact; fast for a few columns: the planar scenes);
  - `least_t_float` computes the least such t with scipy's HiGHS (floating point; for scenes in
    space, where elimination is slow), run by Debian's /usr/bin/python3.
The answer's change du is taken as it is (the engines here keep it in the range of M^-1 W).
"""
import json
import subprocess

from friction_lcp import fm_point, solve
from fractions import Fraction as F


def _minv(S):
    n = S.n
    cols = [solve(S.M, [F(int(i == j)) for i in range(n)]) for j in range(n)]
    return [[cols[j][i] for j in range(n)] for i in range(n)]


def finding(w):
    """A finding's change of velocity du = y - x (exact, from its hex doubles), t* and tolerance."""
    u = [F(float.fromhex(t)) for t in w["input"]]
    du = [F(float.fromhex(t)) - a for t, a in zip(w["output"], u)]
    return du, F(w["exact"]["t"]), F(w["exact"]["tolerance"])


def box_feasible(S, du, t, w, kind="friction_cone"):
    """Whether some Lambda of the kind gives |(M^-1 W Lambda - du)_i| <= t w_i for every i."""
    n, d, N = S.n, S.d, len(S.normals)
    Minv = _minv(S)
    V = [[sum(Minv[i][j] * S.columns[k][j] for j in range(n)) for k in range(d)] for i in range(n)]
    cons = []
    for i in range(n):
        cons.append(([-x for x in V[i]], du[i] + t * w[i], False))
        cons.append((list(V[i]), -du[i] + t * w[i], False))
    for k in range(N):
        cons.append(([F(int(j == k)) for j in range(d)], F(0), False))
    if kind == "friction_cone":
        for j, (k, mu, _, _) in enumerate(S.tangents):
            for s in (1, -1):
                row = [F(0)] * d
                row[k], row[N + j] = mu, F(-s)
                cons.append((row, F(0), False))
    return fm_point(cons, d) is not None


def least_t_float(S, du, w, kind="friction_cone"):
    """The least t (a float) by scipy's linear programming, in a Debian python3 process."""
    Minv = _minv(S)
    job = {"V": [[float(sum(Minv[i][j] * S.columns[k][j] for j in range(S.n))) for k in range(S.d)] for i in range(S.n)],
           "du": [float(x) for x in du], "w": [float(x) for x in w], "N": len(S.normals),
           "tangents": [[k, float(mu)] for (k, mu, _, _) in S.tangents] if kind == "friction_cone" else []}
    script = r'''
import json, sys
import numpy as np
from scipy.optimize import linprog
j = json.load(sys.stdin)
V, du, w, N, T = np.array(j["V"]), np.array(j["du"]), np.array(j["w"]), j["N"], j["tangents"]
n, d = V.shape
A, b = [], []
for i in range(n):
    A.append(list(V[i]) + [-w[i]]); b.append(du[i])
    A.append(list(-V[i]) + [-w[i]]); b.append(-du[i])
for jj, (k, mu) in enumerate(T):
    for s in (1, -1):
        r = np.zeros(d + 1); r[N + jj] = s; r[k] = -mu; A.append(r); b.append(0.0)
c = np.zeros(d + 1); c[-1] = 1
bounds = [(0, None)] * N + [(None, None)] * (d - N) + [(0, None)]
res = linprog(c, A_ub=np.array(A), b_ub=np.array(b), bounds=bounds, method="highs")
print(json.dumps(res.fun if res.status == 0 else None))
'''
    p = subprocess.run(["/usr/bin/python3", "-c", script], input=json.dumps(job), capture_output=True, text=True,
                       check=True)
    return json.loads(p.stdout)


def widths(S):
    """w_i >= sqrt((M^-1)_ii), rational: the least multiple of 2^-40 whose square is not below."""
    out = []
    for i, row in enumerate(_minv(S)):
        x = row[i]
        lo, hi = 0, 2 ** 40 * (int(x) + 1)
        while lo < hi:  # the least k with (k / 2^40)^2 >= x
            mid = (lo + hi) // 2
            if F(mid, 2 ** 40) ** 2 >= x:
                hi = mid
            else:
                lo = mid + 1
        out.append(F(lo, 2 ** 40))
    return out
