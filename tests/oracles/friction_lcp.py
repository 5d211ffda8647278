# SPDX-License-Identifier: GPL-3.0-or-later
"""An independent oracle for the Newton-type impact law with Coulomb friction (SPEC section 9).

Written separately from src/derive/derive_friction.cpp, in body velocities and Python fractions: for a
system (M, W_N, tangents with mu and e_T) and u-, every contact mode (open; closed with stick or
slip either way per tangent) is a square linear system in (u+, Lambda),
    M (u+ - u-) = W Lambda,  and per contact the mode's equalities,
solved by Gaussian elimination over the rationals, then the mode's inequalities are checked. The
distinct u+ found are the solutions. G = W^T M^-1 W is never formed.

With dependent columns (more columns of W than its rank: a box flat on rough ground) a mode's
system can be singular; `solutions(..., dependent=True)` then takes its whole solution set, an
affine set x0 + N t, and decides by Fourier-Motzkin elimination over t whether some point of it
meets the mode's inequalities (and which u+ that point has; `spread` tells whether u+ varies over
the mode's feasible set, decided by the same elimination).
"""
from fractions import Fraction as F
import itertools


def solve(A, b):
    """A x = b over the rationals; None when A is singular."""
    n = len(A)
    m = [list(A[i]) + [b[i]] for i in range(n)]
    for col in range(n):
        piv = next((r for r in range(col, n) if m[r][col] != 0), None)
        if piv is None:
            return None
        m[col], m[piv] = m[piv], m[col]
        p = m[col][col]
        for r in range(n):
            if r != col and m[r][col] != 0:
                f = m[r][col] / p
                row_c = m[col]
                row_r = m[r]
                for k in range(col, n + 1):
                    row_r[k] -= f * row_c[k]
    return [m[i][n] / m[i][i] for i in range(n)]


def affine_solve(A, b):
    """Every solution of A x = b: (x0, N) with x = x0 + N t (N a list of null vectors), or None."""
    rows, n = len(A), len(A[0])
    m = [list(A[i]) + [b[i]] for i in range(rows)]
    pivots, r = [], 0
    for col in range(n):
        piv = next((i for i in range(r, rows) if m[i][col] != 0), None)
        if piv is None:
            continue
        m[r], m[piv] = m[piv], m[r]
        p = m[r][col]
        m[r] = [x / p for x in m[r]]
        for i in range(rows):
            if i != r and m[i][col] != 0:
                f = m[i][col]
                m[i] = [a - f * c for a, c in zip(m[i], m[r])]
        pivots.append(col)
        r += 1
    if any(m[i][n] != 0 for i in range(r, rows)):
        return None
    x0 = [F(0)] * n
    for i, col in enumerate(pivots):
        x0[col] = m[i][n]
    free = [c for c in range(n) if c not in pivots]
    N = []
    for fcol in free:
        v = [F(0)] * n
        v[fcol] = F(1)
        for i, col in enumerate(pivots):
            v[col] = -m[i][fcol]
        N.append(v)
    return x0, N


def fm_point(ineqs, k):
    """A point t in Q^k with a . t + c >= 0 for every (a, c) in ineqs (strict: (a, c, True) for
    a . t + c > 0), by Fourier-Motzkin elimination; None when there is none."""
    if k == 0:
        return [] if all((c > 0) if strict else (c >= 0) for (_, c, strict) in ineqs) else None
    pos = [q for q in ineqs if q[0][k - 1] > 0]
    neg = [q for q in ineqs if q[0][k - 1] < 0]
    rest = [(a[:k - 1], c, st) for (a, c, st) in ineqs if a[k - 1] == 0]
    for (ap, cp, sp) in pos:
        for (an, cn, sn) in neg:
            fp, fn = 1 / ap[k - 1], -1 / an[k - 1]
            rest.append(([fp * x + fn * y for x, y in zip(ap[:k - 1], an[:k - 1])], fp * cp + fn * cn, sp or sn))
    t = fm_point(rest, k - 1)
    if t is None:
        return None
    # x_k >= lo (from pos) and x_k <= hi (from neg); strict bounds get the midpoint or a step.
    lo = [(-(sum(a * b for a, b in zip(ap[:k - 1], t)) + cp) / ap[k - 1], sp) for (ap, cp, sp) in pos]
    hi = [((sum(a * b for a, b in zip(an[:k - 1], t)) + cn) / -an[k - 1], sn) for (an, cn, sn) in neg]
    L = max(lo, key=lambda x: x[0]) if lo else None
    U = min(hi, key=lambda x: x[0]) if hi else None
    if L and U:
        x = L[0] if not any(st for (v, st) in lo if v == L[0]) and not any(st for (v, st) in hi if v == L[0]) \
            else (L[0] + U[0]) / 2
    elif L:
        x = L[0] + (1 if any(st for (v, st) in lo if v == L[0]) else 0)
    elif U:
        x = U[0] - (1 if any(st for (v, st) in hi if v == U[0]) else 0)
    else:
        x = F(0)
    return t + [x]


class System:
    def __init__(self, M, WN, friction):
        """M: n x n; WN: list of normal columns (each n entries); friction: list of
        (contact index, mu, e_T, [tangent columns])."""
        self.M = [[F(x) for x in row] for row in M]
        self.n = len(M)
        self.normals = [[F(x) for x in col] for col in WN]
        self.tangents = []  # (contact, mu, e_T, column)
        for (k, mu, eT, cols) in friction:
            for col in cols:
                self.tangents.append((k, F(mu), F(eT), [F(x) for x in col]))
        self.columns = self.normals + [t[3] for t in self.tangents]
        self.d = len(self.columns)

    def velocities(self, u):
        return [sum(c[i] * u[i] for i in range(self.n)) for c in self.columns]

    def impulses(self, u, up):
        """gamma-, gamma+ and the contact impulses Lambda = G^-1 (gamma+ - gamma-), G = W^T M^-1 W,
        that a change of velocity u -> up would take, exactly (the columns independent)."""
        gm, gp = self.velocities(u), self.velocities(up)
        Minv_cols = [solve(self.M, c) for c in self.columns]
        G = [[sum(a[i] * mc[i] for i in range(self.n)) for mc in Minv_cols] for a in self.columns]
        return gm, gp, solve(G, [a - b for a, b in zip(gp, gm)])

    def energy2(self, u):
        return sum(u[i] * self.M[i][j] * u[j] for i in range(self.n) for j in range(self.n))

    def solutions(self, u_minus, e, approaching=False, dependent=False):
        """Every distinct u+ of the Newton law with friction at u-; e: one value per normal.
        dependent: singular modes too (their whole solution sets); self.spread is then set when
        some mode's feasible set holds two different u+."""
        self.spread = False
        n, d, N = self.n, self.d, len(self.normals)
        u_minus = [F(x) for x in u_minus]
        gm = self.velocities(u_minus)
        Dn = []
        for k in range(N):
            applies = (not approaching) or gm[k] < 0
            Dn.append(1 + F(e[k]) if applies else F(1))
        Dt = [1 + t[2] for t in self.tangents]
        tang_of = [[j for j, t in enumerate(self.tangents) if t[0] == k] for k in range(N)]
        states = []
        for k in range(N):
            s = ["open"]
            if not tang_of[k]:
                s.append("closed")
            else:
                s += ["".join(w) for w in itertools.product("sfb", repeat=len(tang_of[k]))]
            states.append(s)
        Mu = [sum(self.M[i][j] * u_minus[j] for j in range(n)) for i in range(n)]
        found = []
        for choice in itertools.product(*states):
            # Unknowns x = (u+ [n], Lambda [d]).
            A, b = [], []
            for i in range(n):
                A.append([self.M[i][j] for j in range(n)] + [-self.columns[c][i] for c in range(d)])
                b.append(Mu[i])
            ineq = []  # functions of (gp, lam) that must be >= 0

            def xi(q, gp, D=None):
                return gp[q] + (D - 1) * gm[q]

            def row_xi(q, D):  # xi_q = col_q . u+ + (D - 1) gm_q = 0
                A.append([self.columns[q][i] for i in range(n)] + [F(0)] * d)
                b.append(-(D - 1) * gm[q])

            def row_lam(coef):
                A.append([F(0)] * n + coef)
                b.append(F(0))

            def unit(q, s=1):
                v = [F(0)] * d
                v[q] = F(s)
                return v

            for k, st in enumerate(choice):
                if st == "open":
                    row_lam(unit(k))
                    ineq.append(lambda gp, lam, k=k: xi(k, gp, Dn[k]))
                    for j in tang_of[k]:
                        row_lam(unit(N + j))
                    continue
                row_xi(k, Dn[k])
                ineq.append(lambda gp, lam, k=k: lam[k])
                if st == "closed":
                    continue
                for t, j in enumerate(tang_of[k]):
                    T = N + j
                    mu = self.tangents[j][1]
                    if st[t] == "s":
                        row_xi(T, Dt[j])
                        ineq.append(lambda gp, lam, k=k, T=T, mu=mu: mu * lam[k] - lam[T])
                        ineq.append(lambda gp, lam, k=k, T=T, mu=mu: mu * lam[k] + lam[T])
                    elif st[t] == "f":
                        c = unit(T)
                        c[k] += mu
                        row_lam(c)
                        ineq.append(lambda gp, lam, T=T, j=j: xi(T, gp, Dt[j]))
                    else:
                        c = unit(T)
                        c[k] -= mu
                        row_lam(c)
                        ineq.append(lambda gp, lam, T=T, j=j: -xi(T, gp, Dt[j]))
            x = solve(A, b)
            if x is None and dependent:
                x = self._singular_mode(A, b, ineq, n)
            if x is None:
                continue
            up, lam = x[:n], x[n:]
            gp = self.velocities(up)
            if all(f(gp, lam) >= 0 for f in ineq) and up not in found:
                found.append(up)
        return found


def _value(S, f, x, n):
    return f(S.velocities(x[:n]), x[n:])


def _singular_mode(self, A, b, ineq, n):
    """A point of the mode (A x = b, every f in ineq >= 0) when there is one; sets self.spread
    when u+ is not constant on the mode's feasible set."""
    sol = affine_solve(A, b)
    if sol is None:
        return None
    x0, N = sol
    k = len(N)

    def at(t):
        return [x0[i] + sum(N[j][i] * t[j] for j in range(k)) for i in range(len(x0))]

    forms = []
    for f in ineq:
        c = _value(self, f, x0, n)
        forms.append(([_value(self, f, [a + v for a, v in zip(x0, N[j])], n) - c for j in range(k)], c, False))
    t = fm_point(forms, k)
    if t is None:
        return None
    x = at(t)
    for i in range(n):  # u+_i(t') - u+_i(t) > 0 or < 0 somewhere on the feasible set?
        a = [N[j][i] for j in range(k)]
        if any(a):
            ref = sum(a[j] * t[j] for j in range(k))
            for sgn in (1, -1):
                if fm_point(forms + [([sgn * v for v in a], -sgn * ref, True)], k) is not None:
                    self.spread = True
    return x


System._singular_mode = _singular_mode


def breaks(S, u, up, prop):
    """Whether the answer up at u breaks `prop` (kinematic, friction_cone, coulomb, momentum), as the
    fuzzer's worst case claims, recomputed in contact space from M and W alone: kinematic and the
    friction cone by more than 1e-6 times the input's scale (far above a float engine's rounding
    at --max-rel-error 1e-5 or finer), Coulomb's slip signs and momentum exactly."""
    gm, gp, lam = S.impulses(u, up)
    N = len(S.normals)
    margin = F(1, 10**6) * (sum(abs(x) for x in gm) + 1)
    if prop == "kinematic":
        return any(gp[k] < -margin for k in range(N))
    for j, (k, mu, _, _) in enumerate(S.tangents):
        T = N + j
        if prop == "friction_cone" and abs(lam[T]) - mu * lam[k] > margin:
            return True
        if prop == "coulomb" and ((gp[T] > 0 and lam[T] + mu * lam[k] > 0) or (gp[T] < 0 and mu * lam[k] - lam[T] > 0)):
            return True
    if prop == "momentum":  # du - M^-1 W Lambda != 0
        Minv_cols = [solve(S.M, c) for c in S.columns]
        du = [a - b for a, b in zip(up, u)]
        return any(du[i] != sum(Minv_cols[c][i] * lam[c] for c in range(S.d)) for i in range(S.n))
    return False

