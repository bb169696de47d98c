//! The closed forms that carry the singular terms `1/xi`, `ln(1/xi)` and `xi ln(1/xi)`
//! of every function exactly (module docs of [`crate::two_sphere`]), at one
//! separation, and their Taylor coefficients in `t = 2/s'`.

use super::check_lambda;
use super::functions::FUNCTIONS;
use super::TwoSphereError;

/// The closed forms carrying the singular terms (module docs) at one separation, for the
/// functions at any size ratio: the two spheres of a pair see the same separation and
/// inverse ratios, and share these (three logarithms).
pub struct SingularForms(Geometry);

impl SingularForms {
    /// The closed forms at `s_dash > 2`.
    pub fn new(s_dash: f64) -> Result<Self, TwoSphereError> {
        Geometry::new(s_dash).map(SingularForms)
    }

    /// `ln xi = ln(s' - 2)`.
    pub fn ln_gap(&self) -> f64 {
        self.0.ln_xi
    }

    /// The singular parts `h . S(t)` of the first `count` functions at `lambda`: the
    /// closed forms times their coefficients ([`super::singular_coefficients`]); the
    /// others zero. With [`super::PairSeries::regular`] they add up to
    /// [`super::PairSeries::scalars`], bit for bit.
    pub fn parts(&self, lambda: f64, count: usize) -> Result<[f64; 22], TwoSphereError> {
        check_lambda(lambda)?;
        Ok(self.sums(count, |k| (FUNCTIONS[k].singular)(lambda)))
    }

    /// [`SingularForms::parts`] from the coefficients of [`super::singular_coefficients`],
    /// computed once for a size ratio: the same numbers, bit for bit.
    pub fn parts_from(&self, coefficients: &[[f64; 3]; 22], count: usize) -> [f64; 22] {
        self.sums(count, |k| coefficients[k])
    }

    /// `h . S(t)` of the first `count` functions, `h` of function `k` from
    /// `coefficient(k)`; the others zero.
    fn sums(&self, count: usize, coefficient: impl Fn(usize) -> [f64; 3]) -> [f64; 22] {
        std::array::from_fn(|k| {
            if k < count {
                singular_part(k, &coefficient(k), &self.0)
            } else {
                0.0
            }
        })
    }
}

/// `h . S(t)` of function `k`.
#[inline]
pub(super) fn singular_part(k: usize, h: &[f64; 3], geo: &Geometry) -> f64 {
    let closed = if FUNCTIONS[k].odd { geo.odd } else { geo.even };
    h[0] * closed[0] + h[1] * closed[1] + h[2] * closed[2]
}

/// `t = 2/s'` and the closed-form singular functions, written in `xi = s' - 2` so that
/// nothing cancels near contact: `1 - t^2 = xi (4 + xi)/(2 + xi)^2`.
pub(super) struct Geometry {
    /// `ln xi`
    ln_xi: f64,
    pub(super) t: f64,
    /// `[1/(1-t^2), -ln(1-t^2), -(1-t^2) ln(1-t^2)]`
    even: [f64; 3],
    /// `[t/(1-t^2), ln((1+t)/(1-t)), (1-t^2) ln((1+t)/(1-t))]`
    odd: [f64; 3],
}

impl Geometry {
    pub(super) fn new(s_dash: f64) -> Result<Self, TwoSphereError> {
        if !(s_dash.is_finite() && s_dash > 2.0) {
            return Err(TwoSphereError::Separation(s_dash));
        }
        let xi = s_dash - 2.0; // exact for s' in (2, 4] (Sterbenz)
        let t = 2.0 / s_dash;
        let one_m_t2 = xi * (4.0 + xi) / (s_dash * s_dash);
        let (ln_xi, ln_4_xi) = (xi.ln(), (4.0 + xi).ln());
        let mln = -(ln_xi + ln_4_xi - 2.0 * s_dash.ln()); // -ln(1 - t^2)
        let lnr = ln_4_xi - ln_xi; // ln((1+t)/(1-t)) = ln((s'+2)/(s'-2))
        Ok(Geometry {
            ln_xi,
            t,
            even: [1.0 / one_m_t2, mln, one_m_t2 * mln],
            odd: [t / one_m_t2, lnr, one_m_t2 * lnr],
        })
    }
}

/// Taylor coefficient of `t^m` in the closed forms (index 0, 1, 2 as in [`Geometry`]).
pub(super) fn singular_taylor(parity_odd: bool, m: usize) -> [f64; 3] {
    let mf = m as f64;
    if parity_odd {
        let s3 = if m == 1 {
            2.0
        } else {
            -4.0 / (mf * (mf - 2.0))
        };
        [1.0, 2.0 / mf, s3]
    } else if m == 0 {
        [1.0, 0.0, 0.0]
    } else {
        let s3 = if m == 2 {
            1.0
        } else {
            -4.0 / (mf * (mf - 2.0))
        };
        [1.0, 2.0 / mf, s3]
    }
}
