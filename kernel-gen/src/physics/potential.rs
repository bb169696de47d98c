//! The far field of a Green's function as derivatives of one scalar potential: what a
//! fast multipole method expands.
//!
//! The Stokeslet is a second derivative of the biharmonic potential `phi(r) = |r|`,
//! `J_ab(r) = (delta_ab lap - d_a d_b) phi(r)` (`lap |r| = 2/|r|`, `d_a d_b |r| =
//! delta_ab/|r| - r_a r_b/|r|^3`), and every image term of a confinement
//! ([`ImageTerm`], `c w h^p d'^gamma J'_ab(R')` with `R = x - y*` and `h = n.y - offset`)
//! is a derivative of the same potential at the image point `y*`, weighted by powers of
//! `h`. So is what the multipole functional at the source (Eq. 8: `(1 + a^2/6 lap_y)` for
//! the force, the half curl for the torque) makes of them: a derivative in `y` of a
//! function of `x - y` is minus the derivative in `x`, and of a term at the image point
//! (Eq. 10, for any normal `n`)
//!
//! `d_{y_m} [h^p f(R)] = p n_m h^(p-1) f(R) - h^p P_mq d_q f(R)`, `P = I - 2 n n`.
//!
//! The far field of a source `b` with moments `m_l` at a field point `x` is therefore,
//! row `k` of `G` (the velocity before the field point's Faxén functional),
//!
//! `Psi_k(x) = sum c w_j h^p a_b^(2 s) m_l d_x^alpha phi(x - y_point)`,
//!
//! one [`PotentialSource`] per term, `y_point` the source itself or its image in one
//! mirror. A fast multipole method expands these derivative sources (their moments are
//! those of point sources shifted by `alpha`) and applies the field point's Faxén
//! functional ([`super::operators::field`]) to the local expansion of `Psi`. This module
//! derives the terms from a Green's function's declaration alone; a Green's function
//! with a reflected field but no image structure, or with another potential than the
//! Stokeslet's ([`Green::radial`]), has none ([`NoExpansion`]).

use super::green::{Green, ImageTerm, Mat3};
use super::operators::{self, Basis, Moment};
use std::collections::BTreeMap;

/// One derivative source of the potential `phi(r) = |r|`: the field of source moment
/// component `moment` in row `channel` of `G` holds
/// `coef * w[weight] * h^h_power * a^(2 a2) * m[moment] * d_x^d phi(x - y_point)`,
/// where `y_point` is the source (`point = 0`) or its image in mirror `point - 1`
/// ([`Green::mirrors`]), `h` the source's signed distance from that mirror (its power 0
/// for `point = 0`), `w` the Green's function's weights ([`Green::weights`]; none for
/// `point = 0`) and `a` the source's radius. The Faxén factors (`1/6`) are in `coef`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PotentialSource {
    /// Row of `G` (world frame): the component of the velocity field.
    pub channel: usize,
    /// Component of the source's moments (forces `0..3`, then torques `3..6`).
    pub moment: usize,
    /// 0: the source; `1 + k`: its image in mirror `k`.
    pub point: usize,
    /// Index into [`Green::weights`] (`None` for the source itself).
    pub weight: Option<usize>,
    /// Power of `h`.
    pub h_power: u8,
    /// Power of `a^2`.
    pub a2: u8,
    /// Derivative multi-index in `x` (world frame).
    pub d: [u8; 3],
    /// Coefficient.
    pub coef: f64,
}

/// Why a Green's function has no expansion in derivative sources.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NoExpansion {
    /// Its reflected field is declared as ordinary Rust only, without image terms.
    NoImageTerms,
    /// Its terms are made of another potential than the Stokeslet's `|r|`.
    OtherPotential,
}

impl std::fmt::Display for NoExpansion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoExpansion::NoImageTerms => {
                write!(
                    f,
                    "its reflected field has no image terms (Green::image_terms)"
                )
            }
            NoExpansion::OtherPotential => write!(
                f,
                "it is made of another potential than the Stokeslet's (Green::radial)"
            ),
        }
    }
}

/// A term of a field before the moments: `(point, weight, h_power, a2, d)`.
type Key = (usize, Option<usize>, u8, u8, [u8; 3]);

/// A linear combination of derivatives of `phi` at the source or its images.
#[derive(Clone, Debug, Default)]
struct Field(BTreeMap<Key, f64>);

impl Field {
    fn one(point: usize, weight: Option<usize>, h_power: u8, coef: f64) -> Field {
        let mut m = BTreeMap::new();
        m.insert((point, weight, h_power, 0, [0; 3]), coef);
        Field(m)
    }

    fn add(&mut self, other: &Field, scale: f64) {
        if scale == 0.0 {
            return;
        }
        for (k, v) in &other.0 {
            *self.0.entry(*k).or_insert(0.0) += scale * v;
        }
    }

    /// `d_{x_m}`.
    fn dx(&self, m: usize) -> Field {
        Field(
            self.0
                .iter()
                .map(|(&(p, w, h, a2, mut d), &c)| {
                    d[m] += 1;
                    ((p, w, h, a2, d), c)
                })
                .collect(),
        )
    }

    /// The derivative along `v` (world frame), `sum_m v_m d_{x_m}`.
    fn along(&self, v: [f64; 3]) -> Field {
        let mut f = Field::default();
        for (m, &c) in v.iter().enumerate() {
            if c != 0.0 {
                f.add(&self.dx(m), c);
            }
        }
        f
    }

    /// `d_{y_m}`: minus `d_{x_m}` at the source; at an image (mirror normals `normals`),
    /// the rule of Eq. 10 in the module's documentation.
    fn dy(&self, m: usize, normals: &[[f64; 3]]) -> Field {
        let mut f = Field::default();
        for (&(p, w, h, a2, d), &c) in &self.0 {
            let mut single = Field::default();
            single.0.insert((p, w, h, a2, d), c);
            if p == 0 {
                f.add(&single.dx(m), -1.0);
                continue;
            }
            let n = normals[p - 1];
            if h > 0 && n[m] != 0.0 {
                f.0.entry((p, w, h - 1, a2, d))
                    .and_modify(|v| *v += c * h as f64 * n[m])
                    .or_insert(c * h as f64 * n[m]);
            }
            // - P_mq d_q, P = I - 2 n n
            let row: [f64; 3] = std::array::from_fn(|q| {
                let delta = if q == m { 1.0 } else { 0.0 };
                -(delta - 2.0 * n[m] * n[q])
            });
            f.add(&single.along(row), 1.0);
        }
        f
    }

    /// The Stokeslet component `J_ab = (delta_ab lap - d_a d_b) phi` applied to this
    /// field, `a` and `b` along the directions `ea`, `eb` (world frame).
    fn stokeslet(&self, ea: [f64; 3], eb: [f64; 3]) -> Field {
        let mut f = Field::default();
        let dot: f64 = (0..3).map(|k| ea[k] * eb[k]).sum();
        if dot != 0.0 {
            for m in 0..3 {
                f.add(&self.dx(m).dx(m), dot);
            }
        }
        f.add(&self.along(ea).along(eb), -1.0);
        f
    }
}

fn axis(k: usize) -> [f64; 3] {
    std::array::from_fn(|m| if m == k { 1.0 } else { 0.0 })
}

/// Row `a` of the frame `q` (an axis of the plane's frame in the world).
fn row(q: &Mat3<f64>, a: usize) -> [f64; 3] {
    q[a]
}

/// `G_kj` (world frame) as derivatives of `phi`: the Stokeslet at the source, each image
/// term at its image point.
fn green_fields(terms: &[ImageTerm], frames: &[Mat3<f64>]) -> [[Field; 3]; 3] {
    let mut g: [[Field; 3]; 3] = Default::default();
    for (k, row_k) in g.iter_mut().enumerate() {
        for (j, gkj) in row_k.iter_mut().enumerate() {
            *gkj = Field::one(0, None, 0, 1.0).stokeslet(axis(k), axis(j));
        }
    }
    for t in terms {
        let q = &frames[t.plane];
        // d'^gamma J'_ab(R'), the plane's axes as world directions
        let mut f = Field::one(1 + t.plane, Some(t.weight), t.h_power, t.coef);
        for (axis_index, &n) in t.d.iter().enumerate() {
            for _ in 0..n {
                f = f.along(row(q, axis_index));
            }
        }
        let f = f.stokeslet(row(q, t.j.0), row(q, t.j.1));
        // J^w = Q^T J^w' Q: world (k, j) takes Q_{i k} Q_{l j} of the plane's (i, l)
        let (i, l) = t.out;
        for (k, row_k) in g.iter_mut().enumerate() {
            for (j, gkj) in row_k.iter_mut().enumerate() {
                gkj.add(&f, q[i][k] * q[l][j]);
            }
        }
    }
    g
}

/// Row `k` of the far field of each source moment component `l`, `G` under the
/// multipole functional at the source (Eq. 8), as derivatives of `phi` (keyed `(k, l)`),
/// and the mirrors' normals.
#[allow(clippy::type_complexity)]
fn moment_fields<G: Green>(
    g: &G,
    moments: &[Moment],
) -> Result<(BTreeMap<(usize, usize), Field>, Vec<[f64; 3]>), NoExpansion> {
    let terms = g.image_terms().ok_or(NoExpansion::NoImageTerms)?;
    if super::green::is_radial(g) {
        return Err(NoExpansion::OtherPotential);
    }
    let examples = super::green::examples(g);
    let mirrors = g.mirrors(&examples);
    let frames: Vec<Mat3<f64>> = mirrors.iter().map(|m| m.frame()).collect();
    let normals: Vec<[f64; 3]> = mirrors.iter().map(|m| m.normal).collect();
    let gk = green_fields(&terms, &frames);
    let mut out: BTreeMap<(usize, usize), Field> = BTreeMap::new();
    let mut offset = 0;
    for &m in moments {
        let fb = operators::faxen(match m {
            Moment::F => operators::Response::U,
            Moment::L => operators::Response::Omega,
            Moment::S => operators::Response::E,
        });
        for (l, sides) in operators::source(m, Basis::Orthonormal).iter().enumerate() {
            for (k, gk_row) in gk.iter().enumerate() {
                let mut f = Field::default();
                for s in sides {
                    let mut d = gk_row[s.comp].clone();
                    for (axis_index, &n) in s.d.iter().enumerate() {
                        for _ in 0..n {
                            d = d.dy(axis_index, &normals);
                        }
                    }
                    let d = Field(
                        d.0.into_iter()
                            .map(|((p, w, h, a2, dd), c)| ((p, w, h, a2 + s.a2, dd), c))
                            .collect(),
                    );
                    f.add(&d, s.coef * fb.powi(s.a2 as i32));
                }
                out.entry((k, offset + l)).or_default().add(&f, 1.0);
            }
        }
        offset += operators::moment_dim(m, Basis::Orthonormal);
    }
    Ok((out, normals))
}

/// Below this fraction of the largest coefficient of the far field's own sources, a
/// coefficient is the round-off of terms that cancel (the coefficients are sums of
/// products of small rationals, image weights' factors and frames' entries, all of size
/// one).
const CANCELLED: f64 = 1e-12;

/// The largest coefficient of `fields`.
fn largest(fields: &BTreeMap<(usize, usize), Field>) -> f64 {
    fields
        .values()
        .flat_map(|f| f.0.values())
        .fold(0.0f64, |m, c| m.max(c.abs()))
}

/// The rows of `fields` (keyed `(channel, moment)`), every coefficient that cancels
/// dropped (below [`CANCELLED`] times `scale`, the size of the terms they were summed
/// from), in the order of [`PotentialSource`]'s fields.
fn rows(fields: BTreeMap<(usize, usize), Field>, scale: f64) -> Vec<PotentialSource> {
    let mut out: BTreeMap<(usize, usize, Key), f64> = BTreeMap::new();
    for ((k, l), f) in fields {
        for (key, c) in f.0 {
            *out.entry((k, l, key)).or_insert(0.0) += c;
        }
    }
    out.into_iter()
        .filter(|(_, c)| c.abs() > CANCELLED * scale)
        .map(
            |((channel, moment, (point, weight, h_power, a2, d)), coef)| PotentialSource {
                channel,
                moment,
                point,
                weight,
                h_power,
                a2,
                d,
                coef,
            },
        )
        .collect()
}

/// The derivative sources of `g`'s far field for the source moments `moments` (forces;
/// forces and torques), in the order of [`PotentialSource`]'s fields, with every
/// coefficient that cancels dropped.
pub fn potential_sources<G: Green>(
    g: &G,
    moments: &[Moment],
) -> Result<Vec<PotentialSource>, NoExpansion> {
    let fields = moment_fields(g, moments)?.0;
    let scale = largest(&fields);
    Ok(rows(fields, scale))
}

/// The derivative sources of the far field's divergence over the source's position,
/// `sum_l d_{y_l} Psi_k[m_l = 1]` (the Brownian drift's pair terms, `sum_l d M_kl /
/// d y_l`): each force column's field differentiated by Eq. 10 and summed. Every row
/// has `moment = 0` and stands for a unit source (a sphere's own weight, such as a
/// damping factor, goes there). The free-space Stokeslet is divergence-free in `y`, so
/// what remains are image terms.
pub fn divergence_sources<G: Green>(g: &G) -> Result<Vec<PotentialSource>, NoExpansion> {
    let (fields, normals) = moment_fields(g, &[Moment::F])?;
    let scale = largest(&fields);
    let mut div: BTreeMap<(usize, usize), Field> = BTreeMap::new();
    for ((k, l), f) in fields {
        div.entry((k, 0)).or_default().add(&f.dy(l, &normals), 1.0);
    }
    Ok(rows(div, scale))
}
