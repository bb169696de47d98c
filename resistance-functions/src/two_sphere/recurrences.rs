//! The twin-multipole recurrences of Jeffrey & Onishi (1984) and Jeffrey (1992) as
//! corrected by Townsend (2023): the families `P`, `V`, `Q` evaluated to a truncation, the
//! triangles `R_{n, m-q, q}` read off them ([`Coefficients`], built at run time), and the
//! committed triangles to [`TRUNCATION`] read from `src/generated/` on first use.

use super::TRUNCATION;
use std::sync::OnceLock;

/// The recurrence families of JO84/J92.
#[derive(Clone, Copy)]
enum Recurrence {
    /// Motion along the line of centres (JO84 3.6-3.9, "X^A"):
    /// `P`, `V`, binomial `C(n+s, n)`.
    Axisymmetric,
    /// Motion across it (JO84 4.6-4.11, "Y^A/Y^B/Y^C"): `P`, `V`, `Q`, `C(n+s, n+1)`.
    Transverse,
    /// The `Z^M` mode (J92 73-76): `P`, `V`, `Q`, `C(n+s, n+2)`, `s >= 2`.
    Twist,
    /// Rotation about the line of centres (JO84 sec. 6): rotlets only, `Q`, `C(n+s, n)`.
    AxialRotation,
}

/// A family: recurrence, initial conditions (`P_{n00} = V_{n00} = delta_{pv n}`, `Q_{n00}
/// = delta_{q n}`; 0 for none) and which coefficients are read off.
struct Family {
    rec: Recurrence,
    init_pv: usize,
    init_q: usize,
    /// `(use Q rather than P, n)` for each output sequence
    outputs: &'static [(bool, usize)],
}

/// Output of one family: for each requested sequence the triangle `R_{n, m-q, q}`, `0 <= q
/// <= m <= TRUNCATION`, stored row by row (`m (m+1)/2 + q`).
pub(super) type Triangles = Vec<Vec<f64>>;

pub(super) fn tri(m: usize, q: usize) -> usize {
    m * (m + 1) / 2 + q
}

/// Flat storage of `(n, p, q)`, `n >= 1`, `p, q >= 0`, `n + p + q <= top`, ordered by `q`,
/// then `n + p`, then `n`: the recurrences read, for one coefficient, the children
/// `(s, sigma - s, r)` at fixed `sigma` and `r` for consecutive `s`, which this order
/// makes adjacent in memory (in `(n, p, q)` order every child was a cache miss, and
/// building took several times longer).
struct Tetra {
    top: usize,
    off: Vec<usize>,
    len: usize,
}

impl Tetra {
    fn new(top: usize) -> Self {
        let w = top + 1;
        let mut off = vec![usize::MAX; w * w];
        let mut len = 0;
        for q in 0..top {
            for sigma in 1..=(top - q) {
                off[q * w + sigma] = len;
                len += sigma; // n = 1..=sigma
            }
        }
        Tetra { top, off, len }
    }

    /// Index of `(n, p, q)`, or `None` when `p` or `q` is negative (those coefficients are
    /// zero). Callers only ask for totals below the current one, so the index exists.
    #[inline]
    fn at(&self, n: usize, p: i64, q: i64) -> Option<usize> {
        if p < 0 || q < 0 {
            None
        } else {
            Some(self.off[q as usize * (self.top + 1) + n + p as usize] + n - 1)
        }
    }
}

fn binomials(nmax: usize) -> Vec<Vec<f64>> {
    let mut b = vec![vec![0.0; nmax + 1]; nmax + 1];
    for n in 0..=nmax {
        b[n][0] = 1.0;
        for k in 1..=n {
            b[n][k] = b[n - 1][k - 1] + if k < n { b[n - 1][k] } else { 0.0 };
        }
    }
    b
}

/// Builds the `P, V, Q` tables of one family up to total order `truncation + 2` and
/// extracts the requested triangles.
fn build(family: &Family, truncation: usize) -> Triangles {
    let top = truncation + 2; // n = 2 outputs need n + m <= top
    let tet = Tetra::new(top);
    let binom = binomials(2 * top + 2);
    let mut p_t = vec![0.0; tet.len];
    let mut v_t = vec![0.0; tet.len];
    let mut q_t = vec![0.0; tet.len];
    let get = |v: &Vec<f64>, n: usize, p: i64, q: i64| tet.at(n, p, q).map_or(0.0, |i| v[i]);
    // The recurrence coefficients depend on (n, s) only: tabulated once (the divisions
    // would otherwise dominate the innermost loop).
    let w = top + 2;
    let table = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
        (0..w * w)
            .map(|i| {
                let (n, s) = (i / w, i % w);
                if n == 0 || s == 0 {
                    0.0
                } else {
                    f(n as f64, s as f64)
                }
            })
            .collect()
    };
    let coef: Vec<Vec<f64>> = match family.rec {
        Recurrence::Axisymmetric => vec![
            table(&|nf, sf| {
                nf * (2.0 * nf + 1.0) * (2.0 * nf * sf - nf - sf + 2.0)
                    / (2.0 * (nf + 1.0) * (2.0 * sf - 1.0) * (nf + sf))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| nf * (4.0 * nf * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))),
        ],
        Recurrence::Transverse => vec![
            table(&|nf, sf| {
                (2.0 * nf + 1.0) / (2.0 * (nf + 1.0))
                    * (3.0 * (nf + sf) - (nf * sf + 1.0) * (2.0 * nf * sf - sf - nf + 2.0))
                    / (sf * (nf + sf) * (2.0 * sf - 1.0))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| nf * (4.0 * nf * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))),
            table(&|nf, _| 2.0 * (4.0 * nf * nf - 1.0) / (3.0 * (nf + 1.0))),
            table(&|nf, sf| sf / (nf + 1.0)),
            table(&|nf, sf| 3.0 / (2.0 * nf * sf * (nf + 1.0))),
        ],
        Recurrence::Twist => vec![
            table(&|nf, _| 2.0 * (2.0 * nf + 1.0) * (2.0 * nf - 1.0) / (nf + 1.0)),
            table(&|nf, sf| {
                nf * (2.0 * nf + 1.0) * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0) * (2.0 * sf + 1.0))
            }),
            table(&|nf, sf| {
                (2.0 * nf + 1.0) / (nf + 1.0)
                    * (nf * sf * (nf + sf - 2.0 * nf * sf - 2.0)
                        - 4.0 * (2.0 * nf * sf - 4.0 * sf - 4.0 * nf + 2.0))
                    / (2.0 * sf * (nf + sf) * (2.0 * sf - 1.0))
            }),
            table(&|nf, _| nf * (2.0 * nf - 1.0) / (2.0 * (nf + 1.0))),
            table(&|nf, sf| sf / (nf + 1.0)),
            table(&|nf, sf| 2.0 / (nf * sf * (nf + 1.0))),
        ],
        Recurrence::AxialRotation => vec![table(&|nf, sf| sf / (nf + 1.0))],
    };
    for total in 1..=top {
        for n in 1..=total {
            let nf = n as f64;
            for p in 0..=(total - n) {
                let q = total - n - p;
                let idx = tet.at(n, p as i64, q as i64).expect("in range");
                if p == 0 && q == 0 {
                    p_t[idx] = if n == family.init_pv { 1.0 } else { 0.0 };
                    v_t[idx] = p_t[idx];
                    q_t[idx] = if n == family.init_q { 1.0 } else { 0.0 };
                    continue;
                }
                // Structural zeros: every term of P_npq, V_npq needs p >= n - 1 and every
                // term of Q_npq needs p >= n (the third index of each child is p - n + 1,
                // p - n or p - n - 1), unless it is an initial value (n, 0, 0).
                if p + 1 < n {
                    continue;
                }
                let (pi, qi, ni) = (p as i64, q as i64, n as i64);
                let (mut ps, mut vs, mut qs) = (0.0, 0.0, 0.0);
                // By the same rule a child (s, q - s - k, .) vanishes unless q - s - k >= s - 1
                // or it is the initial value (s = q - k); so s runs over 1..=(q+1)/2 and the
                // last three values.
                let s_low = q.div_ceil(2).min(q);
                let s_range = (1..=s_low).chain((q.saturating_sub(2).max(s_low + 1))..=q);
                match family.rec {
                    Recurrence::Axisymmetric => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            let b = binom[n + s][n];
                            let k = n * w + s;
                            let (c1, c2, c3) = (coef[0][k], coef[1][k], coef[2][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (c1 * get(&p_t, s, qi - si, pi - ni + 1)
                                    - c2 * pm
                                    - c3 * get(&v_t, s, qi - si - 2, pi - ni + 1));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        v_t[idx] = ps - 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::Transverse => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            let b = binom[n + s][n + 1];
                            let k = n * w + s;
                            let (c1, c2, c3, c4) = (coef[0][k], coef[1][k], coef[2][k], coef[3][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (c1 * get(&p_t, s, qi - si, pi - ni + 1)
                                    + c2 * pm
                                    + c3 * get(&v_t, s, qi - si - 2, pi - ni + 1)
                                    - c4 * get(&q_t, s, qi - si - 1, pi - ni + 1));
                            qs += b
                                * (coef[4][k] * get(&q_t, s, qi - si - 1, pi - ni)
                                    - coef[5][k] * get(&p_t, s, qi - si, pi - ni));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        q_t[idx] = qs;
                        v_t[idx] = ps + 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::Twist => {
                        for s in s_range.clone().filter(|&s| s >= 2) {
                            let si = s as i64;
                            let b = binom[n + s][n + 2];
                            let k = n * w + s;
                            let (c_q, c_v, c_p, c_m) =
                                (coef[0][k], coef[1][k], coef[2][k], coef[3][k]);
                            let pm = get(&p_t, s, qi - si, pi - ni - 1);
                            ps += b
                                * (-c_q * get(&q_t, s, qi - si - 1, pi - ni + 1)
                                    + c_v * get(&v_t, s, qi - si - 2, pi - ni + 1)
                                    + c_p * get(&p_t, s, qi - si, pi - ni + 1)
                                    + c_m * pm);
                            qs += b
                                * (coef[4][k] * get(&q_t, s, qi - si - 1, pi - ni)
                                    - coef[5][k] * get(&p_t, s, qi - si, pi - ni));
                            vs += b * pm;
                        }
                        p_t[idx] = ps;
                        q_t[idx] = qs;
                        v_t[idx] = ps + 2.0 * nf / ((nf + 1.0) * (2.0 * nf + 3.0)) * vs;
                    }
                    Recurrence::AxialRotation => {
                        for s in s_range.clone() {
                            let si = s as i64;
                            qs += binom[n + s][n]
                                * coef[0][n * w + s]
                                * get(&q_t, s, qi - si - 1, pi - ni);
                        }
                        q_t[idx] = qs;
                    }
                }
            }
        }
    }
    family
        .outputs
        .iter()
        .map(|&(use_q, n)| {
            let src = if use_q { &q_t } else { &p_t };
            let mut out = vec![0.0; tri(truncation, truncation) + 1];
            for m in 0..=truncation {
                for q in 0..=m {
                    out[tri(m, q)] = src[tet.at(n, (m - q) as i64, q as i64).expect("in range")];
                }
            }
            out
        })
        .collect()
}

static XA: Family = Family {
    rec: Recurrence::Axisymmetric,
    init_pv: 1,
    init_q: 0,
    outputs: &[(false, 1), (false, 2)],
};
static XM: Family = Family {
    rec: Recurrence::Axisymmetric,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static YA: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 1,
    init_q: 0,
    outputs: &[(false, 1), (true, 1), (false, 2)],
};
static YC: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 0,
    init_q: 1,
    outputs: &[(true, 1), (false, 2)],
};
static YM: Family = Family {
    rec: Recurrence::Transverse,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static ZM: Family = Family {
    rec: Recurrence::Twist,
    init_pv: 2,
    init_q: 0,
    outputs: &[(false, 2)],
};
static XC: Family = Family {
    rec: Recurrence::AxialRotation,
    init_pv: 0,
    init_q: 1,
    outputs: &[(true, 1)],
};

/// The recurrence coefficients of every family, as written by `cargo xtask gen` from
/// [`crate::generate::two_sphere_coefficients`]: the triangles `R_{n, m-q, q}` (`0 <= q <= m <=
/// TRUNCATION`, row by row) of each family's outputs, families in the order of
/// [`Table::ALL`], little-endian `f64`. They do not depend on `lambda`; `gen --check`
/// fails when this file differs from a fresh evaluation of the recurrences.
static COEFFICIENTS: &[u8; 11 * TRIANGLE * 8] =
    include_bytes!("../generated/two_sphere_coefficients.bin");

/// Numbers in one triangle.
const TRIANGLE: usize = TRUNCATION * (TRUNCATION + 1) / 2 + TRUNCATION + 1;

/// Each family's triangles once read, indexed by `Table as usize`.
static TRIANGLES: [OnceLock<Triangles>; 7] = [const { OnceLock::new() }; 7];

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Table {
    Xa,
    Xm,
    Ya,
    Yc,
    Ym,
    Zm,
    Xc,
}

impl Table {
    /// The order of the families in [`COEFFICIENTS`] (that of the declaration, which
    /// `Table as usize` follows).
    const ALL: [Table; 7] = [
        Table::Xa,
        Table::Xm,
        Table::Ya,
        Table::Yc,
        Table::Ym,
        Table::Zm,
        Table::Xc,
    ];

    fn family(self) -> &'static Family {
        match self {
            Table::Xa => &XA,
            Table::Xm => &XM,
            Table::Ya => &YA,
            Table::Yc => &YC,
            Table::Ym => &YM,
            Table::Zm => &ZM,
            Table::Xc => &XC,
        }
    }

    /// The family's triangles, read from [`COEFFICIENTS`] on first use (a copy of
    /// about 160 kB per triangle, no arithmetic).
    pub(super) fn triangles(self) -> &'static Triangles {
        TRIANGLES[self as usize].get_or_init(|| {
            let before: usize = Table::ALL
                .iter()
                .take_while(|&&t| t != self)
                .map(|t| t.family().outputs.len())
                .sum();
            (0..self.family().outputs.len())
                .map(|k| {
                    let start = (before + k) * TRIANGLE * 8;
                    COEFFICIENTS[start..start + TRIANGLE * 8]
                        .chunks_exact(8)
                        .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
                        .collect()
                })
                .collect()
        })
    }
}

/// The recurrence coefficients of every family to a chosen truncation, built at run time
/// (for [`super::PairSeries::from_coefficients`]; the library itself reads the committed ones,
/// [`TRUNCATION`]). Building costs `O(truncation^4)` operations (doubling the
/// truncation costs sixteen times as much) and memory `O(truncation^3)` while it runs.
pub struct Coefficients {
    pub(super) truncation: usize,
    /// Indexed by `Table as usize`.
    pub(crate) triangles: Vec<Triangles>,
}

impl Coefficients {
    /// The recurrences of every family evaluated to `m <= truncation` (one thread per
    /// family: not rayon's pool, which the other generators of `cargo xtask gen` share).
    pub fn build(truncation: usize) -> Self {
        let triangles = std::thread::scope(|scope| {
            let jobs: Vec<_> = Table::ALL
                .iter()
                .map(|t| scope.spawn(move || build(t.family(), truncation)))
                .collect();
            jobs.into_iter()
                .map(|j| j.join().expect("the recurrences do not panic"))
                .collect()
        });
        Coefficients {
            truncation,
            triangles,
        }
    }

    /// The largest power of `2/s'` the coefficients reach.
    pub fn truncation(&self) -> usize {
        self.truncation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `TRIANGLES` is indexed by `Table as usize`, `COEFFICIENTS` ordered by `Table::ALL`.
    #[test]
    fn table_order_is_the_declaration_order() {
        assert!(Table::ALL.iter().enumerate().all(|(i, &t)| t as usize == i));
    }
}
