# SPDX-License-Identifier: GPL-3.0-or-later
"""Scenes written by hand, in Python fractions, for the tests that check impactcert's scenes and
their laws against an oracle (tests/scene_shapes_test.py, tests/redundant_contacts_test.py).

hand_system (the plane: (x, y, theta) per body) and hand_system3 (space: (v, omega) per body)
build M and the columns of W from the bodies and contacts exactly as the scene format defines
them (lever arms; a rough contact's tangent (n_y, -n_x) in the plane, H e1 and H e2 of the
reflection H = I - 2 v v^T / v.v, v = n - e3, in space), without reading impactcert's output.
law_columns reads a law file's M and columns; pieces_of and locate evaluate its pieces.
"""
from fractions import Fraction as F

from friction_lcp import solve


def hand_system(bodies, contacts):
    n = 3 * len(bodies)
    M = [[F(0)] * n for _ in range(n)]
    for b, (m, J, _) in enumerate(bodies):
        M[3 * b][3 * b] = M[3 * b + 1][3 * b + 1] = F(m)
        M[3 * b + 2][3 * b + 2] = F(J)

    def column(a, b, p, d):
        col = [F(0)] * n
        for body, s in ((a, -1), (b, 1)):
            if body is None:
                continue
            cx, cy = (F(x) for x in bodies[body][2])
            rx, ry = F(p[0]) - cx, F(p[1]) - cy
            col[3 * body] += s * F(d[0])
            col[3 * body + 1] += s * F(d[1])
            col[3 * body + 2] += s * (rx * F(d[1]) - ry * F(d[0]))
        return col

    normals = [column(a, b, p, nrm) for (a, b, p, nrm, _) in contacts]
    friction = [(k, F(mu), F(0), [column(a, b, p, (nrm[1], -nrm[0]))])
                for k, (a, b, p, nrm, mu) in enumerate(contacts) if mu]
    return M, normals, friction


def law_columns(law):
    W = law["contacts"]["W"]
    cols = [[F(W[i][k]) for i in range(len(W))] for k in range(len(W[0]))]
    tangents = [[F(x) for x in t] for f in law["contacts"].get("friction", []) for t in f["tangents"]]
    n = len(W)
    if "M" in law:
        M = [[F(x) for x in row] for row in law["M"]]
    else:
        M = [[F(law["masses"][i]) if i == j else F(0) for j in range(n)] for i in range(n)]
    return cols, tangents, M


def pieces_of(law):
    out = []
    for piece in law["pieces"]:
        d = len(piece["rays"][0])
        R = [[F(r[i]) for r in piece["rays"]] for i in range(d)]
        cols = [solve(R, [F(int(i == j)) for i in range(d)]) for j in range(d)]
        Rinv = [[cols[j][i] for j in range(d)] for i in range(d)]
        out.append((Rinv, [[F(x) for x in row] for row in piece["Q"]]))
    return out


def locate(pieces, gamma):
    values = []
    for Rinv, Q in pieces:
        if any(sum(row[j] * gamma[j] for j in range(len(gamma))) < 0 for row in Rinv):
            continue
        v = [sum(Q[i][j] * gamma[j] for j in range(len(gamma))) for i in range(len(gamma))]
        if v not in values:
            values.append(v)
    return values


def hand_system3(bodies, contacts):
    n = 6 * len(bodies)
    M = [[F(0)] * n for _ in range(n)]
    for b, (m, moments, _, R) in enumerate(bodies):
        for k in range(3):
            M[6 * b + k][6 * b + k] = F(m)
        R = R or [[F(int(i == j)) for j in range(3)] for i in range(3)]
        Ib = moments if isinstance(moments[0], (list, tuple)) else [[moments[i] if i == j else 0 for j in range(3)]
                                                                      for i in range(3)]
        for i in range(3):
            for j in range(3):
                M[6 * b + 3 + i][6 * b + 3 + j] = sum(R[i][k] * F(Ib[k][l]) * R[j][l] for k in range(3) for l in range(3))

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    def column(a, b, p, d):
        col = [F(0)] * n
        for body, s in ((a, -1), (b, 1)):
            if body is None:
                continue
            arm = cross([F(p[k]) - F(bodies[body][2][k]) for k in range(3)], [F(x) for x in d])
            for k in range(3):
                col[6 * body + k] += s * F(d[k])
                col[6 * body + 3 + k] += s * arm[k]
        return col

    def tangents(nrm):
        v = [F(nrm[0]), F(nrm[1]), F(nrm[2]) - 1]
        vv = sum(x * x for x in v)
        if vv == 0:
            return (1, 0, 0), (0, 1, 0)
        out = []
        for e in ((1, 0, 0), (0, 1, 0)):
            c = 2 * sum(v[k] * e[k] for k in range(3)) / vv
            out.append(tuple(e[k] - c * v[k] for k in range(3)))
        return out

    normals = [column(a, b, p, nrm) for (a, b, p, nrm, _) in contacts]
    friction = [(k, F(mu), F(0), [column(a, b, p, t) for t in tangents(nrm)])
                for k, (a, b, p, nrm, mu) in enumerate(contacts) if mu]
    return M, normals, friction
