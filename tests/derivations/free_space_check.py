#!/usr/bin/env python3
"""Free-space far-field grand mobility of two spheres of unequal radii: an independent check.

Derives every pair block M^{ab} (sphere a, radius aa, at xa; sphere b, radius ab, at xb;
r = xa - xb; viscosity eta) from its definition by symbolic differentiation (sympy) of the
Oseen tensor

    G_ij(x, y) = J_ij(x - y),   J_ij(r) = (delta_ij/r + r_i r_j/r^3) / (8 pi eta),

and compares it with the closed forms that tests/src/closed_forms.rs implements (transcribed
here once more, in `closed_core` below). The definitions (d/dx at x = xa, d/dy at y = xb,
Lap = Laplacian, eps right-handed, eps_123 = +1):

    UF_ij   = (1 + aa^2/6 Lap_x)(1 + ab^2/6 Lap_y) G_ij
    UL_im   = (1 + aa^2/6 Lap_x) V_im,                V_im  = 1/2 eps_mkj d/dy_k G_ij
    US_ikl  = (1 + aa^2/6 Lap_x)(1 + ab^2/10 Lap_y) W_ikl,  W_ikl = 1/2 (d/dy_k G_il + d/dy_l G_ik)
    OF_mj   = 1/2 eps_mki d/dx_k (1 + ab^2/6 Lap_y) G_ij
    OL_mn   = 1/2 eps_mki d/dx_k V_in
    OS_mkl  = 1/2 eps_mpi d/dx_p (1 + ab^2/10 Lap_y) W_ikl
    EF_pqj  = 1/2 (d/dx_p G_qj + d/dx_q G_pj) with (1 + aa^2/10 Lap_x)(1 + ab^2/6 Lap_y)
    EL_pqm  = 1/2 (d/dx_p V_qm + d/dx_q V_pm) with (1 + aa^2/10 Lap_x)
    ES_pqkl = 1/2 (d/dx_p W_qkl + d/dx_q W_pkl) with (1 + aa^2/10 Lap_x)(1 + ab^2/10 Lap_y)

Every operator is a polynomial in the partial derivatives; since G depends on x - y only,
d/dx_k = d/dr_k and d/dy_k = -d/dr_k, so each block entry is a sum of coefficients (in aa, ab)
times partial derivatives of J_ij in r. Those are taken symbolically, cached by multi-index,
as polynomials in (r1, r2, r3, u = 1/|r|) with du/dr_k = -r_k u^3 (chain rule).

Checks, all printed:
  0. a few 6th-order derivatives of J from the u-representation against sympy's own
     differentiation of the sqrt expression (exact values, 40 digits);
  1. exact, for all r != 0 and symbolic aa, ab: derived - closed form, a polynomial in
     (r1, r2, r3, u, aa, ab), reduces to 0 modulo u^2 (r1^2 + r2^2 + r3^2) - 1 (a single
     polynomial is its own Groebner basis, so the remainder is canonical); likewise the trace
     parts US_ikk, OS_mkk, EF_ppj, EL_ppm, ES_ppkl, ES_pqkk;
  2. numeric: at N random configurations (|r| log-uniform in [2.01, 1000] x max(aa, ab),
     radius ratio max/min uniform in [1, 10], larger radius log-uniform in [0.1, 10], random
     direction, eta log-uniform in [0.1, 10]), the derivation and the closed forms are
     evaluated with mpmath at 50 digits and the max relative deviation (Frobenius norm over
     the block) is printed per block; a float64 evaluation of the closed forms is compared
     too (this measures the conditioning of the closed forms in double precision);
  3. the fixed configuration r = (1.3, -2.1, 0.7), aa = 1.0, ab = 0.4, eta = 0.9 (the exact
     binary64 values of these decimal literals): every block's entries from the symbolic
     derivation, to 17 significant digits, printed as Rust constants indexed like the arrays
     of tests/src/closed_forms.rs (UF[i][j], UL[i][m], US[i][k][l], OF[m][j], OL[m][n],
     OS[m][k][l], EF[p][q][j], EL[p][q][m], ES[p][q][k][l]).

Usage:
    python3 tests/derivations/free_space_check.py                # all checks (~30 s)
    python3 tests/derivations/free_space_check.py --samples 1000 # more random configs (~80 s)
    python3 tests/derivations/free_space_check.py --dump FILE   # also write the random
        configurations and their 50-digit reference entries (one JSON object per line)
"""

import argparse
import itertools
import json
import math
import random
import time

import mpmath
import sympy as sp

BLOCKS = ["UF", "UL", "US", "OF", "OL", "OS", "EF", "EL", "ES"]
SHAPES = {
    "UF": (3, 3), "UL": (3, 3), "US": (3, 3, 3),
    "OF": (3, 3), "OL": (3, 3), "OS": (3, 3, 3),
    "EF": (3, 3, 3), "EL": (3, 3, 3), "ES": (3, 3, 3, 3),
}
IDX = (0, 1, 2)


def delta(i, j):
    return 1 if i == j else 0


def eps(i, j, k):
    return (i - j) * (j - k) * (k - i) // 2  # right-handed, eps(0,1,2) = +1


# ---------------------------------------------------------------------------------------------
# 1. Symbolic derivation from the definitions
# ---------------------------------------------------------------------------------------------
#
# J_ij = C (delta_ij u + r_i r_j u^3) with u = 1/|r| and C = 1/(8 pi eta). Every derivative of
# J is a polynomial in (r1, r2, r3, u): d/dr_k acts as the partial derivative in r_k plus
# (du/dr_k = -r_k u^3) times the partial derivative in u (chain rule). Entries are kept as
# polynomials in (r1, r2, r3, u, aa, ab) over the rationals; C is a common factor.

R1, R2, R3, U, AA, AB = GENS = sp.symbols("r1 r2 r3 u a_a a_b")
RV = (R1, R2, R3)
D1, D2, D3 = DV = sp.symbols("d1 d2 d3")  # d/dr_k, as commuting symbols of an operator


def poly(expr):
    return sp.Poly(expr, *GENS, domain="QQ")


ZERO = poly(0)
DU = [poly(-RV[k] * U**3) for k in IDX]  # du/dr_k
JP = [[poly(delta(i, j) * U + RV[i] * RV[j] * U**3) for j in IDX] for i in IDX]  # J_ij / C
# the only relation among the generators: u^2 (r1^2 + r2^2 + r3^2) = 1
RELATION = poly(U**2 * (R1**2 + R2**2 + R3**2) - 1)

_dcache = {}


def ddr(p, k):
    """d/dr_k of a polynomial in (r1, r2, r3, u, aa, ab), u = 1/|r| (chain rule)."""
    return p.diff(RV[k]) + p.diff(U) * DU[k]


def dJ(i, j, alpha):
    """d^alpha J_ij / dr^alpha (over C), alpha = (n1, n2, n3); cached, one derivative at a time."""
    i, j = min(i, j), max(i, j)
    key = (i, j, alpha)
    if key not in _dcache:
        if sum(alpha) == 0:
            _dcache[key] = JP[i][j]
        else:
            k = next(n for n in IDX if alpha[n] > 0)
            lower = tuple(alpha[n] - (1 if n == k else 0) for n in IDX)
            _dcache[key] = ddr(dJ(i, j, lower), k)
    return _dcache[key]


def apply(op, i, j):
    """Apply the differential operator op (a polynomial in d1, d2, d3 with coefficients in aa,
    ab) to J_ij."""
    op = sp.expand(op)
    out = ZERO
    if op == 0:
        return out
    for m, c in sp.Poly(op, *DV).terms():
        out = out + poly(c) * dJ(i, j, m)
    return out


def derive_blocks():
    Dx = list(DV)                     # d/dx_k =  d/dr_k
    Dy = [-d for d in DV]             # d/dy_k = -d/dr_k
    lap = D1**2 + D2**2 + D3**2       # Lap_x = Lap_y = Lap_r
    fax_a6 = 1 + AA**2 / 6 * lap
    fax_b6 = 1 + AB**2 / 6 * lap
    fax_a10 = 1 + AA**2 / 10 * lap
    fax_b10 = 1 + AB**2 / 10 * lap
    half = sp.Rational(1, 2)

    def V(op, i, m):  # op V_im,  V_im = 1/2 eps_mkj d/dy_k G_ij
        out = ZERO
        for k in IDX:
            for jj in IDX:
                if eps(m, k, jj):
                    out = out + apply(op * half * eps(m, k, jj) * Dy[k], i, jj)
        return out

    def W(op, i, k, l):  # op W_ikl,  W_ikl = 1/2 (d/dy_k G_il + d/dy_l G_ik)
        return apply(op * half * Dy[k], i, l) + apply(op * half * Dy[l], i, k)

    def curl(m, f):  # 1/2 eps_mki d/dx_k acting on index i of f(op, i)
        out = ZERO
        for k in IDX:
            for i in IDX:
                if eps(m, k, i):
                    out = out + f(half * eps(m, k, i) * Dx[k], i)
        return out

    out = {}
    out["UF"] = [[apply(fax_a6 * fax_b6, i, j) for j in IDX] for i in IDX]
    out["UL"] = [[V(fax_a6, i, m) for m in IDX] for i in IDX]
    out["US"] = [[[W(fax_a6 * fax_b10, i, k, l) for l in IDX] for k in IDX] for i in IDX]
    out["OF"] = [[curl(m, lambda op, i, j=j: apply(op * fax_b6, i, j)) for j in IDX] for m in IDX]
    out["OL"] = [[curl(m, lambda op, i, n=n: V(op, i, n)) for n in IDX] for m in IDX]
    out["OS"] = [[[curl(m, lambda op, i, k=k, l=l: W(op * fax_b10, i, k, l))
                   for l in IDX] for k in IDX] for m in IDX]
    out["EF"] = [[[apply(half * Dx[p] * fax_a10 * fax_b6, q, j)
                   + apply(half * Dx[q] * fax_a10 * fax_b6, p, j)
                   for j in IDX] for q in IDX] for p in IDX]
    out["EL"] = [[[V(half * Dx[p] * fax_a10, q, m) + V(half * Dx[q] * fax_a10, p, m)
                   for m in IDX] for q in IDX] for p in IDX]
    out["ES"] = [[[[W(half * Dx[p] * fax_a10 * fax_b10, q, k, l)
                    + W(half * Dx[q] * fax_a10 * fax_b10, p, k, l)
                    for l in IDX] for k in IDX] for q in IDX] for p in IDX]
    return out


def reduce_rel(p):
    """Canonical remainder of p modulo u^2 |r|^2 - 1 (a single generator is a Groebner basis)."""
    _, rem = sp.reduced(p.as_expr(), [RELATION.as_expr()], *GENS, order="grevlex")
    return poly(rem)


# ---------------------------------------------------------------------------------------------
# 2. The closed forms (same formulas as tests/src/closed_forms.rs), generic in the number type
# ---------------------------------------------------------------------------------------------

def closed_core(e, ir, aa, ab, c, rat):
    """All nine blocks from the scalar mobility functions and e-based isotropic forms.

    e = r/|r|, ir = 1/|r|, c = 1/(8 pi eta), rat(n, d) = the rational n/d in the number type
    (float, mpmath.mpf, or sympy, so that the same code serves every check)."""
    s = aa**2 + ab**2
    ir2, ir3 = ir * ir, ir * ir * ir
    third = rat(1, 3)

    def ee(i, j):
        return e[i] * e[j]

    def eps_e(i, j):  # eps_ijk e_k
        return sum(eps(i, j, k) * e[k] for k in IDX)

    # UF: Rotne-Prager-Yamakawa, unequal radii
    xa = c * (2 * ir - rat(2, 3) * s * ir3)
    ya = c * (ir + rat(1, 3) * s * ir3)
    uf = [[xa * ee(i, j) + ya * (delta(i, j) - ee(i, j)) for j in IDX] for i in IDX]
    # UL, OF: rotlet coupling (no radius dependence)
    yb = c * ir2
    ul = [[yb * eps_e(i, m) for m in IDX] for i in IDX]
    of = [[yb * eps_e(m, j) for j in IDX] for m in IDX]
    # OL: rotlet-rotlet coupling
    xc = c * ir3
    yc = -rat(1, 2) * c * ir3
    ol = [[xc * ee(m, n) + yc * (delta(m, n) - ee(m, n)) for n in IDX] for m in IDX]
    # US: velocity of a due to stresslet on b
    tu = aa**2 + rat(3, 5) * ab**2
    xgu = c * (3 * ir2 - 3 * tu * ir2 * ir2)
    ygu = c * tu * ir2 * ir2
    us = [[[xgu * (ee(k, l) - delta(k, l) * third) * e[i]
            + ygu * (e[k] * delta(i, l) + e[l] * delta(i, k) - 2 * e[i] * ee(k, l))
            for l in IDX] for k in IDX] for i in IDX]
    # EF: strain of a due to force on b
    te = rat(3, 5) * aa**2 + ab**2
    xge = -c * (3 * ir2 - 3 * te * ir2 * ir2)
    yge = -c * te * ir2 * ir2
    ef = [[[xge * (ee(p, q) - delta(p, q) * third) * e[j]
            + yge * (e[p] * delta(q, j) + e[q] * delta(p, j) - 2 * ee(p, q) * e[j])
            for j in IDX] for q in IDX] for p in IDX]
    # EL, OS: strain due to torque / rotation due to stresslet (no radius dependence)
    yh = -rat(3, 2) * c * ir3
    el = [[[yh * (e[p] * eps_e(q, m) + e[q] * eps_e(p, m)) for m in IDX]
           for q in IDX] for p in IDX]
    os_ = [[[-yh * (eps_e(m, k) * e[l] + eps_e(m, l) * e[k]) for l in IDX]
            for k in IDX] for m in IDX]
    # ES: strain of a due to stresslet on b
    ir5 = ir3 * ir2
    xm = c * (-6 * ir3 + rat(36, 5) * s * ir5)
    ym = c * (3 * ir3 - rat(24, 5) * s * ir5)
    zm = c * rat(6, 5) * s * ir5

    def es_entry(p, q, k, l):
        four = (delta(p, k) * ee(q, l) + delta(p, l) * ee(q, k)
                + delta(q, k) * ee(p, l) + delta(q, l) * ee(p, k))
        e4 = ee(p, q) * ee(k, l)
        d0 = rat(3, 2) * (ee(p, q) - delta(p, q) * third) * (ee(k, l) - delta(k, l) * third)
        d1 = rat(1, 2) * (four - 4 * e4)
        d2 = rat(1, 2) * (delta(p, k) * delta(q, l) + delta(q, k) * delta(p, l)
                          - delta(p, q) * delta(k, l)
                          + ee(p, q) * delta(k, l) + delta(p, q) * ee(k, l) - four + e4)
        return xm * d0 + ym * d1 + zm * d2

    es = [[[[es_entry(p, q, k, l) for l in IDX] for k in IDX] for q in IDX] for p in IDX]
    return {"UF": uf, "UL": ul, "US": us, "OF": of, "OL": ol, "OS": os_,
            "EF": ef, "EL": el, "ES": es}


def closed_forms_f64(r, aa, ab, eta):
    rr = math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    return closed_core([x / rr for x in r], 1.0 / rr, aa, ab, 1.0 / (8.0 * math.pi * eta),
                       lambda n, d: n / d)


def closed_forms_mp(r, aa, ab, eta):
    rr = mpmath.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    return closed_core([x / rr for x in r], 1 / rr, aa, ab, 1 / (8 * mpmath.pi * eta),
                       lambda n, d: mpmath.mpf(n) / d)


# ---------------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------------

def entries(block, shape):
    """Flatten a nested list in row-major order."""
    out = []
    for ix in itertools.product(*[range(n) for n in shape]):
        v = block
        for i in ix:
            v = v[i]
        out.append(v)
    return out


def evaluator(p):
    """mpmath evaluator of a derived entry (a polynomial in r1, r2, r3, u, aa, ab, times C);
    takes the power table of `powers`."""
    terms = [(m, mpmath.mpf(int(c.p)) / int(c.q)) for m, c in p.terms()]

    def f(pw):
        tot = mpmath.mpf(0)
        for m, c in terms:
            t = c
            for tab, n in zip(pw[1], m):
                if n:
                    t *= tab[n]
            tot += t
        return tot * pw[0]
    return f


def powers(r, aa, ab, eta, top=16):
    """Powers 0..top of (r1, r2, r3, u = 1/|r|, aa, ab) and the factor C = 1/(8 pi eta)."""
    vals = (r[0], r[1], r[2], 1 / mpmath.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2), aa, ab)
    tabs = []
    for v in vals:
        t = [mpmath.mpf(1)]
        for _ in range(top):
            t.append(t[-1] * v)
        tabs.append(t)
    return 1 / (8 * mpmath.pi * eta), tabs


def rel_frobenius(a, b):
    num = mpmath.sqrt(sum((mpmath.mpf(x) - mpmath.mpf(y)) ** 2 for x, y in zip(a, b)))
    den = mpmath.sqrt(sum(mpmath.mpf(y) ** 2 for y in b))
    return num / den


def random_config(rng):
    ratio = rng.uniform(1.0, 10.0)
    big = 10.0 ** rng.uniform(-1.0, 1.0)
    aa, ab = (big, big / ratio) if rng.random() < 0.5 else (big / ratio, big)
    dist = max(aa, ab) * 10.0 ** rng.uniform(math.log10(2.01), 3.0)
    while True:
        v = [rng.gauss(0.0, 1.0) for _ in IDX]
        n = math.sqrt(sum(x * x for x in v))
        if n > 1e-3:
            break
    r = [dist * x / n for x in v]
    eta = 10.0 ** rng.uniform(-1.0, 1.0)
    return r, aa, ab, eta


def fmt17(x):
    if x == 0:
        return "0.0"
    s = mpmath.nstr(x, 17, min_fixed=1, max_fixed=0)
    return s if "e" in s else s + "e+0"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=200, help="random configurations (default 200)")
    ap.add_argument("--seed", type=int, default=20070101)
    ap.add_argument("--dump", metavar="FILE", help="write random configs + references (JSON lines)")
    args = ap.parse_args()
    mpmath.mp.dps = 50
    t0 = time.time()

    derived = derive_blocks()
    print(f"# symbolic derivation: {len(_dcache)} cached derivatives of J, {time.time() - t0:.1f} s")

    # -- 0. the chain-rule derivatives against sympy's own differentiation of sqrt ------------
    rs = sp.symbols("s1 s2 s3", real=True)
    rho = sp.sqrt(rs[0] ** 2 + rs[1] ** 2 + rs[2] ** 2)
    point = {rs[0]: sp.Rational(13, 10), rs[1]: sp.Rational(-21, 10), rs[2]: sp.Rational(7, 10)}
    worst0 = mpmath.mpf(0)
    for (i, j, alpha) in [(0, 0, (2, 2, 2)), (0, 1, (3, 1, 2)), (1, 2, (0, 1, 5)), (2, 2, (1, 4, 0)),
                          (0, 2, (6, 0, 0))]:
        direct = sp.diff(delta(i, j) / rho + rs[i] * rs[j] / rho**3, *[rs[k] for k in IDX
                                                                      for _ in range(alpha[k])])
        a = sp.N(direct.subs(point), 40)
        pv = dJ(i, j, alpha).as_expr().subs({R1: point[rs[0]], R2: point[rs[1]], R3: point[rs[2]],
                                              U: 1 / rho.subs(point)})
        worst0 = max(worst0, abs(mpmath.mpf(str(sp.N(pv, 40))) - mpmath.mpf(str(a)))
                     / abs(mpmath.mpf(str(a))))
    print(f"# 0. five 6th-order derivatives of J (u-chain rule vs sympy diff of sqrt): "
          f"max rel dev {mpmath.nstr(worst0, 3)}")

    # -- 1. exact check for all r: derived - closed form reduces to 0 modulo u^2 |r|^2 = 1 ------
    cf_sym = closed_core([R1 * U, R2 * U, R3 * U], U, AA, AB, 1, sp.Rational)
    print("# 1. exact, for all r != 0 and symbolic aa, ab: derived - closed form, reduced modulo "
          "u^2 |r|^2 = 1")
    for b in BLOCKS:
        bad = 0
        for d, c in zip(entries(derived[b], SHAPES[b]), entries(cf_sym[b], SHAPES[b])):
            if not reduce_rel(d - poly(c)).is_zero:
                bad += 1
        print(f"   {b}: {'identical' if bad == 0 else f'{bad} entries DIFFER'}")
    # trace parts: US_ikk, EF_ppj, ES_ppkl, ES_pqkk, OS_mkk, EL_ppm
    traces = {
        "US_ikk": [sum((derived["US"][i][k][k] for k in IDX), ZERO) for i in IDX],
        "OS_mkk": [sum((derived["OS"][m][k][k] for k in IDX), ZERO) for m in IDX],
        "EF_ppj": [sum((derived["EF"][p][p][j] for p in IDX), ZERO) for j in IDX],
        "EL_ppm": [sum((derived["EL"][p][p][m] for p in IDX), ZERO) for m in IDX],
        "ES_ppkl": [sum((derived["ES"][p][p][k][l] for p in IDX), ZERO) for k in IDX for l in IDX],
        "ES_pqkk": [sum((derived["ES"][p][q][k][k] for k in IDX), ZERO) for p in IDX for q in IDX],
    }
    print("   trace parts of the derived blocks (strain / stresslet pairs): " + ", ".join(
        f"{n} {'= 0' if all(reduce_rel(t).is_zero for t in ts) else '!= 0'}"
        for n, ts in traces.items()))

    # -- 2. numeric check at random configurations ----------------------------------------------
    top = max(max(m) for b in BLOCKS for x in entries(derived[b], SHAPES[b]) for m in x.monoms())
    assert top <= 16, top
    ev = {b: [evaluator(x) for x in entries(derived[b], SHAPES[b])] for b in BLOCKS}
    rng = random.Random(args.seed)
    worst_mp = {b: mpmath.mpf(0) for b in BLOCKS}
    worst_f64 = {b: 0.0 for b in BLOCKS}
    dump = open(args.dump, "w") if args.dump else None
    for _ in range(args.samples):
        r, aa, ab, eta = random_config(rng)
        rm = [mpmath.mpf(x) for x in r]  # exact binary64 values
        am, bm, em = mpmath.mpf(aa), mpmath.mpf(ab), mpmath.mpf(eta)
        cf_mp = closed_forms_mp(rm, am, bm, em)
        cf_64 = closed_forms_f64(r, aa, ab, eta)
        rec = {"r": r, "aa": aa, "ab": ab, "eta": eta}
        pw = powers(rm, am, bm, em)
        for b in BLOCKS:
            ref = [f(pw) for f in ev[b]]
            worst_mp[b] = max(worst_mp[b], rel_frobenius(entries(cf_mp[b], SHAPES[b]), ref))
            worst_f64[b] = max(worst_f64[b], float(rel_frobenius(entries(cf_64[b], SHAPES[b]), ref)))
            rec[b] = [mpmath.nstr(x, 25) for x in ref]
        if dump:
            dump.write(json.dumps(rec) + "\n")
    if dump:
        dump.close()
    print(f"# 2. {args.samples} random configurations: |r|/max(aa,ab) in [2.01, 1000], "
          "max/min radius in [1, 10]; max relative Frobenius deviation from the derivation")
    print("   block   closed form at 50 digits   closed form in float64")
    for b in BLOCKS:
        print(f"   {b}      {mpmath.nstr(worst_mp[b], 3):>12}               {worst_f64[b]:.2e}")

    # -- 3. fixed configuration, from the derivation ----------------------------------------------
    fixed = (1.3, -2.1, 0.7, 1.0, 0.4, 0.9)
    fx = [mpmath.mpf(x) for x in fixed]
    print("\n# 3. fixed configuration r = (1.3, -2.1, 0.7), aa = 1.0, ab = 0.4, eta = 0.9")
    print("#    (binary64 values of the literals), entries from the symbolic derivation,")
    print("#    17 significant digits, as Rust constants indexed like the closed_forms.rs arrays:")
    pw = powers(fx[:3], fx[3], fx[4], fx[5])
    for b in BLOCKS:
        shape = SHAPES[b]
        vals = [fmt17(f(pw)) for f in ev[b]]

        def nest(vs, sh):
            if len(sh) == 1:
                return "[" + ", ".join(vs) + "]"
            step = len(vs) // sh[0]
            return "[" + ", ".join(nest(vs[n * step:(n + 1) * step], sh[1:])
                                   for n in range(sh[0])) + "]"

        ty = "f64"
        for n in reversed(shape):
            ty = f"[{ty}; {n}]"
        print(f"pub const {b}: {ty} =\n    {nest(vals, shape)};")
    print(f"\n# total time {time.time() - t0:.1f} s")


if __name__ == "__main__":
    main()
