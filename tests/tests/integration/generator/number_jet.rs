use approx::assert_relative_eq;
use kernel_gen::number::dd::Dd;
use kernel_gen::number::jet::*;
use kernel_gen::number::scalar::Scalar;
use std::rc::Rc;

// Each primitive against a series known in closed form. Tolerances: the exact
// coefficients are small rationals, and the recurrences use a few dozen
// operations, so 1e-14 relative covers round-off with a wide margin while any
// wrong rule is off by O(1).

fn xy(l: &Rc<Layout>, x0: f64, y0: f64) -> (Jet<f64>, Jet<f64>) {
    (Jet::variable(l, 0, x0), Jet::variable(l, 1, y0))
}

fn binom(n: u32, k: u32) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

#[test]
fn layout_counts() {
    // C(n + D, D) monomials
    assert_eq!(Layout::get(6, 6).len(), 924);
    assert_eq!(Layout::get(3, 8).len(), 165);
}

#[test]
fn product_rule_binomial() {
    // (1 + x + y)^5 = sum 5!/(i! j! k!) x^i y^j
    let l = Layout::get(2, 5);
    let (x, y) = xy(&l, 0.0, 0.0);
    let s = Jet::cst(1.0) + x + y;
    let p = s.clone() * s.clone() * s.clone() * s.clone() * s;
    for i in 0..=5u8 {
        for j in 0..=(5 - i) {
            let exact = binom(5, i as u32) * binom(5 - i as u32, j as u32);
            assert_relative_eq!(p.coeff(&[i, j]), exact, max_relative = 1e-14);
        }
    }
}

#[test]
fn quotient_and_reciprocal_rules_geometric() {
    // 1/(1 - x - y) = sum (i+j)!/(i! j!) x^i y^j ; x/(1 - x - y) shifts it by one in x.
    let l = Layout::get(2, 6);
    let (x, y) = xy(&l, 0.0, 0.0);
    let d = Jet::cst(1.0) - x.clone() - y;
    let r = d.recip();
    let q = x / d;
    for i in 0..=6u8 {
        for j in 0..=(6 - i) {
            let exact = binom((i + j) as u32, i as u32);
            assert_relative_eq!(r.coeff(&[i, j]), exact, max_relative = 1e-14);
            if i >= 1 {
                let e2 = binom((i + j - 1) as u32, (i - 1) as u32);
                assert_relative_eq!(q.coeff(&[i, j]), e2, max_relative = 1e-14);
            }
        }
    }
}

#[test]
fn sqrt_rule_binomial_series() {
    // sqrt(4 + x) = 2 sqrt(1 + x/4) = 2 sum binom(1/2, k) (x/4)^k
    let l = Layout::get(1, 8);
    let x = Jet::variable(&l, 0, 4.0);
    let s = x.sqrt();
    let mut b = 1.0; // binom(1/2, k)
    for k in 0..=8u8 {
        if k > 0 {
            b *= (0.5 - (k - 1) as f64) / k as f64;
        }
        let exact = 2.0 * b / 4f64.powi(k as i32);
        assert_relative_eq!(s.coeff(&[k]), exact, max_relative = 1e-14);
    }
}

#[test]
fn power_rule_inverse_distance() {
    // (1 + x^2 ... ) : f(x, y) = (x^2 + y^2)^(-1/2) about (1, 0): along x it is 1/x,
    // whose coefficients are (-1)^k; along y it is (1 + y^2)^(-1/2).
    let l = Layout::get(2, 8);
    let (x, y) = xy(&l, 1.0, 0.0);
    let s = x.clone() * x + y.clone() * y;
    let f = s.powf(-0.5, 1.0);
    let mut b = 1.0; // binom(-1/2, k)
    for k in 0..=8u8 {
        assert_relative_eq!(
            f.coeff(&[k, 0]),
            (-1f64).powi(k as i32),
            max_relative = 1e-14
        );
        if k % 2 == 0 && k > 0 {
            let kk = (k / 2) as i32;
            b *= (-0.5 - (kk - 1) as f64) / kk as f64;
            assert_relative_eq!(f.coeff(&[0, k]), b, max_relative = 1e-14);
        }
    }
    // mixed: d^2/dx dy of (x^2+y^2)^(-1/2) at (1,0) is 0; d^3/dx dy^2 = 3 (3x^2 ... ) check
    // against the closed form d^2/dy^2 r^-1 = (2y^2 - x^2)/r^5 -> d/dx at (1,0): 3.
    assert_relative_eq!(f.derivative(&[1, 2]), 3.0, max_relative = 1e-14);
}

#[test]
fn integer_powers_both_signs() {
    // (2 + x)^3 and (2 + x)^-3 against the binomial theorem
    let l = Layout::get(1, 6);
    let x = Jet::variable(&l, 0, 2.0);
    let p = x.powi(3);
    let n = x.powi(-3);
    for k in 0..=6u8 {
        let e3 = if k <= 3 {
            binom(3, k as u32) * 2f64.powi(3 - k as i32)
        } else {
            0.0
        };
        assert_relative_eq!(p.coeff(&[k]), e3, max_relative = 1e-14);
        // binom(-3, k) = (-1)^k binom(k+2, 2)
        let en = (-1f64).powi(k as i32) * binom(k as u32 + 2, 2) * 2f64.powi(-3 - k as i32);
        assert_relative_eq!(n.coeff(&[k]), en, max_relative = 1e-14);
    }
}

#[test]
fn exp_and_erfc_rules_taylor_series_at_zero() {
    // e^x = sum x^k / k!; erfc x = 1 - (2/sqrt(pi)) sum_n (-1)^n x^(2n+1) / (n! (2n+1))
    let l = Layout::get(1, 9);
    let x = Jet::variable(&l, 0, 0.0);
    let (e, c) = (x.exp(), x.erfc());
    let mut fact = 1.0;
    for k in 0..=9u8 {
        if k > 0 {
            fact *= k as f64;
        }
        assert_relative_eq!(e.coeff(&[k]), 1.0 / fact, max_relative = 1e-14);
        let want = match k {
            0 => 1.0,
            _ if k % 2 == 0 => 0.0,
            _ => {
                let n = (k - 1) / 2;
                let nf: f64 = (1..=n as u32).map(f64::from).product();
                -std::f64::consts::FRAC_2_SQRT_PI * (-1f64).powi(n as i32)
                    / (nf * (2 * n + 1) as f64)
            }
        };
        assert_relative_eq!(c.coeff(&[k]), want, max_relative = 1e-14);
    }
}

/// `d^m f` at `p` by the tensor product of the central stencils of
/// [`kernel_gen::physics::fd`] with step `h`, in double-double.
fn finite_difference(f: fn(&[Dd]) -> Dd, p: &[f64], m: &[u8], h: f64) -> Dd {
    let stencils: Vec<Vec<(i32, f64)>> = m
        .iter()
        .map(|&n| kernel_gen::physics::fd::stencil(n))
        .collect();
    let mut acc = Dd::new(0.0);
    let mut idx = vec![0usize; m.len()];
    'odometer: loop {
        let mut w = 1.0;
        let q: Vec<Dd> = (0..m.len())
            .map(|v| {
                let (o, wv) = stencils[v][idx[v]];
                w *= wv;
                Dd::new(p[v]) + Dd::new(h) * Dd::new(o as f64)
            })
            .collect();
        acc = acc + Dd::new(w) * f(&q);
        for v in 0..m.len() {
            idx[v] += 1;
            if idx[v] < stencils[v].len() {
                continue 'odometer;
            }
            idx[v] = 0;
        }
        break;
    }
    let n: i32 = m.iter().map(|&e| e as i32).sum();
    acc / Dd::new(h).powi(n)
}

/// The exponential and erfc rules in two variables, every derivative up to order 4
/// of `e^{-(x^2 + x y)}` and `erfc(x y + x)` (jets of double-double), against finite
/// differences in double-double: second-order stencils with `h = 1e-4` leave a
/// truncation error of about `h^2` times the next derivatives (`1e-8` here) and a
/// round-off of `eps_dd / h^4 = 1e-16`; 1e-6 of the largest derivative covers it,
/// and a wrong weight is off by O(1).
#[test]
fn exp_and_erfc_rules_against_finite_differences() {
    let gauss = |v: &[Dd]| -> Dd { (-(v[0] * v[0] + v[0] * v[1])).exp() };
    let screen = |v: &[Dd]| -> Dd { (v[0] * v[1] + v[0]).erfc() };
    let p = [0.4, -0.7];
    let l = Layout::get(2, 4);
    let x = Jet::variable(&l, 0, Dd::new(p[0]));
    let y = Jet::variable(&l, 1, Dd::new(p[1]));
    let jets = [
        (-(x.clone() * x.clone() + x.clone() * y.clone())).exp(),
        (x.clone() * y + x).erfc(),
    ];
    let fs: [fn(&[Dd]) -> Dd; 2] = [gauss, screen];
    for (jet, f) in jets.iter().zip(fs) {
        let fd: Vec<(Dd, Dd)> = l
            .monos
            .iter()
            .map(|m| (jet.derivative(m), finite_difference(f, &p, m, 1e-4)))
            .collect();
        let scale = fd.iter().map(|(_, b)| b.to_f64().abs()).fold(0.0, f64::max);
        for (m, (a, b)) in l.monos.iter().zip(&fd) {
            let err = (*a - *b).to_f64().abs();
            assert!(err < 1e-6 * scale, "{m:?}: {a:?} vs {b:?}");
        }
    }
}

#[test]
fn nested_jets_and_expression_coefficients() {
    use kernel_gen::graph::Trace;
    // jets of expression nodes: d/dx (x^2 + x y) at symbolic (x0, y0) is 2 x0 + y0
    let t = Trace::begin();
    let x0 = t.input("x0");
    let y0 = t.input("y0");
    let l = Layout::get(2, 2);
    let x = Jet::variable(&l, 0, x0);
    let y = Jet::variable(&l, 1, y0);
    let f = x.clone() * x.clone() + x * y;
    let d = f.derivative(&[1, 0]);
    let g = t.finish();
    let v: Vec<f64> = g.eval(&[3.0, 5.0], &[d.0]);
    assert_eq!(v[0], 11.0);
}
