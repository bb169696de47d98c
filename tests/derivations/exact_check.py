#!/usr/bin/env python3
"""Independent high-precision (mpmath) evaluation of the exact sphere-wall and
two-sphere resistance series implemented in double precision in tests/src/exact.rs.

Run:   python3 tests/derivations/exact_check.py [--quick | --tables]

  --quick    skip the slowest heights (h/a = 1.001, 1.0001) of the parallel problems
  --tables   print only the reference tables embedded in tests/tests/integration/references/exact.rs
             (MP_WALL, MP_PAIR, the JO84 coefficients), at the exact binary values of the
             f64 inputs (about 30 s)

Prints, for a set of heights / gaps, the values of every function of exact.rs computed
here in 40-digit arithmetic straight from the published formulas (no rewriting for
stability: the working precision absorbs the cancellations), so that the numbers
quoted in exact.rs and the tolerances of tests/tests/integration/references/exact.rs can be
checked.  Conventions: tests/src/exact.rs (wall z = 0, radius a, centre height h,
alpha = arccosh(h/a); two spheres: gap xi = r/a - 2, KK normalisation).

Independent checks done here (not by the Rust code):
  * the free-surface Brenner series and the Stimson-Jeffery series against the
    far-field two-sphere series of Jeffrey & Onishi (1984) (P, V recurrence for X^A,
    docs/lubrication.md, "The twin-multipole series"), exact rationals;
  * the rigid-wall and free-surface Jeffery rotation sums against an explicit
    image construction (azimuthal Stokes flow v(rho, z) e_phi: v cos(phi) is
    harmonic, so a rotating sphere is an x-dipole and Kelvin inversion gives the
    images; rigid plane = odd image, shear-free plane = even image);
  * convergence of the O'Neill / Dean & O'Neill tridiagonal truncations in N and the
    reciprocity F^r* = (4/3) T^t* between the two independent solves.
"""
import sys
from fractions import Fraction
from math import comb

import mpmath as mp

mp.mp.dps = 40


def alpha_of(h):
    return mp.acosh(mp.mpf(h))


# ---------------------------------------------------------------- axisymmetric series
def _series(h, bracket, tol=None):
    """(4/3) sinh(alpha) sum_n n(n+1)/((2n-1)(2n+3)) bracket(n, alpha)."""
    a = alpha_of(h)
    tol = tol or mp.mpf(10) ** (-mp.mp.dps + 2)
    s = mp.mpf(0)
    n = 1
    while True:
        t = mp.mpf(n * (n + 1)) / ((2 * n - 1) * (2 * n + 3)) * bracket(n, a)
        s += t
        if abs(t) < tol * abs(s) and n > 3:
            break
        n += 1
    return mp.mpf(4) / 3 * mp.sinh(a) * s, n


def brenner_wall(h):
    """Brenner (1961) eq. 2.19, rigid wall."""
    def br(n, a):
        m = 2 * n + 1
        return (2 * mp.sinh(m * a) + m * mp.sinh(2 * a)) / (
            4 * mp.sinh((n + mp.mpf(1) / 2) * a) ** 2 - m**2 * mp.sinh(a) ** 2) - 1
    return _series(h, br)


def brenner_free(h):
    """Brenner (1961), free (shear-free, flat) surface."""
    def br(n, a):
        m = 2 * n + 1
        return (4 * mp.cosh((n + mp.mpf(1) / 2) * a) ** 2 + m**2 * mp.sinh(a) ** 2) / (
            2 * mp.sinh(m * a) - m * mp.sinh(2 * a)) - 1
    return _series(h, br)


def stimson_jeffery(h):
    """Stimson & Jeffery (1926): two equal spheres, centres 2 h apart, translating
    together along the line of centres; drag on each / (6 pi mu a U)."""
    def br(n, a):
        m = 2 * n + 1
        return 1 - (4 * mp.sinh((n + mp.mpf(1) / 2) * a) ** 2 - m**2 * mp.sinh(a) ** 2) / (
            2 * mp.sinh(m * a) + m * mp.sinh(2 * a))
    return _series(h, br)


def jeffery_xc(h, sign=1):
    """sinh^3(alpha) sum_n sign^(n+1) csch^3(n alpha): sign=+1 rigid wall (Jeffery
    1915), sign=-1 shear-free plane."""
    a = alpha_of(h)
    s = mp.mpf(0)
    n = 1
    tol = mp.mpf(10) ** (-mp.mp.dps + 2)
    while True:
        t = (mp.sinh(a) / mp.sinh(n * a)) ** 3 * (sign ** (n + 1))
        s += t
        if abs(t) < tol * abs(s):
            break
        n += 1
    return s


def xc_images(h, sign, kmax=4000):
    """Independent check of jeffery_xc: images of x-dipoles (rotlets) between the
    sphere (centre h, radius 1) and the plane z = 0 (image factor -1 for a rigid
    plane: v = 0; +1 for a shear-free plane: dv/dz = 0).  Torque / (8 pi mu a^3 Omega)
    = total dipole strength inside the sphere / a^3.  A dipole p at z0 (below the
    sphere, distance d = h - z0 from its centre) has the zero-Dirichlet sphere image
    -p (a/d)^3 at h - a^2/d."""
    h = mp.mpf(h)
    total = mp.mpf(1)           # the sphere's own rotlet, strength a^3 Omega, at z = h
    p, z = mp.mpf(1), h
    for _ in range(kmax):
        pw, zw = -sign * p, -z  # plane image (rigid: -p)
        d = h - zw
        p, z = -pw / d**3, h - 1 / d
        total += p
        if abs(p) < mp.mpf(10) ** (-mp.mp.dps + 2):
            break
    return total


# ---------------------------------------------------------------- O'Neill / Dean & O'Neill
def _k(n, a):
    return (n + mp.mpf(1) / 2) * mp.coth((n + mp.mpf(1) / 2) * a) - mp.coth(a)


def _tridiag(a, N, rhs_fn):
    """Solve O'Neill's (1964) eq. 23 matrix for A_1..A_N (A_0 = A_{N+1} = 0)."""
    k = [_k(n, a) for n in range(0, N + 3)]
    lo, di, up, r = [], [], [], []
    for n in range(1, N + 1):
        ca = (2 * n - 1) * k[n - 1] - (2 * n - 3) * k[n]
        cb = (2 * n + 5) * k[n] - (2 * n + 3) * k[n + 1]
        lo.append(ca * mp.mpf(n - 1) / (2 * n - 1))
        di.append(-ca * mp.mpf(n) / (2 * n + 1) - cb * mp.mpf(n + 1) / (2 * n + 1))
        up.append(cb * mp.mpf(n + 2) / (2 * n + 3))
        r.append(rhs_fn(n))
    # Thomas algorithm
    for i in range(1, N):
        w = lo[i] / di[i - 1]
        di[i] -= w * up[i - 1]
        r[i] -= w * r[i - 1]
    x = [mp.mpf(0)] * N
    x[N - 1] = r[N - 1] / di[N - 1]
    for i in range(N - 2, -1, -1):
        x[i] = (r[i] - up[i] * x[i + 1]) / di[i]
    A = [mp.mpf(0)] + x + [mp.mpf(0), mp.mpf(0)]  # A[0] = 0, A[N+1] = 0
    return k, A


def _forces(a, N, k, A, Lterm):
    """Y (force) and T (torque) sums of O'Neill eqs. 26-27 / Dean & O'Neill;
    Lterm(n) = (extra C_n, extra E_n) of the rotation problem."""
    sh, ch = mp.sinh(a), mp.coth(a)
    sF = mp.mpf(0)
    sT = mp.mpf(0)
    for n in range(0, N + 1):
        An = A[n]
        Am = A[n - 1] if n >= 1 else mp.mpf(0)
        Ap = A[n + 1]
        Bn = (n - 1) * Am - (2 * n + 1) * An + (n + 2) * Ap if n >= 1 else mp.mpf(0)
        Dn = mp.mpf((n + 1) * (n + 2)) / 2 * Ap - mp.mpf((n - 1) * n) / 2 * Am
        Cn = 2 * k[n] * (An - mp.mpf(n + 2) / (2 * n + 3) * Ap - mp.mpf(n - 1) / (2 * n - 1) * Am) if n >= 1 else mp.mpf(0)
        En = -k[n] * (mp.mpf((n + 1) * (n + 2)) / (2 * n + 3) * Ap - mp.mpf((n - 1) * n) / (2 * n - 1) * Am)
        c_extra, e_extra = Lterm(n)
        if n >= 1:
            Cn += c_extra
        En += e_extra
        sF += En + n * (n + 1) * Cn
        e = mp.exp(-(2 * n + 1) * a)
        sT += (2 + e) * (2 * n * (n + 1) * An + n * (n + 1) * Cn * ch - (2 * n + 1 - ch) * En)
        sT += (2 - e) * (n * (n + 1) * Bn * ch - (2 * n + 1 - ch) * Dn)
    return sF, sT


def oneill_translation(h, N):
    """(Y^A_w, T^t*) from O'Neill (1964)."""
    a = alpha_of(h)
    s2 = mp.sqrt(2)

    def rhs(n):
        m = n + mp.mpf(1) / 2
        return s2 * (2 * mp.coth(m * a) - mp.coth((m - 1) * a) - mp.coth((m + 1) * a))

    k, A = _tridiag(a, N, rhs)

    def L(n):
        m = n + mp.mpf(1) / 2
        return mp.mpf(0), 2 * s2 * mp.exp(-m * a) / mp.sinh(m * a)

    sF, sT = _forces(a, N, k, A, L)
    ya = s2 / 6 * mp.sinh(a) * sF
    tt = mp.sinh(a) ** 2 / (12 * s2) * sT
    return ya, tt


def dean_oneill_rotation(h, N):
    """(F^r*, Y^C_w) from Dean & O'Neill (1963) as corrected by GCB (1967)."""
    a = alpha_of(h)
    s2 = mp.sqrt(2)
    sh = mp.sinh(a)

    def rhs(n):
        m = n + mp.mpf(1) / 2
        bracket = (2 * n + 1) ** 2 * (mp.exp(a) / (2 * n - 1) + mp.exp(-a) / (2 * n + 3)) / mp.sinh(m * a) \
            - (2 * n - 1) / mp.sinh((m - 1) * a) - (2 * n + 3) / mp.sinh((m + 1) * a)
        return -s2 * mp.exp(-m * a) / ((2 * n + 1) * sh) * bracket

    k, A = _tridiag(a, N, rhs)

    def Lfun(n):
        return -(1 / s2) * (mp.exp(-(n - mp.mpf(1) / 2) * a) / (2 * n - 1)
                            - mp.exp(-(n + mp.mpf(3) / 2) * a) / (2 * n + 3))

    def L(n):
        m = n + mp.mpf(1) / 2
        ln = Lfun(n)
        c = 4 * ln / (sh * mp.sinh(m * a))
        e = (s2 * (2 * n + 1) * mp.exp(-m * a) - ln / sh) / mp.sinh(m * a)
        return c, e

    sF, sT = _forces(a, N, k, A, L)
    fr = -s2 / 6 * sh**2 * sF
    yc = (mp.mpf(1) / 3) * (1 - sh**3 / (4 * s2) * sT)
    return fr, yc


def converged(fn, h, N0=40):
    a = float(alpha_of(h))
    N = max(N0, int(40 / a) + 20)
    v1 = fn(h, N)
    v2 = fn(h, 2 * N)
    err = max(abs(x - y) for x, y in zip(v1, v2))
    return v2, N, err


# ---------------------------------------------------------------- JO84 far-field X^A
def jo84_xa_coeffs(kmax):
    """sum_q P_{1,k-q,q} for lambda = 1 (exact rationals), k = 0..kmax: then
    X11A +- X12A = sum_k (+-1)^k c_k s^-k, s = r/a (KK normalisation)."""
    P, V = {}, {}

    def g(D, n, p, q):
        if p < 0 or q < 0:
            return Fraction(0)
        return D.get((n, p, q), Fraction(0))

    nmax = kmax + 2
    for n in range(1, nmax + 1):
        P[(n, 0, 0)] = Fraction(1 if n == 1 else 0)
        V[(n, 0, 0)] = Fraction(1 if n == 1 else 0)
    for tot in range(1, kmax + 1):        # p + q = tot
        for q in range(0, tot + 1):
            p = tot - q
            for n in range(1, nmax + 1):
                if q == 0:
                    P[(n, p, q)] = Fraction(0)
                    V[(n, p, q)] = Fraction(0)
                    continue
                sP = Fraction(0)
                sV = Fraction(0)
                for s in range(1, q + 1):
                    c = comb(n + s, n)
                    sP += c * (Fraction(n * (2 * n + 1) * (2 * n * s - n - s + 2), 2 * (n + 1) * (2 * s - 1) * (n + s)) * g(P, s, q - s, p - n + 1)
                               - Fraction(n * (2 * n - 1), 2 * (n + 1)) * g(P, s, q - s, p - n - 1)
                               - Fraction(n * (4 * n * n - 1), 2 * (n + 1) * (2 * s + 1)) * g(V, s, q - s - 2, p - n + 1))
                    sV += c * g(P, s, q - s, p - n - 1)
                P[(n, p, q)] = sP
                V[(n, p, q)] = sP - Fraction(2 * n, (n + 1) * (2 * n + 3)) * sV
    return [sum((g(P, 1, k - q, q) for q in range(k + 1)), Fraction(0)) for k in range(kmax + 1)]


def tables():
    """The reference tables embedded in tests/tests/integration/references/exact.rs, at the exact
    binary values of the f64 inputs (near contact the functions are ill-conditioned in h)."""
    mp.mp.dps = 50
    print("MP_WALL: (h/a, X^A_w, Y^A_w, T^t*, F^r*, Y^C_w, X^C_w)")
    for hf in [1.0001, 1.001, 1.01, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0, 30.0, 100.0]:
        h = mp.mpf(hf)
        (ya, tt), N, e1 = converged(oneill_translation, h)
        (fr, yc), _, e2 = converged(dean_oneill_rotation, h)
        xa, _ = brenner_wall(h)
        xc = jeffery_xc(h, 1)
        print(f"({hf}, {', '.join(mp.nstr(v, 20) for v in (xa, ya, tt, fr, yc, xc))}),  # doubling N changes < {mp.nstr(max(e1, e2), 2)}")
    print("MP_PAIR: (xi, X11A, X12A, X11C, X12C)")
    for xf in [1e-4, 1e-3, 0.01, 0.1, 1.0]:
        h = 1 + mp.mpf(xf) / 2
        sj, _ = stimson_jeffery(h)
        fr, _ = brenner_free(h)
        w, f = jeffery_xc(h, 1), jeffery_xc(h, -1)
        vals = ((sj + fr) / 2, (sj - fr) / 2, (w + f) / 2, (f - w) / 2)
        print(f"({xf}, {', '.join(mp.nstr(v, 20) for v in vals)}),")
    print("JO84 c_k (X11A +- X12A = sum_k (+-1)^k c_k rho^-k):", [str(c) for c in jo84_xa_coeffs(14)])
    mp.mp.dps = 40


def main():
    quick = "--quick" in sys.argv
    print("== X^A_w (Brenner 1961, rigid wall) ==")
    for h in ["1.0001", "1.001", "1.01", "1.1", "1.5", "2", "3", "10", "100"]:
        v, n = brenner_wall(h)
        print(f"h/a={h:>8}  X^A_w = {mp.nstr(v, 20)}   (terms to 1e-38: {n})")
    for eps in ["1e-4", "1e-5"]:
        e = mp.mpf(eps)
        v, _ = brenner_wall(1 + e)
        print(f"eps={eps}: X^A_w - 1/eps - ln(1/eps)/5 = {mp.nstr(v - 1 / e - mp.log(1 / e) / 5, 15)}")

    print("\n== X^C_w (Jeffery 1915) and image check ==")
    for h in ["1.0001", "1.01", "1.5", "3", "10"]:
        w = jeffery_xc(h, 1)
        f = jeffery_xc(h, -1)
        print(f"h/a={h:>8}  X^C_w = {mp.nstr(w, 20)}  images {mp.nstr(xc_images(h, 1), 20)}"
              f"   free: {mp.nstr(f, 20)}  images {mp.nstr(xc_images(h, -1), 20)}")

    print("\n== two spheres X^A (KK), r = 2h ==")
    cs = jo84_xa_coeffs(30 if quick else 60)
    for xi in ["1e-4", "1e-3", "0.01", "0.1", "1", "2", "6"]:
        h = 1 + mp.mpf(xi) / 2
        sj, _ = stimson_jeffery(h)
        fr, _ = brenner_free(h)
        x11, x12 = (sj + fr) / 2, (sj - fr) / 2
        line = f"xi={xi:>6}  SJ={mp.nstr(sj, 17)}  free={mp.nstr(fr, 17)}  X11A={mp.nstr(x11, 17)}  X12A={mp.nstr(x12, 17)}"
        s = 2 * h
        if s >= 4:
            jp = sum(mp.mpf(c.numerator) / c.denominator * s**-k for k, c in enumerate(cs))
            jm = sum(mp.mpf(c.numerator) / c.denominator * (-s)**-k for k, c in enumerate(cs))
            line += f"\n           JO84 far field: sum={mp.nstr(jp, 17)}  diff={mp.nstr(jm, 17)}"
        print(line)
    for xi in ["1e-5", "1e-6"]:
        x = mp.mpf(xi)
        h = 1 + x / 2
        sj, _ = stimson_jeffery(h)
        fr, _ = brenner_free(h)
        L = mp.log(1 / x)
        x11 = (sj + fr) / 2
        print(f"xi={xi}: SJ = {mp.nstr(sj, 12)};  free - 1/(2xi) - (9/20)L = {mp.nstr(fr - 1/(2*x) - mp.mpf(9)/20*L, 12)};"
              f"  X11A - 1/(4xi) - (9/40)L = {mp.nstr(x11 - 1/(4*x) - mp.mpf(9)/40*L, 12)}")

    print("\n== X^C two spheres ==")
    for xi in ["1e-4", "0.01", "1"]:
        h = 1 + mp.mpf(xi) / 2
        w, f = jeffery_xc(h, 1), jeffery_xc(h, -1)
        print(f"xi={xi}: X11C={mp.nstr((w + f) / 2, 17)}  X12C={mp.nstr((f - w) / 2, 17)}")

    print("\n== parallel translation (O'Neill 1964) and rotation (Dean & O'Neill 1963) ==")
    hs = ["10.0677", "3.7622", "1.5431", "1.1276", "1.0453", "1.005", "1.0032", "1.003202", "1.1", "2", "1.01"]
    if not quick:
        hs += ["1.001", "1.0001"]
    for h in hs:
        (ya, tt), N, e1 = converged(oneill_translation, h)
        (fr, yc), _, e2 = converged(dean_oneill_rotation, h)
        print(f"h/a={h:>9} N={N:5d}  Y^A_w={mp.nstr(ya, 16)}  T^t*={mp.nstr(tt, 16)}  F^r*={mp.nstr(fr, 16)}"
              f"  Y^C_w={mp.nstr(yc, 16)}  |F^r*-4/3T^t*|={mp.nstr(abs(fr - 4 * tt / 3), 3)}  dN={mp.nstr(max(e1, e2), 3)}")


if __name__ == "__main__":
    if "--tables" in sys.argv:
        tables()
    else:
        main()
