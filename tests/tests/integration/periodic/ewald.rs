//! The Ewald sums of a triply periodic box against references independent of them:
//! Hasimoto's self mobility of a sphere in a cubic box (J. Fluid Mech. 5, 317 (1959);
//! the coefficient 2.8372974794806 also in Yeh & Hummer, J. Phys. Chem. B 108, 15873
//! (2004), and Beenakker, J. Chem. Phys. 85, 1581 (1986)), and the sum over replicas of
//! the open RPY kernels (`kernels::pair_ft` of free space) with a Gaussian window,
//! extrapolated in the window's width; and the independence of the split parameter.

use kernels::{pair_ft, self_ft, BlocksFT, Confinement};
use std::f64::consts::PI;
use stokesian::periodic::ewald::Ewald;
use stokesian::Particle;

fn largest(b: &BlocksFT) -> f64 {
    let m = b.matrix();
    m.iter().flatten().fold(0.0f64, |acc, v| acc.max(v.abs()))
}

fn difference(a: &BlocksFT, b: &BlocksFT) -> f64 {
    let (ma, mb) = (a.matrix(), b.matrix());
    (0..36).fold(0.0f64, |acc, k| {
        acc.max((ma[k / 6][k % 6] - mb[k / 6][k % 6]).abs())
    })
}

/// A sphere in a cubic box, `x = a/L`: `6 pi eta a M_UF = 1 - 2.8372974794806 x + (4 pi/3)
/// x^3` and `8 pi eta a^3 M_OmegaL = 1 - (4 pi/3) x^3` exactly for the RPY tensor (the
/// `c^2` term of Hasimoto's series belongs to the exact multipole solution); the other
/// entries vanish by the cube's symmetry. At tolerance 1e-13 the sums are good to about
/// that; the printed coefficient has 14 digits: 1e-12.
#[test]
fn self_mobility_in_a_cube_is_hasimotos() {
    let (eta, a) = (0.7, 1.3);
    for x in [0.05, 0.1, 0.2, 0.3, 0.45] {
        let l = a / x;
        let e = Ewald::new([l; 3], 1e-13, None);
        let p = Particle {
            x: [0.3, -0.2, 0.1],
            a,
        };
        let s = e.blocks(eta, &p, &p, true);
        let uf = 1.0 - 2.8372974794806 * x + 4.0 * PI / 3.0 * x.powi(3);
        let ol = 1.0 - 4.0 * PI / 3.0 * x.powi(3);
        for i in 0..3 {
            for j in 0..3 {
                let d = if i == j { 1.0 } else { 0.0 };
                let got_uf = s.uf[i][j] * 6.0 * PI * eta * a;
                let got_ol = s.ol[i][j] * 8.0 * PI * eta * a.powi(3);
                assert!(
                    (got_uf - d * uf).abs() < 1e-12,
                    "x = {x}: UF {i}{j} {got_uf} vs {}",
                    d * uf
                );
                assert!(
                    (got_ol - d * ol).abs() < 1e-12,
                    "x = {x}: OL {i}{j} {got_ol} vs {}",
                    d * ol
                );
                assert!(s.of[i][j].abs() * 6.0 * PI * eta * a * a < 1e-12);
                assert!(s.ul[i][j].abs() * 6.0 * PI * eta * a * a < 1e-12);
            }
        }
    }
}

/// The case of the split-parameter tests: viscosity, a box that is not a cube, two
/// spheres of unequal radii, and the balanced `xi` of the box.
fn split_case() -> (f64, [f64; 3], Particle, Particle, f64) {
    let (eta, lengths) = (1.1, [9.0, 11.0, 13.0]);
    let a = Particle {
        x: [0.4, 8.7, 2.0],
        a: 1.0,
    };
    let b = Particle {
        x: [3.1, 1.2, 11.5],
        a: 0.6,
    };
    let volume: f64 = lengths.iter().product();
    (eta, lengths, a, b, PI.sqrt() / volume.cbrt())
}

/// The real and the reciprocal parts move with the split parameter in opposite
/// directions; their sum must not: three values of `xi` a factor 2.5 apart, pairs of
/// unequal radii in a box that is not a cube, and the self mobility, at tolerance 1e-13:
/// 1e-12 of the largest entry.
#[test]
fn the_split_parameter_changes_nothing() {
    let (eta, lengths, a, b, xi0) = split_case();
    for (p, q, same) in [(&a, &b, false), (&b, &a, false), (&a, &a, true)] {
        let sums: Vec<BlocksFT> = [0.6, 1.0, 1.5]
            .iter()
            .map(|f| Ewald::new(lengths, 1e-13, Some(f * xi0)).blocks(eta, p, q, same))
            .collect();
        let scale = largest(&sums[1]);
        for s in &sums {
            let d = difference(s, &sums[1]);
            assert!(d < 1e-12 * scale, "{d:e} of {scale:e} (same: {same})");
        }
    }
}

/// The windowed sum over replicas (an independent reference: the open RPY kernels
/// only), `S(R) = sum_n K(r + n L) w(|r + n L|/R) - (1/V) int K w d^3r`, `w(s) =
/// exp(-s^2)`: by Poisson summation it is the reciprocal sum of `K w` without its `k = 0`
/// term (the Ewald convention), and `K w -> K` in Fourier space with errors in powers
/// of `R^-2`. `int UF w = ((8 pi/3) R^2 - (a_a^2 + a_b^2)(8 pi/9)) I / (8 pi eta)`,
/// `int OmegaL w = (4 pi/3) I / (8 pi eta)` (the delta part of `d d (1/r)`), `int
/// OmegaF w = 0`. Richardson extrapolation from `R = 4, 6, 8, 10, 12 L` (replicas to
/// `6 R`, where `w < 3e-16`; compensated sums); from `6 L` on (one order less) it moves
/// by 2e-11 of the largest entry. Measured against the Ewald sums at tolerance 1e-13:
/// 2e-12 (pair) and 4e-13 (self) of the largest entry, so 1e-11.
#[test]
fn ewald_sum_equals_the_extrapolated_sum_over_replicas() {
    let (eta, l) = (1.0, 10.0);
    let (a, b) = (
        Particle {
            x: [0.0, 0.0, 0.0],
            a: 1.0,
        },
        Particle {
            x: [-2.1, 1.3, -3.7],
            a: 0.7,
        },
    );
    let free = Confinement::Free;
    let volume = l * l * l;
    for (p, q, same) in [(&a, &b, false), (&a, &a, true)] {
        let windowed = |width: f64| -> [f64; 36] {
            let nmax = (6.0 * width / l).ceil() as i64 + 1;
            let mut sum = [0.0; 36];
            let mut carry = [0.0; 36];
            let r0: [f64; 3] = std::array::from_fn(|d| p.x[d] - q.x[d]);
            for n1 in -nmax..=nmax {
                for n2 in -nmax..=nmax {
                    for n3 in -nmax..=nmax {
                        let r = [
                            r0[0] + n1 as f64 * l,
                            r0[1] + n2 as f64 * l,
                            r0[2] + n3 as f64 * l,
                        ];
                        let d2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
                        if d2 == 0.0 || d2 > 36.0 * width * width {
                            continue;
                        }
                        let w = (-d2 / (width * width)).exp();
                        let xb = std::array::from_fn(|d| p.x[d] - r[d]);
                        let m = pair_ft(&free, eta, p.x, p.a, xb, q.a).matrix();
                        for k in 0..36 {
                            // Neumaier's compensated sum: the sum grows like R^2 while
                            // the result stays of order one
                            let v = w * m[k / 6][k % 6];
                            let t = sum[k] + v;
                            carry[k] += if sum[k].abs() >= v.abs() {
                                (sum[k] - t) + v
                            } else {
                                (v - t) + sum[k]
                            };
                            sum[k] = t;
                        }
                    }
                }
            }
            for k in 0..36 {
                sum[k] += carry[k];
            }
            let c = 1.0 / (8.0 * PI * eta * volume);
            let uf =
                c * ((8.0 * PI / 3.0) * width * width - (p.a * p.a + q.a * q.a) * 8.0 * PI / 9.0);
            let ol = c * 4.0 * PI / 3.0;
            for i in 0..3 {
                sum[6 * i + i] -= uf;
                sum[6 * (3 + i) + 3 + i] -= ol;
            }
            if same {
                let s = self_ft(&free, eta, p.x, p.a).matrix();
                for k in 0..36 {
                    sum[k] += s[k / 6][k % 6];
                }
            }
            sum
        };
        let widths = [4.0 * l, 6.0 * l, 8.0 * l, 10.0 * l, 12.0 * l];
        let sums: Vec<[f64; 36]> = widths.iter().map(|&w| windowed(w)).collect();
        // S(R) = S + c1 R^-2 + c2 R^-4 + ...: solve for S entry by entry
        let extrapolate = |from: usize| -> [f64; 36] {
            let ws = &widths[from..];
            let m =
                nalgebra::DMatrix::from_fn(ws.len(), ws.len(), |i, j| ws[i].powi(-2 * j as i32));
            let lu = m.lu();
            let mut out = [0.0; 36];
            for (k, e) in out.iter_mut().enumerate() {
                let rhs = nalgebra::DVector::from_fn(ws.len(), |i, _| sums[from + i][k]);
                *e = lu.solve(&rhs).expect("regular")[0];
            }
            out
        };
        let extrapolated = extrapolate(0);
        // the reference converges: without the smallest width (one order less), the same
        // to 1e-10
        let other = extrapolate(1);
        let spread = (0..36).fold(0.0f64, |acc, k| acc.max((extrapolated[k] - other[k]).abs()));
        let ewald = Ewald::new([l; 3], 1e-13, None)
            .blocks(eta, p, q, same)
            .matrix();
        let scale = ewald
            .iter()
            .flatten()
            .fold(0.0f64, |acc, v| acc.max(v.abs()));
        let worst = (0..36).fold(0.0f64, |acc, k| {
            acc.max((extrapolated[k] - ewald[k / 6][k % 6]).abs())
        });
        println!("same {same}: worst {worst:e}, spread {spread:e} of {scale:e}");
        assert!(
            spread < 1e-10 * scale,
            "same {same}: spread {spread:e} of {scale:e}"
        );
        assert!(worst < 1e-11 * scale, "same {same}: {worst:e} of {scale:e}");
    }
}

/// The largest absolute entry of an 11 x 11 grand block.
fn largest_grand(m: &nalgebra::SMatrix<f64, 11, 11>) -> f64 {
    m.iter().fold(0.0f64, |acc, v| acc.max(v.abs()))
}

/// FTS: the sum does not depend on the split parameter. The real part is the generated
/// FTS kernel of the screened Stokeslet (`scene_ewald_real_fts`), the reciprocal part the
/// Faxén functionals in Fourier space (`Ewald::reciprocal_grand`); moving `xi` moves
/// weight between them, so any error of a symbol (a sign, a factor, a Faxén term) shows
/// as a change with `xi` of every block it touches (a 1% change of the strain's Faxén
/// factor, `g + 0.01 k^2`, moves the pair by 2.4e-3 of its largest entry). Measured:
/// 5e-15 of the largest entry at tolerance 1e-13 (pairs both ways, unequal radii, and
/// a self block; a box that is not a cube); 1e-12, the sums' own truncation with room,
/// as for F and FT.
#[test]
fn the_split_parameter_changes_nothing_fts() {
    let (eta, lengths, a, b, xi0) = split_case();
    for (p, q, same) in [(&a, &b, false), (&b, &a, false), (&a, &a, true)] {
        let sums: Vec<_> = [0.6, 1.0, 1.5]
            .iter()
            .map(|f| {
                Ewald::new(lengths, 1e-13, Some(f * xi0))
                    .grand(eta, p, q, same)
                    .matrix()
            })
            .collect();
        let scale = largest_grand(&sums[1]);
        for s in &sums {
            let d = largest_grand(&(s - sums[1]));
            println!("same {same}: {d:e} of {scale:e}");
            assert!(d < 1e-12 * scale, "{d:e} of {scale:e} (same: {same})");
        }
    }
}

/// FTS: reciprocity, `M^{ba} = (M^{ab})^T` (the pair summed from either end: the source
/// functionals are the field's at `-k`) and a symmetric self block; and its force and
/// torque blocks are the FT sums (`Ewald::blocks`: another real-space kernel, the
/// symbols written out), to 1e-13 of the largest entry (roundings of different sums).
#[test]
fn fts_sums_are_reciprocal_and_contain_the_ft_sums() {
    let (eta, lengths) = (0.8, [10.0, 9.0, 12.0]);
    let (a, b) = (
        Particle {
            x: [1.0, 2.0, 3.0],
            a: 1.2,
        },
        Particle {
            x: [4.0, 0.5, 9.0],
            a: 0.5,
        },
    );
    let ewald = Ewald::new(lengths, 1e-12, None);
    let ab = ewald.grand(eta, &a, &b, false).matrix();
    let ba = ewald.grand(eta, &b, &a, false).matrix();
    let aa = ewald.grand(eta, &a, &a, true).matrix();
    let scale = largest_grand(&ab);
    assert!(largest_grand(&(ab - ba.transpose())) < 1e-13 * scale);
    assert!(largest_grand(&(aa - aa.transpose())) < 1e-13 * largest_grand(&aa));
    for (p, q, same, m) in [(&a, &b, false, &ab), (&a, &a, true, &aa)] {
        let ft = ewald.blocks(eta, p, q, same).matrix();
        let scale = largest_grand(m);
        for i in 0..6 {
            for j in 0..6 {
                let d = (ft[i][j] - m[(i, j)]).abs();
                assert!(d < 1e-13 * scale, "[{i}][{j}] {d:e} of {scale:e}");
            }
        }
    }
}
