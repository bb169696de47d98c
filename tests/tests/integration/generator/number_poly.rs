use kernel_gen::number::dd::Dd;
use kernel_gen::number::jet::{Jet, Layout};
use kernel_gen::number::poly::*;
use kernel_gen::number::scalar::Scalar;

/// The jet of `1/|e + d|` on polynomials gives the closed forms:
/// `d_1 (1/r) = -e1`, `d_1 d_1 (1/r) = 3 e1^2 - 1`, `d_1 d_2 d_3 (1/r) = -15 e1 e2 e3`
/// at `|e| = 1` (here as polynomials, before using `|e| = 1`: `3 e1^2 - |e|^2`...);
/// checked by evaluating at a unit vector against the f64 jet.
#[test]
fn polynomial_jets_equal_the_numerical_jets() {
    let l = Layout::get(3, 4);
    let e = [0.48, -0.6, 0.64]; // a unit vector
    let jet_of = |ev: [Poly; 3]| {
        let d: [Jet<Poly>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, Poly::cst(0.0)));
        let mut s = Jet::cst(1.0);
        for k in 0..3 {
            s = s
                + Jet::constant(Poly::cst(2.0) * ev[k].clone()) * d[k].clone()
                + d[k].clone() * d[k].clone();
        }
        s.powf(-0.5, Poly::cst(1.0))
    };
    let p = jet_of([Poly::var(0), Poly::var(1), Poly::var(2)]);
    let d: [Jet<f64>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, 0.0));
    let mut s = Jet::cst(1.0);
    for k in 0..3 {
        s = s + Jet::constant(2.0 * e[k]) * d[k].clone() + d[k].clone() * d[k].clone();
    }
    let f = s.powf(-0.5, 1.0);
    for nu in [[1u8, 0, 0], [2, 0, 0], [1, 1, 1], [0, 2, 2], [4, 0, 0]] {
        let want = f.derivative(&nu);
        let got: f64 = p.derivative(&nu).eval(&e);
        assert!(
            (got - want).abs() <= 1e-13 * want.abs().max(1.0),
            "{nu:?}: {got} {want}"
        );
    }
    // d_1 d_1 (1/r) = 3 e1^2 - 1 (with |e| = 1): at e the value is 3 * 0.2304 - 1
    let v: f64 = p.derivative(&[2, 0, 0]).eval(&e);
    assert!((v - (3.0 * 0.48 * 0.48 - 1.0)).abs() < 1e-15);
}

/// On the unit sphere `|e|^2` is 1 and the jets' `3 e1^2 - |e|^2` is `3 e1^2 - 1`,
/// and every form keeps the values at unit vectors (to rounding of coefficients of
/// size up to 15: 1e-13); with `e2` known to be zero the rewriting uses `e1^2 + e3^2
/// = 1` alone.
#[test]
fn forms_on_the_unit_sphere_keep_the_values_and_drop_monomials() {
    let sq = |k| Poly::var(k) * Poly::var(k);
    let r2 = sq(0) + sq(1) + sq(2);
    assert_eq!(r2.on_unit_sphere([false; 3]), Poly::cst(1.0));
    let p = Poly::cst(3.0) * sq(0) - r2.clone();
    assert_eq!(p.on_unit_sphere([false; 3]).0.len(), 2);
    // a jet's polynomial: d_1 d_1 d_3 d_3 (1/r), with monomials in all three
    let l = Layout::get(3, 4);
    let d: [Jet<Poly>; 3] = std::array::from_fn(|k| Jet::variable(&l, k, Poly::cst(0.0)));
    let mut s = Jet::cst(1.0);
    for (k, dk) in d.iter().enumerate() {
        s = s + Jet::constant(Poly::cst(2.0) * Poly::var(k)) * dk.clone() + dk.clone() * dk.clone();
    }
    let q = s.powf(-0.5, Poly::cst(1.0)).derivative(&[2, 0, 2]);
    for (zero, e) in [
        ([false; 3], [0.48, -0.6, 0.64]),
        ([false, true, false], [0.6, 0.0, -0.8]),
    ] {
        let want: f64 = q.eval(&e);
        let form = q.on_unit_sphere(zero);
        assert!(form.0.len() <= q.0.len());
        let got: f64 = form.eval(&e);
        assert!((got - want).abs() <= 1e-13, "{zero:?}: {got} {want}");
    }
}

#[test]
fn horner_drops_known_zeros_and_uses_even_powers() {
    use kernel_gen::graph::{Ex, Trace};
    // 1 + 3 e1^2 - 2 e1^4 + 5 e2 e3: with e2 = 0, an even polynomial in e1
    let one = Poly::cst(1.0);
    let mut p = one.clone();
    p.add_shifted(&one, Dd::new(3.0), [2, 0, 0, 0, 0, 0]);
    p.add_shifted(&one, Dd::new(-2.0), [4, 0, 0, 0, 0, 0]);
    p.add_shifted(&one, Dd::new(5.0), [0, 1, 1, 0, 0, 0]);
    let t = Trace::begin();
    let e = [t.input("e1"), Ex::cst(0.0), t.input("e3")];
    let v = p.eval(&e);
    let g = t.finish();
    // e1^2, (-2 x + 3), (..) x, + 1: 1 powi + 2 mul + 2 add
    let c = g.op_count(&[v.0]);
    assert_eq!(c.total(), 5, "{c}");
    let x: f64 = 0.7;
    let got = g.eval(&[x, 0.2], &[v.0])[0];
    assert!((got - (1.0 + 3.0 * x * x - 2.0 * x.powi(4))).abs() < 1e-15);
}
