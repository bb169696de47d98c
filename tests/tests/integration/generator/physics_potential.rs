use kernel_gen::number::dd::Dd;
use kernel_gen::number::jet::{Jet, Layout};
use kernel_gen::number::scalar::Scalar;
use kernel_gen::physics::green::{
    self, free::Free, free_surface::FreeSurface, interface::Interface, side_wall::SideWall,
    slit::Slit, wall::Wall, Green,
};
use kernel_gen::physics::operators::{self, Basis, Moment};
use kernel_gen::physics::potential::{divergence_sources, potential_sources};

/// `d^alpha |r|` at `r` by a jet in three variables.
fn phi_derivative(r: [f64; 3], d: [u8; 3]) -> f64 {
    let order = d.iter().map(|&e| e as usize).sum();
    let layout = Layout::get(3, order);
    let x: [Jet<Dd>; 3] = std::array::from_fn(|k| Jet::variable(&layout, k, Dd::new(r[k])));
    let s = x[0].clone() * x[0].clone() + x[1].clone() * x[1].clone() + x[2].clone() * x[2].clone();
    s.sqrt().derivative(&d).to_f64()
}

/// The sources' sum against the multipole functional (Eq. 8) applied to the Green's
/// function's ordinary-Rust form ([`Green::full`]), differentiated in `y` by jets: an
/// independent path (no image terms, no Eq. 10).
fn check<G: Green>(g: &G, x: [f64; 3], y: [f64; 3], a: f64) {
    let p = green::examples(g);
    let src = potential_sources(g, &[Moment::F, Moment::L]).unwrap();
    let mirrors = g.mirrors(&p);
    let weights = g.weights(&p);
    let layout = Layout::get(3, 2);
    let yj: [Jet<Dd>; 3] = std::array::from_fn(|k| Jet::variable(&layout, k, Dd::new(y[k])));
    let xj: [Jet<Dd>; 3] = x.map(|v| Jet::constant(Dd::new(v)));
    let pj: Vec<Jet<Dd>> = p.iter().map(|&v| Jet::constant(Dd::new(v))).collect();
    let full = g.full(&xj, &yj, &pj);
    let mut column = 0;
    for m in [Moment::F, Moment::L] {
        let fb = operators::faxen(match m {
            Moment::F => operators::Response::U,
            _ => operators::Response::Omega,
        });
        for (l, sides) in operators::source(m, Basis::Orthonormal).iter().enumerate() {
            for k in 0..3 {
                let reference: f64 = sides
                    .iter()
                    .map(|s| {
                        s.coef
                            * (fb * a * a).powi(s.a2 as i32)
                            * full[k][s.comp].derivative(&s.d).to_f64()
                    })
                    .sum();
                let mut sum = 0.0;
                for s in src
                    .iter()
                    .filter(|s| s.channel == k && s.moment == column + l)
                {
                    let (at, h, w) = match s.point {
                        0 => (y, 0.0, 1.0),
                        q => {
                            let n = mirrors[q - 1].normal;
                            let h =
                                (0..3).map(|c| n[c] * y[c]).sum::<f64>() - mirrors[q - 1].offset;
                            let ys: [f64; 3] = std::array::from_fn(|c| y[c] - 2.0 * h * n[c]);
                            (ys, h, weights[s.weight.unwrap()])
                        }
                    };
                    let r: [f64; 3] = std::array::from_fn(|c| x[c] - at[c]);
                    sum += s.coef
                        * w
                        * h.powi(s.h_power as i32)
                        * (a * a).powi(s.a2 as i32)
                        * phi_derivative(r, s.d);
                }
                // entries of size 1/|r| to 1/|r|^3 near 1; round-off of many terms
                approx::assert_relative_eq!(sum, reference, epsilon = 1e-12, max_relative = 1e-11);
            }
        }
        column += 3;
    }
}

#[test]
fn the_sources_sum_to_the_multipole_functional_of_the_green_function() {
    check(&Wall, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3], 0.7);
    check(&Interface, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3], 0.7);
    check(&SideWall, [2.1, 0.4, -0.2], [1.3, -0.5, 0.6], 0.7);
    check(&Free, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3], 0.7);
}

#[test]
fn free_space_has_the_source_alone() {
    let src = potential_sources(&Free, &[Moment::F]).unwrap();
    assert!(src.iter().all(|s| s.point == 0 && s.h_power == 0));
    assert!(src.iter().any(|s| s.a2 == 1));
}

/// The drift's pair terms `sum_l d_{y_l} [(1 + a^2/6 lap_y) G_kl(x, y)]` of the Green's
/// function's ordinary-Rust form, differentiated in `y` by jets (no image terms, no
/// Eq. 10), and the size of the terms summed.
fn divergence_by_jets<G: Green>(g: &G, x: [f64; 3], y: [f64; 3], a: f64) -> ([f64; 3], f64) {
    let p = green::examples(g);
    let layout = Layout::get(3, 3);
    let yj: [Jet<Dd>; 3] = std::array::from_fn(|k| Jet::variable(&layout, k, Dd::new(y[k])));
    let xj: [Jet<Dd>; 3] = x.map(|v| Jet::constant(Dd::new(v)));
    let pj: Vec<Jet<Dd>> = p.iter().map(|&v| Jet::constant(Dd::new(v))).collect();
    let full = g.full(&xj, &yj, &pj);
    let fb = operators::faxen(operators::Response::U);
    let mut size: f64 = 0.0;
    let div = std::array::from_fn(|k| {
        let mut sum = 0.0;
        for (l, sides) in operators::source(Moment::F, Basis::Orthonormal)
            .iter()
            .enumerate()
        {
            for s in sides {
                let mut d = s.d;
                d[l] += 1;
                let term = s.coef
                    * (fb * a * a).powi(s.a2 as i32)
                    * full[k][s.comp].derivative(&d).to_f64();
                size = size.max(term.abs());
                sum += term;
            }
        }
        sum
    });
    (div, size)
}

/// The far field of the drift's pair terms cancels for every Green's function with
/// image terms: the generator's divergence table (Eq. 10 on each force column's sources)
/// is empty, as the Green's function itself says when differentiated by jets (by the
/// reciprocal theorem `G_kl(x, y) = G_lk(y, x)` and incompressibility in `x`, to which
/// the multipole functional adds derivatives that commute with the divergence).
#[test]
fn the_far_field_of_the_drift_cancels() {
    fn check<G: Green>(g: &G, x: [f64; 3], y: [f64; 3]) {
        assert_eq!(divergence_sources(g).unwrap(), vec![], "{}", g.name());
        let (div, size) = divergence_by_jets(g, x, y, 0.7);
        // a sum of terms of size `size`, evaluated in double-double
        for d in div {
            approx::assert_abs_diff_eq!(d, 0.0, epsilon = 1e-14 * size);
        }
        assert!(size > 1e-3, "{}: terms of size {size}", g.name());
    }
    check(&Wall, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3]);
    check(&FreeSurface, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3]);
    check(&Interface, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3]);
    check(&Slit, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3]);
    check(&SideWall, [2.1, 0.4, -0.2], [1.3, -0.5, 0.6]);
    check(&Free, [0.4, -0.2, 2.1], [-0.5, 0.6, 1.3]);
}
