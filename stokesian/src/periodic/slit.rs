//! The Rotne-Prager-Yamakawa mobility of spheres in a slit between two parallel no-slip
//! walls, `x3 = z0` and `x3 = z0 + H`, in a box periodic along them (`Lx`, `Ly`, area
//! `A`), with the slit's exact Green's function: the Stokeslet plus the flow `W` that
//! cancels it on both walls, lateral mode by lateral mode.
//!
//! The Green's function is `G = J + W` (units of `1/(8 pi eta)`, `J = I/r + r r/r^3`).
//! `J` is summed as in the triply periodic box but over the lateral lattice only
//! (Beenakker's split `J = J^R + J^K`): its real part is the generated screened
//! Stokeslet (`kernels::generated::scene_ewald_real_ft`, the isolated sphere in the self
//! kernel) over the lateral images within `r_c`, its smooth part `J^K` the wall's
//! reciprocal sum without the image ([`super::wall::WallEwald::reciprocal`]). `W` is
//! smooth in the slit and is summed in lateral Fourier modes, each in closed form in the
//! heights:
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
//!   real systems, one per `kappa`: the data are complex, the matrices real).
//! - **Operators.** At the field point `i k` and `d/dz` (Faxén `1 + a^2/6 (d^2 -
//!   kappa^2)`, rotation `(1/2) curl`); at the source `-i k` and `d/dy3`, which acts on
//!   the walls' data (`Jhat` at `z_wall - y3`): the source's Faxén operator and rotlet
//!   are applied to the data before the solve (the flow is linear in them).
//! - **Truncation.** A mode of `W` decays like `e^{-kappa s}`, `s = min(h_a + h_b, 2 H -
//!   h_a - h_b)` the distance of the field point to the nearer image of the source
//!   (`h` the heights above the lower wall): the modes within `k_W`, the smallest
//!   `kappa` with `e^{-kappa s} (1 + kappa H)^3 (1 + kappa^2 a^2/6)^2 <= tol/100` (the
//!   polynomial factors of the data, of the solve and of both Faxén operators).
//! - **The mode `k_par = 0`** in closed form: a force sheet `F/A` at height `h_b`
//!   between no-slip walls drives the Couette profile `u = F (min(z, h_b) - z h_b/H)/(eta
//!   A)` along the walls (a normal force is taken by the pressure: no flow), `8 pi
//!   (min(h_a, h_b) - h_a h_b/H)/A` in units of `1/(8 pi eta)`; minus the plane average
//!   of the real part, `-4 pi |h_a - h_b| - Psi(h_a - h_b)` ([`super::wall`]'s `Psi`),
//!   it is `(I - e3 e3) f/A`, `f = Psi(h_a - h_b) + 4 pi (h_a + h_b) - 8 pi h_a h_b/H`,
//!   entire, to which the operators in the heights give every FT block (as along one
//!   wall). So, as along one wall, the mobility is the lattice sum itself: velocities
//!   relative to the walls, a net lateral force drives a bounded Couette flow.
//!
//! Unlike the open slit of the kernels (`kernels::generated::slit`, two walls' images
//! superposed, Swan & Brady Sec. IV), this Green's function satisfies no slip on both
//! walls exactly; its far field along the walls is Hele-Shaw's (`rho^-2`), whose
//! lattice sum only the Fourier modes define (the mode `k_par = 0` above), and so the
//! periodic slit has no open counterpart among our kernels.

use super::wall::{lateral_waves, plane_blocks, Psi, WallEwald};
use crate::system::input::Particle;
use kernels::generated::scene_ewald_real_ft::{ewald_real_ft_pair, ewald_real_ft_self};
use kernels::BlocksFT;
use rustfft::num_complex::Complex64;
use std::f64::consts::PI;

/// The split and truncation of a slit periodic along its walls, at one tolerance.
#[derive(Clone, Debug)]
pub struct SlitEwald {
    /// The Stokeslet's lateral lattice sum: the split of the wall `x3 = z0` (its image
    /// is not used), its shifts and its reciprocal sum of `J^K`.
    pub(super) direct: WallEwald,
    /// The gap `H` between the walls `x3 = z0` and `x3 = z0 + H`.
    pub gap: f64,
}

type C = Complex64;

/// `[UF, UL, OmegaF, OmegaL]` in one frame, complex.
type Blocks = [[[C; 3]; 3]; 4];

impl SlitEwald {
    /// The slit between `x3 = bottom` and `x3 = bottom + gap`, periodic with lateral
    /// `lengths`, at relative tolerance `tol`; `xi` chosen as along one wall or given.
    pub fn new(lengths: [f64; 2], bottom: f64, gap: f64, tol: f64, xi: Option<f64>) -> SlitEwald {
        SlitEwald {
            direct: WallEwald::new(lengths, bottom, tol, xi),
            gap,
        }
    }

    /// The lateral lengths `[Lx, Ly]`.
    pub fn lengths(&self) -> [f64; 2] {
        self.direct.lengths
    }

    /// The lower wall's plane `x3 = z0`.
    pub fn bottom(&self) -> f64 {
        self.direct.height
    }

    /// The FT blocks `M^{ab}` of spheres `a` (field) and `b` (source) summed over every
    /// lateral image of `b`; with `same`, `b` is `a` and the result its self mobility.
    pub fn blocks(&self, eta: f64, a: &Particle, b: &Particle, same: bool) -> BlocksFT {
        let w = &self.direct;
        let sigma = 1.0 / w.xi;
        let r = if same {
            [0.0; 3]
        } else {
            w.minimum_image(a.x, b.x)
        };
        let mut out = if same {
            ewald_real_ft_self(a.x, a.a, eta, sigma)
        } else {
            BlocksFT::default()
        };
        let rc2 = w.r_cut * w.r_cut;
        for s in w.shifts() {
            let ri = [r[0] + s[0], r[1] + s[1]];
            let lateral2 = ri[0] * ri[0] + ri[1] * ri[1];
            if lateral2 + r[2] * r[2] > rc2 || (same && lateral2 == 0.0) {
                continue;
            }
            let xb = [a.x[0] - ri[0], a.x[1] - ri[1], b.x[2]];
            out += &ewald_real_ft_pair(a.x, xb, a.a, b.a, eta, sigma);
        }
        let (ha, hb) = (a.x[2] - w.height, b.x[2] - w.height);
        w.reciprocal([r[0], r[1]], ha, hb, a.a, b.a, eta, false, &mut out);
        let area = w.lengths[0] * w.lengths[1];
        let unit = 1.0 / (8.0 * PI * eta * area);
        plane_blocks(&self.plane_kernel(ha, hb), a.a, b.a, unit, &mut out);
        self.walls([r[0], r[1]], ha, hb, a.a, b.a, unit, &mut out);
        out
    }

    /// The derivatives `d_a^m d_b^n f` (`m, n <= 2`, indexed `[m][n]`) of the mode
    /// `k_par = 0`'s `f(h_a, h_b) = Psi(h_a - h_b) + 4 pi (h_a + h_b) - 8 pi h_a h_b/H`
    /// (module docs).
    pub(crate) fn plane_kernel(&self, ha: f64, hb: f64) -> [[f64; 3]; 3] {
        let psi = Psi::at(self.direct.xi, ha - hb);
        let h = self.gap;
        std::array::from_fn(|m| {
            std::array::from_fn(|n| {
                let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                let polynomial = match (m, n) {
                    (0, 0) => 4.0 * PI * (ha + hb) - 8.0 * PI * ha * hb / h,
                    (1, 0) => 4.0 * PI - 8.0 * PI * hb / h,
                    (0, 1) => 4.0 * PI - 8.0 * PI * ha / h,
                    (1, 1) => -8.0 * PI / h,
                    _ => 0.0,
                };
                sign * psi.0[m + n] + polynomial
            })
        })
    }

    /// The cut-off `k_W` of the modes of `W` for heights `ha`, `hb` and radii `aa`, `ab`
    /// (module docs).
    pub fn wall_cutoff(&self, ha: f64, hb: f64, aa: f64, ab: f64) -> f64 {
        let h = self.gap;
        let s = (ha + hb).min(2.0 * h - ha - hb);
        let c = aa.max(ab).powi(2) / 6.0;
        let target = (100.0 / self.direct.tolerance).ln();
        // kappa s = target + 3 ln(1 + kappa H) + 2 ln(1 + kappa^2 c), by fixed point
        let mut kappa = target / s;
        for _ in 0..50 {
            let next =
                (target + 3.0 * (1.0 + kappa * h).ln() + 2.0 * (1.0 + kappa * kappa * c).ln()) / s;
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
    /// is a reciprocal Green's function, divergence-free in its field point), and of the
    /// sphere's own terms only `W` depends on its height (the real part and `J^K` on
    /// differences of heights, the mode `k_par = 0` has no third column): `sum_k (d_a +
    /// d_b) UF_i3` of `W`'s modes at `h_a = h_b = h`.
    pub fn drift(&self, eta: f64, p: &Particle) -> [f64; 3] {
        let h = p.x[2] - self.direct.height;
        let k_cut = self.wall_cutoff(h, h, p.a, p.a);
        let mut sum = [0.0; 3];
        let mut waves: Vec<([f64; 2], f64)> = lateral_waves(self.direct.lengths, k_cut)
            .map(|k| (k, (k[0] * k[0] + k[1] * k[1]).sqrt()))
            .collect();
        waves.sort_by(|x, y| x.1.total_cmp(&y.1));
        let mut last: Option<(f64, [C; 3])> = None;
        for (k, kappa) in waves {
            let column = match &last {
                Some((kl, col)) if *kl == kappa => *col,
                _ => {
                    let col = Gap::new(kappa, self.gap).drift_column(h, p.a);
                    last = Some((kappa, col));
                    col
                }
            };
            // column 3 of R X R^T: R X_{., 3}
            let (c, s) = (k[0] / kappa, k[1] / kappa);
            sum[0] += (column[0] * c - column[1] * s).re;
            sum[1] += (column[0] * s + column[1] * c).re;
            sum[2] += column[2].re;
        }
        let area = self.direct.lengths[0] * self.direct.lengths[1];
        let unit = 1.0 / (8.0 * PI * eta * area);
        sum.map(|v| 2.0 * unit * v)
    }

    /// The modes `k_par != 0` of `W` (module docs) of the FT blocks at lateral separation
    /// `rho`, heights `ha`, `hb` above the lower wall, radii `aa`, `ab`, times `unit =
    /// 1/(8 pi eta A)`, added to `out`. Each `+-k_par` pair once, twice its real part.
    #[allow(clippy::too_many_arguments)]
    fn walls(
        &self,
        rho: [f64; 2],
        ha: f64,
        hb: f64,
        aa: f64,
        ab: f64,
        unit: f64,
        out: &mut BlocksFT,
    ) {
        let k_cut = self.wall_cutoff(ha, hb, aa, ab);
        let mut sum = [[[0.0; 3]; 3]; 4];
        // the blocks in a mode's frame depend on `kappa` alone: the modes in order of
        // `kappa` (exact ties, `kappa^2` the same sum of the same squares), each `kappa`'s
        // blocks once
        let mut waves: Vec<([f64; 2], f64)> = lateral_waves(self.direct.lengths, k_cut)
            .map(|k| (k, (k[0] * k[0] + k[1] * k[1]).sqrt()))
            .collect();
        waves.sort_by(|x, y| x.1.total_cmp(&y.1));
        let mut last: Option<(f64, Blocks)> = None;
        for (k, kappa) in waves {
            let frame = match &last {
                Some((kl, b)) if *kl == kappa => *b,
                _ => {
                    let b = Gap::new(kappa, self.gap).blocks(ha, hb, aa, ab);
                    last = Some((kappa, b));
                    b
                }
            };
            let phase = C::from_polar(1.0, k[0] * rho[0] + k[1] * rho[1]);
            let (c, s) = (k[0] / kappa, k[1] / kappa);
            // R = [khat, e3 x khat, e3] as columns: X_lab = R X R^T
            let rot = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
            for (acc, x) in sum.iter_mut().zip(&frame) {
                for i in 0..3 {
                    for j in 0..3 {
                        let mut v = C::new(0.0, 0.0);
                        for p in 0..3 {
                            for q in 0..3 {
                                v += x[p][q] * (rot[i][p] * rot[j][q]);
                            }
                        }
                        acc[i][j] += (phase * v).re;
                    }
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

/// The homogeneous Stokes flows of one lateral wave number `kappa` in the gap `[0, H]`
/// (module docs), in the frame `(khat, e3 x khat, e3)`.
struct Gap {
    kappa: f64,
    h: f64,
    /// `e^{-kappa H}`.
    e: f64,
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
            normal: invert4(m),
        }
    }

    /// The flow that takes the velocities `bottom` and `top` (frame components) on the
    /// walls.
    fn flow(&self, bottom: [C; 3], top: [C; 3]) -> Flow {
        let (k, e) = (self.kappa, self.e);
        // v(0) = alpha + beta e, v(H) = alpha e + beta
        let det = -(-2.0 * k * self.h).exp_m1();
        let alpha = (bottom[1] - top[1] * e) / det;
        let beta = (top[1] - bottom[1] * e) / det;
        // w' = -i kappa u_1
        let minus_ik = C::new(0.0, -k);
        let rhs = [bottom[2], minus_ik * bottom[0], top[2], minus_ik * top[0]];
        let abcd = std::array::from_fn(|r| {
            (0..4).fold(C::new(0.0, 0.0), |acc, c| acc + rhs[c] * self.normal[r][c])
        });
        Flow { alpha, beta, abcd }
    }

    /// `d^m w/dz^m` and `d^m v/dz^m` of `f` at height `z`.
    fn derivatives(&self, f: &Flow, z: f64, m: i32) -> (C, C) {
        let k = self.kappa;
        let (lo, hi) = ((-k * z).exp(), (-k * (self.h - z)).exp());
        let [a, b, c, d] = f.abcd;
        let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
        let w = exp_poly(k, a, b, z, m) * lo + exp_poly(k, c, d, self.h - z, m) * (hi * sign);
        let v = f.alpha * ((-k).powi(m) * lo) + f.beta * (k.powi(m) * hi);
        (w, v)
    }

    /// The velocity (with the Faxén operator `1 + c lap`) and the angular velocity `(1/2)
    /// curl` of `f` at height `z`.
    fn field(&self, f: &Flow, z: f64, c: f64) -> ([C; 3], [C; 3]) {
        let k = self.kappa;
        let d: Vec<(C, C)> = (0..4).map(|m| self.derivatives(f, z, m)).collect();
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

    /// `d^m/dy3^m` of the lateral transform `Jhat(k, z_wall - y3)` (module docs, without
    /// the factor `2 pi/kappa`) at the lower wall (`bottom`) or the upper one, the source
    /// at height `y3`: `[row][column]`.
    fn stokeslet(&self, y3: f64, bottom: bool, m: i32) -> [[C; 3]; 3] {
        let k = self.kappa;
        // s = z_wall - y3 = sgn t, t = |s|; d/dy3 = -sgn d/dt
        let (t, sgn): (f64, f64) = if bottom {
            (y3, -1.0)
        } else {
            (self.h - y3, 1.0)
        };
        let scale = (-sgn).powi(m) * (-k * t).exp();
        let term = |p0: C, p1: C| exp_poly(k, p0, p1, t, m) * scale;
        let r = |x: f64| C::new(x, 0.0);
        let g11 = term(r(1.0), r(-k));
        let g22 = term(r(2.0), r(0.0));
        let g33 = term(r(1.0), r(k));
        let g13 = term(r(0.0), C::new(0.0, -k * sgn));
        let zero = C::new(0.0, 0.0);
        [[g11, zero, g13], [zero, g22, zero], [g13, zero, g33]]
    }

    /// `(d_a + d_b)` of the column `UF_i3` of this mode (frame components, as
    /// [`Gap::blocks`]) at `h_a = h_b = h`, radius `a`: the field's derivative one more
    /// `d/dz`, the source's one more `d/dy3` on the walls' data.
    fn drift_column(&self, h: f64, a: f64) -> [C; 3] {
        let k = self.kappa;
        let c = a * a / 6.0;
        let scale = -2.0 * PI / k;
        let i = C::new(0.0, 1.0);
        // the force column along e3 from the data's derivatives `m` and `m + 2`
        let column = |bottom: bool, m: i32| -> [C; 3] {
            let g0 = self.stokeslet(h, bottom, m);
            let g2 = self.stokeslet(h, bottom, m + 2);
            std::array::from_fn(|r| (g0[r][2] * (1.0 - c * k * k) + g2[r][2] * c) * scale)
        };
        // d_b: the flow of the data's first derivative, at the field point
        let along_source = self.flow(column(true, 1), column(false, 1));
        let (u_b, _) = self.field(&along_source, h, c);
        // d_a: the field's derivative of the flow of the data
        let f = self.flow(column(true, 0), column(false, 0));
        let d: Vec<(C, C)> = (1..5).map(|m| self.derivatives(&f, h, m)).collect();
        // d[m - 1] = (w^(m), v^(m)); u = (i w'/kappa, v, w) and lap = d^2 - kappa^2
        let du1 = i * (d[1].0 + (d[3].0 - d[1].0 * (k * k)) * c) / k;
        let dv = d[0].1 + (d[2].1 - d[0].1 * (k * k)) * c;
        let dw = d[0].0 + (d[2].0 - d[0].0 * (k * k)) * c;
        [u_b[0] + du1, u_b[1] + dv, u_b[2] + dw]
    }

    /// The FT blocks of this mode (its frame, without the phase and `1/A`, units of `1/(8
    /// pi eta)`) of `W` between a field point at height `ha` and a source at `hb` above
    /// the lower wall, radii `aa`, `ab`.
    fn blocks(&self, ha: f64, hb: f64, aa: f64, ab: f64) -> Blocks {
        let k = self.kappa;
        let (ca, cb) = (aa * aa / 6.0, ab * ab / 6.0);
        let scale = -2.0 * PI / k;
        // the walls' data, d^m/dy3^m for m = 0, 1, 2
        let data = |bottom: bool| -> [[[C; 3]; 3]; 3] {
            std::array::from_fn(|m| self.stokeslet(hb, bottom, m as i32))
        };
        let (lo, hi) = (data(true), data(false));
        let zero = C::new(0.0, 0.0);
        let i = C::new(0.0, 1.0);
        // a source column (its values on both walls) from the data: Faxén for a force
        // along j, the rotlet for a torque along j: (1/2) eps_jnl D_n G_l, D = (-i kappa,
        // 0, d/dy3)
        let force = |g: &[[[C; 3]; 3]; 3], j: usize| -> [C; 3] {
            std::array::from_fn(|r| (g[0][r][j] * (1.0 - cb * k * k) + g[2][r][j] * cb) * scale)
        };
        let torque = |g: &[[[C; 3]; 3]; 3], j: usize| -> [C; 3] {
            std::array::from_fn(|r| {
                let v = match j {
                    0 => -0.5 * g[1][r][1],
                    1 => 0.5 * (g[1][r][0] + i * k * g[0][r][2]),
                    _ => -0.5 * i * k * g[0][r][1],
                };
                v * scale
            })
        };
        let mut out = [[[zero; 3]; 3]; 4];
        for j in 0..3 {
            let f = self.flow(force(&lo, j), force(&hi, j));
            let (u, o) = self.field(&f, ha, ca);
            let t = self.flow(torque(&lo, j), torque(&hi, j));
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
