use crate::generator::physics_derivatives::path_differences;
use kernel_gen::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path};
use kernel_gen::number::dd::Dd;
use kernel_gen::number::scalar::Scalar;
use kernel_gen::physics::green::ewald::*;
use kernel_gen::physics::green::free::Free;
use kernel_gen::physics::green::stokeslet;
use kernel_gen::physics::operators::{Basis, Moment, Response, BLOCKS};

fn spec(interaction: Interaction, blocks: &[(Response, Moment)]) -> KernelSpec {
    KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii: false,
        blocks: blocks.to_vec(),
        path: Path::Structured,
        product: false,
        drift: None,
    }
}

const FT: [(Response, Moment); 4] = [
    (Response::U, Moment::F),
    (Response::U, Moment::L),
    (Response::Omega, Moment::F),
    (Response::Omega, Moment::L),
];

/// The blocks' sizes (entries per block) of `blocks`.
fn sizes(blocks: &[(Response, Moment)]) -> Vec<usize> {
    use kernel_gen::physics::operators::{moment_dim, response_dim};
    blocks
        .iter()
        .map(|&(r, m)| response_dim(r, Basis::Orthonormal) * moment_dim(m, Basis::Orthonormal))
        .collect()
}

/// Every derivative `d_x^alpha d_y^beta J^R` up to order 4 from the generic path's
/// jets in `r` alone (`d_y = -d_x`), in double-double, against finite differences of
/// `J^R` in all six coordinates ([`kernel_gen::physics::fd`], `h = 1e-4`: truncation about
/// `h^2` of the next derivatives, round-off `eps_dd / h^4`): 1e-6 of the largest
/// derivative of the same order, at `xi r = 1.1` where `erfc` and the Gaussian are
/// both of order 1.
#[test]
fn jets_in_r_equal_finite_differences_in_x_and_y() {
    use kernel_gen::physics::derivatives::{GenericJets, Part};
    use kernel_gen::physics::fd::FiniteDifferences;
    use kernel_gen::physics::operators::{Deriv, Derivatives};
    let (x, y, p) = ([0.3, -0.4, 0.9], [-0.5, 0.4, 0.1], [1.2]);
    let dd = |v: [f64; 3]| v.map(Dd::new);
    let mut jets = GenericJets::new(&EwaldReal, Part::Full, &dd(x), &dd(y), &[Dd::new(p[0])], 4);
    let mut fd = FiniteDifferences::new(&EwaldReal, Part::Full, x, y, &p, 1e-4);
    let l = kernel_gen::number::jet::Layout::get(6, 4);
    for order in 0..=4usize {
        let mut pairs = Vec::new();
        for m in l
            .monos
            .iter()
            .filter(|m| m.iter().map(|&e| e as usize).sum::<usize>() == order)
        {
            for i in 0..3 {
                for j in 0..3 {
                    let d = Deriv {
                        i,
                        j,
                        dx: [m[0], m[1], m[2]],
                        dy: [m[3], m[4], m[5]],
                    };
                    pairs.push((jets.get(&d), fd.get(&d)));
                }
            }
        }
        let scale = pairs
            .iter()
            .map(|(_, b)| b.to_f64().abs())
            .fold(0.0, f64::max);
        for (a, b) in pairs {
            assert!(
                (a - b).to_f64().abs() < 1e-6 * scale,
                "order {order}: {a:?} vs {b:?}"
            );
        }
    }
}

/// `(traced in f64, direct in double-double by the generic path)` of the pair kernel of `blocks`
/// at separation `r` (field at the origin), radii 1 and 0.6, `eta = 0.8`, `sigma`.
fn pair_values(blocks: &[(Response, Moment)], r: [f64; 3], sigma: f64) -> (Vec<f64>, Vec<Dd>) {
    let sp = spec(Interaction::Pair, blocks);
    let inputs = [
        0.1,
        -0.2,
        0.3,
        0.1 - r[0],
        -0.2 - r[1],
        0.3 - r[2],
        1.0,
        0.6,
        0.8,
        sigma,
    ];
    let traced = trace(&EwaldReal, &sp).eval(&inputs);
    let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
    // the reference: the generic jets of the closed form, not the kernels' path
    let generic = KernelSpec {
        path: Path::Generic,
        ..sp
    };
    (traced, evaluate_direct(&EwaldReal, &generic, &dd))
}

/// The traced FTS pair kernel (lowered `exp`, `erfc`, `f64`) against the direct sum in
/// double-double, at `xi r` from 0.4 to 6 (where the real part has decayed to
/// `1e-15` of `J`), every block to 1e-13 of its largest entry: the lowered functions
/// are good to 5e-15 relative, and the jets' sums of a few hundred terms of mixed
/// signs lose a few digits more; a wrong lowering is off by far more.
#[test]
fn pair_kernel_equals_the_direct_sum_in_double_double() {
    let sigma = 1.3;
    for r in [
        [0.4, 0.2, -0.3],
        [1.1, -0.9, 0.5],
        [2.0, 2.5, -1.5],
        [4.0, -5.0, 3.0],
    ] {
        let (got, want) = pair_values(&BLOCKS, r, sigma);
        let mut at = 0;
        for (b, n) in sizes(&BLOCKS).into_iter().enumerate() {
            let (g, w) = (&got[at..at + n], &want[at..at + n]);
            at += n;
            let scale = w.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
            for (x, y) in g.iter().zip(w) {
                let err = (Dd::new(*x) - *y).to_f64().abs();
                assert!(err <= 1e-13 * scale, "block {b} at {r:?}: {x:e} vs {y:?}");
            }
        }
    }
}

/// As `xi = 1/sigma -> 0`: `r erf(xi r) = (2/sqrt(pi))(xi r^2 - xi^3 r^4/3 + O(xi^5))`
/// and `(delta lap - d d)` takes `r^2` to `4 delta`, `r^4` to `16 r^2 delta - 8 r r`,
/// whose Laplacian is `80 delta`; so the UF pair block of the real part minus that of
/// free space (the structured path, an independent evaluation of `J`), times
/// `8 pi eta`, is `-8 xi/sqrt(pi) delta + (2 xi^3/(3 sqrt(pi))) [16 r^2 delta - 8 r r
/// + 80 (a_a^2 + a_b^2)/6 delta] + O(xi^5)`, here to 1e-12 of its leading term (the
/// `xi^3` term is 4e-8 of it at `xi = 1e-4`, the `xi^5` term 1e-16; the difference is
/// formed in double-double). The other blocks differ from free space by `O(xi^3)`.
#[test]
fn the_real_part_tends_to_the_stokeslet() {
    let sigma = 1e4;
    let xi = 1.0 / sigma;
    let r = [1.1, -0.9, 0.5];
    let (_, ewald) = pair_values(&FT, r, sigma);
    let sp = spec(Interaction::Pair, &FT);
    let inputs = [
        0.1,
        -0.2,
        0.3,
        0.1 - r[0],
        -0.2 - r[1],
        0.3 - r[2],
        1.0,
        0.6,
        0.8,
    ];
    let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
    let free = evaluate_direct(&Free, &sp, &dd);
    let eight_pi_eta = 8.0 * std::f64::consts::PI * 0.8;
    let sqrt_pi = std::f64::consts::PI.sqrt();
    let w0 = -8.0 * xi / sqrt_pi;
    let r2: f64 = r.iter().map(|v| v * v).sum();
    let faxen = 80.0 * (1.0 + 0.36) / 6.0;
    for i in 0..3 {
        for j in 0..3 {
            let d = (ewald[3 * i + j] - free[3 * i + j]).to_f64() * eight_pi_eta;
            let delta = if i == j { 1.0 } else { 0.0 };
            let want = w0 * delta
                + 2.0 * xi.powi(3) / (3.0 * sqrt_pi)
                    * ((16.0 * r2 + faxen) * delta - 8.0 * r[i] * r[j]);
            assert!(
                (d - want).abs() < 1e-12 * w0.abs(),
                "UF {i}{j}: {d:e} vs {want:e}"
            );
        }
    }
    let scale = free.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
    for (e, f) in ewald.iter().zip(&free).skip(9) {
        assert!((*e - *f).to_f64().abs() < 1e-10 * scale);
    }
}

/// The self blocks are the isolated sphere plus the operators on `W(0)`, against the
/// closed forms in units of `1/(8 pi eta)` (Beenakker's, with the `a_a^2 a_b^2 lap^2`
/// term of the workspace's Faxén product): UF
/// `(-72 xi + 160 a^2 xi^3 - 168 a^4 xi^5)/(9 sqrt(pi)) I`, Omega-L
/// `-40 xi^3/(3 sqrt(pi)) I`, Omega-F and U-L zero. The traced self kernel (f64)
/// to 1e-14 of the isolated sphere: the terms are a handful of products.
#[test]
fn self_blocks_are_the_isolated_sphere_plus_w_at_zero() {
    let (a, eta, sigma) = (0.9, 0.8, 1.3);
    let xi = 1.0 / sigma;
    let sp = spec(Interaction::SelfTerm, &FT);
    let got = trace(&EwaldReal, &sp).eval(&[0.3, -0.1, 0.7, a, eta, sigma]);
    let pi = std::f64::consts::PI;
    let unit = 1.0 / (8.0 * pi * eta);
    let uf = 1.0 / (6.0 * pi * eta * a)
        + unit * (-72.0 * xi + 160.0 * a * a * xi.powi(3) - 168.0 * a.powi(4) * xi.powi(5))
            / (9.0 * pi.sqrt());
    let ol = 1.0 / (8.0 * pi * eta * a.powi(3)) - unit * 40.0 * xi.powi(3) / (3.0 * pi.sqrt());
    let blocks: Vec<&[f64]> = [0, 9, 18, 27].iter().map(|&k| &got[k..k + 9]).collect();
    for i in 0..3 {
        for j in 0..3 {
            let d = if i == j { 1.0 } else { 0.0 };
            let (uf_tol, ol_tol) = (1e-14 * uf.abs(), 1e-14 * ol.abs());
            assert!((blocks[0][3 * i + j] - d * uf).abs() < uf_tol, "UF {i}{j}");
            assert!((blocks[3][3 * i + j] - d * ol).abs() < ol_tol, "OL {i}{j}");
            assert!(blocks[1][3 * i + j].abs() < uf_tol, "UL {i}{j}");
            assert!(blocks[2][3 * i + j].abs() < uf_tol, "OF {i}{j}");
        }
    }
}

/// Each declared Laplacian of the screened potential against the Laplacian of the
/// one before, `4 s f'' + 6 f'` from its jet in `s` (double-double), for `m` up to
/// 5 (FTS wall kernels need 5), at `xi r` from 0.3 to 3: independent of the
/// recurrence of `Q_m` and of the closed form of `lap (r E)`. Relative to
/// `|4 s f''| + |6 f'|`, the size of the terms that cancel (up to `(xi r)^-6` times the
/// result at `xi r = 0.3`): 1e-26.
#[test]
fn each_laplacian_is_the_laplacian_of_the_one_before() {
    use kernel_gen::number::jet::{Jet, Layout};
    let sigma = Dd::new(1.3);
    let l = Layout::get(1, 2);
    for xr in [0.3, 1.0, 3.0] {
        let s0 = Dd::new(xr * 1.3) * Dd::new(xr * 1.3);
        let x = Jet::variable(&l, 0, s0);
        for m in 0..5u8 {
            let f = screened_laplacian(m, &x, &Jet::constant(sigma));
            let (f1, f2) = (f.derivative(&[1]), f.derivative(&[2]));
            let want = screened_laplacian(m + 1, &s0, &sigma);
            let (a, b) = (Dd::new(4.0) * s0 * f2, Dd::new(6.0) * f1);
            let size = a.to_f64().abs() + b.to_f64().abs();
            let err = (a + b - want).to_f64().abs();
            assert!(
                err < 1e-26 * size,
                "m {m} at xi r {xr}: {err:e} of {size:e}"
            );
        }
    }
}

/// The structured path (the atoms of `lap^m [r erfc(xi r)]`, radial coefficients
/// times universal polynomials in the unit vector) against the generic jets of the
/// closed form `J^R` ([`Green::full`]), every derivative `d_x^alpha d_y^beta J^R` to
/// order 6 (FTS pair kernels), in double-double, at `xi r` from 0.05 to 5: to 1e-24
/// of the largest derivative of its order (both are exact up to round-off of about
/// 1e-31 times the terms, which at order 6 and `xi r = 0.05` exceed the result by up
/// to the `(xi r)^-7` of `lap^3 J^R` against `J^R`'s own sixth derivatives).
#[test]
fn structured_atoms_equal_the_generic_jets() {
    let sigma = 1.3;
    let dir = [0.48, -0.6, 0.64];
    for xr in [0.05, 0.7, 2.0, 5.0] {
        let x = [0.3, -0.4, 0.9].map(Dd::new);
        let y: [Dd; 3] = std::array::from_fn(|k| x[k] - Dd::new(xr * sigma * dir[k]));
        let p = [Dd::new(sigma)];
        for (n, err, scale) in path_differences(&EwaldReal, &x, &y, &p, 6) {
            assert!(
                err < 1e-24 * scale,
                "order {n} at xi r {xr}: {err:e} of {scale:e}"
            );
        }
    }
}

/// The series of `W` (the self kernels' reflected field) against the closed form
/// `J^R - J` at `|r| = 0.0135 sigma`, in double-double: the first terms dropped are
/// of order `(xi r)^12 W(0) / (6! 13)`, 2e-28 of `W(0)`, and `J^R - J` loses 2 of 32
/// digits; so 1e-24 of `W(0)`.
#[test]
fn series_of_w_equals_the_closed_form_near_zero() {
    let sigma = Dd::new(1.3);
    let r = [0.008, -0.006, 0.009].map(Dd::new);
    let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let series = reflected_series(&r, &s, &sigma);
    let (jr, j) = (screened(&r, &s, &sigma), stokeslet(&r));
    let w0 = 8.0 / 1.3 / std::f64::consts::PI.sqrt();
    for i in 0..3 {
        for k in 0..3 {
            let err = (series[i][k] - (jr[i][k] - j[i][k])).to_f64().abs();
            assert!(err < 1e-24 * w0, "{i}{k}: {err:e}");
        }
    }
}
