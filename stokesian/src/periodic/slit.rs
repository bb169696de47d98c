//! The Rotne-Prager-Yamakawa mobility of spheres in a slit between two parallel no-slip
//! walls, `x3 = z0` and `x3 = z0 + H`, in a box periodic along them (`Lx`, `Ly`, area
//! `A`), with the slit's exact Green's function: the Stokeslet plus the flow `W` that
//! cancels it on both walls, lateral mode by lateral mode.
//!
//! The Green's function is `G = J + W` (units of `1/(8 pi eta)`, `J = I/r + r r/r^3`), and
//! `W = B_0 + B_H + R`: the two walls' Blake images (each cancels `J` on its own wall) and
//! the remainder `R`, the flow of the images' images, which decays like `e^{-kappa (2 H -
//! |h_a - h_b|)}` in lateral wave number `kappa` (the double reflections lie at least `H
//! + 2a` from the field point). So the mobility is the lower wall's periodic sum
//! ([`WallEwald`]: `J` and `B_0` by Ewald summation), the upper wall's (the same in the
//! mirror `z' = z0 + H - z`, its blocks mirrored back: velocities and forces are vectors,
//! angular velocities and torques pseudovectors), less `J`'s sum that both hold (its real
//! part the generated screened Stokeslet `scene_ewald_real_ft`, its smooth part the wall's
//! reciprocal sum without the image), plus `R` in lateral modes and the mode `k_par = 0`:
//!
//! - **One mode of the Stokeslet.** In the frame `(khat, e3 x khat, e3)` of a lateral
//!   wave vector `k` (`kappa = |k|`), the lateral Fourier transform of `J` at height
//!   difference `s` is `Jhat(k, s) = (2 pi/kappa) e^{-kappa |s|} [[1 - kappa |s|, 0, -i
//!   kappa s], [0, 2, 0], [-i kappa s, 0, 1 + kappa |s|]]` (from `J = (I lap - grad
//!   grad) r` and the transform `-2 pi (1 + kappa |s|) e^{-kappa |s|}/kappa^3` of `r`).
//! - **One mode of `W`.** A homogeneous Stokes flow `u e^{i k . x}` in the gap: the
//!   component along `e3 x khat` (no pressure) is `v = alpha e^{-kappa z} + beta
//!   e^{-kappa (H - z)}`; the normal one solves `(d^2 - kappa^2)^2 w = 0`, `w = (A + B z)
//!   e^{-kappa z} + (C + D (H - z)) e^{-kappa (H - z)}`, and continuity gives the one
//!   along `khat`, `u_1 = i w'/kappa` (`z` measured from the lower wall). The six
//!   coefficients make `u = -Jhat(k, z_wall - y3)` on both walls (two 2 x 2 and 4 x 4
//!   real systems, one per `kappa`: the data are complex, the matrices real). Blake's
//!   image of one wall alone is the same flow with the other wall's terms left out (`v =
//!   v(0) e^{-kappa z}`, `A = w(0)`, `B = w'(0) + kappa A`); `R`'s coefficients are the
//!   difference.
//! - **Operators.** At the field point `i k` and `d/dz` (Faxén `1 + a^2/6 (d^2 -
//!   kappa^2)`, rotation `(1/2) curl`); at the source `-i k` and `d/dy3`, which acts on
//!   the walls' data (`Jhat` at `z_wall - y3`): the source's Faxén operator and rotlet
//!   are applied to the data before the solve (the flow is linear in them).
//! - **Truncation.** `R`'s modes within the smallest `kappa` with `e^{-kappa s} (1 +
//!   kappa H)^3 (1 + kappa^2 a^2/6)^2 <= tol/100`, `s = 2 H - |h_a - h_b|` (`h` the
//!   heights above the lower wall; the polynomial factors of the data, of the solve and
//!   of both Faxén operators); the walls' sums truncated as along one wall.
//! - **The mode `k_par = 0`** in closed form: a force sheet `F/A` at height `h_b`
//!   between no-slip walls drives the Couette profile `u = F (min(z, h_b) - z h_b/H)/(eta
//!   A)` along the walls (a normal force is taken by the pressure: no flow), `8 pi
//!   (min(h_a, h_b) - h_a h_b/H)/A` in units of `1/(8 pi eta)`. Each wall's sum holds its
//!   own, `8 pi min(h, h')` less the plane averages of its real parts; with `J`'s plane
//!   average `-4 pi |h_a - h_b| - Psi(h_a - h_b)` ([`super::wall`]'s `Psi`) the slit's is
//!   reached by adding `(I - e3 e3) f/A`, `f = -Psi(h_a - h_b) + 4 pi (h_a + h_b) - 8 pi
//!   (H + h_a h_b/H)` (entire), to which the operators in the heights give every FT
//!   block. As along one wall the mobility is the lattice sum itself: velocities relative
//!   to the walls, a net lateral force drives a bounded Couette flow.
//!
//! [`SlitEwald::blocks_by_modes`] evaluates the same sum with all of `W` in modes (no
//! image in real space, its own mode `k_par = 0`, `f = Psi(h_a - h_b) + 4 pi (h_a + h_b) -
//! 8 pi h_a h_b/H`): a second path for the tests, slower where a sphere is near a wall
//! (the modes of `W` decay only like `e^{-kappa (h_a + h_b)}`).
//!
//! Unlike the open slit of the kernels (`kernels::generated::slit`, two walls' images
//! superposed, Swan & Brady Sec. IV), this Green's function satisfies no slip on both
//! walls exactly; its far field along the walls is Hele-Shaw's (`rho^-2`), whose
//! lattice sum only the Fourier modes define (the mode `k_par = 0` above), and so the
//! periodic slit has no open counterpart among our kernels.

use super::wall::{lateral_waves, plane_blocks, plane_grand, Psi, WallEwald};
use super::wall_spectral::Layout;
use crate::system::input::Particle;
use kernels::generated::scene_ewald_real_ft::{ewald_real_ft_pair, ewald_real_ft_self};
use kernels::generated::scene_ewald_real_fts::{ewald_real_fts_pair, ewald_real_fts_self};
use kernels::{BlocksFT, Grand, STRAIN_BASIS};
use nalgebra::SMatrix;
use rustfft::num_complex::Complex64;
use std::borrow::Cow;
use std::f64::consts::PI;

/// The split and truncation of a slit periodic along its walls, at one tolerance.
#[derive(Clone, Debug)]
pub struct SlitEwald {
    /// The lower wall's periodic sum (the Stokeslet and Blake's image of `x3 = z0`); its
    /// split (`xi`, `r_c`, shifts) is the Stokeslet's too.
    pub(super) lower: WallEwald,
    /// The upper wall's, in the mirror `z' = z0 + H - z` (the wall at `z' = 0`).
    pub(super) upper: WallEwald,
    /// The gap `H` between the walls `x3 = z0` and `x3 = z0 + H`.
    pub gap: f64,
    /// The lateral modes of the remainder within the largest cut-off any pair of spheres
    /// in the gap asks for ([`SlitEwald::waves`]; radii at most `H/2`, so `s >= H`).
    remainder_waves: Vec<([f64; 2], f64)>,
}

type C = Complex64;

/// `[UF, UL, OmegaF, OmegaL]` in one frame, complex.
type Blocks = [[[C; 3]; 3]; 4];

/// The Stokeslet's transform and its derivatives in the source's height, `[m][row][column]`.
type Data<const N: usize> = [[[C; 3]; 3]; N];

/// Which part of the walls' flow `W` the lateral modes sum: all of it, or what is left
/// of it without the two walls' own Blake images (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Part {
    Whole,
    Remainder,
}

impl SlitEwald {
    /// The slit between `x3 = bottom` and `x3 = bottom + gap`, periodic with lateral
    /// `lengths`, at relative tolerance `tol`; `xi` chosen as along one wall or given.
    pub fn new(lengths: [f64; 2], bottom: f64, gap: f64, tol: f64, xi: Option<f64>) -> SlitEwald {
        let lower = WallEwald::new(lengths, bottom, tol, xi);
        let upper = WallEwald::new(lengths, 0.0, tol, Some(lower.xi));
        let mut slit = SlitEwald {
            lower,
            upper,
            gap,
            remainder_waves: Vec::new(),
        };
        // the smallest distance `2 H - |h_a - h_b| = H` and the largest radius `H/2`
        let widest = slit.mode_cutoff(0.0, gap, 0.5 * gap, 0.5 * gap, Part::Remainder, true);
        slit.remainder_waves = slit.waves(widest);
        slit
    }

    /// The lateral lengths `[Lx, Ly]`.
    pub fn lengths(&self) -> [f64; 2] {
        self.lower.lengths
    }

    /// The lower wall's plane `x3 = z0`.
    pub fn bottom(&self) -> f64 {
        self.lower.height
    }

    /// A sphere in the upper wall's mirror, `z' = z0 + H - z`.
    pub(super) fn mirrored(&self, p: &Particle) -> Particle {
        Particle {
            x: [p.x[0], p.x[1], self.lower.height + self.gap - p.x[2]],
            a: p.a,
        }
    }

    /// The FT blocks `M^{ab}` of spheres `a` (field) and `b` (source) summed over every
    /// lateral image of `b`; with `same`, `b` is `a` and the result its self mobility:
    /// the lower wall's periodic sum, the upper wall's (mirrored), less the Stokeslet's
    /// that both hold, the mode `k_par = 0` brought to the slit's, and the remainder's
    /// modes (module docs).
    pub fn blocks(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let mut out = self.lower.blocks(eta, a, b, same);
        let upper = self
            .upper
            .blocks(eta, &self.mirrored(a), &self.mirrored(b), same);
        out += &mirror(&upper);
        out -= &self.stokeslet_sum(eta, a, b, same);
        self.walls_flow(eta, a, b, same, Part::Remainder, &mut out);
        out
    }

    /// The same blocks with the walls' flow `W` summed in lateral modes alone (no image
    /// in real space): a second evaluation of the same sum, slower (the modes decay like
    /// `e^{-kappa s}` at the distance `s` to the nearer image instead of the remainder's
    /// `2 H - |h_a - h_b|`), which the tests compare with [`SlitEwald::blocks`].
    pub fn blocks_by_modes(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let mut out = self.stokeslet_sum(eta, a, b, same);
        self.walls_flow(eta, a, b, same, Part::Whole, &mut out);
        out
    }

    /// The FTS blocks (all nine, the 11 x 11 grand block) of spheres `a` (field) and `b`
    /// (source), as [`SlitEwald::blocks`]: the two walls' [`WallEwald::grand`] (the upper
    /// one mirrored, [`mirror_grand`]), less the Stokeslet's sum, the mode `k_par = 0` and
    /// the remainder's modes with their strain rows and stresslet columns
    /// ([`Gap::grand`]).
    pub fn grand(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> Grand {
        let mut out = self.lower.grand(eta, a, b, same).matrix();
        let upper = self
            .upper
            .grand(eta, &self.mirrored(a), &self.mirrored(b), same);
        out += mirror_grand(&upper.matrix());
        out -= self.stokeslet_sum_grand(eta, a, b, same);
        self.walls_flow_grand(eta, a, b, same, Part::Remainder, &mut out);
        Grand::from_matrix(&out)
    }

    /// The FTS blocks with the walls' flow `W` summed in lateral modes alone, as
    /// [`SlitEwald::blocks_by_modes`]: the tests' second evaluation of
    /// [`SlitEwald::grand`].
    pub fn grand_by_modes(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> Grand {
        let mut out = self.stokeslet_sum_grand(eta, a, b, same);
        self.walls_flow_grand(eta, a, b, same, Part::Whole, &mut out);
        Grand::from_matrix(&out)
    }

    /// [`SlitEwald::walls_flow`] of the FTS blocks.
    fn walls_flow_grand(
        &self,
        eta: f64,
        a: &Particle,
        b: &Particle,
        same: bool,
        part: Part,
        out: &mut SMatrix<f64, 11, 11>,
    ) {
        let (ha, hb) = (a.x[2] - self.lower.height, b.x[2] - self.lower.height);
        let unit = self.lower.unit(eta);
        plane_grand(
            &self.plane_kernel(self.lower.xi, ha, hb, part),
            a.a,
            b.a,
            unit,
            out,
        );
        let r = self.lower.minimum_image(a.x, b.x);
        let rho = if same { [0.0; 2] } else { [r[0], r[1]] };
        self.modes_grand(rho, ha, hb, a.a, b.a, unit, part, out);
    }

    /// [`SlitEwald::stokeslet_sum`] of the FTS blocks: the generated FTS kernels of the
    /// screened Stokeslet, the wall's reciprocal sum without its image.
    fn stokeslet_sum_grand(
        &self,
        eta: f64,
        a: &Particle,
        b: &Particle,
        same: bool,
    ) -> SMatrix<f64, 11, 11> {
        let w = &self.lower;
        let (mut out, r) = w.real_part(
            a,
            b,
            same,
            SMatrix::zeros(),
            |sigma| ewald_real_fts_self(a.x, a.a, eta, sigma).matrix(),
            |xb, sigma| ewald_real_fts_pair(a.x, xb, a.a, b.a, eta, sigma).matrix(),
        );
        let (ha, hb) = (a.x[2] - w.height, b.x[2] - w.height);
        w.reciprocal_grand([r[0], r[1]], ha, hb, a.a, b.a, eta, false, &mut out);
        out
    }

    /// The walls' flow `W` (or its remainder) in modes, with its mode `k_par = 0`, added
    /// to `out`.
    fn walls_flow(
        &self,
        eta: f64,
        a: &Particle,
        b: &Particle,
        same: bool,
        part: Part,
        out: &mut BlocksFT,
    ) {
        let (ha, hb) = (a.x[2] - self.lower.height, b.x[2] - self.lower.height);
        let unit = self.lower.unit(eta);
        plane_blocks(
            &self.plane_kernel(self.lower.xi, ha, hb, part),
            a.a,
            b.a,
            unit,
            out,
        );
        let r = self.lower.minimum_image(a.x, b.x);
        let rho = if same { [0.0; 2] } else { [r[0], r[1]] };
        self.modes(rho, ha, hb, a.a, b.a, unit, part, out);
    }

    /// The Stokeslet's lateral lattice sum but its mode `k_par = 0`: the real part (the
    /// isolated sphere and `W(0)` in the self kernel) and the reciprocal sum of `J^K`.
    fn stokeslet_sum(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let w = &self.lower;
        let (mut out, r) = w.real_part(
            a,
            b,
            same,
            BlocksFT::default(),
            |sigma| ewald_real_ft_self(a.x, a.a, eta, sigma),
            |xb, sigma| ewald_real_ft_pair(a.x, xb, a.a, b.a, eta, sigma),
        );
        let (ha, hb) = (a.x[2] - w.height, b.x[2] - w.height);
        w.reciprocal([r[0], r[1]], ha, hb, a.a, b.a, eta, false, &mut out);
        out
    }

    /// The derivatives `d_a^m d_b^n f` (`m, n < N <= 4`, indexed `[m][n]`) of the mode
    /// `k_par = 0`'s `f(h_a, h_b)` (module docs): with the whole of `W` in modes, `f =
    /// Psi(h_a - h_b) + 4 pi (h_a + h_b) - 8 pi h_a h_b/H`; beside the two walls' sums,
    /// what brings theirs to the slit's, `-Psi(h_a - h_b) + 4 pi (h_a + h_b) - 8 pi H - 8
    /// pi h_a h_b/H`.
    pub(super) fn plane_kernel<const N: usize>(
        &self,
        xi: f64,
        ha: f64,
        hb: f64,
        part: Part,
    ) -> [[f64; N]; N] {
        let psi = Psi::at(xi, ha - hb);
        let h = self.gap;
        let (sign_psi, constant) = match part {
            Part::Whole => (1.0, 0.0),
            Part::Remainder => (-1.0, -8.0 * PI * h),
        };
        std::array::from_fn(|m| {
            std::array::from_fn(|n| {
                let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                let polynomial = match (m, n) {
                    (0, 0) => 4.0 * PI * (ha + hb) - 8.0 * PI * ha * hb / h + constant,
                    (1, 0) => 4.0 * PI - 8.0 * PI * hb / h,
                    (0, 1) => 4.0 * PI - 8.0 * PI * ha / h,
                    (1, 1) => -8.0 * PI / h,
                    _ => 0.0,
                };
                sign_psi * sign * psi.0[m + n] + polynomial
            })
        })
    }

    /// The cut-off `k_W` of the modes of `W` (or of its remainder) for heights `ha`, `hb`
    /// and radii `aa`, `ab` (module docs), of the F and FT blocks; with `strains`, of the
    /// FTS blocks too, whose strain rows and stresslet columns carry one more derivative
    /// at each end (a factor `(1 + kappa a)^2` more).
    pub(super) fn mode_cutoff(
        &self,
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        part: Part,
        strains: bool,
    ) -> f64 {
        let h = self.gap;
        let s = match part {
            Part::Whole => (ha + hb).min(2.0 * h - ha - hb),
            Part::Remainder => 2.0 * h - (ha - hb).abs(),
        };
        let a = aa.max(ab);
        let c = a * a / 6.0;
        let target = (100.0 / self.lower.tolerance).ln();
        let strain = if strains { 2.0 } else { 0.0 };
        // kappa s = target + 3 ln(1 + kappa H) + 2 ln(1 + kappa^2 c) (+ 2 ln(1 + kappa a)),
        // by fixed point
        let mut kappa = target / s;
        for _ in 0..50 {
            let next = (target
                + 3.0 * (1.0 + kappa * h).ln()
                + 2.0 * (1.0 + kappa * kappa * c).ln()
                + strain * (1.0 + kappa * a).ln())
                / s;
            if (next - kappa).abs() <= 1e-12 * next {
                return next;
            }
            kappa = next;
        }
        kappa
    }

    /// The Brownian drift of sphere `p` (its translational rows), the column `d S_i3/dh`
    /// of its periodic self mobility `S(h)`, as along one wall
    /// ([`WallEwald::drift`]): the pairs of distinct spheres add nothing (the lattice sum
    /// is a reciprocal Green's function, divergence-free in its field point). Of the
    /// sphere's own terms, the two walls' sums give their drifts (the upper one's
    /// mirrored), the Stokeslet's none (it depends on differences of heights), the mode
    /// `k_par = 0` none (no third column), and the remainder's modes `sum_k (d_a + d_b)
    /// UF_i3` at `h_a = h_b = h`.
    pub fn drift(&self, eta: f64, p: &Particle) -> [f64; 3] {
        let mut out = self.lower.drift(eta, p);
        let upper = self.upper.drift(eta, &self.mirrored(p));
        out[0] += upper[0];
        out[1] += upper[1];
        out[2] -= upper[2];
        let h = p.x[2] - self.lower.height;
        let k_cut = self.mode_cutoff(h, h, p.a, p.a, Part::Remainder, false);
        let mut sum = [0.0; 3];
        let mut current = f64::NAN;
        let mut column = [C::new(0.0, 0.0); 3];
        for &(k, kappa) in self.remainder_waves.iter().take_while(|w| w.1 <= k_cut) {
            if kappa != current {
                column = Gap::new(kappa, self.gap).drift_column(h, p.a);
                current = kappa;
            }
            // column 3 of R X R^T: R X_{., 3}
            let (c, s) = (k[0] / kappa, k[1] / kappa);
            sum[0] += (column[0] * c - column[1] * s).re;
            sum[1] += (column[0] * s + column[1] * c).re;
            sum[2] += column[2].re;
        }
        let unit = self.lower.unit(eta);
        for (o, v) in out.iter_mut().zip(sum) {
            *o += 2.0 * unit * v;
        }
        out
    }

    /// The remainder's modes within `k_cut` (one of each pair `+-k_par`, in order of
    /// `kappa`).
    pub(super) fn remainder_modes(&self, k_cut: f64) -> impl Iterator<Item = [f64; 2]> + '_ {
        (self.remainder_waves.iter())
            .take_while(move |w| w.1 <= k_cut)
            .map(|w| w.0)
    }

    /// One mode `k` of the remainder `R` in a product (as [`SlitEwald::modes`], for the
    /// product's mode sum, [`super::low_modes::ModeSum`]): from the moments `q` (`[j][f]`,
    /// the fields of `layout`: `F`, `[a^2 F/6]`, `[L]`) of virtual sources at heights
    /// `t_j` above the lower wall, the field point's fields (`U`, `[lap U/6]`, `[Omega]`)
    /// at the same heights, `[i][f]`, times `1/(8 pi eta A)`. The flow is linear in the
    /// walls' data, so the sources' data are summed before the one solve.
    pub(super) fn remainder_nodal(
        &self,
        eta: f64,
        layout: Layout,
        k: [f64; 2],
        t: &[f64],
        q: &[C],
    ) -> Vec<C> {
        let nf = layout.fields();
        let kappa = (k[0] * k[0] + k[1] * k[1]).sqrt();
        let (c, s) = (k[0] / kappa, k[1] / kappa);
        let gap = Gap::new(kappa, self.gap);
        let scale = -2.0 * PI / kappa;
        let i = C::new(0.0, 1.0);
        let k2 = kappa * kappa;
        // frame components (khat, e3 x khat, e3) of a lateral-frame vector, and back
        let to_frame = |v: &[C]| [v[0] * c + v[1] * s, v[1] * c - v[0] * s, v[2]];
        let to_lab = |v: [C; 3]| [v[0] * c - v[1] * s, v[0] * s + v[1] * c, v[2]];
        let (o_cf, o_torque) = match layout.equal {
            Some(_) => (None, 3),
            None => (Some(3), 6),
        };
        let zero = C::new(0.0, 0.0);
        let (mut bottom, mut top) = ([zero; 3], [zero; 3]);
        for (j, &tj) in t.iter().enumerate() {
            let qj = &q[j * nf..(j + 1) * nf];
            let f = to_frame(&qj[0..3]);
            // the force's Faxén factor: (1 - c kappa^2) g0 + c g2, c a^2/6 (equal radii)
            // or the field a^2 F/6
            let cf = match (layout.equal, o_cf) {
                (Some(a), _) => f.map(|v| v * (a * a / 6.0)),
                (None, Some(o)) => to_frame(&qj[o..o + 3]),
                (None, None) => unreachable!("unequal radii carry a^2 F/6"),
            };
            let l = layout.ft.then(|| to_frame(&qj[o_torque..o_torque + 3]));
            let (lo, hi): (Data<3>, Data<3>) = (gap.stokeslet(tj, true), gap.stokeslet(tj, false));
            for (g, wall) in [(&lo, &mut bottom), (&hi, &mut top)] {
                for (r, w) in wall.iter_mut().enumerate() {
                    let mut v = zero;
                    for n in 0..3 {
                        v += g[0][r][n] * f[n] + (g[2][r][n] - g[0][r][n] * k2) * cf[n];
                    }
                    if let Some(l) = l {
                        // (1/2) eps_jnl D_n G_l, D = (-i kappa, 0, d/dy3) ([`Gap::blocks`])
                        v += -0.5 * g[1][r][1] * l[0]
                            + 0.5 * (g[1][r][0] + i * kappa * g[0][r][2]) * l[1]
                            - 0.5 * i * kappa * g[0][r][1] * l[2];
                    }
                    *w += v * scale;
                }
            }
        }
        let flow = gap.part(bottom, top, Part::Remainder);
        let unit = self.lower.unit(eta);
        let mut out = vec![zero; t.len() * nf];
        for (ti, o) in t.iter().zip(out.chunks_mut(nf)) {
            let (u0, omega) = gap.field(&flow, *ti, 0.0);
            let (u1, _) = gap.field(&flow, *ti, 1.0);
            // lap u = (u + 1 lap u) - u
            let lap: [C; 3] = std::array::from_fn(|d| u1[d] - u0[d]);
            let u = match layout.equal {
                Some(a) => std::array::from_fn(|d| u0[d] + lap[d] * (a * a / 6.0)),
                None => u0,
            };
            o[0..3].copy_from_slice(&to_lab(u).map(|v| v * unit));
            if layout.equal.is_none() {
                o[3..6].copy_from_slice(&to_lab(lap).map(|v| v * (unit / 6.0)));
            }
            if layout.ft {
                o[nf - 3..nf].copy_from_slice(&to_lab(omega).map(|v| v * unit));
            }
        }
        out
    }

    /// The lateral modes `k_par != 0` within `k_cut`, one of each pair `+-k_par`, in order
    /// of `kappa = |k_par|` (exact ties: `kappa^2` the same sum of the same squares), with
    /// `kappa`: the blocks in a mode's frame depend on `kappa` alone.
    fn waves(&self, k_cut: f64) -> Vec<([f64; 2], f64)> {
        let mut waves: Vec<([f64; 2], f64)> = lateral_waves(self.lower.lengths, k_cut)
            .map(|k| (k, (k[0] * k[0] + k[1] * k[1]).sqrt()))
            .collect();
        waves.sort_by(|x, y| x.1.total_cmp(&y.1));
        waves
    }

    /// The modes `k_par != 0` of `W` or of its remainder (module docs) of the FT blocks
    /// at lateral separation `rho`, heights `ha`, `hb` above the lower wall, radii `aa`,
    /// `ab`, times `unit = 1/(8 pi eta A)`, added to `out`. Each `+-k_par` pair once,
    /// twice its real part.
    #[allow(clippy::too_many_arguments)]
    fn modes(
        &self,
        rho: [f64; 2],
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        unit: f64,
        part: Part,
        out: &mut BlocksFT,
    ) {
        let k_cut = self.mode_cutoff(ha, hb, aa, ab, part, false);
        let mut sum = [[[0.0; 3]; 3]; 4];
        let waves = self.mode_waves(k_cut, part);
        let mut current = f64::NAN;
        let mut frame: Blocks = [[[C::new(0.0, 0.0); 3]; 3]; 4];
        for &(k, kappa) in waves.iter() {
            if kappa != current {
                frame = Gap::new(kappa, self.gap).blocks(ha, hb, aa, ab, part);
                current = kappa;
            }
            let phase = C::from_polar(1.0, k[0] * rho[0] + k[1] * rho[1]);
            let (c, s) = (k[0] / kappa, k[1] / kappa);
            for (acc, x) in sum.iter_mut().zip(&frame) {
                // Re(phase R X R^T) = R Re(phase X) R^T, R = [khat, e3 x khat, e3] as
                // columns ([[c, -s, 0], [s, c, 0], [0, 0, 1]])
                let z: [[f64; 3]; 3] =
                    std::array::from_fn(|p| std::array::from_fn(|q| (phase * x[p][q]).re));
                // Y = Z R^T, then R Y
                let y: [[f64; 3]; 3] = std::array::from_fn(|p| {
                    [
                        c * z[p][0] - s * z[p][1],
                        s * z[p][0] + c * z[p][1],
                        z[p][2],
                    ]
                });
                for j in 0..3 {
                    acc[0][j] += c * y[0][j] - s * y[1][j];
                    acc[1][j] += s * y[0][j] + c * y[1][j];
                    acc[2][j] += y[2][j];
                }
            }
        }
        for (acc, o) in sum
            .iter()
            .zip([&mut out.uf, &mut out.ul, &mut out.of, &mut out.ol])
        {
            for i in 0..3 {
                for j in 0..3 {
                    o[i][j] += 2.0 * unit * acc[i][j];
                }
            }
        }
    }
}

impl SlitEwald {
    /// The modes within `k_cut` of `W` (`part` [`Part::Whole`]) or of its remainder, in
    /// order of `kappa`, with `kappa`.
    fn mode_waves(&self, k_cut: f64, part: Part) -> Cow<'_, [([f64; 2], f64)]> {
        let waves = match part {
            Part::Remainder => Cow::Borrowed(self.remainder_waves.as_slice()),
            Part::Whole => Cow::Owned(self.waves(k_cut)),
        };
        let within = waves.iter().take_while(|w| w.1 <= k_cut).count();
        match waves {
            Cow::Borrowed(w) => Cow::Borrowed(&w[..within]),
            Cow::Owned(mut w) => {
                w.truncate(within);
                Cow::Owned(w)
            }
        }
    }

    /// [`SlitEwald::modes`] of the FTS blocks: each mode's grand block in its frame
    /// ([`Gap::grand`], once per `kappa`) brought to the lab's by [`frame_to_lab`].
    #[allow(clippy::too_many_arguments)]
    fn modes_grand(
        &self,
        rho: [f64; 2],
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        unit: f64,
        part: Part,
        out: &mut SMatrix<f64, 11, 11>,
    ) {
        let k_cut = self.mode_cutoff(ha, hb, aa, ab, part, true);
        let mut sum = SMatrix::<f64, 11, 11>::zeros();
        let mut current = f64::NAN;
        let mut frame = [[C::new(0.0, 0.0); 11]; 11];
        for &(k, kappa) in self.mode_waves(k_cut, part).iter() {
            if kappa != current {
                frame = Gap::new(kappa, self.gap).grand(ha, hb, aa, ab, part, &STRAIN_BASIS);
                current = kappa;
            }
            let phase = C::from_polar(1.0, k[0] * rho[0] + k[1] * rho[1]);
            let t = frame_to_lab(k[0] / kappa, k[1] / kappa);
            let z = SMatrix::<f64, 11, 11>::from_fn(|p, q| (phase * frame[p][q]).re);
            sum += t * z * t.transpose();
        }
        *out += sum * (2.0 * unit);
    }
}

/// `blockdiag(R, R, Q_5)`, a mode's frame `(khat, e3 x khat, e3)` to the lab's for the
/// grand block's rows (and, transposed, its columns), `khat = (c, s, 0)`: `R` on vectors
/// and pseudovectors, `Q_5,pq = B_p : (R B_q R^T)` on strains and stresslets in the
/// strain basis `B`.
fn frame_to_lab(c: f64, s: f64) -> SMatrix<f64, 11, 11> {
    let r = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    let mut t = SMatrix::<f64, 11, 11>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            t[(i, j)] = r[i][j];
            t[(3 + i, 3 + j)] = r[i][j];
        }
    }
    for (q, bq) in STRAIN_BASIS.iter().enumerate() {
        // R B_q R^T
        let rotated: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                (0..3)
                    .flat_map(|m| (0..3).map(move |n| (m, n)))
                    .map(|(m, n)| r[i][m] * bq[m][n] * r[j][n])
                    .sum()
            })
        });
        for (p, bp) in STRAIN_BASIS.iter().enumerate() {
            t[(6 + p, 6 + q)] = (0..9)
                .map(|e| bp[e / 3][e % 3] * rotated[e / 3][e % 3])
                .sum();
        }
    }
    t
}

/// The grand block of the mirror image of a system in the plane `x3 = const`, as
/// [`mirror`]: vectors `P`, pseudovectors `-P`, strains and stresslets `P E P`, which in
/// the strain basis keeps `B_1` (`xy`), `B_4`, `B_5` and flips `B_2` (`xz`), `B_3` (`yz`):
/// `M -> S M S` with `S` the diagonal of those signs.
fn mirror_grand(m: &SMatrix<f64, 11, 11>) -> SMatrix<f64, 11, 11> {
    const SIGN: [f64; 11] = [1.0, 1.0, -1.0, -1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, 1.0];
    SMatrix::from_fn(|i, j| SIGN[i] * SIGN[j] * m[(i, j)])
}

/// The FT blocks of the mirror image of a system in the plane `x3 = const`, `P = diag(1,
/// 1, -1)`: velocities and forces are vectors (`P`), angular velocities and torques
/// pseudovectors (`-P`): `UF -> P UF P`, `UL -> -P UL P`, `OmegaF -> -P OmegaF P`,
/// `OmegaL -> P OmegaL P`.
fn mirror(b: &BlocksFT) -> BlocksFT {
    let p = [1.0, 1.0, -1.0];
    let m = |x: &[[f64; 3]; 3], sign: f64| -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| sign * p[i] * p[j] * x[i][j]))
    };
    BlocksFT {
        uf: m(&b.uf, 1.0),
        ul: m(&b.ul, -1.0),
        of: m(&b.of, -1.0),
        ol: m(&b.ol, 1.0),
    }
}

/// The homogeneous Stokes flows of one lateral wave number `kappa` in the gap `[0, H]`
/// (module docs), in the frame `(khat, e3 x khat, e3)`.
struct Gap {
    kappa: f64,
    h: f64,
    /// `e^{-kappa H}`.
    e: f64,
    /// `1 - e^{-2 kappa H}`, the determinant of the 2 x 2 system.
    det: f64,
    /// The inverse of the normal flow's 4 x 4 system, unknowns `(A, B, C, D)`.
    normal: [[f64; 4]; 4],
}

/// A flow of [`Gap`]: `v = alpha e^{-kappa z} + beta e^{-kappa (H - z)}` and `w = (A + B z)
/// e^{-kappa z} + (C + D (H - z)) e^{-kappa (H - z)}`.
struct Flow {
    alpha: C,
    beta: C,
    abcd: [C; 4],
}

/// `d^m/dt^m [(p0 + p1 t) e^{-kappa t}] e^{kappa t} = (-kappa)^m (p0 + p1 t) + m
/// (-kappa)^(m-1) p1`.
fn exp_poly(kappa: f64, p0: C, p1: C, t: f64, m: i32) -> C {
    let k = -kappa;
    let lower = if m == 0 {
        0.0
    } else {
        m as f64 * k.powi(m - 1)
    };
    (p0 + p1 * t) * k.powi(m) + p1 * lower
}

impl Gap {
    fn new(kappa: f64, h: f64) -> Gap {
        let e = (-kappa * h).exp();
        // rows: w(0), w'(0), w(H), w'(H); columns A, B, C, D
        let m = [
            [1.0, 0.0, e, h * e],
            [-kappa, 1.0, kappa * e, (kappa * h - 1.0) * e],
            [e, h * e, 1.0, 0.0],
            [-kappa * e, (1.0 - kappa * h) * e, kappa, -1.0],
        ];
        Gap {
            kappa,
            h,
            e,
            det: -(-2.0 * kappa * h).exp_m1(),
            normal: invert4(m),
        }
    }

    /// The flow that takes the velocities `bottom` and `top` (frame components) on the
    /// walls.
    fn flow(&self, bottom: [C; 3], top: [C; 3]) -> Flow {
        let (k, e) = (self.kappa, self.e);
        // v(0) = alpha + beta e, v(H) = alpha e + beta
        let alpha = (bottom[1] - top[1] * e) / self.det;
        let beta = (top[1] - bottom[1] * e) / self.det;
        // w' = -i kappa u_1
        let minus_ik = C::new(0.0, -k);
        let rhs = [bottom[2], minus_ik * bottom[0], top[2], minus_ik * top[0]];
        let abcd = std::array::from_fn(|r| {
            (0..4).fold(C::new(0.0, 0.0), |acc, c| acc + rhs[c] * self.normal[r][c])
        });
        Flow { alpha, beta, abcd }
    }

    /// The flow that takes the velocities `bottom` and `top` on the walls, or (`part`
    /// [`Part::Remainder`]) what is left of it without the flows that take them on each
    /// wall alone (the two walls' Blake images of the mode: `v = v(0) e^{-kappa z}`, `w =
    /// (A + B z) e^{-kappa z}` with `A = w(0)`, `B = w'(0) + kappa A`; the upper wall's
    /// mirrored).
    fn part(&self, bottom: [C; 3], top: [C; 3], part: Part) -> Flow {
        let mut f = self.flow(bottom, top);
        if part == Part::Remainder {
            let k = self.kappa;
            let minus_ik = C::new(0.0, -k);
            f.alpha -= bottom[1];
            f.beta -= top[1];
            // w'(0) = -i kappa u_1(0); at H, w' = -D + kappa C = -i kappa u_1(H)
            f.abcd[0] -= bottom[2];
            f.abcd[1] -= minus_ik * bottom[0] + bottom[2] * k;
            f.abcd[2] -= top[2];
            f.abcd[3] -= top[2] * k - minus_ik * top[0];
        }
        f
    }

    /// `(d^m w/dz^m, d^m v/dz^m)` of `f` at height `z`, `m = 0..N`.
    fn derivatives<const N: usize>(&self, f: &Flow, z: f64) -> [(C, C); N] {
        let k = self.kappa;
        let (lo, hi) = ((-k * z).exp(), (-k * (self.h - z)).exp());
        let [a, b, c, d] = f.abcd;
        std::array::from_fn(|m| {
            let m = m as i32;
            let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
            let w = exp_poly(k, a, b, z, m) * lo + exp_poly(k, c, d, self.h - z, m) * (hi * sign);
            let v = f.alpha * ((-k).powi(m) * lo) + f.beta * (k.powi(m) * hi);
            (w, v)
        })
    }

    /// The velocity (with the Faxén operator `1 + c lap`) and the angular velocity `(1/2)
    /// curl` of `f` at height `z`.
    fn field(&self, f: &Flow, z: f64, c: f64) -> ([C; 3], [C; 3]) {
        let k = self.kappa;
        let d: [(C, C); 4] = self.derivatives(f, z);
        let (w, v) = d[0];
        let i = C::new(0.0, 1.0);
        // u = (i w'/kappa, v, w), lap = d^2 - kappa^2
        let u1 = i * d[1].0 / k;
        let lap_u1 = i * (d[3].0 - d[1].0 * (k * k)) / k;
        let lap_v = d[2].1 - v * (k * k);
        let lap_w = d[2].0 - w * (k * k);
        let velocity = [u1 + lap_u1 * c, v + lap_v * c, w + lap_w * c];
        // (1/2) curl with grad = (i kappa, 0, d/dz)
        let omega = [
            -0.5 * d[1].1,
            0.5 * (i * d[2].0 / k - i * k * w),
            0.5 * i * k * v,
        ];
        (velocity, omega)
    }

    /// `d^m/dy3^m`, `m = 0..N`, of the lateral transform `Jhat(k, z_wall - y3)` (module
    /// docs, without the factor `2 pi/kappa`) at the lower wall (`bottom`) or the upper
    /// one, the source at height `y3`: `[m][row][column]`.
    fn stokeslet<const N: usize>(&self, y3: f64, bottom: bool) -> Data<N> {
        let k = self.kappa;
        // s = z_wall - y3 = sgn t, t = |s|; d/dy3 = -sgn d/dt
        let (t, sgn): (f64, f64) = if bottom {
            (y3, -1.0)
        } else {
            (self.h - y3, 1.0)
        };
        let decay = (-k * t).exp();
        let r = |x: f64| C::new(x, 0.0);
        let zero = C::new(0.0, 0.0);
        std::array::from_fn(|m| {
            let m = m as i32;
            let scale = (-sgn).powi(m) * decay;
            let term = |p0: C, p1: C| exp_poly(k, p0, p1, t, m) * scale;
            let g11 = term(r(1.0), r(-k));
            let g22 = term(r(2.0), r(0.0));
            let g33 = term(r(1.0), r(k));
            let g13 = term(r(0.0), C::new(0.0, -k * sgn));
            [[g11, zero, g13], [zero, g22, zero], [g13, zero, g33]]
        })
    }

    /// `(d_a + d_b)` of the column `UF_i3` of this mode's remainder `R` (frame components, as
    /// [`Gap::blocks`]) at `h_a = h_b = h`, radius `a`: the field's derivative one more
    /// `d/dz`, the source's one more `d/dy3` on the walls' data.
    fn drift_column(&self, h: f64, a: f64) -> [C; 3] {
        let k = self.kappa;
        let c = a * a / 6.0;
        let scale = -2.0 * PI / k;
        let i = C::new(0.0, 1.0);
        // the force column along e3 from the data's derivatives `m` and `m + 2`
        let (lo, hi): (Data<4>, Data<4>) = (self.stokeslet(h, true), self.stokeslet(h, false));
        let column = |bottom: bool, m: usize| -> [C; 3] {
            let g = if bottom { &lo } else { &hi };
            std::array::from_fn(|r| (g[m][r][2] * (1.0 - c * k * k) + g[m + 2][r][2] * c) * scale)
        };
        // d_b: the flow of the data's first derivative, at the field point
        let along_source = self.part(column(true, 1), column(false, 1), Part::Remainder);
        let (u_b, _) = self.field(&along_source, h, c);
        // d_a: the field's derivative of the flow of the data
        let f = self.part(column(true, 0), column(false, 0), Part::Remainder);
        let d: [(C, C); 5] = self.derivatives(&f, h);
        // d[m] = (w^(m), v^(m)); u = (i w'/kappa, v, w) and lap = d^2 - kappa^2
        let du1 = i * (d[2].0 + (d[4].0 - d[2].0 * (k * k)) * c) / k;
        let dv = d[1].1 + (d[3].1 - d[1].1 * (k * k)) * c;
        let dw = d[1].0 + (d[3].0 - d[1].0 * (k * k)) * c;
        [u_b[0] + du1, u_b[1] + dv, u_b[2] + dw]
    }

    /// The FT blocks of this mode (its frame, without the phase and `1/A`, units of `1/(8
    /// pi eta)`) of `W` or of its remainder between a field point at height `ha` and a source at `hb` above
    /// the lower wall, radii `aa`, `ab`.
    fn blocks(&self, ha: f64, hb: f64, aa: f64, ab: f64, part: Part) -> Blocks {
        let k = self.kappa;
        let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
        let scale = -2.0 * PI / k;
        // the walls' data, d^m/dy3^m for m = 0, 1, 2
        let (lo, hi): (Data<3>, Data<3>) = (self.stokeslet(hb, true), self.stokeslet(hb, false));
        let zero = C::new(0.0, 0.0);
        let force = |g: &Data<3>, j: usize| force_column(g, j, k, cb, scale);
        let torque = |g: &Data<3>, j: usize| torque_column(g, j, k, scale);
        let mut out = [[[zero; 3]; 3]; 4];
        for j in 0..3 {
            let f = self.part(force(&lo, j), force(&hi, j), part);
            let (u, o) = self.field(&f, ha, ca);
            let t = self.part(torque(&lo, j), torque(&hi, j), part);
            let (ut, ot) = self.field(&t, ha, ca);
            for r in 0..3 {
                out[0][r][j] = u[r];
                out[1][r][j] = ut[r];
                out[2][r][j] = o[r];
                out[3][r][j] = ot[r];
            }
        }
        out
    }
}

/// A force column of a mode (its values on both walls' rows `r`, frame components) from
/// the walls' data `g` (`d^m/dy3^m`, `m >= 0..=2`): the Faxén operator `1 + c_b lap_y`,
/// `lap_y = d^2/dy3^2 - kappa^2`, on the force along `j`, times `scale`.
fn force_column<const N: usize>(g: &Data<N>, j: usize, k: f64, cb: f64, scale: f64) -> [C; 3] {
    std::array::from_fn(|r| (g[0][r][j] * (1.0 - cb * k * k) + g[2][r][j] * cb) * scale)
}

/// A torque column of a mode from the walls' data `g`: the rotlet `(1/2) eps_jnl D_n G_l`,
/// `D = (-i kappa, 0, d/dy3)`, of the torque along `j`, times `scale`.
fn torque_column<const N: usize>(g: &Data<N>, j: usize, k: f64, scale: f64) -> [C; 3] {
    let i = C::new(0.0, 1.0);
    std::array::from_fn(|r| {
        let v = match j {
            0 => -0.5 * g[1][r][1],
            1 => 0.5 * (g[1][r][0] + i * k * g[0][r][2]),
            _ => -0.5 * i * k * g[0][r][1],
        };
        v * scale
    })
}

/// A stresslet column of a mode from the walls' data `g` (`m` to 3): `(1 + g_b lap_y)
/// sum_lq B_lq D_q G_l` for the symmetric traceless `basis` `B` in the mode's frame
/// (`g_b = a_b^2/10`), times `scale`.
fn stresslet_column(g: &Data<4>, basis: &[[f64; 3]; 3], k: f64, gb: f64, scale: f64) -> [C; 3] {
    let i = C::new(0.0, 1.0);
    std::array::from_fn(|r| {
        let mut v = C::new(0.0, 0.0);
        for (l, row) in basis.iter().enumerate() {
            // (1 + g_b lap_y) of the data's m-th derivative
            let faxen = |m: usize| g[m][r][l] * (1.0 - gb * k * k) + g[m + 2][r][l] * gb;
            // D_1 = -i kappa, D_2 = 0, D_3 = d/dy3
            v += (-i * k) * faxen(0) * row[0] + faxen(1) * row[2];
        }
        v * scale
    })
}

impl Gap {
    /// The strain rate `(1 + g lap) B : grad u` of the flow `f` at height `z` for each
    /// symmetric traceless `basis` tensor in the mode's frame, `grad = (i kappa, 0,
    /// d/dz)`, `u = (i w'/kappa, v, w)`.
    fn strain(&self, f: &Flow, z: f64, g: f64, basis: &[[[f64; 3]; 3]; 5]) -> [C; 5] {
        let k = self.kappa;
        let d: [(C, C); 5] = self.derivatives(f, z);
        let i = C::new(0.0, 1.0);
        // the velocity's m-th derivative in z with the Faxén operator 1 + g (d^2 - kappa^2)
        let u = |m: usize| -> [C; 3] {
            let at = |n: usize| [i * d[n + 1].0 / k, d[n].1, d[n].0];
            let (a, b) = (at(m), at(m + 2));
            std::array::from_fn(|c| a[c] * (1.0 - g * k * k) + b[c] * g)
        };
        let (u0, u1) = (u(0), u(1));
        // grad_q u_i: q = 1 i kappa u_i, q = 2 zero, q = 3 u_i'
        std::array::from_fn(|p| {
            (0..3).fold(C::new(0.0, 0.0), |acc, c| {
                acc + (i * k) * u0[c] * basis[p][c][0] + u1[c] * basis[p][c][2]
            })
        })
    }

    /// The FTS blocks of this mode (the 11 x 11 grand block in its frame: vectors and
    /// pseudovectors in frame components, strains and stresslets in the strain basis
    /// rotated into the frame, `basis`), as [`Gap::blocks`].
    #[allow(clippy::too_many_arguments)]
    fn grand(
        &self,
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        part: Part,
        basis: &[[[f64; 3]; 3]; 5],
    ) -> [[C; 11]; 11] {
        let k = self.kappa;
        let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
        let (ga, gb) = (aa * aa / 10.0, ab * ab / 10.0);
        let scale = -2.0 * PI / k;
        let (lo, hi): (Data<4>, Data<4>) = (self.stokeslet(hb, true), self.stokeslet(hb, false));
        let mut out = [[C::new(0.0, 0.0); 11]; 11];
        for j in 0..11 {
            let (bottom, top) = match j {
                0..3 => (
                    force_column(&lo, j, k, cb, scale),
                    force_column(&hi, j, k, cb, scale),
                ),
                3..6 => (
                    torque_column(&lo, j - 3, k, scale),
                    torque_column(&hi, j - 3, k, scale),
                ),
                _ => (
                    stresslet_column(&lo, &basis[j - 6], k, gb, scale),
                    stresslet_column(&hi, &basis[j - 6], k, gb, scale),
                ),
            };
            let f = self.part(bottom, top, part);
            let (u, o) = self.field(&f, ha, ca);
            let e = self.strain(&f, ha, ga, basis);
            for r in 0..3 {
                out[r][j] = u[r];
                out[3 + r][j] = o[r];
            }
            for r in 0..5 {
                out[6 + r][j] = e[r];
            }
        }
        out
    }
}

/// The inverse of a 4 x 4 matrix by Gauss-Jordan elimination with partial pivoting.
fn invert4(m: [[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut a = m;
    let mut inv: [[f64; 4]; 4] =
        std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
    for col in 0..4 {
        let pivot = (col..4)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for j in 0..4 {
            a[col][j] /= p;
            inv[col][j] /= p;
        }
        for row in 0..4 {
            if row != col {
                let f = a[row][col];
                for j in 0..4 {
                    a[row][j] -= f * a[col][j];
                    inv[row][j] -= f * inv[col][j];
                }
            }
        }
    }
    inv
}
