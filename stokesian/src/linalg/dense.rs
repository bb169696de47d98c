//! Large dense linear algebra through faer: the blocked, multithreaded Cholesky
//! factorisation, its triangular solves and products, and matrix-vector products, on the
//! nalgebra matrices the rest of the crate holds. nalgebra keeps the fixed-size blocks
//! and small systems; a `DMatrix` is column-major like faer's matrices and is viewed by
//! faer in place, never copied on the way in. (nalgebra's Cholesky is unblocked and runs
//! on one thread: an order of magnitude slower than faer's at thousands of rows.)
//! Below [`SMALL`] rows the factorisation is nalgebra's: faer hands every call to the
//! thread pool and allocates its workspace, which costs more than the factorisation of a
//! 6 x 6 matrix (the FT resistance of one sphere, factored three times per lubricated
//! Brownian step).

use faer::linalg::solvers::{DenseSolveCore, Llt, Solve};
use faer::{Mat, MatRef, Side};
use nalgebra::{DMatrix, DMatrixView, DVector};

/// faer's view of a nalgebra matrix (no copy).
fn view(m: &DMatrix<f64>) -> MatRef<'_, f64> {
    MatRef::from_column_major_slice(m.as_slice(), m.nrows(), m.ncols())
}

/// faer's view of a vector as a column.
fn column(x: &[f64]) -> MatRef<'_, f64> {
    MatRef::from_column_major_slice(x, x.len(), 1)
}

/// The first column of a faer matrix as a `Vec`.
fn to_vec(m: Mat<f64>) -> Vec<f64> {
    m.col_as_slice(0).to_vec()
}

/// `m x` (faer's matrix-vector product, parallel over rows).
pub fn mul_vec(m: &DMatrix<f64>, x: &[f64]) -> Vec<f64> {
    assert_eq!(m.ncols(), x.len(), "matrix-vector dimensions");
    to_vec(view(m) * column(x))
}

/// Dimension below which [`Cholesky`] uses nalgebra's unblocked factorisation.
pub const SMALL: usize = 96;

/// The Cholesky factorisation `M = L L^T` of a symmetric positive-definite matrix (its
/// lower triangle is read).
pub enum Cholesky {
    /// Below [`SMALL`]: nalgebra's.
    Small(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    /// faer's blocked, multithreaded factorisation.
    Large(Llt<f64>),
}

impl Cholesky {
    /// Factor `m`; `None` if it is not (numerically) positive definite.
    pub fn new(m: &DMatrix<f64>) -> Option<Cholesky> {
        assert_eq!(m.nrows(), m.ncols(), "a square matrix");
        if m.nrows() < SMALL {
            m.clone().cholesky().map(Cholesky::Small)
        } else {
            view(m).llt(Side::Lower).ok().map(Cholesky::Large)
        }
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        match self {
            Cholesky::Small(c) => c.l_dirty().nrows(),
            Cholesky::Large(c) => c.L().nrows(),
        }
    }

    /// `L w`: a vector of covariance `M` from standard normal `w`.
    pub fn l_mul(&self, w: &[f64]) -> Vec<f64> {
        assert_eq!(self.dim(), w.len(), "factor-vector dimensions");
        match self {
            Cholesky::Small(c) => (c.l() * DVector::from_column_slice(w)).data.into(),
            Cholesky::Large(c) => to_vec(c.L() * column(w)),
        }
    }

    /// `L^{-T} w`: a vector of covariance `M^{-1}` from standard normal `w`.
    pub fn lt_solve(&self, w: &[f64]) -> Vec<f64> {
        assert_eq!(self.dim(), w.len(), "factor-vector dimensions");
        match self {
            Cholesky::Small(c) => {
                let mut x = DVector::from_column_slice(w);
                c.l().tr_solve_lower_triangular_mut(&mut x);
                x.data.into()
            }
            Cholesky::Large(c) => {
                let mut x = Mat::from_fn(w.len(), 1, |i, _| w[i]);
                c.L()
                    .transpose()
                    .solve_upper_triangular_in_place(x.as_mut());
                to_vec(x)
            }
        }
    }

    /// `M^{-1} b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        assert_eq!(self.dim(), b.len(), "factor-vector dimensions");
        match self {
            Cholesky::Small(c) => c.solve(&DVector::from_column_slice(b)).data.into(),
            Cholesky::Large(c) => to_vec(c.solve(column(b))),
        }
    }

    /// `M^{-1}`, symmetric.
    pub fn inverse(&self) -> DMatrix<f64> {
        match self {
            Cholesky::Small(c) => small_inverse(c.l_dirty()),
            Cholesky::Large(c) => {
                let inv = c.inverse();
                let n = self.dim();
                DMatrix::from_fn(n, n, |i, j| inv[(i.max(j), i.min(j))])
            }
        }
    }

    /// The diagonal of `L`.
    pub fn diagonal(&self) -> Vec<f64> {
        match self {
            Cholesky::Small(c) => c.l_dirty().diagonal().data.into(),
            Cholesky::Large(c) => {
                let l = c.L();
                (0..l.nrows()).map(|i| l[(i, i)]).collect()
            }
        }
    }
}

/// A zeroed column-major matrix in an anonymous memory map that asks the kernel for
/// transparent huge pages (Linux `madvise(MADV_HUGEPAGE)`, through `memmap2`), for the
/// large matrices the command line assembles and writes ([`crate::System::mobility_into`]).
/// A fresh `Vec` is mapped 4 KiB at a time where it is first written: at FTS, N = 1000
/// (968 MB) mapping and clearing its pages and the TLB misses of the column-wise writes
/// cost more than the kernels (more than twice the time of the whole assembly into huge
/// pages). Elsewhere than Linux, or where the kernel declines the advice, the same matrix
/// in ordinary pages.
pub struct LargeMatrix {
    map: memmap2::MmapMut,
    rows: usize,
    cols: usize,
}

impl LargeMatrix {
    /// A `rows x cols` matrix of zeros; an error if the memory cannot be mapped.
    pub fn zeros(rows: usize, cols: usize) -> std::io::Result<LargeMatrix> {
        let bytes = rows
            .checked_mul(cols)
            .and_then(|len| len.checked_mul(std::mem::size_of::<f64>()))
            .ok_or_else(|| {
                std::io::Error::new(
                    std::io::ErrorKind::OutOfMemory,
                    format!("a {rows} x {cols} matrix exceeds the address space"),
                )
            })?;
        // (at least one value: a map cannot be empty)
        let map = memmap2::MmapOptions::new()
            .len(bytes.max(std::mem::size_of::<f64>()))
            .map_anon()?;
        // a hint: declined, the matrix is the same, only slower to fill
        #[cfg(target_os = "linux")]
        let _ = map.advise(memmap2::Advice::HugePage);
        Ok(LargeMatrix { map, rows, cols })
    }

    /// The values, column-major.
    pub fn as_slice(&self) -> &[f64] {
        &bytemuck::cast_slice(&self.map[..])[..self.rows * self.cols]
    }

    /// The values, column-major, to write.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut bytemuck::cast_slice_mut(&mut self.map[..])[..self.rows * self.cols]
    }

    /// nalgebra's view of the matrix (no copy).
    pub fn view(&self) -> DMatrixView<'_, f64> {
        DMatrixView::from_slice(self.as_slice(), self.rows, self.cols)
    }
}

/// `M^{-1} = L^-T L^-1` from the lower triangle of `l`: `X = L^-1` by forward
/// substitution, column by column, then the lower triangle of `X^T X`, mirrored; about
/// `n^3/3` flops in all. nalgebra's inverse solves the identity one column at a time
/// through its generic solver, which took a quarter of a lubricated resistance's time in
/// its 22 x 22 pair inverses.
fn small_inverse(l: &DMatrix<f64>) -> DMatrix<f64> {
    let n = l.nrows();
    let mut x = DMatrix::zeros(n, n);
    for j in 0..n {
        x[(j, j)] = 1.0 / l[(j, j)];
        for i in j + 1..n {
            let s: f64 = (j..i).map(|k| l[(i, k)] * x[(k, j)]).sum();
            x[(i, j)] = -s / l[(i, i)];
        }
    }
    let mut inv = DMatrix::zeros(n, n);
    for j in 0..n {
        for i in j..n {
            let v: f64 = (i..n).map(|k| x[(k, i)] * x[(k, j)]).sum();
            inv[(i, j)] = v;
            inv[(j, i)] = v;
        }
    }
    inv
}

/// The outcome of [`check_spd`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpdCheck {
    /// `||M - M^T||_F / ||M||_F`.
    pub asymmetry: f64,
    /// Whether the Cholesky factorisation of the symmetric part succeeded.
    pub positive_definite: bool,
}

impl SpdCheck {
    /// Symmetric to `1e-12` relative and positive definite. (The assembled matrix is
    /// symmetric by construction up to the round-off of the self blocks, ~1e-16.)
    pub fn passed(&self) -> bool {
        self.asymmetry <= 1e-12 && self.positive_definite
    }
}

/// Symmetry and positive-definiteness (Cholesky) of a mobility or resistance matrix
/// (`&DMatrix` or a view, such as [`LargeMatrix::view`]).
pub fn check_spd<'a>(m: impl Into<DMatrixView<'a, f64>>) -> SpdCheck {
    let m: DMatrixView<f64> = m.into();
    let norm = m.norm();
    let asymmetry = if norm > 0.0 {
        (m - m.transpose()).norm() / norm
    } else {
        0.0
    };
    let sym = (m + m.transpose()) * 0.5;
    SpdCheck {
        asymmetry,
        positive_definite: Cholesky::new(&sym).is_some(),
    }
}
