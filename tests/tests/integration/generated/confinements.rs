//! Checks written once and run on every registered confinement (the registry in
//! `kernel_gen::physics::green::for_each`): a new Green's function gets them without new code.

use integration_tests::{
    above, all_confinements, blocks, frame_of, norm, rel_diff, sample_params, with_params,
};
use kernel_gen::physics::derivatives::Structured;
use kernel_gen::physics::green::{frame, Condition, Green, Visitor};
use kernel_gen::physics::operators::{Deriv, Derivatives};
use kernels::{pair, self_mobility, Confinement, Dimension};

/// All multi-indices of total order <= n in three variables.
fn multi_indices(n: u8) -> Vec<[u8; 3]> {
    let mut v = Vec::new();
    for a in 0..=n {
        for b in 0..=n - a {
            for c in 0..=n - a - b {
                v.push([a, b, c]);
            }
        }
    }
    v
}

/// Eqs. 3 and 11: on every boundary a Green's function declares exact, the Stokeslet
/// plus its reflection, and every source derivative of it up to third order, satisfy
/// the boundary's condition, in the plane's own frame (`t1, t2, n`). No slip:
/// `d_y^n G = 0`. Free surface: no penetration `d_y^n n.G = 0` and no tangential
/// stress `d_y^n (n . grad_x)(t.G) = 0`. Interface: no penetration. Evaluated by the
/// structured (Eq. 10) path that the kernels are emitted from. Tolerance: 1e-13 of the
/// largest derivative of the same order of the free-space part (the image cancels it
/// to round-off). Returns the confinements with an exact boundary.
/// The largest value a condition must make zero, and the largest of the derivatives
/// it is made of, at source derivative `beta`, in the frame `[t1, t2, n]`.
fn residual(
    src: &mut Structured<f64>,
    beta: [u8; 3],
    condition: Condition,
    [t1, t2, n]: [[f64; 3]; 3],
) -> (f64, f64) {
    let mut at = |dx: [u8; 3]| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| src.get(&Deriv { i, j, dx, dy: beta })))
    };
    let g0 = at([0, 0, 0]);
    let gd: [[[f64; 3]; 3]; 3] = std::array::from_fn(|k| {
        let mut d = [0u8; 3];
        d[k] = 1;
        at(d)
    });
    let contract =
        |v: &[f64; 3], m: &[[f64; 3]; 3], j: usize| -> f64 { (0..3).map(|i| v[i] * m[i][j]).sum() };
    let mut values: Vec<f64> = Vec::new();
    for j in 0..3 {
        match condition {
            Condition::NoSlip => values.extend((0..3).map(|i| g0[i][j])),
            Condition::Interface => values.push(contract(&n, &g0, j)),
            Condition::FreeSurface => {
                values.push(contract(&n, &g0, j));
                for t in [t1, t2] {
                    values.push((0..3).map(|k| n[k] * contract(&t, &gd[k], j)).sum());
                }
            }
        }
    }
    let max = |it: &mut dyn Iterator<Item = &f64>| it.fold(0.0f64, |a, v| a.max(v.abs()));
    let size = max(&mut g0.iter().flatten().chain(gd.iter().flatten().flatten()));
    (max(&mut values.iter()), size)
}

struct BoundaryConditions {
    checked: Vec<&'static str>,
}

impl Visitor for BoundaryConditions {
    fn visit<G: Green>(&mut self, g: &G) {
        let p = sample_params(g.name());
        let exact: Vec<_> = g.boundaries(&p).into_iter().filter(|b| b.exact).collect();
        if exact.is_empty() {
            return;
        }
        for b in exact {
            let [t1, t2, n] = frame(b.plane.normal);
            let at = |lateral: [f64; 2], up: f64| -> [f64; 3] {
                std::array::from_fn(|k| {
                    b.plane.offset * n[k] + lateral[0] * t1[k] + lateral[1] * t2[k] + up * n[k]
                })
            };
            for (x, y) in [
                (at([0.7, -0.2], 0.0), at([0.1, 0.3], 1.3)),
                (at([4.0, 2.5], 0.0), at([-0.6, 0.2], 0.4)),
            ] {
                let mut full = Structured::new(g, &x, &y, &p, 4, true, true);
                let mut free = Structured::new(
                    &kernel_gen::physics::green::free::Free,
                    &x,
                    &y,
                    &[],
                    4,
                    true,
                    true,
                );
                for order in 0..=3u8 {
                    let mut scale: f64 = 0.0;
                    let mut worst: f64 = 0.0;
                    for beta in multi_indices(order)
                        .into_iter()
                        .filter(|m| m.iter().sum::<u8>() == order)
                    {
                        let (_, size) = residual(&mut free, beta, b.condition, [t1, t2, n]);
                        let (r, _) = residual(&mut full, beta, b.condition, [t1, t2, n]);
                        scale = scale.max(size);
                        worst = worst.max(r);
                    }
                    assert!(
                        worst <= 1e-13 * scale,
                        "{}: {:?} violated at source-derivative order {order}: {worst:e} (scale {scale:e})",
                        g.name(),
                        b.condition
                    );
                }
            }
        }
        self.checked.push(g.name());
    }
}

#[test]
fn boundary_conditions_hold_for_the_image_and_its_source_derivatives() {
    let mut v = BoundaryConditions { checked: vec![] };
    kernel_gen::physics::green::for_each(&mut v);
    // every confinement with a boundary it declares exact was checked
    let mut with_exact = Vec::new();
    struct Exact<'a>(&'a mut Vec<&'static str>);
    impl Visitor for Exact<'_> {
        fn visit<G: Green>(&mut self, g: &G) {
            let p = sample_params(g.name());
            if g.boundaries(&p).iter().any(|b| b.exact) {
                self.0.push(g.name());
            }
        }
    }
    kernel_gen::physics::green::for_each(&mut Exact(&mut with_exact));
    assert!(!with_exact.is_empty());
    assert_eq!(v.checked, with_exact);
}

/// Far from the boundary (h = 1e6 a) every block of the self and pair kernels tends to
/// free space: the image corrections are O(a/h) = 1e-6 relative at most (UF self:
/// 9/16 a/h), so 1e-5 relative per block, and each block's relative difference must
/// also shrink from h = 1e4 a to h = 1e6 a.
///
/// The spheres are placed at heights h and h + 0.7 over the first boundary, along its
/// normal (`integration_tests::above`), and moved by h along the normal of any other
/// boundary they are nearer than h / 2 (a side wall meeting the floor), the parameters
/// chosen by their dimension: every position 0 (the planes through the origin), every
/// length 2 h (a slit's gap: the spheres midway), every pure number its example. That
/// this puts the spheres far from every boundary is checked, not assumed.
struct FarField {
    checked: usize,
}

impl Visitor for FarField {
    fn visit<G: Green>(&mut self, g: &G) {
        if g.boundaries(&sample_params(g.name())).is_empty() {
            return;
        }
        let diff = |h: f64| -> Vec<f64> {
            let c = with_params(g.name(), |p| match p.dimension {
                Dimension::Position(_) => 0.0,
                Dimension::Length => 2.0 * h,
                Dimension::Number => p.example,
            });
            // over the first boundary, then away from every other boundary it is near
            // (a corner's side wall), along that boundary's normal
            let clear = |mut x: [f64; 3]| {
                for b in c.boundaries() {
                    if b.distance(x) < 0.5 * h {
                        x = std::array::from_fn(|k| x[k] + h * b.normal[k]);
                    }
                }
                x
            };
            let (xa, xb) = (
                clear(above(&c, [0.5, 0.1], h)),
                clear(above(&c, [2.5, 2.1], h + 0.7)),
            );
            for b in c.boundaries() {
                for x in [xa, xb] {
                    assert!(
                        b.distance(x) > 0.5 * h,
                        "{}: {x:?} is not far from the boundary {b}",
                        g.name()
                    );
                }
            }
            let s = self_mobility(&c, 1.0, xa, 1.0);
            let s0 = self_mobility(&Confinement::Free, 1.0, xa, 1.0);
            let q = pair(&c, 1.0, xa, 1.0, xb, 0.6);
            let q0 = pair(&Confinement::Free, 1.0, xa, 1.0, xb, 0.6);
            let mut out = Vec::new();
            for (x, y) in blocks(&s).into_iter().zip(blocks(&s0)) {
                if norm(&y.1) > 0.0 {
                    out.push(rel_diff(&x.1, &y.1));
                } else {
                    // blocks that vanish in free space: compare to the matching
                    // diagonal block's size
                    out.push(norm(&x.1) / norm(&blocks(&s0)[0].1));
                }
            }
            for (x, y) in blocks(&q).into_iter().zip(blocks(&q0)) {
                out.push(rel_diff(&x.1, &y.1));
            }
            out
        };
        let (near, far) = (diff(1e4), diff(1e6));
        for (k, (n, f)) in near.iter().zip(&far).enumerate() {
            assert!(
                *f < 1e-5,
                "{}: block {k} differs from free space by {f:e} at h = 1e6 a",
                g.name()
            );
            // Decrease is only meaningful above round-off (blocks that vanish by
            // symmetry, e.g. the slit's self US with the sphere midway, are noise).
            assert!(
                f <= n || *n < 1e-14,
                "{}: block {k} does not approach free space ({n:e} -> {f:e})",
                g.name()
            );
        }
        self.checked += 1;
    }
}

#[test]
fn far_from_the_boundary_every_block_tends_to_free_space() {
    let mut v = FarField { checked: 0 };
    kernel_gen::physics::green::for_each(&mut v);
    // every confinement with a boundary, as the generated dispatch lists them
    let bounded = all_confinements()
        .iter()
        .filter(|(_, c)| !c.boundaries().is_empty())
        .count();
    assert!(bounded > 0);
    assert_eq!(v.checked, bounded);
}

/// Physical signs, wall below the sphere (docs/conventions.md). A force +x parallel to the wall
/// makes the sphere rotate in the rolling sense, Omega_y > 0 (the image flow is slower
/// nearer the wall, so its vorticity at the sphere is +y); a torque +y makes it
/// translate +x (reciprocity of the same coupling).
///
/// Strain from a force pushing the sphere away from the wall (F = +z): the image flow
/// opposes the motion (u_z^image < 0 at the sphere) and weakens with distance from
/// the wall, so d u_z / d z > 0: the image strain at the sphere is a uniaxial
/// extension along z, E_33 > 0, with E_11 = E_22 = -E_33 / 2 (axisymmetry and
/// incompressibility). In the orthonormal basis only the B5 component is non-zero,
/// and it is positive.
#[test]
fn physical_signs_above_a_wall() {
    let wall = Confinement::Wall { height: 0.0 };
    for h in [1.0001, 1.5, 3.0, 10.0] {
        let s = self_mobility(&wall, 1.0, [0.0, 0.0, h], 1.0);
        assert!(
            s.of[1][0] > 0.0,
            "h = {h}: force +x must give Omega_y > 0, got {}",
            s.of[1][0]
        );
        assert!(
            s.ul[0][1] > 0.0,
            "h = {h}: torque +y must give U_x > 0, got {}",
            s.ul[0][1]
        );
        let c = s.cartesian();
        let e33 = c.ef[2][2][2];
        assert!(e33 > 0.0, "h = {h}: force +z must give E_33 > 0, got {e33}");
        for (p, q) in [(0, 0), (1, 1)] {
            let rel = (c.ef[p][q][2] + 0.5 * e33).abs() / e33;
            assert!(
                rel < 1e-13,
                "h = {h}: E_{p}{q} = {} is not -E_33/2",
                c.ef[p][q][2]
            );
        }
        assert!(s.ef[4][2] > 0.0);
        for m in 0..4 {
            assert!(
                s.ef[m][2].abs() < 1e-14 * s.ef[4][2],
                "h = {h}: component B{} = {}",
                m + 1,
                s.ef[m][2]
            );
        }
    }
}

/// The interface reduces to the free surface at lambda = 0 and to the wall as
/// lambda -> infinity (Eq. 22); at lambda = 1e12 the difference from the wall is
/// 1e-12 relative (the weights are 1/(1 + lambda) and lambda/(1 + lambda)).
#[test]
fn interface_limits() {
    let (xa, xb) = ([0.3, 0.2, 1.4], [2.6, -0.9, 2.1]);
    let cases = [
        (0.0, Confinement::FreeSurface { height: 0.0 }, 1e-14),
        (1e12, Confinement::Wall { height: 0.0 }, 1e-11),
    ];
    for (lambda, limit, tol) in cases {
        let i = Confinement::Interface {
            height: 0.0,
            lambda,
        };
        for (a, b) in [
            (
                self_mobility(&i, 1.0, xa, 1.0),
                self_mobility(&limit, 1.0, xa, 1.0),
            ),
            (
                pair(&i, 1.0, xa, 1.0, xb, 0.7),
                pair(&limit, 1.0, xa, 1.0, xb, 0.7),
            ),
        ] {
            for ((n, x), (_, y)) in blocks(&a).into_iter().zip(blocks(&b)) {
                let e = rel_diff(&x, &y);
                assert!(e < tol, "lambda = {lambda}, block {n}: {e:e}");
            }
        }
    }
}

/// A plane with a given condition has one Green's function (no slip: Blake's image,
/// Eq. 5; a free surface: the mirror image, Eq. 21), whatever its normal. So any two
/// registered confinements bounded by one plane each, with the same condition
/// satisfied exactly and no parameter but positions, are the same Green's function in
/// two frames: the planes through the origin (every position 0), `R = Q_b^T Q_a` the
/// map between their frames (`integration_tests::frame_of`) and `x_b = R x_a`,
/// `M_b = T M_a T^T` with `T = diag(R, det(R) R, D(R))` on `(U, Omega, E)` and
/// `(F, L, S)` alike (the angular velocity and torque are axial vectors) and
/// `D_mn = B_m : (R B_n R^T)` the rotation of the orthonormal strain basis. Every block
/// of the self and pair kernels (either particle the higher one) to 1e-13 of its
/// norm: the same quantity evaluated in two frames, one of them possibly by another
/// branch (the wall's lateral far field, its canonical frame), each to about 1e-15.
#[test]
fn one_plane_with_one_condition_is_one_green_function_in_any_frame() {
    use kernels::STRAIN_BASIS as B;
    use nalgebra::SMatrix;
    let single: Vec<(&str, Confinement)> = all_confinements()
        .into_iter()
        .filter(|(_, c)| {
            let params = c.declaration().params;
            c.boundaries().len() == 1
                && c.boundaries()[0].exact
                && params
                    .iter()
                    .all(|p| matches!(p.dimension, Dimension::Position(_)))
        })
        .map(|(name, _)| {
            let origin = with_params(name, |_| 0.0);
            (name, origin)
        })
        .collect();
    let mut checked = Vec::new();
    for (i, (na, a)) in single.iter().enumerate() {
        for (nb, b) in &single[i + 1..] {
            if a.boundaries()[0].condition != b.boundaries()[0].condition {
                continue;
            }
            let (qa, qb) = (frame_of(a), frame_of(b));
            let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|k| qb[k][i] * qa[k][j]).sum())
            });
            let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
                - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
                + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
            let mut t = SMatrix::<f64, 11, 11>::zeros();
            for i in 0..3 {
                for j in 0..3 {
                    t[(i, j)] = r[i][j];
                    t[(3 + i, 3 + j)] = det * r[i][j];
                }
            }
            for m in 0..5 {
                for n in 0..5 {
                    // B_m : (R B_n R^T)
                    let mut s = 0.0;
                    for p in 0..3 {
                        for q in 0..3 {
                            let rbr: f64 = (0..3)
                                .flat_map(|k| (0..3).map(move |l| (k, l)))
                                .map(|(k, l)| r[p][k] * B[n][k][l] * r[q][l])
                                .sum();
                            s += B[m][p][q] * rbr;
                        }
                    }
                    t[(6 + m, 6 + n)] = s;
                }
            }
            let rotate = |x: [f64; 3]| -> [f64; 3] {
                std::array::from_fn(|i| (0..3).map(|k| r[i][k] * x[k]).sum())
            };
            let (x1, x2) = (above(a, [0.3, -0.2], 1.7), above(a, [2.1, 1.4], 2.9));
            let cases = [
                (
                    self_mobility(a, 1.3, x1, 0.8),
                    self_mobility(b, 1.3, rotate(x1), 0.8),
                ),
                (
                    pair(a, 1.3, x1, 0.8, x2, 1.1),
                    pair(b, 1.3, rotate(x1), 0.8, rotate(x2), 1.1),
                ),
                (
                    pair(a, 1.3, x2, 1.1, x1, 0.8),
                    pair(b, 1.3, rotate(x2), 1.1, rotate(x1), 0.8),
                ),
            ];
            let mut worst: f64 = 0.0;
            for (k, (ma, mb)) in cases.into_iter().enumerate() {
                let want = kernels::Grand::from_matrix(&(t * ma.matrix() * t.transpose()));
                for ((block, x), (_, y)) in blocks(&mb).into_iter().zip(blocks(&want)) {
                    let e = rel_diff(&x, &y);
                    assert!(
                        e < 1e-13,
                        "{nb} against {na} rotated, case {k}, {block}: {e:e}"
                    );
                    worst = worst.max(e);
                }
            }
            checked.push(format!("{nb} = {na} rotated (worst block {worst:.1e})"));
        }
    }
    println!("{}", checked.join(", "));
}
