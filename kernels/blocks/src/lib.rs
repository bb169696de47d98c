//! The nine blocks of the grand mobility for one ordered pair of particles (or one
//! particle with itself), and their conversions.

use nalgebra::SMatrix;

/// The orthonormal basis of symmetric traceless tensors in which strains and
/// stresslets are stored (docs/conventions.md): `B1 = (e1e2 + e2e1)/sqrt2`,
/// `B2 = (e1e3 + e3e1)/sqrt2`, `B3 = (e2e3 + e3e2)/sqrt2`, `B4 = (e1e1 - e2e2)/sqrt2`,
/// `B5 = (2e3e3 - e1e1 - e2e2)/sqrt6`. A symmetric traceless `E` has components
/// `E_m = B_m : E`, and `E = sum_m E_m B_m`.
pub const STRAIN_BASIS: [[[f64; 3]; 3]; 5] = {
    const S2: f64 = std::f64::consts::FRAC_1_SQRT_2;
    const S6: f64 = 0.408_248_290_463_863_016_366_214_012_450_981_698_8;
    const S6X2: f64 = 0.816_496_580_927_726_032_732_428_024_901_963_797_3;
    [
        [[0.0, S2, 0.0], [S2, 0.0, 0.0], [0.0, 0.0, 0.0]],
        [[0.0, 0.0, S2], [0.0, 0.0, 0.0], [S2, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, S2], [0.0, S2, 0.0]],
        [[S2, 0.0, 0.0], [0.0, -S2, 0.0], [0.0, 0.0, 0.0]],
        [[-S6, 0.0, 0.0], [0.0, -S6, 0.0], [0.0, 0.0, S6X2]],
    ]
};

/// The blocks `M^{ab}` of the grand mobility: rows are the velocity `U`, angular
/// velocity `Omega` and strain `E` of particle `a`; columns the force `F`, torque `L`
/// and stresslet `S` that particle `b` exerts on the fluid. Strain and stresslet in the
/// 5-component basis [`STRAIN_BASIS`]. Row-major: `uf[i][j] = dU_i / dF_j`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Grand {
    /// Velocity from force, 3x3.
    pub uf: [[f64; 3]; 3],
    /// Velocity from torque, 3x3.
    pub ul: [[f64; 3]; 3],
    /// Velocity from stresslet, 3x5.
    pub us: [[f64; 5]; 3],
    /// Angular velocity from force, 3x3.
    pub of: [[f64; 3]; 3],
    /// Angular velocity from torque, 3x3.
    pub ol: [[f64; 3]; 3],
    /// Angular velocity from stresslet, 3x5.
    pub os: [[f64; 5]; 3],
    /// Strain from force, 5x3.
    pub ef: [[f64; 3]; 5],
    /// Strain from torque, 5x3.
    pub el: [[f64; 3]; 5],
    /// Strain from stresslet, 5x5.
    pub es: [[f64; 5]; 5],
}

fn mat<const R: usize, const C: usize>(a: &[[f64; C]; R]) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|i, j| a[i][j])
}

impl Grand {
    /// The 11x11 grand block `[[UF, UL, US], [OF, OL, OS], [EF, EL, ES]]`.
    pub fn matrix(&self) -> SMatrix<f64, 11, 11> {
        let mut m = SMatrix::<f64, 11, 11>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&mat(&self.uf));
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&mat(&self.ul));
        m.fixed_view_mut::<3, 5>(0, 6).copy_from(&mat(&self.us));
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&mat(&self.of));
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&mat(&self.ol));
        m.fixed_view_mut::<3, 5>(3, 6).copy_from(&mat(&self.os));
        m.fixed_view_mut::<5, 3>(6, 0).copy_from(&mat(&self.ef));
        m.fixed_view_mut::<5, 3>(6, 3).copy_from(&mat(&self.el));
        m.fixed_view_mut::<5, 5>(6, 6).copy_from(&mat(&self.es));
        m
    }

    /// `UF` as a static matrix.
    pub fn uf_matrix(&self) -> SMatrix<f64, 3, 3> {
        mat(&self.uf)
    }
    /// `ES` as a static matrix.
    pub fn es_matrix(&self) -> SMatrix<f64, 5, 5> {
        mat(&self.es)
    }

    /// The blocks of `M^{ba}` from those of `M^{ab}` (reciprocity: the grand mobility
    /// is symmetric, so `M^{ba}_{XY} = (M^{ab}_{YX})^T`).
    pub fn transposed(&self) -> Grand {
        let t = self.matrix().transpose();
        Grand::from_matrix(&t)
    }

    /// Inverse of [`Grand::matrix`].
    pub fn from_matrix(m: &SMatrix<f64, 11, 11>) -> Grand {
        fn get<const R: usize, const C: usize>(
            m: &SMatrix<f64, 11, 11>,
            r0: usize,
            c0: usize,
        ) -> [[f64; C]; R] {
            std::array::from_fn(|i| std::array::from_fn(|j| m[(r0 + i, c0 + j)]))
        }
        Grand {
            uf: get(m, 0, 0),
            ul: get(m, 0, 3),
            us: get(m, 0, 6),
            of: get(m, 3, 0),
            ol: get(m, 3, 3),
            os: get(m, 3, 6),
            ef: get(m, 6, 0),
            el: get(m, 6, 3),
            es: get(m, 6, 6),
        }
    }

    /// The Cartesian forms of the strain and stresslet blocks: the strain index pair
    /// `(p, q)` is `sum_m B_m[p][q] E_m` and a stresslet pair `(k, l)` acts as
    /// `sum_n B_n[k][l] S_n`. These are the symmetric traceless parts of the paper's
    /// appendix tensors (trace parts there act on zero, since strain and stresslet
    /// are traceless).
    pub fn cartesian(&self) -> GrandCartesian {
        let b = &STRAIN_BASIS;
        let e3 = |blk: &[[f64; 3]; 5]| -> [[[f64; 3]; 3]; 3] {
            std::array::from_fn(|p| {
                std::array::from_fn(|q| {
                    std::array::from_fn(|j| (0..5).map(|m| b[m][p][q] * blk[m][j]).sum())
                })
            })
        };
        let s3 = |blk: &[[f64; 5]; 3]| -> [[[f64; 3]; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|k| {
                    std::array::from_fn(|l| (0..5).map(|n| blk[i][n] * b[n][k][l]).sum())
                })
            })
        };
        let es = std::array::from_fn(|p| {
            std::array::from_fn(|q| {
                std::array::from_fn(|k| {
                    std::array::from_fn(|l| {
                        let mut s = 0.0;
                        for m in 0..5 {
                            for n in 0..5 {
                                s += b[m][p][q] * self.es[m][n] * b[n][k][l];
                            }
                        }
                        s
                    })
                })
            })
        });
        GrandCartesian {
            uf: self.uf,
            ul: self.ul,
            us: s3(&self.us),
            of: self.of,
            ol: self.ol,
            os: s3(&self.os),
            ef: e3(&self.ef),
            el: e3(&self.el),
            es,
        }
    }
}

/// A Cartesian 3-tensor whose first index pair is a strain or stresslet pair, `t[p][q][j]`,
/// in the orthonormal basis: `out[m][j] = B_m : t[..][..][j]` (the inverse of the
/// expansion in [`Grand::cartesian`] on symmetric traceless pairs).
pub fn basis_rows(t: &[[[f64; 3]; 3]; 3]) -> [[f64; 3]; 5] {
    std::array::from_fn(|m| std::array::from_fn(|j| contract(m, |p, q| t[p][q][j])))
}

/// A Cartesian 3-tensor whose last index pair is a strain or stresslet pair, `t[i][k][l]`,
/// in the orthonormal basis: `out[i][n] = t[i][..][..] : B_n`.
pub fn basis_cols(t: &[[[f64; 3]; 3]; 3]) -> [[f64; 5]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|n| contract(n, |k, l| t[i][k][l])))
}

/// A Cartesian 4-tensor between two strain or stresslet pairs, `t[p][q][k][l]`, in the
/// orthonormal basis: `out[m][n] = B_m : t : B_n`.
pub fn basis_both(t: &[[[[f64; 3]; 3]; 3]; 3]) -> [[f64; 5]; 5] {
    std::array::from_fn(|m| {
        std::array::from_fn(|n| contract(m, |p, q| contract(n, |k, l| t[p][q][k][l])))
    })
}

/// `B_m : f`, `f(p, q)` a Cartesian index pair. Each `B_m` has at most three non-zero
/// entries, and only those are visited (nine times fewer evaluations of `f` in
/// [`basis_both`], whose `f` is itself a contraction).
fn contract(m: usize, f: impl Fn(usize, usize) -> f64) -> f64 {
    let mut s = 0.0;
    for p in 0..3 {
        for q in 0..3 {
            let b = STRAIN_BASIS[m][p][q];
            if b != 0.0 {
                s += b * f(p, q);
            }
        }
    }
    s
}

/// The blocks with Cartesian strain and stresslet indices, as in the paper's
/// appendices: `us[i][k][l]`, `os[m][k][l]`, `ef[p][q][j]`, `el[p][q][m]`,
/// `es[p][q][k][l]`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct GrandCartesian {
    /// Velocity from force.
    pub uf: [[f64; 3]; 3],
    /// Velocity from torque.
    pub ul: [[f64; 3]; 3],
    /// Velocity `i` from stresslet `(k, l)`.
    pub us: [[[f64; 3]; 3]; 3],
    /// Angular velocity from force.
    pub of: [[f64; 3]; 3],
    /// Angular velocity from torque.
    pub ol: [[f64; 3]; 3],
    /// Angular velocity `m` from stresslet `(k, l)`.
    pub os: [[[f64; 3]; 3]; 3],
    /// Strain `(p, q)` from force `j`.
    pub ef: [[[f64; 3]; 3]; 3],
    /// Strain `(p, q)` from torque `m`.
    pub el: [[[f64; 3]; 3]; 3],
    /// Strain `(p, q)` from stresslet `(k, l)`.
    pub es: [[[[f64; 3]; 3]; 3]; 3],
}

/// The force-velocity block alone (F-only scenes).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BlocksF {
    /// Velocity from force, 3x3.
    pub uf: [[f64; 3]; 3],
}

/// The force/torque blocks (FT scenes).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BlocksFT {
    /// Velocity from force.
    pub uf: [[f64; 3]; 3],
    /// Velocity from torque.
    pub ul: [[f64; 3]; 3],
    /// Angular velocity from force.
    pub of: [[f64; 3]; 3],
    /// Angular velocity from torque.
    pub ol: [[f64; 3]; 3],
}

/// The fused pair product: `a = M^{ab} vb` and `b = M^{ba} va = (M^{ab})^T va`, the
/// contributions of one pair to both particles' velocities, in grand order (`U`, then
/// `Omega`, then `E` as kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Product<const K: usize> {
    /// Contribution to particle a.
    pub a: [f64; K],
    /// Contribution to particle b.
    pub b: [f64; K],
}

impl From<&Grand> for BlocksF {
    fn from(g: &Grand) -> Self {
        BlocksF { uf: g.uf }
    }
}

impl From<&Grand> for BlocksFT {
    fn from(g: &Grand) -> Self {
        BlocksFT {
            uf: g.uf,
            ul: g.ul,
            of: g.of,
            ol: g.ol,
        }
    }
}

/// The rows of `blocks` (each `[T; C]`) one after another.
fn push_rows<const C: usize>(out: &mut Vec<f64>, blocks: &[[f64; C]]) {
    for row in blocks {
        out.extend_from_slice(row);
    }
}

/// The rows of a block taken from `flat`, from `at` on; `at` moves past them.
fn take_rows<const R: usize, const C: usize>(flat: &[f64], at: &mut usize) -> [[f64; C]; R] {
    let rows = std::array::from_fn(|i| std::array::from_fn(|j| flat[*at + i * C + j]));
    *at += R * C;
    rows
}

impl Grand {
    /// The fields flattened in their order, each row-major: the layout of
    /// [`GRAND_FLAT`].
    pub fn flat(&self) -> [f64; 121] {
        let mut v = Vec::with_capacity(121);
        push_rows(&mut v, &self.uf);
        push_rows(&mut v, &self.ul);
        push_rows(&mut v, &self.us);
        push_rows(&mut v, &self.of);
        push_rows(&mut v, &self.ol);
        push_rows(&mut v, &self.os);
        push_rows(&mut v, &self.ef);
        push_rows(&mut v, &self.el);
        push_rows(&mut v, &self.es);
        std::array::from_fn(|i| v[i])
    }

    /// The inverse of [`Grand::flat`].
    pub fn from_flat(m: &[f64; 121]) -> Grand {
        let at = &mut 0;
        Grand {
            uf: take_rows(m, at),
            ul: take_rows(m, at),
            us: take_rows(m, at),
            of: take_rows(m, at),
            ol: take_rows(m, at),
            os: take_rows(m, at),
            ef: take_rows(m, at),
            el: take_rows(m, at),
            es: take_rows(m, at),
        }
    }
}

impl BlocksF {
    /// `uf` row-major: the layout of [`F_FLAT`].
    pub fn flat(&self) -> [f64; 9] {
        std::array::from_fn(|k| self.uf[k / 3][k % 3])
    }

    /// The inverse of [`BlocksF::flat`].
    pub fn from_flat(m: &[f64; 9]) -> BlocksF {
        BlocksF {
            uf: take_rows(m, &mut 0),
        }
    }
}

impl BlocksFT {
    /// `uf`, `ul`, `of`, `ol`, each row-major: the layout of [`FT_FLAT`].
    pub fn flat(&self) -> [f64; 36] {
        let mut v = Vec::with_capacity(36);
        for b in [&self.uf, &self.ul, &self.of, &self.ol] {
            push_rows(&mut v, b);
        }
        std::array::from_fn(|i| v[i])
    }

    /// The inverse of [`BlocksFT::flat`].
    pub fn from_flat(m: &[f64; 36]) -> BlocksFT {
        let at = &mut 0;
        BlocksFT {
            uf: take_rows(m, at),
            ul: take_rows(m, at),
            of: take_rows(m, at),
            ol: take_rows(m, at),
        }
    }
}

/// `(M x, M^T y)` for a small dense block stored row-major.
fn mat_products<const K: usize>(m: &[[f64; K]; K], x: &[f64; K], y: &[f64; K]) -> Product<K> {
    let mut a = [0.0; K];
    let mut b = [0.0; K];
    for i in 0..K {
        for j in 0..K {
            a[i] += m[i][j] * x[j];
            b[j] += m[i][j] * y[i];
        }
    }
    Product { a, b }
}

impl Grand {
    /// The pair product from the 11x11 grand block (`va`, `vb`: force, torque and
    /// stresslet of a and b): `a = M^{ab} vb`, `b = (M^{ab})^T va`.
    pub fn product(&self, va: [f64; 11], vb: [f64; 11]) -> Product<11> {
        let m = self.matrix();
        let rows: [[f64; 11]; 11] = std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]));
        mat_products(&rows, &vb, &va)
    }
}

/// Where entry `(i, j)` of [`Grand::matrix`] sits among [`Grand`]'s fields flattened in
/// their order (`uf`, `ul`, `us`, `of`, `ol`, `os`, `ef`, `el`, `es`, each row-major): the
/// layout of the lane kernels' outputs (`kernels::pair_lanes_ordered`).
pub const GRAND_FLAT: [[usize; 11]; 11] = flat();

/// [`GRAND_FLAT`] for [`BlocksFT`] (`uf`, `ul`, `of`, `ol`; [`BlocksFT::matrix`]): the
/// layout of `kernels::pair_ft_lanes_ordered`.
pub const FT_FLAT: [[usize; 6]; 6] = flat();

/// [`GRAND_FLAT`] for [`BlocksF`] (`uf`, row-major): the layout of
/// `kernels::pair_f_lanes_ordered`.
pub const F_FLAT: [[usize; 3]; 3] = flat();

/// Where entry `(i, j)` of the `K x K` matrix in grand order (`K` = 3, 6, 11: rows
/// `U`, `Omega`, `E` and columns `F`, `L`, `S` of sizes 3, 3, 5, as many as fit) sits
/// among its blocks flattened one after another, each row-major.
const fn flat<const K: usize>() -> [[usize; K]; K] {
    const SIZE: [usize; 3] = [3, 3, 5];
    const START: [usize; 3] = [0, 3, 6];
    let parts = match K {
        3 => 1,
        6 => 2,
        11 => 3,
        _ => panic!("K is 3, 6 or 11"),
    };
    let mut at = [[0; K]; K];
    let mut offset = 0;
    let mut rb = 0;
    while rb < parts {
        let mut cb = 0;
        while cb < parts {
            let mut i = 0;
            while i < SIZE[rb] {
                let mut j = 0;
                while j < SIZE[cb] {
                    at[START[rb] + i][START[cb] + j] = offset + i * SIZE[cb] + j;
                    j += 1;
                }
                i += 1;
            }
            offset += SIZE[rb] * SIZE[cb];
            cb += 1;
        }
        rb += 1;
    }
    at
}

/// The F or FT blocks (`K` = 3 or 6, `N = K^2`), flattened as [`F_FLAT`] or [`FT_FLAT`]
/// say, from the flattened FTS blocks of `kernels::pair_lanes_ordered`: the truncation
/// for a confinement without F or FT lane kernels of its own.
#[inline(always)]
pub fn truncate_lanes<L: lanes::Lane, const K: usize, const N: usize>(
    m: [L; 121],
    at: &[[usize; K]; K],
) -> [L; N] {
    let mut out = [L::splat(0.0); N];
    for i in 0..K {
        for j in 0..K {
            out[at[i][j]] = m[GRAND_FLAT[i][j]];
        }
    }
    out
}

/// The pair product of [`Grand::product`] on lanes, from the flattened blocks of
/// `kernels::pair_lanes_ordered`: `a = M^{ab} vb`, `b = (M^{ab})^T va`.
#[inline(always)]
pub fn grand_lanes_product<L: lanes::Lane>(
    m: &[L; 121],
    va: [L; 11],
    vb: [L; 11],
) -> ([L; 11], [L; 11]) {
    let mut a = [L::splat(0.0); 11];
    let mut b = [L::splat(0.0); 11];
    for (i, row) in GRAND_FLAT.iter().enumerate() {
        for (j, &k) in row.iter().enumerate() {
            a[i] = m[k].mul_add(vb[j], a[i]);
            b[j] = m[k].mul_add(va[i], b[j]);
        }
    }
    (a, b)
}

impl BlocksF {
    /// The pair product from the blocks (`va`, `vb`: forces on a and b).
    pub fn product(&self, va: [f64; 3], vb: [f64; 3]) -> Product<3> {
        mat_products(&self.uf, &vb, &va)
    }
}

/// Block by block: a correction or one more image added to a pair's blocks.
impl core::ops::AddAssign<&BlocksFT> for BlocksFT {
    fn add_assign(&mut self, b: &BlocksFT) {
        for i in 0..3 {
            for j in 0..3 {
                self.uf[i][j] += b.uf[i][j];
                self.ul[i][j] += b.ul[i][j];
                self.of[i][j] += b.of[i][j];
                self.ol[i][j] += b.ol[i][j];
            }
        }
    }
}

/// Block by block: a part that two sums both hold taken out once.
impl core::ops::SubAssign<&BlocksFT> for BlocksFT {
    fn sub_assign(&mut self, b: &BlocksFT) {
        for i in 0..3 {
            for j in 0..3 {
                self.uf[i][j] -= b.uf[i][j];
                self.ul[i][j] -= b.ul[i][j];
                self.of[i][j] -= b.of[i][j];
                self.ol[i][j] -= b.ol[i][j];
            }
        }
    }
}

impl BlocksFT {
    /// The 6x6 block `[[UF, UL], [OF, OL]]`.
    pub fn matrix(&self) -> [[f64; 6]; 6] {
        let mut m = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = self.uf[i][j];
                m[i][j + 3] = self.ul[i][j];
                m[i + 3][j] = self.of[i][j];
                m[i + 3][j + 3] = self.ol[i][j];
            }
        }
        m
    }

    /// The pair product from the blocks (`va`, `vb`: force then torque of a and b).
    pub fn product(&self, va: [f64; 6], vb: [f64; 6]) -> Product<6> {
        mat_products(&self.matrix(), &vb, &va)
    }
}

/// A per-particle vector from a self kernel, e.g. the Brownian drift
/// `sum_j d/dx_j M^{aa}_{ij}` (rows `U`, then `Omega`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift<const K: usize> {
    /// The vector.
    pub a: [f64; K],
}

/// A scalar pair product evaluated lane by lane: the lane twin of a confinement that
/// has no lane kernel of its own (the general path), in `f64` whatever the lanes'
/// element. Returns `(a, b)` as lanes.
#[inline(always)]
pub fn lane_by_lane<L: lanes::Lane, const K: usize>(
    f: impl Fn([f64; 3], f64, [f64; 3], f64, [f64; K], [f64; K]) -> Product<K>,
    xa: [L; 3],
    aa: L,
    xb: [L; 3],
    ab: L,
    va: [L; K],
    vb: [L; K],
) -> ([L; K], [L; K]) {
    use lanes::{Element, MAX_WIDTH};
    let unpack = |v: L| {
        let mut b = [L::Elem::default(); MAX_WIDTH];
        v.store(&mut b);
        b.map(Element::to_f64)
    };
    let (xa, xb) = (xa.map(unpack), xb.map(unpack));
    let (aa, ab) = (unpack(aa), unpack(ab));
    let (va, vb) = (va.map(unpack), vb.map(unpack));
    let mut a = [[L::Elem::default(); MAX_WIDTH]; K];
    let mut b = [[L::Elem::default(); MAX_WIDTH]; K];
    for l in 0..L::WIDTH {
        let p = f(
            std::array::from_fn(|k| xa[k][l]),
            aa[l],
            std::array::from_fn(|k| xb[k][l]),
            ab[l],
            std::array::from_fn(|k| va[k][l]),
            std::array::from_fn(|k| vb[k][l]),
        );
        for k in 0..K {
            a[k][l] = L::Elem::from_f64(p.a[k]);
            b[k][l] = L::Elem::from_f64(p.b[k]);
        }
    }
    (a.map(|v| L::load(&v)), b.map(|v| L::load(&v)))
}
