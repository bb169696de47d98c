//! The paper's closed forms as a kernel variant: the grand mobility blocks of one sphere
//! (Appendix B) or two equal spheres (Appendix C) above a no-slip wall at `x3 = 0`,
//! assembled in the kernels' layout (orthonormal strain basis, dimensional) from
//!
//! - the wall image: `integration_tests::paper::corrected` (the printed formulas with the
//!   errata of `docs/errata.md` corrected), which give `6 pi eta a^n` times the image
//!   part in the paper's Cartesian indices;
//! - the free-space part: `integration_tests::closed_forms` (Rotne-Prager-Yamakawa and
//!   the Durlofsky-Brady-Bossis / Kim-Karrila couplings) for pairs, and the isolated
//!   sphere (Eq. 17: `1/(6 pi eta a)`, `1/(8 pi eta a^3)`, `(6/5)/(8 pi eta a^3)`) for
//!   self terms, through `kernel_gen::physics::operators::isolated`.
//!
//! The appendices give UF, OF, OL, EF, EL, ES; UL, US and OS follow by reciprocity
//! (`M_UL^{ab} = (M_OF^{ba})^T`, `M_US^{ab} = (M_EF^{ba})^T`, `M_OS^{ab} = (M_EL^{ba})^T`).

use integration_tests::closed_forms as cf;
use integration_tests::paper::corrected as paper;
use kernel_gen::physics::operators::{isolated, Basis, BLOCKS};
use kernels::{basis_both, basis_cols, basis_rows};
use std::f64::consts::PI;

type T2 = [[f64; 3]; 3];
type T3 = [[[f64; 3]; 3]; 3];
type T4 = [[[[f64; 3]; 3]; 3]; 3];

/// The six blocks of the appendices (Cartesian) for the field sphere at `xa` and the
/// source at `xb` (units of `a`), image part only, in the paper's normalisation.
struct Image {
    uf: T2,
    of: T2,
    ol: T2,
    ef: T3,
    el: T3,
    es: T4,
}

fn image_self(h: f64) -> Image {
    Image {
        uf: paper::b1_uf(h),
        of: paper::b2_of(h),
        ol: paper::b3_ol(h),
        ef: paper::b4_ef(h),
        el: paper::b5_el(h),
        es: paper::b6_es(h),
    }
}

fn image_pair(xa: [f64; 3], xb: [f64; 3]) -> Image {
    Image {
        uf: paper::c2_uf(xa, xb),
        of: paper::c3_of(xa, xb),
        ol: paper::c4_ol(xa, xb),
        ef: paper::c5_ef(xa, xb),
        el: paper::c6_el(xa, xb),
        es: paper::c7_es(xa, xb),
    }
}

fn transpose<const R: usize, const C: usize>(m: &[[f64; C]; R]) -> [[f64; R]; C] {
    std::array::from_fn(|j| std::array::from_fn(|i| m[i][j]))
}

fn scaled<const R: usize, const C: usize>(m: [[f64; C]; R], s: f64) -> [[f64; C]; R] {
    m.map(|r| r.map(|v| v * s))
}

/// The nine blocks from `ab` (field a, source b) and `ba`, flattened in the kernels'
/// order, each image block divided by `6 pi eta a^n`.
fn assemble(ab: &Image, ba: &Image, a: f64, eta: f64) -> Vec<f64> {
    let n = |k: i32| 1.0 / (6.0 * PI * eta * a.powi(k));
    let uf = scaled(ab.uf, n(1));
    let of = scaled(ab.of, n(2));
    let ol = scaled(ab.ol, n(3));
    let ef = scaled(basis_rows(&ab.ef), n(2));
    let el = scaled(basis_rows(&ab.el), n(3));
    let es = scaled(basis_both(&ab.es), n(3));
    let ul = transpose(&scaled(ba.of, n(2)));
    let us = transpose(&scaled(basis_rows(&ba.ef), n(2)));
    let os = transpose(&scaled(basis_rows(&ba.el), n(3)));
    let mut v = Vec::with_capacity(121);
    let mut push = |rows: &[&[f64]]| rows.iter().for_each(|r| v.extend_from_slice(r));
    push(&uf.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ul.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&us.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&of.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ol.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&os.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ef.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&el.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&es.iter().map(|r| &r[..]).collect::<Vec<_>>());
    v
}

fn add(v: &mut [f64], w: &[f64]) {
    for (x, y) in v.iter_mut().zip(w) {
        *x += y;
    }
}

/// The self blocks of a sphere of radius `a` centred at `x` above the wall `x3 = 0`:
/// isolated sphere plus Appendix B (Eq. 17).
pub fn self_blocks(x: [f64; 3], a: f64, eta: f64) -> Vec<f64> {
    let img = image_self(x[2] / a);
    let mut v = assemble(&img, &img, a, eta);
    let c = 1.0 / (8.0 * PI * eta);
    let iso: Vec<f64> = BLOCKS
        .iter()
        .flat_map(|&(r, m)| isolated(r, m, Basis::Orthonormal, &a).into_iter().flatten())
        .map(|e| e * c)
        .collect();
    add(&mut v, &iso);
    v
}

/// The pair blocks `M^{ab}` of two spheres of radius `a` above the wall `x3 = 0`:
/// free-space closed forms plus Appendix C.
pub fn pair_blocks(xa: [f64; 3], xb: [f64; 3], a: f64, eta: f64) -> Vec<f64> {
    let (ua, ub) = (xa.map(|c| c / a), xb.map(|c| c / a));
    let mut v = assemble(&image_pair(ua, ub), &image_pair(ub, ua), a, eta);
    let r = [xa[0] - xb[0], xa[1] - xb[1], xa[2] - xb[2]];
    let mut free = Vec::with_capacity(121);
    let mut push = |rows: &[&[f64]]| rows.iter().for_each(|r| free.extend_from_slice(r));
    let uf = cf::uf(r, a, a, eta);
    let ul = cf::ul(r, a, a, eta);
    let us = basis_cols(&cf::us(r, a, a, eta));
    let of = cf::of(r, a, a, eta);
    let ol = cf::ol(r, a, a, eta);
    let os = basis_cols(&cf::os(r, a, a, eta));
    let ef = basis_rows(&cf::ef(r, a, a, eta));
    let el = basis_rows(&cf::el(r, a, a, eta));
    let es = basis_both(&cf::es(r, a, a, eta));
    push(&uf.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ul.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&us.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&of.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ol.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&os.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&ef.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&el.iter().map(|r| &r[..]).collect::<Vec<_>>());
    push(&es.iter().map(|r| &r[..]).collect::<Vec<_>>());
    add(&mut v, &free);
    v
}
