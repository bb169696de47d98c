use kernel_gen::kernel::{evaluate_direct, trace, Interaction, KernelSpec, Path};
use kernel_gen::number::dd::Dd;
use kernel_gen::number::scalar::Scalar;
use kernel_gen::physics::green::ewald::screened;
use kernel_gen::physics::green::ewald_wall::*;
use kernel_gen::physics::green::wall::Wall;
use kernel_gen::physics::green::Mat3;
use kernel_gen::physics::operators::{moment_dim, response_dim, Basis, Moment, Response};

const FT: [(Response, Moment); 4] = [
    (Response::U, Moment::F),
    (Response::U, Moment::L),
    (Response::Omega, Moment::F),
    (Response::Omega, Moment::L),
];

fn spec(interaction: Interaction) -> KernelSpec {
    KernelSpec {
        interaction,
        basis: Basis::Orthonormal,
        equal_radii: false,
        blocks: FT.to_vec(),
        path: Path::Structured,
        product: false,
        drift: None,
    }
}

/// The largest entry of each FT block of `v`, repeated for each of its entries.
fn block_scales(v: &[Dd]) -> Vec<f64> {
    let mut out = Vec::new();
    let mut at = 0;
    for &(r, m) in &FT {
        let n = response_dim(r, Basis::Orthonormal) * moment_dim(m, Basis::Orthonormal);
        let scale = v[at..at + n]
            .iter()
            .map(|x| x.to_f64().abs())
            .fold(0.0, f64::max);
        out.extend(std::iter::repeat_n(scale, n));
        at += n;
    }
    out
}

/// The gradient and Laplacian of `J^R` against central differences of [`screened`] in
/// double-double (step `1e-6`: truncation about `1e-12` of the third derivatives,
/// round-off `1e-32/1e-12`), to 1e-9 of the largest entry, at `xi r` from 0.3 to 4.
#[test]
fn derivatives_equal_finite_differences() {
    let sigma = Dd::new(1.3);
    let h = Dd::new(1e-6);
    let at = |r: [Dd; 3]| {
        let s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
        screened(&r, &s, &sigma)
    };
    for r in [[0.3, -0.2, 0.1], [1.1, 0.7, -0.4], [2.0, -3.0, 3.5]] {
        let r = r.map(Dd::new);
        let (_, grad, lap) = screened_with_derivatives(&r, &sigma);
        let shifted = |k: usize, t: Dd| {
            let mut q = r;
            q[k] = q[k] + t;
            at(q)
        };
        let mut fd_grad = [[[Dd::new(0.0); 3]; 3]; 3];
        let mut fd_lap = [[Dd::new(0.0); 3]; 3];
        let centre = at(r);
        for (k, fd_k) in fd_grad.iter_mut().enumerate() {
            let (p, m) = (shifted(k, h), shifted(k, -h));
            for i in 0..3 {
                for l in 0..3 {
                    fd_k[i][l] = (p[i][l] - m[i][l]) / (Dd::new(2.0) * h);
                    fd_lap[i][l] =
                        fd_lap[i][l] + (p[i][l] - Dd::new(2.0) * centre[i][l] + m[i][l]) / (h * h);
                }
            }
        }
        let scale = |m: &[Mat3<Dd>]| {
            m.iter()
                .flatten()
                .flatten()
                .map(|v| v.to_f64().abs())
                .fold(0.0, f64::max)
        };
        let (sg, sl) = (scale(&grad), scale(std::slice::from_ref(&lap)));
        for k in 0..3 {
            for i in 0..3 {
                for l in 0..3 {
                    let e = (grad[k][i][l] - fd_grad[k][i][l]).to_f64().abs();
                    assert!(e < 1e-9 * sg, "d{k} J{i}{l} at {r:?}: {e:e}");
                }
            }
        }
        for i in 0..3 {
            for l in 0..3 {
                let e = (lap[i][l] - fd_lap[i][l]).to_f64().abs();
                assert!(e < 1e-6 * sl, "lap J{i}{l} at {r:?}: {e:e}");
            }
        }
    }
}

/// The structured path (Blake's image terms by Eq. 10, made of the atoms of the
/// screened potential) against the generic six-variable jets of the closed form
/// [`Green::full`], every derivative to order 4 (the FT pair kernels'; the image terms
/// add 2 more to the potential's), in double-double, pairs from near the wall to
/// `xi |R|` of 5: to 1e-24 of the largest derivative of its order (round-off of about
/// 1e-31 of the terms, which exceed the result where `J^R(r)` and the screened
/// image cancel).
#[test]
fn structured_terms_equal_the_generic_jets() {
    use crate::generator::physics_derivatives::path_differences;
    let p = [Dd::new(0.3), Dd::new(1.3)];
    for (x, y) in [
        ([0.1, -0.2, 1.5], [0.4, 0.1, 1.8]),
        ([0.1, -0.2, 0.5], [1.6, -1.1, 0.4]),
        ([3.0, -2.0, 1.6], [-1.0, 2.5, 4.1]),
    ] {
        let (x, y) = (x.map(Dd::new), y.map(Dd::new));
        for (n, err, scale) in path_differences(&EwaldWall, &x, &y, &p, 4) {
            assert!(
                err < 1e-24 * scale,
                "order {n} at {x:?}, {y:?}: {err:e} of {scale:e}"
            );
        }
    }
}

/// Inputs of the pair kernel: `xa, xb, aa, ab, eta, height, sigma`.
fn pair_inputs(xa: [f64; 3], xb: [f64; 3], height: f64, sigma: f64) -> Vec<f64> {
    let mut v = xa.to_vec();
    v.extend(xb);
    v.extend([1.0, 0.6, 0.8, height, sigma]);
    v
}

/// The traced FT pair kernel (canonical frame, lowered `exp` and `erfc`, `f64`) against
/// the direct sum in double-double by the generic jets of the closed form, pairs at heights 1.2 to 5 above the wall, lateral
/// distances up to `5 sigma`, every block to 1e-12 of its largest entry (the lowered
/// functions are good to 5e-15 relative; the image terms add `h^2 lap J^R(R)`, of up
/// to `(h/R)^2` times the terms they partly cancel, and the jets sum a few hundred
/// terms of mixed signs).
#[test]
fn pair_kernel_equals_the_direct_sum_in_double_double() {
    let (height, sigma) = (0.3, 1.3);
    let traced = trace(&EwaldWall, &spec(Interaction::Pair));
    for (xa, xb) in [
        ([0.1, -0.2, 1.5], [0.4, 0.1, 1.8]),
        ([0.1, -0.2, 2.3], [1.6, -1.1, 1.5]),
        ([-1.0, 0.5, 5.3], [1.5, 2.0, 3.0]),
        ([3.0, -2.0, 1.6], [-1.0, 2.5, 4.1]),
    ] {
        let inputs = pair_inputs(xa, xb, height, sigma);
        let got = traced.eval(&inputs);
        let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
        let generic = KernelSpec {
            path: Path::Generic,
            ..spec(Interaction::Pair)
        };
        let want = evaluate_direct(&EwaldWall, &generic, &dd);
        for ((g, w), s) in got.iter().zip(&want).zip(block_scales(&want)) {
            let err = (Dd::new(*g) - *w).to_f64().abs();
            assert!(err <= 1e-12 * s, "{xa:?} {xb:?}: {g:e} vs {w:?}");
        }
    }
}

/// As `xi -> 0` the screened image system is Blake's: `J^R - J = W = -8 xi/sqrt(pi) I +
/// O(xi^3)`, and the image of the constant `-8 xi/sqrt(pi) I` is its opposite (Eq. 5:
/// `-W(R)`, derivatives of `W` are `O(xi^3)`), so the pair and self FT blocks differ
/// from the wall's (the structured path: an independent evaluation) by `O(xi^3 (r^2 +
/// h^2 + a^2) / (8 pi eta))`, about 1e-12 at `xi = 1e-4` with lengths of order 1: here
/// to 1e-10 absolute (the smallest blocks, the self rotation-translation coupling, are
/// of order 1e-3; a wrong image term is off by a fraction of the block).
#[test]
fn the_real_part_tends_to_the_wall() {
    let (height, sigma) = (0.3, 1e4);
    let (xa, xb) = ([0.1, -0.2, 2.3], [1.6, -1.1, 1.5]);
    let dd = |v: Vec<f64>| v.into_iter().map(Dd::new).collect::<Vec<_>>();
    let sp = spec(Interaction::Pair);
    let ewald = evaluate_direct(&EwaldWall, &sp, &dd(pair_inputs(xa, xb, height, sigma)));
    let mut wall_inputs = pair_inputs(xa, xb, height, sigma);
    wall_inputs.pop();
    let wall = evaluate_direct(&Wall, &sp, &dd(wall_inputs));
    for (e, w) in ewald.iter().zip(&wall) {
        assert!((*e - *w).to_f64().abs() < 1e-10, "pair: {e:?} vs {w:?}");
    }
    let sp = spec(Interaction::SelfTerm);
    let x = [0.1, -0.2, 1.7];
    let self_inputs = |with_sigma: bool| {
        let mut v = x.to_vec();
        v.extend([0.9, 0.8, height]);
        if with_sigma {
            v.push(sigma);
        }
        dd(v)
    };
    let ewald = evaluate_direct(&EwaldWall, &sp, &self_inputs(true));
    let wall = evaluate_direct(&Wall, &sp, &self_inputs(false));
    for (e, w) in ewald.iter().zip(&wall) {
        assert!((*e - *w).to_f64().abs() < 1e-10, "self: {e:?} vs {w:?}");
    }
}

/// The traced self kernel (`f64`) against the direct sum in double-double, to 1e-13 of
/// each block's largest entry (the isolated sphere dominates; the reflected terms are
/// a few hundred products).
#[test]
fn self_kernel_equals_the_direct_sum_in_double_double() {
    let sp = spec(Interaction::SelfTerm);
    let traced = trace(&EwaldWall, &sp);
    for (z, sigma) in [(1.2, 1.3), (2.5, 0.7), (4.0, 2.0)] {
        let inputs = vec![0.3, -0.1, z, 0.9, 0.8, 0.3, sigma];
        let got = traced.eval(&inputs);
        let dd: Vec<Dd> = inputs.iter().map(|&v| Dd::new(v)).collect();
        let want = evaluate_direct(&EwaldWall, &sp, &dd);
        for ((g, w), s) in got.iter().zip(&want).zip(block_scales(&want)) {
            let err = (Dd::new(*g) - *w).to_f64().abs();
            assert!(err <= 1e-13 * s, "z {z}: {g:e} vs {w:?}");
        }
    }
}
