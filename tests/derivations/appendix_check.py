#!/usr/bin/env python3
"""Check Swan & Brady (2007), Appendices B (B1-B6) and C (C2-C7), against an
independent sympy derivation from Blake's image (Eq. 5) and the block definitions
(Eqs. 8, 12-15, A1-A9).

Run:   python3 tests/derivations/appendix_check.py [--dump FILE] [--coefficients]

  --dump FILE      also write the derived blocks at every configuration to FILE (plain
                   text, one block per line) so that tests/src/paper.rs can be checked
                   against the same numbers (see docs/errata.md).
  --coefficients   also extract, exactly (rational arithmetic), the derived coefficient of
                   every printed tensor structure of C5, C6 and C7 and print them all, for
                   term-by-term comparison with the paper (about 20 s more).

Conventions (docs/errata.md, docs/conventions.md): wall x3 = 0, fluid x3 > 0, Levi-Civita
right-handed, the mobility maps the force/torque/stresslet exerted ON THE FLUID to
(U, Omega, -E_inf).  Only the image part Jw enters (the paper's hat-M).  Blocks are
normalised by 6 pi eta a^n (n = 1 UF; 2 OF, EF; 3 OL, EL, ES), lengths by a.

Derivation
----------
Write R = x - y' (y' = (y1, y2, -y3)) and h = y3.  With D_k = d/dR_k and the
biharmonic r = |R|, the Stokeslet is J_ij = (delta_ij D^2 - D_i D_j) r / (8 pi eta), so
Blake's image (Eq. 5, z-derivatives taken before z = y'; d/dz = -d/dR)

    Jw_il = -J_il(R) + h^2 (D^2 J)_il P_ll - 2 h P_ll D_l J_i3(R)

is a polynomial in (D_1, D_2, D_3, h) applied to r.  Derivatives act on it as
    d/dx_k = D_k,      d/dy_k = -P_kk D_k + delta_k3 d/dh      (Eq. 10: explicit h too),
so every block is again a polynomial in (D, h); it is evaluated exactly through
D^alpha r = P_alpha(R) / r^(1 + 2|alpha|), with the polynomials P_alpha from the
recursion D_k (P / r^m) = (r^2 D_k P - m R_k P) / r^(m+2), in 40-digit arithmetic.

That machinery is cross-checked against a literal transcription of Eq. 5 in the six
variables (x, y) (sympy expression, z-derivatives then z = y', differentiated
numerically by mpmath.diff at 50 digits), and the derived blocks are checked for the
no-slip condition, reciprocity/symmetry and the physical sign (a force +x makes the
sphere roll, Omega_y > 0; a torque +y makes it translate +x).

Comparison
----------
For each equation: max over the configurations of |printed - derived|_F / |derived|_F
(Frobenius norm over the whole block), and the same for the corrected form.  EF, EL,
ES are compared in full Cartesian form AND after projecting the strain pair (pq) and the
stresslet pair (kl) onto the 5 symmetric traceless basis tensors of docs/conventions.md (the
trace parts cannot matter: E_inf and S are traceless).  The derived tensors are exactly
traceless in pq and in kl; the printed C5/C7 carry delta_ij / delta_kl terms but, once
corrected, agree in full Cartesian form too, so no projection is needed for the verdict.
"""
import argparse
import math
import sys
import time

import mpmath as mp
import numpy as np
import sympy as sp

T_START = time.time()
mp.mp.dps = 40
R3 = range(3)
Z = 2  # the paper's index "3"


# ----------------------------------------------------------------------------------
# 1. Derivation: operator calculus on the biharmonic r
# ----------------------------------------------------------------------------------
d1, d2, d3, hs = sp.symbols("d1 d2 d3 h")
D = [d1, d2, d3]
PD = [1, 1, -1]  # P = diag(1, 1, -1)
LAP = d1**2 + d2**2 + d3**2


def eps_i(i, j, k):
    return (i - j) * (j - k) * (k - i) // 2


def j_op(i, j):
    """Stokeslet (without 1/(8 pi eta)) as an operator on r: delta_ij D^2 - D_i D_j."""
    return (LAP if i == j else 0) - D[i] * D[j]


# Blake's image, Eq. 5 with H = 0, as an operator on r(R), R = x - y'.
G = [[sp.expand(-j_op(i, l) + hs**2 * LAP * j_op(i, l) * PD[l] - 2 * hs * PD[l] * D[l] * j_op(i, Z))
      for l in R3] for i in R3]


def dx(e, k):
    return sp.expand(D[k] * e)


def dy(e, k):
    # d/dy_k through R (dR/dy = -P) and through the explicit h = y3 (Eq. 10)
    return sp.expand(-PD[k] * D[k] * e + (sp.diff(e, hs) if k == Z else 0))


def lap_x(e):
    return sp.expand(LAP * e)


def lap_y(e):
    return sp.expand(sum(dy(dy(e, k), k) for k in R3))


def faxen(e, cx, cy):
    """(1 + cx Lap_x)(1 + cy Lap_y) e  (a = 1)."""
    e1 = e + cy * lap_y(e) if cy else e
    return sp.expand(e1 + cx * lap_x(e1)) if cx else sp.expand(e1)


half = sp.Rational(1, 2)
sixth, tenth = sp.Rational(1, 6), sp.Rational(1, 10)
UF = [[faxen(G[i][j], sixth, sixth) for j in R3] for i in R3]
G_y6 = [[faxen(G[i][j], 0, sixth) for j in R3] for i in R3]
OF = [[sp.expand(sum(half * eps_i(m, k, i) * dx(G_y6[i][j], k) for k in R3 for i in R3))
       for j in R3] for m in R3]
V = [[sp.expand(sum(half * eps_i(n, l, j) * dy(G[i][j], l) for l in R3 for j in R3))
      for n in R3] for i in R3]
OL = [[sp.expand(sum(half * eps_i(m, k, i) * dx(V[i][n], k) for k in R3 for i in R3))
       for n in R3] for m in R3]
UL = [[faxen(V[i][n], sixth, 0) for n in R3] for i in R3]  # for the symmetry check only
G_t = [[faxen(G[i][j], tenth, sixth) for j in R3] for i in R3]
EF = [[[sp.expand(half * (dx(G_t[q][j], p) + dx(G_t[p][j], q))) for j in R3] for q in R3] for p in R3]
V_t = [[faxen(V[i][n], tenth, 0) for n in R3] for i in R3]
EL = [[[sp.expand(half * (dx(V_t[q][n], p) + dx(V_t[p][n], q))) for n in R3] for q in R3] for p in R3]
W = [[[sp.expand(half * (dy(G[i][l], k) + dy(G[i][k], l))) for l in R3] for k in R3] for i in R3]
W_t = [[[faxen(W[i][k][l], tenth, tenth) for l in R3] for k in R3] for i in R3]
ES = [[[[sp.expand(half * (dx(W_t[q][k][l], p) + dx(W_t[p][k][l], q))) for l in R3] for k in R3]
        for q in R3] for p in R3]

X1, X2, X3 = XS = sp.symbols("X1 X2 X3")
R2POLY = sp.Poly(X1**2 + X2**2 + X3**2, *XS)
_PALPHA = {(0, 0, 0): R2POLY}


def p_alpha(a):
    """D^a r = P_a(R) / r^(1 + 2|a|)."""
    if a not in _PALPHA:
        k = max(i for i in R3 if a[i] > 0)
        b = list(a)
        b[k] -= 1
        b = tuple(b)
        pb = p_alpha(b)
        m = 1 + 2 * sum(b)
        _PALPHA[a] = R2POLY * pb.diff(XS[k]) - m * sp.Poly(XS[k], *XS) * pb
    return _PALPHA[a]


class Terms(tuple):
    """(alpha, power of h, rational coefficient) of one tensor component."""


def to_terms(t):
    if isinstance(t, list):
        return [to_terms(v) for v in t]
    p = sp.Poly(t, d1, d2, d3, hs)
    return Terms(((a1, a2, a3), pw, sp.Rational(c)) for (a1, a2, a3, pw), c in p.terms())


BLOCKS = {"UF": UF, "OF": OF, "OL": OL, "EF": EF, "EL": EL, "ES": ES, "UL": UL}
TERMS = {k: to_terms(v) for k, v in BLOCKS.items()}
T_DERIVED = time.time() - T_START


def _evaluate(terms, rv, h):
    """Evaluate term lists at R = rv (mp), h (mp); normalisation 6/8 = 3/4."""
    cache = {}
    r = mp.sqrt(rv[0] ** 2 + rv[1] ** 2 + rv[2] ** 2)

    def dr(a):
        if a not in cache:
            val = mp.mpf(0)
            for mon, c in p_alpha(a).terms():
                val += int(c) * rv[0] ** mon[0] * rv[1] ** mon[1] * rv[2] ** mon[2]
            cache[a] = val / r ** (1 + 2 * sum(a))
        return cache[a]

    def ev(t):
        if isinstance(t, list):
            return [ev(v) for v in t]
        return mp.mpf(3) / 4 * mp.fsum(mp.mpf(c.p) / c.q * h**pw * dr(a) for a, pw, c in t)

    return {k: ev(v) for k, v in terms.items()}


def derived_pair(xa, xb, which=None):
    xa = [mp.mpf(v) for v in xa]
    xb = [mp.mpf(v) for v in xb]
    rv = [xa[0] - xb[0], xa[1] - xb[1], xa[2] + xb[2]]
    terms = TERMS if which is None else {k: TERMS[k] for k in which}
    return _evaluate(terms, rv, xb[2])


def derived_self(h):
    h = mp.mpf(h)
    return _evaluate(TERMS, [mp.mpf(0), mp.mpf(0), 2 * h], h)


def derived_self_symbolic(name, idx):
    """Exact closed form of one self-block component as a function of h (R = (0, 0, 2h))."""
    hh = sp.symbols("h", positive=True)
    t = TERMS[name]
    for i in idx:
        t = t[i]
    val = sum(c * hh**pw * p_alpha(a).as_expr().subs({X1: 0, X2: 0, X3: 2 * hh}) / (2 * hh) ** (1 + 2 * sum(a))
              for a, pw, c in t)
    return sp.expand(sp.Rational(3, 4) * val), hh


# ----------------------------------------------------------------------------------
# 2. Printed formulas (exactly as in seed-paper.md) and corrected formulas.
#    fix=False: as printed; fix=True: the corrected form (tests/src/paper.rs `corrected`).
#    Every difference is marked "ERRATUM".
# ----------------------------------------------------------------------------------
def dd(i, j):
    return 1.0 if i == j else 0.0


ERRATA = {  # label -> equation
    "B2 sign": "B2", "B4 sign": "B4", "B5 sign": "B5", "C3 sign": "C3",
    "C5 sign": "C5", "C5 J: hhat": "C5", "C5 J: R^-6 sign": "C5",
    "C6 sign": "C6", "C6 F: eps_3kl e_l": "C6",
    "C7 T8: e3^2": "C7", "C7 T10: 28": "C7", "C7 T12: e3^2": "C7", "C7 T14: 7": "C7",
    "C7 T16: e3^2": "C7", "C7 T18: e3": "C7", "C7 T18: 18": "C7",
}


def on(fix, label):
    """fix is False (as printed), True (all corrections) or a set of erratum labels."""
    assert label in ERRATA
    return fix is True or (fix is not False and label in fix)


def eps(i, j, k):
    return float(eps_i(i, j, k))


def t2(f):
    return np.array([[f(i, j) for j in R3] for i in R3])


def t3(f):
    return np.array([[[f(i, j, k) for k in R3] for j in R3] for i in R3])


def t4(f):
    return np.array([[[[f(i, j, k, l) for l in R3] for k in R3] for j in R3] for i in R3])


def b1_uf(h, fix=False):
    a = -1 / 16 * (9 / h - 2 / h**3 + 1 / h**5)
    b = -1 / 8 * (9 / h - 4 / h**3 + 1 / h**5)
    return t2(lambda i, j: a * (dd(i, j) - dd(i, Z) * dd(j, Z)) + b * dd(i, Z) * dd(j, Z))


def b2_of(h, fix=False):
    s = -1.0 if on(fix, "B2 sign") else 1.0  # ERRATUM: overall sign
    return s * t2(lambda i, j: 3 / 32 / h**4 * eps(Z, i, j))


def b3_ol(h, fix=False):
    return t2(lambda i, j: -15 / 64 / h**3 * (dd(i, j) - dd(i, Z) * dd(j, Z)) - 3 / 32 / h**3 * dd(i, Z) * dd(j, Z))


def b4_ef(h, fix=False):
    s = -1.0 if on(fix, "B4 sign") else 1.0  # ERRATUM: overall sign
    a = -3 / 160 * (15 / h**2 - 12 / h**4 + 5 / h**6)
    b = 3 / 32 * (3 / h**2 - 3 / h**4 + 1 / h**6)
    c = -3 / 16 * (3 / h**2 - 3 / h**4 + 1 / h**6)
    return s * t3(lambda i, j, k: a * ((dd(i, k) - dd(i, Z) * dd(k, Z)) * dd(j, Z) + (dd(j, k) - dd(j, Z) * dd(k, Z)) * dd(i, Z))
                  + b * (dd(i, j) - dd(i, Z) * dd(j, Z)) * dd(k, Z) + c * dd(i, Z) * dd(j, Z) * dd(k, Z))


def b5_el(h, fix=False):
    s = -1.0 if on(fix, "B5 sign") else 1.0  # ERRATUM: overall sign
    a = -9 / 320 * (5 / h**3 - 4 / h**5)
    return s * t3(lambda i, j, k: a * (dd(j, Z) * eps(Z, i, k) + dd(i, Z) * eps(Z, j, k)))


def b6_es(h, fix=False):
    def pp(i, j):
        return dd(i, j) - dd(i, Z) * dd(j, Z)

    a = -3 / 640 * (10 / h**3 - 24 / h**5 + 9 / h**7)
    b = -9 / 640 * (10 / h**3 - 8 / h**5 + 3 / h**7)
    c = 3 / 160 * (20 / h**3 - 24 / h**5 + 9 / h**7)
    e = -9 / 320 * (15 / h**3 - 16 / h**5 + 6 / h**7)
    f = -3 / 80 * (20 / h**3 - 24 / h**5 + 9 / h**7)
    return t4(lambda i, j, k, l: a * pp(i, j) * pp(k, l)
              + b * (pp(i, k) * pp(j, l) + pp(i, l) * pp(j, k))
              + c * (pp(i, j) * dd(k, Z) * dd(l, Z) + pp(k, l) * dd(i, Z) * dd(j, Z))
              + e * (pp(i, k) * dd(j, Z) * dd(l, Z) + pp(i, l) * dd(j, Z) * dd(k, Z)
                     + pp(j, k) * dd(i, Z) * dd(l, Z) + pp(j, l) * dd(i, Z) * dd(k, Z))
              + f * dd(i, Z) * dd(j, Z) * dd(k, Z) * dd(l, Z))


def geom(xa, xb):
    """C1: R = x_a - x_b + 2 h_b e3 (lengths / a), |R|, e = R/|R|, hhat = h_b/(a R_3)."""
    hb = xb[2]
    rv = [xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2] + 2 * hb]
    rn = math.sqrt(rv[0] ** 2 + rv[1] ** 2 + rv[2] ** 2)
    return rn, [v / rn for v in rv], hb / rv[2]


def c2_uf(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]
    a = -1 / 4 * (3 * (1 + 2 * hh * (1 - hh) * e3**2) / R + 2 * (1 - 3 * e3**2) / R**3 - 2 * (1 - 5 * e3**2) / R**5)
    b = -1 / 4 * (3 * (1 - 6 * hh * (1 - hh) * e3**2) / R - 6 * (1 - 5 * e3**2) / R**3 + 10 * (1 - 7 * e3**2) / R**5)
    c = 1 / 2 * e3 * (3 * hh * (1 - 6 * (1 - hh) * e3**2) / R - 6 * (1 - 5 * e3**2) / R**3 + 10 * (2 - 7 * e3**2) / R**5)
    f = 1 / 2 * e3 * (3 * hh / R - 10 / R**5)
    g = -(3 * hh**2 * e3**2 / R + 3 * e3**2 / R**3 + (2 - 15 * e3**2) / R**5)
    return t2(lambda i, j: a * dd(i, j) + b * e[i] * e[j] + c * e[i] * dd(j, Z) + f * dd(i, Z) * e[j]
              + g * dd(i, Z) * dd(j, Z))


def c3_of(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]
    s = -1.0 if on(fix, "C3 sign") else 1.0  # ERRATUM: overall sign

    def ek(i):  # eps_3ki e_k
        return sum(eps(Z, k, i) * e[k] for k in R3)

    a = 3 / 4 / R**2
    b = 3 / 2 * (6 * hh * e3**2 / R**2 + (1 - 10 * e3**2) / R**4)
    c = -3 / 2 * e3 * (3 * hh / R**2 - 5 / R**4)
    f = -3 / 2 * e3 * (hh / R**2 - 1 / R**4)
    return s * t2(lambda i, j: a * sum(eps(i, j, k) * e[k] for k in R3) + b * ek(i) * dd(j, Z)
                  + c * ek(i) * e[j] + f * eps(Z, i, j))


def c4_ol(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]

    def ek(i):
        return sum(eps(Z, k, i) * e[k] for k in R3)

    return t2(lambda i, j: 3 / 8 * (1 - 6 * e3**2) / R**3 * dd(i, j) - 9 / 8 / R**3 * e[i] * e[j]
              + 9 / 4 * e3 / R**3 * dd(i, Z) * e[j] + 9 / 4 / R**3 * ek(i) * ek(j))


def c5_ef(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]
    s = -1.0 if on(fix, "C5 sign") else 1.0  # ERRATUM: overall sign
    q = 5 - 2 * hh
    A = 6 / 5 * e3 * (q / R**4 - 15 / R**6)
    B = 3 / R**6
    C = -3 / 10 * e3 * (5 * hh * (1 - 6 * (1 - hh) * e3**2) / R**2 - 2 * (5 - hh - 5 * q * e3**2) / R**4
                        + 10 * (2 - 7 * e3**2) / R**6)
    Dd = -3 / 10 * (q / R**4 - 10 / R**6) * e3
    E = 3 / 2 * e3 * (q / R**4 - 14 / R**6)
    F = 3 / 2 * (6 * hh * (1 - hh) * e3**2 / R**2 + (1 - 4 * q * e3**2) / R**4 - 2 * (2 - 21 * e3**2) / R**6)
    Gg = -3 / 10 * (15 * hh * (1 - hh) * e3**2 / R**2 + (4 - 5 * q * e3**2) / R**4 - 5 * (1 - 7 * e3**2) / R**6)
    H = 3 / 2 * e3 * (3 * hh * (1 - 10 * (1 - hh) * e3**2) / R**2 - 2 * (5 - hh - 7 * q * e3**2) / R**4
                      + 14 * (2 - 9 * e3**2) / R**6)
    I = 3 / 20 * (5 * (1 - 6 * hh * (1 - hh) * e3**2) / R**2 - 2 * (4 - 5 * q * e3**2) / R**4
                  + 10 * (1 - 7 * e3**2) / R**6)
    jh = hh if on(fix, "C5 J: hhat") else 1.0  # ERRATUM: 3(1 - 10 hhat(1 - hhat)e3^2), hhat missing
    j6 = 1.0 if on(fix, "C5 J: R^-6 sign") else -1.0  # ERRATUM: +14(1 - 9e3^2)R^-6, printed -14
    Jj = -3 / 4 * (3 * (1 - 10 * jh * (1 - hh) * e3**2) / R**2 - 2 * (4 - 7 * q * e3**2) / R**4
                   + j6 * 14 * (1 - 9 * e3**2) / R**6)
    return s * t3(lambda i, j, k: A * dd(i, Z) * dd(j, Z) * dd(k, Z) + B * dd(i, Z) * dd(j, Z) * e[k]
                  + C * dd(i, j) * dd(k, Z) + Dd * (dd(i, k) * dd(j, Z) + dd(i, Z) * dd(j, k))
                  + E * (dd(j, Z) * e[i] * e[k] + dd(i, Z) * e[j] * e[k])
                  + F * (e[i] * dd(j, Z) * dd(k, Z) + e[j] * dd(i, Z) * dd(k, Z))
                  + Gg * (e[i] * dd(j, k) + e[j] * dd(i, k)) + H * e[i] * e[j] * dd(k, Z)
                  + I * dd(i, j) * e[k] + Jj * e[i] * e[j] * e[k])


def c6_el(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]
    s = -1.0 if on(fix, "C6 sign") else 1.0  # ERRATUM: overall sign

    def eel(i, k):  # eps_ikl e_l
        return sum(eps(i, k, l) * e[l] for l in R3)

    def e3k(k):  # eps_3kl e_l
        return sum(eps(Z, k, l) * e[l] for l in R3)

    A = -9 / 8 / R**3
    B = -9 / 10 / R**5
    C = 9 / 4 * (1 / R**3 - 2 / R**5)
    Dd = -9 / 4 * e3 * ((1 - 2 * hh) / R**3 - 2 / R**5)
    E = 9 / 2 * e3 * ((1 - hh) / R**3 - 1 / R**5)
    F = -9 / 2 * e3 * (5 * (1 - hh) / R**3 - 7 / R**5)

    def last(k):
        # printed "e_i e_j" has no index k (read literally: the same for every k);
        # ERRATUM: the factor eps_3kl e_l is missing
        return e3k(k) if on(fix, "C6 F: eps_3kl e_l") else 1.0

    return s * t3(lambda i, j, k: A * (e[j] * eel(i, k) + e[i] * eel(j, k))
                  + B * (dd(j, Z) * eps(Z, i, k) + dd(i, Z) * eps(Z, j, k))
                  + C * (e[i] * dd(j, Z) * e3k(k) + dd(i, Z) * e[j] * e3k(k))
                  + Dd * (e[j] * eps(Z, i, k) + e[i] * eps(Z, j, k))
                  + E * dd(i, j) * e3k(k) + F * e[i] * e[j] * last(k))


def c7_es(xa, xb, fix=False):
    R, e, hh = geom(xa, xb)
    e3 = e[2]
    u = hh * (1 - hh) * e3**2  # the recurring hhat(1 - hhat) e3^2
    f8 = e3**2 if on(fix, "C7 T8: e3^2") else 1.0  # ERRATUM (T8): missing factor e3^2
    f12 = e3**2 if on(fix, "C7 T12: e3^2") else 1.0  # ERRATUM (T12): missing factor e3^2
    T1 = 9 / 5 / R**7
    T2 = -18 / 5 * e3 * (5 / R**5 - 21 / R**7)
    T3 = 9 / 10 * e3 * (5 / R**5 - 14 / R**7)
    T4 = 9 / 5 * (5 * u / R**3 + (1 - 10 * e3**2) / R**5 - (2 - 21 * e3**2) / R**7)
    T5 = -9 / 10 * (5 * u / R**3 + (1 - 5 * e3**2) / R**5 - (1 - 7 * e3**2) / R**7)
    T6 = 3 / 20 * (5 * (1 - 6 * u) / R**3 - 6 * (1 - 5 * e3**2) / R**5 + 6 * (1 - 7 * e3**2) / R**7)
    T7 = -36 / 5 * (5 * u / R**3 + (1 - 15 * e3**2) / R**5 - 3 * (1 - 14 * e3**2) / R**7)
    # printed (garbled): "- (1 - 42e_3^2) + 126e_3^4]R^{-7}]": read -(1 - 42e3^2 + 126e3^4)R^-7
    T8 = -9 / 5 * (5 * (1 - 10 * u) * f8 / R**3 - 10 * (2 - 7 * e3**2) * f8 / R**5
                   - (1 - 42 * e3**2 + 126 * e3**4) / R**7)
    T9 = -9 / 5 * e3 * (5 * (1 - 20 * u) / R**3 - 30 * (1 - 7 * e3**2) / R**5 + 84 * (1 - 6 * e3**2) / R**7)
    c10 = 28 if on(fix, "C7 T10: 28") else 14  # ERRATUM (T10): 28(2 - 9e3^2), printed 14
    T10 = 9 / 20 * e3 * (5 * (1 - 20 * u) / R**3 - 10 * (3 - 14 * e3**2) / R**5 + c10 * (2 - 9 * e3**2) / R**7)
    T11 = -9 / 20 * (5 * (1 - 10 * u) / R**3 - 10 * (1 - 7 * e3**2) / R**5 + 14 * (1 - 9 * e3**2) / R**7)
    T12 = 9 / 5 * (25 * (1 - 14 * u) * e3**2 / R**3 - 70 * (2 - 9 * e3**2) * f12 / R**5
                   - 7 * (1 - 54 * e3**2 + 198 * e3**4) / R**7)
    T13 = 9 / 10 * e3 * (5 * (1 - 10 * u) / R**3 - 5 * (3 - 14 * e3**2) / R**5 + 14 * (2 - 9 * e3**2) / R**7)
    c14 = 7 if on(fix, "C7 T14: 7") else 14  # ERRATUM (T14): -20(1 - 7e3^2)R^-5, printed (1 - 14e3^2)
    T14 = -9 / 40 * (5 * (1 - 20 * u) / R**3 - 20 * (1 - c14 * e3**2) / R**5 + 28 * (1 - 9 * e3**2) / R**7)
    T15 = 9 / 20 * (5 * (1 - 20 * u) / R**3 - 20 * (1 - 14 * e3**2) / R**5 + 28 * (2 - 27 * e3**2) / R**7)
    p16 = 2 if on(fix, "C7 T16: e3^2") else 3  # ERRATUM (T16): 11 e3^2, printed "11e_3^3"
    T16 = -9 / 10 * e3 * (25 * (1 - 14 * u) / R**3 - 105 * (1 - 6 * e3**2) / R**5
                          + 126 * (2 - 11 * e3**p16) / R**7)
    T17 = -63 / 5 / R**7
    # ERRATUM (T18): -63/10 e3 (5R^-5 - 18R^-7), printed -63/10 (5R^-5 - 9R^-7)
    f18 = e3 if on(fix, "C7 T18: e3") else 1.0
    c18 = 18 if on(fix, "C7 T18: 18") else 9
    T18 = -63 / 10 * f18 * (5 / R**5 - c18 / R**7)
    T19 = 9 / 20 * (25 * (1 - 14 * u) / R**3 - 70 * (1 - 9 * e3**2) / R**5 + 126 * (1 - 11 * e3**2) / R**7)
    d = dd

    def f(i, j, k, l):
        return (T1 * d(i, Z) * d(j, Z) * d(k, l)
                + T2 * (d(i, Z) * d(j, Z) * e[k] * d(l, Z) + d(i, Z) * d(j, Z) * d(k, Z) * e[l])
                + T3 * (e[i] * d(j, Z) * d(k, l) + d(i, Z) * e[j] * d(k, l) + d(i, l) * d(j, Z) * e[k]
                        + d(i, Z) * d(j, l) * e[k] + d(i, Z) * d(j, k) * e[l] + d(i, k) * d(j, Z) * e[l])
                + T4 * (d(i, k) * d(j, Z) * d(l, Z) + d(i, l) * d(j, Z) * d(k, Z)
                        + d(i, Z) * d(j, k) * d(l, Z) + d(i, Z) * d(j, l) * d(k, Z))
                + T5 * (d(i, l) * d(j, k) + d(i, k) * d(j, l))
                + T6 * d(i, j) * d(k, l)
                + T7 * d(i, Z) * d(j, Z) * d(k, Z) * d(l, Z)
                + T8 * d(i, j) * d(k, Z) * d(l, Z)
                + T9 * (e[i] * d(j, Z) * d(k, Z) * d(l, Z) + d(i, Z) * e[j] * d(k, Z) * d(l, Z))
                + T10 * (e[i] * d(j, k) * d(l, Z) + e[i] * d(j, l) * d(k, Z) + d(i, k) * e[j] * d(l, Z)
                         + d(i, l) * e[j] * d(k, Z))
                + T11 * (e[i] * e[j] * d(k, l) + d(i, j) * e[k] * e[l])
                + T12 * e[i] * e[j] * d(k, Z) * d(l, Z)
                + T13 * (d(i, j) * e[k] * d(l, Z) + d(i, j) * d(k, Z) * e[l])
                + T14 * (e[i] * d(j, l) * e[k] + d(i, l) * e[j] * e[k] + e[i] * d(j, k) * e[l] + d(i, k) * e[j] * e[l])
                + T15 * (e[i] * d(j, Z) * e[k] * d(l, Z) + d(i, Z) * e[j] * e[k] * d(l, Z)
                         + e[i] * d(j, Z) * d(k, Z) * e[l] + d(i, Z) * e[j] * d(k, Z) * e[l])
                + T16 * (e[i] * e[j] * e[k] * d(l, Z) + e[i] * e[j] * d(k, Z) * e[l])
                + T17 * d(i, Z) * d(j, Z) * e[k] * e[l]
                + T18 * (d(i, Z) * e[j] * e[k] * e[l] + e[i] * d(j, Z) * e[k] * e[l])
                + T19 * e[i] * e[j] * e[k] * e[l])

    return t4(f)


SELF_EQS = [("B1", "UF", b1_uf), ("B2", "OF", b2_of), ("B3", "OL", b3_ol),
            ("B4", "EF", b4_ef), ("B5", "EL", b5_el), ("B6", "ES", b6_es)]
PAIR_EQS = [("C2", "UF", c2_uf), ("C3", "OF", c3_of), ("C4", "OL", c4_ol),
            ("C5", "EF", c5_ef), ("C6", "EL", c6_el), ("C7", "ES", c7_es)]


# ----------------------------------------------------------------------------------
# 3. Configurations (lengths / a, wall at x3 = 0)
# ----------------------------------------------------------------------------------
SELF_HEIGHTS = [1.0001, 1.001, 1.01, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0]


def pair_configs():
    heights = [(1.0001, 1.0001), (1.0001, 3.5), (3.5, 1.0001), (1.5, 2.7), (5.0, 5.0),
               (20.0, 1.0001), (1.0001, 20.0), (20.0, 20.0), (4.0, 12.0)]
    out = []
    for ha, hb in heights:
        for rho in [0.0, 2.0001, 3.0, 7.5, 50.0]:
            for phi in ([0.0] if rho == 0.0 else [0.0, 0.5 * math.pi, 0.6, 2.3]):
                xa = [0.3 + rho * math.cos(phi), -0.2 + rho * math.sin(phi), ha]
                xb = [0.3, -0.2, hb]
                dist = math.sqrt(rho**2 + (ha - hb) ** 2)
                if dist < 2.0:
                    continue  # overlapping spheres
                out.append((xa, xb))
    return out


# ----------------------------------------------------------------------------------
# 4. Projection onto the symmetric traceless basis of docs/conventions.md
# ----------------------------------------------------------------------------------
S2, S6 = 1 / math.sqrt(2), 1 / math.sqrt(6)
BASIS = np.zeros((5, 3, 3))
BASIS[0][0, 1] = BASIS[0][1, 0] = S2
BASIS[1][0, 2] = BASIS[1][2, 0] = S2
BASIS[2][1, 2] = BASIS[2][2, 1] = S2
BASIS[3][0, 0], BASIS[3][1, 1] = S2, -S2
BASIS[4][2, 2], BASIS[4][0, 0], BASIS[4][1, 1] = 2 * S6, -S6, -S6


def project(name, t):
    if name in ("EF", "EL"):
        return np.einsum("apq,pqj->aj", BASIS, t)
    if name == "ES":
        return np.einsum("apq,pqkl,bkl->ab", BASIS, t, BASIS)
    return t


def to_np(x):
    return np.vectorize(float)(np.array(x, dtype=object))


def rel(a, b):
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


# ----------------------------------------------------------------------------------
# 5. Independent cross-check of the operator calculus: literal Eq. 5 in (x, y),
#    differentiated numerically (mpmath.diff, 50 digits).
# ----------------------------------------------------------------------------------
def literal_crosscheck():
    xs, ys, zs = sp.symbols("x1:4"), sp.symbols("y1:4"), sp.symbols("z1:4")
    r = [xs[i] - zs[i] for i in R3]
    rn = sp.sqrt(sum(v**2 for v in r))
    J = [[(1 if i == j else 0) / rn + r[i] * r[j] / rn**3 for j in R3] for i in R3]
    h = ys[2]
    yprime = {zs[0]: ys[0], zs[1]: ys[1], zs[2]: -ys[2]}
    Pm = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]
    jw = [[(-J[i][l]
            + h**2 * sum(sum(sp.diff(J[i][k], zs[m], 2) for m in R3) * Pm[k][l] for k in R3)
            + 2 * h * sum(Pm[l][k] * sp.diff(J[i][2], zs[k]) for k in R3)).subs(yprime)
           for l in R3] for i in R3]
    jfree = [[J[i][l].subs({zs[0]: ys[0], zs[1]: ys[1], zs[2]: ys[2]}) for l in R3] for i in R3]
    fw = [[sp.lambdify(xs + ys, jw[i][l], "mpmath") for l in R3] for i in R3]
    f0 = [[sp.lambdify(xs + ys, jfree[i][l], "mpmath") for l in R3] for i in R3]
    old = mp.mp.dps
    mp.mp.dps = 50
    # (a) no-slip: J + Jw = 0 on the wall, also for source derivatives (Eq. 11)
    noslip = 0.0
    for pt in ([0.3, 1.2, 0, 2.1, -0.7, 1.7], [-4.0, 0.5, 0, 0.0, 0.0, 1.0001]):
        pt = [mp.mpf(v) for v in pt]
        for i in R3:
            for l in R3:
                for orders in [(0, 0, 0, 0, 0, 0), (0, 0, 0, 0, 0, 1), (0, 0, 0, 1, 0, 1), (0, 0, 0, 0, 0, 2)]:
                    v = mp.diff(lambda *a: f0[i][l](*a) + fw[i][l](*a), pt, orders)
                    noslip = max(noslip, abs(float(v)))
    # (b) mixed partials d_x^a d_y^b Jw_il from the operator calculus vs literal
    rng = np.random.default_rng(7)
    worst = 0.0
    count = 0
    for xa, xb in ([[0.3, 1.2, 2.5], [2.1, -0.7, 1.7]], [[0.0, 0.0, 1.3], [0.0, 0.0, 1.3]]):
        pt = [mp.mpf(v) for v in xa + xb]
        rv = [pt[0] - pt[3], pt[1] - pt[4], pt[2] + pt[5]]
        for _ in range(40):
            i, l = int(rng.integers(3)), int(rng.integers(3))
            ox = [0, 0, 0]
            oy = [0, 0, 0]
            for _ in range(int(rng.integers(4))):
                ox[int(rng.integers(3))] += 1
            for _ in range(int(rng.integers(4))):
                oy[int(rng.integers(3))] += 1
            e = G[i][l]
            for k in R3:
                for _ in range(ox[k]):
                    e = dx(e, k)
                for _ in range(oy[k]):
                    e = dy(e, k)
            ours = _evaluate({"x": to_terms(e)}, rv, pt[5])["x"] * 4 / 3
            lit = mp.diff(lambda *a: fw[i][l](*a), pt, tuple(ox + oy))
            worst = max(worst, float(abs(ours - lit) / max(abs(lit), mp.mpf(10) ** -20)))
            count += 1
    mp.mp.dps = old
    return noslip, worst, count


# ----------------------------------------------------------------------------------
# 6. Optional: exact coefficients of the printed tensor structures (C5, C6, C7)
# ----------------------------------------------------------------------------------
def exact_coefficients():
    Rr, hh, cc = sp.symbols("R hhat e3")

    def pyth(t):  # rational point on the unit circle: e = (s, 0, c)
        t = sp.Rational(t)
        return 2 * t / (1 + t**2), (1 - t**2) / (1 + t**2)

    def exact_block(name, s_, c_):
        cache = {}

        def dr(a):
            if a not in cache:
                cache[a] = Rr ** (1 - sum(a)) * sum(int(cf) * s_ ** m[0] * 0 ** m[1] * c_ ** m[2]
                                                     for m, cf in p_alpha(a).terms())
            return cache[a]

        def ev(t):
            if isinstance(t, list):
                return [ev(v) for v in t]
            return sp.expand(sp.Rational(3, 4) * sum(cf * (hh * Rr * c_) ** pw * dr(a) for a, pw, cf in t))

        return ev(TERMS[name])

    I1 = lambda i, j: 1 if i == j else 0  # noqa: E731

    def st5(e):
        d = I1
        S = [lambda i, j, k: d(i, Z) * d(j, Z) * d(k, Z), lambda i, j, k: d(i, Z) * d(j, Z) * e[k],
             lambda i, j, k: d(i, j) * d(k, Z), lambda i, j, k: d(i, k) * d(j, Z) + d(i, Z) * d(j, k),
             lambda i, j, k: d(j, Z) * e[i] * e[k] + d(i, Z) * e[j] * e[k],
             lambda i, j, k: e[i] * d(j, Z) * d(k, Z) + e[j] * d(i, Z) * d(k, Z),
             lambda i, j, k: e[i] * d(j, k) + e[j] * d(i, k), lambda i, j, k: e[i] * e[j] * d(k, Z),
             lambda i, j, k: d(i, j) * e[k], lambda i, j, k: e[i] * e[j] * e[k]]
        return [[[[f(i, j, k) for k in R3] for j in R3] for i in R3] for f in S]

    def st6(e):
        d = I1
        ee = lambda i, k: sum(eps_i(i, k, l) * e[l] for l in R3)  # noqa: E731
        e3k = lambda k: sum(eps_i(Z, k, l) * e[l] for l in R3)  # noqa: E731
        S = [lambda i, j, k: e[j] * ee(i, k) + e[i] * ee(j, k),
             lambda i, j, k: d(j, Z) * eps_i(Z, i, k) + d(i, Z) * eps_i(Z, j, k),
             lambda i, j, k: e[i] * d(j, Z) * e3k(k) + d(i, Z) * e[j] * e3k(k),
             lambda i, j, k: e[j] * eps_i(Z, i, k) + e[i] * eps_i(Z, j, k),
             lambda i, j, k: d(i, j) * e3k(k), lambda i, j, k: e[i] * e[j] * e3k(k)]
        return [[[[f(i, j, k) for k in R3] for j in R3] for i in R3] for f in S]

    def st7(e):
        d = I1
        S = [lambda i, j, k, l: d(i, Z) * d(j, Z) * d(k, l),
             lambda i, j, k, l: d(i, Z) * d(j, Z) * e[k] * d(l, Z) + d(i, Z) * d(j, Z) * d(k, Z) * e[l],
             lambda i, j, k, l: (e[i] * d(j, Z) * d(k, l) + d(i, Z) * e[j] * d(k, l) + d(i, l) * d(j, Z) * e[k]
                                 + d(i, Z) * d(j, l) * e[k] + d(i, Z) * d(j, k) * e[l] + d(i, k) * d(j, Z) * e[l]),
             lambda i, j, k, l: (d(i, k) * d(j, Z) * d(l, Z) + d(i, l) * d(j, Z) * d(k, Z)
                                 + d(i, Z) * d(j, k) * d(l, Z) + d(i, Z) * d(j, l) * d(k, Z)),
             lambda i, j, k, l: d(i, l) * d(j, k) + d(i, k) * d(j, l),
             lambda i, j, k, l: d(i, j) * d(k, l),
             lambda i, j, k, l: d(i, Z) * d(j, Z) * d(k, Z) * d(l, Z),
             lambda i, j, k, l: d(i, j) * d(k, Z) * d(l, Z),
             lambda i, j, k, l: e[i] * d(j, Z) * d(k, Z) * d(l, Z) + d(i, Z) * e[j] * d(k, Z) * d(l, Z),
             lambda i, j, k, l: (e[i] * d(j, k) * d(l, Z) + e[i] * d(j, l) * d(k, Z)
                                 + d(i, k) * e[j] * d(l, Z) + d(i, l) * e[j] * d(k, Z)),
             lambda i, j, k, l: e[i] * e[j] * d(k, l) + d(i, j) * e[k] * e[l],
             lambda i, j, k, l: e[i] * e[j] * d(k, Z) * d(l, Z),
             lambda i, j, k, l: d(i, j) * e[k] * d(l, Z) + d(i, j) * d(k, Z) * e[l],
             lambda i, j, k, l: e[i] * d(j, l) * e[k] + d(i, l) * e[j] * e[k] + e[i] * d(j, k) * e[l] + d(i, k) * e[j] * e[l],
             lambda i, j, k, l: (e[i] * d(j, Z) * e[k] * d(l, Z) + d(i, Z) * e[j] * e[k] * d(l, Z)
                                 + e[i] * d(j, Z) * d(k, Z) * e[l] + d(i, Z) * e[j] * d(k, Z) * e[l]),
             lambda i, j, k, l: e[i] * e[j] * e[k] * d(l, Z) + e[i] * e[j] * d(k, Z) * e[l],
             lambda i, j, k, l: d(i, Z) * d(j, Z) * e[k] * e[l],
             lambda i, j, k, l: d(i, Z) * e[j] * e[k] * e[l] + e[i] * d(j, Z) * e[k] * e[l],
             lambda i, j, k, l: e[i] * e[j] * e[k] * e[l]]
        return [[[[[f(i, j, k, l) for l in R3] for k in R3] for j in R3] for i in R3] for f in S]

    def coeffs(name, structs, tvals):
        res = []
        for t in tvals:
            s_, c_ = pyth(t)
            e = [s_, 0, c_]
            A = sp.Matrix([list(sp.flatten(S)) for S in structs(e)]).T
            b = sp.Matrix(list(sp.flatten(exact_block(name, s_, c_))))
            x = (A.T * A).LUsolve(A.T * b)
            assert all(sp.expand(v) == 0 for v in A * x - b), name + ": not in the span of the printed structures"
            res.append((c_, [sp.expand(v) for v in x]))
        out = []
        for q in range(len(res[0][1])):
            pts = {}
            for c_, x in res:
                for mon, cf in sp.Poly(sp.expand(x[q] * Rr**12), Rr, hh).terms():
                    pts.setdefault(mon, {})[c_] = cf
            expr = 0
            for mon, vals in pts.items():
                lst = [(c_, vals.get(c_, 0)) for c_, _ in res]
                poly = sp.interpolate(lst[:-1], cc)
                assert sp.expand(poly.subs(cc, lst[-1][0]) - lst[-1][1]) == 0
                expr += poly * Rr ** (mon[0] - 12) * hh ** mon[1]
            out.append(sp.expand(expr))
        return out

    tv = [sp.Rational(n, 13) for n in range(1, 11)]
    print("\nExact coefficients of the printed structures (derived; e3 = R_3/R, hhat = h_b/R_3):")
    for name, st, labels in (("EF", st5, "A B C D E F G H I J".split()),
                             ("EL", st6, "A B C D E F".split()),
                             ("ES", st7, ["T%d" % n for n in range(1, 20)])):
        t0 = time.time()
        co = coeffs(name, st, tv)
        print("  %s (%.0f s):" % (name, time.time() - t0))
        for lab, c in zip(labels, co):
            print("    %-3s = %s" % (lab, sp.collect(c, Rr)))


# ----------------------------------------------------------------------------------
# 7. Main
# ----------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dump", metavar="FILE")
    ap.add_argument("--coefficients", action="store_true")
    args = ap.parse_args()
    print("Swan & Brady (2007) Appendices B, C: printed vs derived (sympy)")
    print("operator derivation built in %.1f s" % T_DERIVED)

    # --- cross-checks of the derivation itself
    t0 = time.time()
    noslip, worst, count = literal_crosscheck()
    print("\nDerivation checks:")
    print("  no-slip on the wall, J + Jw and its y-derivatives (orders 0..2): max |.| = %.1e" % noslip)
    print("  operator calculus vs literal Eq. 5 differentiated by mpmath.diff, %d mixed partials"
          " d_x^a d_y^b Jw (|a|,|b| <= 3): max rel. diff = %.1e   (%.1f s)" % (count, worst, time.time() - t0))
    # symmetry / reciprocity
    sym = 0.0
    for h in (1.0001, 2.0):
        b = {k: to_np(v) for k, v in derived_self(h).items()}
        sym = max(sym, np.abs(b["UF"] - b["UF"].T).max(), np.abs(b["OL"] - b["OL"].T).max(),
                  np.abs(b["UL"] - b["OF"].T).max(),
                  np.abs(b["ES"] - b["ES"].transpose(2, 3, 0, 1)).max())
        if h == 2.0:
            print("  self, h = 2: OF[y][x] = %+.6f (rolling: must be > 0), UL[x][y] = %+.6f (torque +y -> +x)"
                  % (b["OF"][1, 0], b["UL"][0, 1]))
    tr = 0.0
    for xa, xb in ([[0.3, 1.2, 2.5], [2.1, -0.7, 1.7]], [[0.0, 0.0, 1.2], [4.0, 3.0, 6.0]]):
        ab = {k: to_np(v) for k, v in derived_pair(xa, xb).items()}
        ba = {k: to_np(v) for k, v in derived_pair(xb, xa).items()}
        sym = max(sym, np.abs(ab["UF"] - ba["UF"].T).max(), np.abs(ab["OL"] - ba["OL"].T).max(),
                  np.abs(ab["UL"] - ba["OF"].T).max(),
                  np.abs(ab["ES"] - ba["ES"].transpose(2, 3, 0, 1)).max())
        tr = max(tr, np.abs(np.einsum("ppj->j", ab["EF"])).max(), np.abs(np.einsum("ppn->n", ab["EL"])).max(),
                 np.abs(np.einsum("ppkl->kl", ab["ES"])).max(), np.abs(np.einsum("pqkk->pq", ab["ES"])).max())
    print("  reciprocity M^ab = (M^ba)^T for UF, OL, UL/OF, ES (self and pairs): max |diff| = %.1e" % sym)
    print("  derived EF, EL, ES traceless in pq and in kl: max |trace| = %.1e" % tr)

    # --- comparisons
    cfgs = pair_configs()
    print("\nConfigurations: %d self heights %s; %d pairs (heights 1.0001..20, lateral 0..50,"
          " directions 0, 90, 34.4, 131.8 deg)" % (len(SELF_HEIGHTS), SELF_HEIGHTS, len(cfgs)))
    dump = open(args.dump, "w") if args.dump else None
    worst = {}

    def record(eq, name, printed, fixed, derived, where):
        for tag in ("full", "proj"):
            dv = project(name, derived) if tag == "proj" else derived
            r0 = rel(project(name, printed) if tag == "proj" else printed, dv)
            r1 = rel(project(name, fixed) if tag == "proj" else fixed, dv)
            w = worst.setdefault((eq, tag), [-1.0, "", -1.0, ""])
            if r0 > w[0]:
                w[0], w[1] = r0, where
            if r1 > w[2]:
                w[2], w[3] = r1, where

    t0 = time.time()
    for h in SELF_HEIGHTS:
        b = derived_self(h)
        for eq, name, fn in SELF_EQS:
            dv = to_np(b[name])
            record(eq, name, fn(h), fn(h, fix=True), dv, "h=%g" % h)
            if dump:
                dump.write("self %r %s %s\n" % (h, name, " ".join(repr(float(v)) for v in dv.ravel())))
    store = []
    for xa, xb in cfgs:
        b = derived_pair(xa, xb)
        where = "xa=(%.4g,%.4g,%.4g) xb=(%.4g,%.4g,%.4g)" % tuple(xa + xb)
        store.append((xa, xb, {}))
        for eq, name, fn in PAIR_EQS:
            dv = to_np(b[name])
            store[-1][2][name] = dv
            record(eq, name, fn(xa, xb), fn(xa, xb, fix=True), dv, where)
            if dump:
                dump.write("pair %s %s %s\n" % (" ".join(repr(v) for v in xa + xb), name,
                                                " ".join(repr(float(v)) for v in dv.ravel())))
    if dump:
        dump.close()
    print("evaluated in %.1f s\n" % (time.time() - t0))
    print("max relative deviation |M - M_derived|_F / |M_derived|_F over all configurations")
    print("(full = Cartesian tensor as indexed in paper.rs; proj = strain/stresslet pairs projected"
          " on the 5 symmetric traceless basis tensors)")
    print("%-4s %-3s %-5s %12s %12s   worst printed case" % ("eq", "blk", "form", "printed", "corrected"))
    for eq, name, _ in SELF_EQS + PAIR_EQS:
        for tag in ("full", "proj"):
            if tag == "proj" and name not in ("EF", "EL", "ES"):
                continue
            r0, w0, r1, w1 = worst[(eq, tag)]
            print("%-4s %-3s %-5s %12.3e %12.3e   %s" % (eq, name, tag, r0, r1, w0))

    # each erratum of a multi-erratum equation is necessary: all corrections but that one
    print("\nLeave-one-out: max full-Cartesian deviation with every correction of the equation"
          " applied except the one named")
    for label, eq in ERRATA.items():
        if eq not in ("C5", "C6", "C7"):
            continue
        name, fn = [(n, f) for e, n, f in PAIR_EQS if e == eq][0]
        others = set(ERRATA) - {label}
        r = max(rel(fn(xa, xb, fix=others), dvs[name]) for xa, xb, dvs in store)
        print("  %-4s without %-20s %10.3e" % (eq, "'" + label + "'", r))

    # exact closed forms of the self blocks (for the record)
    print("\nDerived self terms (exact, h = height/a), one representative component each:")
    for name, idx in (("UF", (0, 0)), ("UF", (2, 2)), ("OF", (1, 0)), ("OL", (0, 0)), ("OL", (2, 2)),
                      ("EF", (0, 2, 0)), ("EF", (0, 0, 2)), ("EF", (2, 2, 2)), ("EL", (0, 2, 1)),
                      ("ES", (0, 1, 0, 1)), ("ES", (0, 2, 0, 2)), ("ES", (2, 2, 2, 2))):
        v, hh = derived_self_symbolic(name, idx)
        print("  %s%s = %s" % (name, "".join(str(i + 1) for i in idx), sp.collect(sp.expand(v), hh)))

    if args.coefficients:
        exact_coefficients()
    print("\ntotal runtime %.1f s" % (time.time() - T_START))


if __name__ == "__main__":
    sys.exit(main())
