//! The generated RPY overlap corrections (`kernels::overlap_f`, `kernels::overlap_ft`)
//! added to the free-space pair kernel, against references independent of the
//! generator: a quadrature of the RPY definition for unequal and nested spheres, and
//! libMobility's equal-radius closed forms written out here.

use kernels::{overlap_along, overlap_f, overlap_ft, pair_f, pair_ft, BlocksFT, Confinement};
use std::f64::consts::PI;

type M3 = [[f64; 3]; 3];

/// `[v]_x`, the matrix of `w -> v x w`.
fn cross(v: [f64; 3]) -> M3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

/// Gauss-Legendre nodes and weights on `[-1, 1]` (Newton on `P_n`).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// The velocity at `y` (relative to the centre of a sphere of radius `a`, `eta = 1`)
/// per unit force spread uniformly over the sphere's surface: the Faxén-corrected
/// Stokeslet outside, the sphere's own uniform translation `F / (6 pi a)` inside.
fn force_shell(y: [f64; 3], a: f64) -> M3 {
    let d = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    if d < a {
        let s = 1.0 / (6.0 * PI * a);
        return std::array::from_fn(|i| std::array::from_fn(|j| if i == j { s } else { 0.0 }));
    }
    let (c1, c2) = (
        1.0 / d + a * a / (3.0 * d.powi(3)),
        1.0 / d - a * a / d.powi(3),
    );
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let iso = if i == j { c1 } else { 0.0 };
            (iso + c2 * y[i] * y[j] / (d * d)) / (8.0 * PI)
        })
    })
}

/// The velocity at `y` per unit torque spread over the sphere as `3 L x n / (8 pi a^3)`:
/// the rotlet `L x y / (8 pi |y|^3)` outside, the rigid rotation `L x y / (8 pi a^3)`
/// inside (as a matrix acting on `L`: `-[y]_x / (8 pi max(|y|, a)^3)`).
fn torque_shell(y: [f64; 3], a: f64) -> M3 {
    let d = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    let s = -1.0 / (8.0 * PI * d.max(a).powi(3));
    cross(y).map(|row| row.map(|v| s * v))
}

/// The RPY FT blocks of spheres `(xa, aa)`, `(xb, ab)` by their definition (`eta = 1`):
/// the surface average over sphere `a` of the field of `b`'s surface forces (velocity),
/// and `3 / (8 pi aa^3)` times the surface integral of `n x u` (angular velocity). In
/// spherical coordinates about the line of centres, the polar integral is split at the
/// circle where the spheres' surfaces cross (the field's kink): Gauss-Legendre on each
/// piece, the trapezoidal rule in the azimuth (periodic), so the quadrature converges
/// fast (1e-14 with 40 and 64 points).
fn quadrature(xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> [M3; 4] {
    let r: [f64; 3] = std::array::from_fn(|k| xa[k] - xb[k]);
    let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    let e3 = r.map(|v| v / len);
    let t = if e3[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let cr = |u: [f64; 3], v: [f64; 3]| -> [f64; 3] {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let e1 = cr(e3, t);
    let n1 = (e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]).sqrt();
    let e1 = e1.map(|v| v / n1);
    let e2 = cr(e3, e1);
    let mu0 = (ab * ab - len * len - aa * aa) / (2.0 * aa * len);
    let mut cuts = vec![-1.0];
    if mu0 > -1.0 && mu0 < 1.0 {
        cuts.push(mu0);
    }
    cuts.push(1.0);
    let nodes = gauss_legendre(40);
    let nphi = 64;
    let mut out = [[[0.0; 3]; 3]; 4];
    for w in cuts.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        for &(x, wx) in &nodes {
            let mu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
            let s = (1.0 - mu * mu).max(0.0).sqrt();
            for k in 0..nphi {
                let phi = 2.0 * PI * k as f64 / nphi as f64;
                let n: [f64; 3] = std::array::from_fn(|c| {
                    mu * e3[c] + s * (phi.cos() * e1[c] + phi.sin() * e2[c])
                });
                // the weight of the surface average
                let weight = wx * 0.5 * (hi - lo) / (2.0 * nphi as f64);
                let y: [f64; 3] = std::array::from_fn(|c| xa[c] + aa * n[c] - xb[c]);
                let (uf, ul) = (force_shell(y, ab), torque_shell(y, ab));
                // Omega = 3 / (8 pi aa^3) oint n x u dS = 3 / (2 aa) <n x u>
                let c = cross(n).map(|row| row.map(|v| v * 1.5 / aa));
                for i in 0..3 {
                    for j in 0..3 {
                        out[0][i][j] += weight * uf[i][j];
                        out[1][i][j] += weight * ul[i][j];
                        for m in 0..3 {
                            out[2][i][j] += weight * c[i][m] * uf[m][j];
                            out[3][i][j] += weight * c[i][m] * ul[m][j];
                        }
                    }
                }
            }
        }
    }
    out
}

/// The free-space pair kernel plus the correction: the RPY overlap form.
fn rpy(xa: [f64; 3], aa: f64, xb: [f64; 3], ab: f64) -> [M3; 4] {
    let far = pair_ft(&Confinement::Free, 1.0, xa, aa, xb, ab);
    let c = overlap_ft(xa, xb, aa, ab, 1.0);
    let add = |p: &M3, q: &M3| -> M3 {
        std::array::from_fn(|i| std::array::from_fn(|j| p[i][j] + q[i][j]))
    };
    [
        add(&far.uf, &c.uf),
        add(&far.ul, &c.ul),
        add(&far.of, &c.of),
        add(&far.ol, &c.ol),
    ]
}

/// The largest difference over the largest entry, block by block (a block that
/// vanishes measured against 1e-2 of the largest entry of all four: the kernels'
/// rounding is that of the far form they subtract, of the size of the largest blocks).
fn worst(a: &[M3; 4], b: &[M3; 4]) -> f64 {
    let largest = |m: &M3| m.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let all = b.iter().map(largest).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let scale = largest(q).max(1e-2 * all);
            let diff = p
                .iter()
                .flatten()
                .zip(q.iter().flatten())
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            diff / scale
        })
        .fold(0.0, f64::max)
}

const DIRECTION: [f64; 3] = [0.48, 0.6, 0.64];

fn at(r: f64) -> ([f64; 3], [f64; 3]) {
    let xa = [0.3, -0.2, 0.1];
    (xa, std::array::from_fn(|k| xa[k] - r * DIRECTION[k]))
}

/// Every block, overlapping and nested, equal and unequal radii, against the
/// quadrature of the definition. The quadrature converges to about 1e-14; the kernels
/// lose a few digits where the far form they subtract is large (`r` well below the
/// radii: 1/r^3 against order one), so 1e-11 of each block's largest entry.
#[test]
fn generated_forms_are_the_rpy_definition() {
    let cases = [
        (1.0, 1.0, 1.3),
        (1.0, 1.0, 0.4),
        (1.0, 0.6, 1.2),
        (0.6, 1.0, 1.2),
        (1.0, 0.5, 0.7),
        (0.5, 1.0, 0.7),
        (0.3, 1.0, 0.5),
        (1.0, 0.3, 0.5),
        (2.0, 0.7, 0.2),
    ];
    for (aa, ab, r) in cases {
        let (xa, xb) = at(r);
        let q = quadrature(xa, aa, xb, ab);
        let e = worst(&rpy(xa, aa, xb, ab), &q);
        assert!(e < 1e-11, "aa {aa}, ab {ab}, r {r}: {e:e}");
    }
}

/// The quadrature itself reproduces the far form (the free-space pair kernel) apart:
/// the reference is not a restatement of the overlap forms (same tolerance).
#[test]
fn quadrature_gives_the_far_form_apart() {
    for (aa, ab, r) in [(1.0, 1.0, 2.5), (1.0, 0.4, 1.6)] {
        let (xa, xb) = at(r);
        let f = pair_ft(&Confinement::Free, 1.0, xa, aa, xb, ab);
        let e = worst(&[f.uf, f.ul, f.of, f.ol], &quadrature(xa, aa, xb, ab));
        assert!(e < 1e-11, "{e:e}");
    }
}

/// libMobility's NBody closed forms at equal radii (units of `a`), written out:
/// `UF = [(1 - 9r/32) I + (3r/32) rr] / (6 pi eta a)`, `WT = [(1 - 27r/32 + 5r^3/64) I +
/// (9r/32 - 3r^3/64) rr] / (8 pi eta a^3)`, `UT = WF = (1/2)(1 - 3r/8) (. x r) / (8 pi
/// eta a^2)` (a torque on `b` turns `a` as a force does: `U_a = L x r`-like, sign
/// fixed by the far form at contact). Radius 0.7 and viscosity 1.3 check the units;
/// the entries are polynomials of order one, so 1e-13.
#[test]
fn equal_radii_are_libmobility_closed_forms() {
    let (a, eta) = (0.7, 1.3);
    for s in [0.2, 0.5, 1.0, 1.7, 1.99] {
        let (xa, xb) = at(s * a);
        let r: [f64; 3] = std::array::from_fn(|k| (xa[k] - xb[k]) / a);
        let rr: M3 = std::array::from_fn(|i| std::array::from_fn(|j| DIRECTION[i] * DIRECTION[j]));
        let id = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
        let uf: M3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                ((1.0 - 9.0 * s / 32.0) * id(i, j) + 3.0 * s / 32.0 * rr[i][j])
                    / (6.0 * PI * eta * a)
            })
        });
        let wt: M3 = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                ((1.0 - 27.0 * s / 32.0 + 5.0 * s.powi(3) / 64.0) * id(i, j)
                    + (9.0 * s / 32.0 - 3.0 * s.powi(3) / 64.0) * rr[i][j])
                    / (8.0 * PI * eta * a.powi(3))
            })
        });
        // Omega_a = c F x r: the matrix -c [r]_x
        let c = 0.5 * (1.0 - 3.0 * s / 8.0) / (8.0 * PI * eta * a * a);
        let ut: M3 = cross(r).map(|row| row.map(|v| -c * v));
        let far = pair_ft(&Confinement::Free, eta, xa, a, xb, a);
        let cor: BlocksFT = overlap_ft(xa, xb, a, a, eta);
        let sum = |p: &M3, q: &M3| -> M3 {
            std::array::from_fn(|i| std::array::from_fn(|j| p[i][j] + q[i][j]))
        };
        let got = [
            sum(&far.uf, &cor.uf),
            sum(&far.ul, &cor.ul),
            sum(&far.of, &cor.of),
            sum(&far.ol, &cor.ol),
        ];
        let e = worst(&got, &[uf, ut, ut, wt]);
        assert!(e < 1e-13, "r = {s} a: {e:e}");
        // the F kernel is the FT kernel's first block
        let f = overlap_f(xa, xb, a, a, eta).uf;
        let ff = pair_f(&Confinement::Free, eta, xa, a, xb, a).uf;
        let e = worst(&[sum(&ff, &f); 4], &[uf; 4]);
        assert!(e < 1e-13, "F, r = {s} a: {e:e}");
    }
}

/// The correction vanishes at contact (to rounding: 1e-13 of the far form's entries)
/// and the overlapping form meets the nested one at `r = |aa - ab|` (both branches of
/// the kernel on either side, 1e-9 apart over a step of 1e-10 in `r`: the forms' slopes
/// are of order one).
#[test]
fn continuous_at_contact_and_at_nesting() {
    for (aa, ab) in [(1.0, 1.0), (1.0, 0.45), (0.3, 1.7)] {
        let (xa, xb) = at(aa + ab);
        let f = pair_ft(&Confinement::Free, 1.0, xa, aa, xb, ab);
        let e = worst(&rpy(xa, aa, xb, ab), &[f.uf, f.ul, f.of, f.ol]);
        assert!(e < 1e-13, "contact {aa} {ab}: {e:e}");
        let d: f64 = (aa - ab).abs();
        if d > 0.0 {
            let (xa, xin) = at(d * (1.0 - 1e-10));
            let (_, xout) = at(d * (1.0 + 1e-10));
            let (p, q) = (rpy(xa, aa, xin, ab), rpy(xa, aa, xout, ab));
            let e = worst(&p, &q);
            assert!(e < 1e-9, "nesting {aa} {ab}: {e:e}");
        }
    }
}

/// Nested spheres: the smaller moves with the larger, `U = F / (6 pi eta a_max)`,
/// `Omega = L / (8 pi eta a_max^3)`, and the larger's rigid rotation carries the smaller
/// along: `U_small = L x r / (8 pi eta a_max^3)`, the reverse coupling zero (1e-13).
#[test]
fn nested_limit() {
    let (small, big, r) = (0.4, 1.5, 0.6);
    let (xa, xb) = at(r);
    for (aa, ab) in [(small, big), (big, small)] {
        let got = rpy(xa, aa, xb, ab);
        let id: M3 =
            std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }));
        let rv: [f64; 3] = std::array::from_fn(|k| xa[k] - xb[k]);
        let carried = cross(rv).map(|row| row.map(|v| -v / (8.0 * PI * big.powi(3))));
        let zero = [[0.0; 3]; 3];
        let (ul, of) = if aa < ab {
            (carried, zero)
        } else {
            (zero, carried)
        };
        let want = [
            id.map(|row| row.map(|v| v / (6.0 * PI * big))),
            ul,
            of,
            id.map(|row| row.map(|v| v / (8.0 * PI * big.powi(3)))),
        ];
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            for (x, y) in g.iter().flatten().zip(w.iter().flatten()) {
                assert!((x - y).abs() < 1e-13, "block {k}: {g:?} vs {w:?}");
            }
        }
    }
}

/// The corrections are divergence-free over the source position (what keeps the
/// Brownian drift of the divergence kernels exact): central differences of step
/// `h = 1e-5` leave below 1e-7, where the blocks' derivatives are of order
/// `1/r^4 > 1` (truncation `h^2 / r^5`, 1e-8 at `r = 0.4`; rounding `1e-16 / (h r^3)`).
#[test]
fn corrections_are_divergence_free() {
    let h = 1e-5;
    for (aa, ab, r) in [(1.0, 1.0, 1.2), (1.0, 0.5, 0.8), (0.3, 1.0, 0.4)] {
        let (xa, xb) = at(r);
        let mut div = [0.0; 6];
        for j in 0..3 {
            let moved = |s: f64| {
                let mut x = xb;
                x[j] += s * h;
                overlap_ft(xa, x, aa, ab, 1.0)
            };
            let (p, m) = (moved(1.0), moved(-1.0));
            for i in 0..3 {
                div[i] += (p.uf[i][j] - m.uf[i][j]) / (2.0 * h);
                div[3 + i] += (p.of[i][j] - m.of[i][j]) / (2.0 * h);
            }
        }
        assert!(div.iter().all(|v| v.abs() < 1e-7), "{aa} {ab} {r}: {div:?}");
    }
}

/// The derivative of the correction along a direction (the drift of an overlapping
/// sphere held on a boundary) against central differences of the correction kernel,
/// overlapping and nested, along an axis and along a direction of no symmetry; step and
/// tolerance as in [`corrections_are_divergence_free`].
#[test]
fn correction_along_a_direction_equals_finite_differences() {
    let h = 1e-5;
    for (aa, ab, r) in [(1.0, 1.0, 1.2), (1.0, 0.5, 0.8), (0.3, 1.0, 0.4)] {
        let (xa, xb) = at(r);
        for v in [[0.0, 0.0, 1.0], [0.48, -0.6, 0.64]] {
            let got = overlap_along(xa, xb, aa, ab, 1.0, v).a;
            let moved = |s: f64| {
                overlap_ft(
                    xa,
                    std::array::from_fn(|k| xb[k] + s * h * v[k]),
                    aa,
                    ab,
                    1.0,
                )
            };
            let (p, m) = (moved(1.0), moved(-1.0));
            let mut want = [0.0; 6];
            for j in 0..3 {
                for i in 0..3 {
                    want[i] += (p.uf[i][j] - m.uf[i][j]) / (2.0 * h) * v[j];
                    want[3 + i] += (p.of[i][j] - m.of[i][j]) / (2.0 * h) * v[j];
                }
            }
            let largest = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
            assert!(largest > 1e-3, "a derivative that can fail: {want:?}");
            assert!(
                got.iter().zip(&want).all(|(g, w)| (g - w).abs() < 1e-7),
                "{aa} {ab} {r} along {v:?}: {got:?} vs {want:?}"
            );
        }
    }
}
