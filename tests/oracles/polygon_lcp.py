# SPDX-License-Identifier: GPL-3.0-or-later
"""An independent oracle for the Newton-type impact law with polygonal friction cones.

Written separately from src/derive/derive_friction.cpp, in body velocities and Python fractions.
A contact k with a friction polygon has two tangents and facets a_j (the polygon {x : a_j . x <=
1}); its friction Lambda_T lies in mu Lambda_N P and minimises Lambda_T . xi_T there (maximal
dissipation), xi = gamma+ + e gamma- (normals) and gamma_T+ (tangents, e_T = 0). For u-, every
combination of contact states is a square linear system in (u+, Lambda):
    M (u+ - u-) = W Lambda, and per contact: open (Lambda_N = 0, Lambda_T = 0), or closed
    (xi_N = 0) with stick (xi_T = 0), the friction at vertex j (Lambda_T = mu Lambda_N v_j), or on
    edge j (a_j . Lambda_T = mu Lambda_N, xi_T parallel to a_j);
solved by Gaussian elimination; its solution counts when Coulomb's law holds there, checked on the
solution itself (not from the state's inequalities): Lambda_N >= 0, xi_N >= 0 (open: xi_N >= 0),
Lambda_T in the polygon, and Lambda_T . xi_T <= mu Lambda_N v . xi_T at every vertex v. The
polygon's vertices are recomputed here from the facets. G = W^T M^-1 W is never formed.
"""
from fractions import Fraction as F
import itertools

from friction_lcp import solve


def vertices(facets):
    """v_j: the intersection of facets j and j + 1 (counterclockwise)."""
    out = []
    for j in range(len(facets)):
        a, b = facets[j], facets[(j + 1) % len(facets)]
        det = a[0] * b[1] - a[1] * b[0]
        out.append(((b[1] - a[1]) / det, (a[0] - b[0]) / det))
    return out


class PolygonSystem:
    def __init__(self, M, normals, contacts):
        """contacts[k]: None (frictionless) or (mu, (t1, t2), facets), columns of length n."""
        self.M, self.n = M, len(M)
        self.normals = normals
        self.contacts = contacts
        self.cols = list(normals)
        self.tcol = {}
        for k, c in enumerate(contacts):
            if c:
                self.tcol[k] = (len(self.cols), len(self.cols) + 1)
                self.cols += list(c[1])
        self.d = len(self.cols)
        self.verts = {k: vertices(c[2]) for k, c in enumerate(contacts) if c}

    def gamma(self, u):
        return [sum(c[i] * u[i] for i in range(self.n)) for c in self.cols]

    def states(self, k):
        if not self.contacts[k]:
            return ["o", "c"]
        K = len(self.contacts[k][2])
        return ["o", "s"] + [f"v{j}" for j in range(K)] + [f"e{j}" for j in range(K)]

    def coulomb(self, u_minus, up, lam, e):
        gm, gp = self.gamma(u_minus), self.gamma(up)
        for k in range(len(self.normals)):
            if lam[k] < 0 or gp[k] + e * gm[k] < 0:
                return False
            if lam[k] != 0 and gp[k] + e * gm[k] != 0:
                return False
            if not self.contacts[k]:
                continue
            mu, _, facets = self.contacts[k]
            T1, T2 = self.tcol[k]
            lt, xi = (lam[T1], lam[T2]), (gp[T1], gp[T2])
            if any(a[0] * lt[0] + a[1] * lt[1] > mu * lam[k] for a in facets):
                return False
            if any(lt[0] * xi[0] + lt[1] * xi[1] > mu * lam[k] * (v[0] * xi[0] + v[1] * xi[1]) for v in self.verts[k]):
                return False
        return True

    def solutions(self, u_minus, e):
        """The distinct u+ of Newton's law (restitution e on every contact) with these cones."""
        n, d, N = self.n, self.d, len(self.normals)
        gm = self.gamma(u_minus)
        Mu = [sum(self.M[i][j] * u_minus[j] for j in range(n)) for i in range(n)]
        found = []
        for combo in itertools.product(*[self.states(k) for k in range(N)]):
            A, b = [], []
            for i in range(n):  # M u+ - W Lambda = M u-
                A.append(list(self.M[i]) + [-c[i] for c in self.cols])
                b.append(Mu[i])

            def lam_row(coef):  # sum coef_q Lambda_q = 0
                A.append([F(0)] * n + [coef.get(q, F(0)) for q in range(d)])
                b.append(F(0))

            def xi_row(coef, extra=F(0)):  # sum coef_q (gamma+_q) = extra
                A.append([sum(coef.get(q, F(0)) * self.cols[q][i] for q in coef) for i in range(n)] + [F(0)] * d)
                b.append(extra)

            for k, s in enumerate(combo):
                if s == "o":
                    lam_row({k: F(1)})
                    if self.contacts[k]:
                        lam_row({self.tcol[k][0]: F(1)})
                        lam_row({self.tcol[k][1]: F(1)})
                    continue
                xi_row({k: F(1)}, -e * gm[k])  # gamma_N+ = -e gamma_N-
                if s == "c":
                    continue
                mu, _, facets = self.contacts[k]
                T1, T2 = self.tcol[k]
                if s == "s":
                    xi_row({T1: F(1)})
                    xi_row({T2: F(1)})
                elif s[0] == "v":
                    v = self.verts[k][int(s[1:])]
                    lam_row({T1: F(1), k: -mu * v[0]})
                    lam_row({T2: F(1), k: -mu * v[1]})
                else:
                    a = facets[int(s[1:])]
                    lam_row({T1: a[0], T2: a[1], k: -mu})
                    xi_row({T1: -a[1], T2: a[0]})  # xi_T parallel to a
            x = solve(A, b)
            if x is None:
                continue
            up, lam = x[:n], x[n:]
            if self.coulomb(u_minus, up, lam, e) and up not in found:
                found.append(up)
        return found
