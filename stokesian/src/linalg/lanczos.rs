//! The square root of a symmetric positive-definite operator applied to a vector,
//! `M^{1/2} w`, by the Lanczos process from matrix-vector products alone (the Brownian
//! displacement of large systems, without the dense mobility).

use thiserror::Error;

/// Why a Krylov square root failed.
#[derive(Debug, Error, PartialEq)]
pub enum LanczosError {
    /// The Lanczos matrix has a non-positive eigenvalue: the operator is not positive
    /// definite.
    #[error("the operator is not positive definite (Lanczos eigenvalue {0:e})")]
    NotPositiveDefinite(f64),
    /// No convergence within the iteration limit.
    #[error(
        "Lanczos did not converge to {tol:e} in {iterations} iterations (last change {change:e})"
    )]
    NotConverged {
        /// Requested relative tolerance.
        tol: f64,
        /// Iterations done.
        iterations: usize,
        /// Relative change of the last iteration.
        change: f64,
    },
}

/// `M^{1/2} w` for a symmetric positive definite `M` known only through products
/// `apply(x) = M x`, by the Lanczos process (Chow & Saad 2014; Ando, Chow, Saad &
/// Skolnick 2012 for Brownian dynamics): with `V_k` the orthonormal Krylov basis
/// (fully reorthogonalised) and `T_k` the tridiagonal Lanczos matrix,
/// `M^{1/2} w ~ |w| V_k T_k^{1/2} e_1`. Stops when successive approximations differ
/// by less than `tol` relative; returns the result and the number of iterations.
pub fn lanczos_sqrt(
    apply: impl Fn(&[f64]) -> Vec<f64>,
    w: &[f64],
    tol: f64,
    max_iter: usize,
) -> Result<(Vec<f64>, usize), LanczosError> {
    let n = w.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let beta0 = dot(w, w).sqrt();
    if beta0 == 0.0 {
        return Ok((vec![0.0; n], 0));
    }
    let mut basis: Vec<Vec<f64>> = vec![w.iter().map(|x| x / beta0).collect()];
    let (mut alpha, mut beta): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut previous: Option<Vec<f64>> = None;
    let mut change = f64::INFINITY;
    for k in 0..max_iter.min(n) {
        let mut z = apply(&basis[k]);
        let a = dot(&basis[k], &z);
        alpha.push(a);
        // full reorthogonalisation against the whole basis (twice is enough)
        for _ in 0..2 {
            for v in &basis {
                let c = dot(v, &z);
                for (zi, vi) in z.iter_mut().zip(v) {
                    *zi -= c * vi;
                }
            }
        }
        let b = dot(&z, &z).sqrt();
        // y = beta0 V T^{1/2} e1 from the eigen-decomposition of the k+1 x k+1 T
        let m = alpha.len();
        let t = nalgebra::DMatrix::from_fn(m, m, |i, j| {
            if i == j {
                alpha[i]
            } else if i + 1 == j {
                beta[i]
            } else if j + 1 == i {
                beta[j]
            } else {
                0.0
            }
        });
        let eig = t.symmetric_eigen();
        let lmin = eig.eigenvalues.min();
        if lmin <= 0.0 {
            return Err(LanczosError::NotPositiveDefinite(lmin));
        }
        let coef: Vec<f64> = (0..m)
            .map(|i| {
                (0..m)
                    .map(|j| {
                        eig.eigenvectors[(i, j)]
                            * eig.eigenvalues[j].sqrt()
                            * eig.eigenvectors[(0, j)]
                    })
                    .sum::<f64>()
                    * beta0
            })
            .collect();
        let mut y = vec![0.0; n];
        for (c, v) in coef.iter().zip(&basis) {
            for (yi, vi) in y.iter_mut().zip(v) {
                *yi += c * vi;
            }
        }
        if let Some(prev) = &previous {
            let d: f64 = y
                .iter()
                .zip(prev)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            change = d / dot(&y, &y).sqrt();
            if change < tol {
                return Ok((y, m));
            }
        }
        // an invariant subspace: the result is exact
        if b <= 1e-14 * beta0 || m == n {
            return Ok((y, m));
        }
        beta.push(b);
        basis.push(z.iter().map(|x| x / b).collect());
        previous = Some(y);
    }
    Err(LanczosError::NotConverged {
        tol,
        iterations: alpha.len(),
        change,
    })
}
