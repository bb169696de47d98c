//! Linked cells over a periodic box: the images of every sphere within `r_c` of a given
//! sphere in `O(1)` per sphere at fixed density. The box is cut into `n_d = max(1,
//! floor(2 L_d / r_c))` cells along each axis, fewer in a sparse box (side `c_d = L_d /
//! n_d >= r_c/2` unless the box is shorter: the `5^3` cells around a sphere hold about
//! 2.3 times the volume of the sphere of radius `r_c`, where `3^3` cells of side `r_c`
//! hold 6.4 times); an image within `r_c` of a sphere lies in a cell at most `ceil(r_c /
//! c_d)` cells away, counted across the periodic boundaries, and each such offset names
//! one cell and one lattice shift, so every image is visited once.
//! Positions are wrapped into `[0, L)` (the lattice sums do not see the wrap). The
//! visiting order (offsets in lexicographic order, the spheres of a cell by index) is
//! fixed, so sums over it do not depend on threads.
//!
//! A cell whose nearest point is farther than `r_c` from the sphere is not visited (the
//! corners of the block of cells around it: about a third of the `5^3` at side `r_c/2`).
//! Along a wall ([`Cells::slab`]) the axis normal to it is not periodic: the spheres
//! fill a slab and no image along it is within `r_c`, so the offsets past the slab's
//! first and last cells are not visited either. Neither changes which images are found,
//! nor their order.

/// Spheres sorted into the cells of a periodic box.
pub(crate) struct Cells {
    lengths: [f64; 3],
    r_cut: f64,
    n: [usize; 3],
    /// The cells' sides `L_d/n_d`.
    side: [f64; 3],
    reach: [i64; 3],
    /// Whether the box is periodic along each axis.
    periodic: [bool; 3],
    /// The spheres of cell `c` are `members[start[c]..start[c + 1]]`, by index.
    start: Vec<usize>,
    members: Vec<usize>,
    /// Positions wrapped into `[0, L)`.
    wrapped: Vec<[f64; 3]>,
    /// Each sphere's cell, `[ix, iy, iz]`.
    cell: Vec<[usize; 3]>,
}

impl Cells {
    /// The cells of side at least `r_cut/2` of the box `lengths`, holding the spheres at
    /// `xs`.
    pub(crate) fn new(lengths: [f64; 3], r_cut: f64, xs: impl Iterator<Item = [f64; 3]>) -> Cells {
        Cells::with_axes(lengths, r_cut, xs, [true; 3])
    }

    /// The cells of a box periodic along `x` and `y` only, of height `lengths[2]`: the
    /// spheres' heights `x_3` must lie in `[0, lengths[2])` and be at least `r_cut` from
    /// the copies of the slab along `z` (`lengths[2]` at least their span plus `r_cut`),
    /// which are not visited.
    pub(crate) fn slab(lengths: [f64; 3], r_cut: f64, xs: impl Iterator<Item = [f64; 3]>) -> Cells {
        Cells::with_axes(lengths, r_cut, xs, [true, true, false])
    }

    fn with_axes(
        lengths: [f64; 3],
        r_cut: f64,
        xs: impl Iterator<Item = [f64; 3]>,
        periodic: [bool; 3],
    ) -> Cells {
        let wrapped: Vec<[f64; 3]> = xs
            .map(|x| {
                std::array::from_fn(|d| {
                    let w = x[d] - lengths[d] * (x[d] / lengths[d]).floor();
                    // rounding can land on L itself
                    if w >= lengths[d] {
                        0.0
                    } else {
                        w
                    }
                })
            })
            .collect();
        let mut n: [usize; 3] =
            std::array::from_fn(|d| ((2.0 * lengths[d] / r_cut).min(1e6) as usize).max(1));
        // no more cells than a few per sphere (a sparse box): larger cells, the same
        // images
        while n.iter().product::<usize>() > 4 * wrapped.len() + 64 {
            let d = (0..3).max_by_key(|&d| n[d]).unwrap_or(0);
            n[d] = (n[d] / 2).max(1);
        }
        let side: [f64; 3] = std::array::from_fn(|d| lengths[d] / n[d] as f64);
        let reach = std::array::from_fn(|d| (r_cut / side[d]).ceil() as i64);
        let cell: Vec<[usize; 3]> = wrapped
            .iter()
            .map(|w| std::array::from_fn(|d| ((w[d] / side[d]) as usize).min(n[d] - 1)))
            .collect();
        let index = |c: &[usize; 3]| (c[0] * n[1] + c[1]) * n[2] + c[2];
        let mut start = vec![0usize; n[0] * n[1] * n[2] + 1];
        for c in &cell {
            start[index(c) + 1] += 1;
        }
        for i in 1..start.len() {
            start[i] += start[i - 1];
        }
        let mut fill = start.clone();
        let mut members = vec![0; cell.len()];
        for (b, c) in cell.iter().enumerate() {
            members[fill[index(c)]] = b;
            fill[index(c)] += 1;
        }
        Cells {
            lengths,
            r_cut,
            n,
            side,
            reach,
            periodic,
            start,
            members,
            wrapped,
            cell,
        }
    }

    /// `f(b, r)` for every image of every sphere `b` within `r_c` of sphere `a`, with
    /// `r = x_a - x_b^image`, in the fixed order of the module docs; `a`'s own term `r =
    /// 0` left out.
    pub(crate) fn for_each_image(&self, a: usize, mut f: impl FnMut(usize, [f64; 3])) {
        let (xa, ca) = (self.wrapped[a], self.cell[a]);
        let rc2 = self.r_cut * self.r_cut;
        // a cell is passed over when its nearest point is beyond `r_c` by more than the
        // rounding of the distances
        let beyond = rc2 * (1.0 + 1e-12);
        let [rx, ry, rz] = self.reach;
        // the cell `c + o` along one axis: its index, the lattice shift of its images and
        // the square of the distance from `x_a` to its nearer face (zero for `a`'s own);
        // `None` past the ends of a non-periodic axis
        let step = |d: usize, o: i64| {
            let i = ca[d] as i64 + o;
            let n = self.n[d] as i64;
            if !self.periodic[d] && !(0..n).contains(&i) {
                return None;
            }
            let x = xa[d] - ca[d] as f64 * self.side[d];
            let gap = match o {
                0 => 0.0,
                o if o > 0 => o as f64 * self.side[d] - x,
                o => x - (o + 1) as f64 * self.side[d],
            }
            .max(0.0);
            Some((
                i.rem_euclid(n) as usize,
                i.div_euclid(n) as f64 * self.lengths[d],
                gap * gap,
            ))
        };
        for ox in -rx..=rx {
            let Some((cx, sx, gx)) = step(0, ox) else {
                continue;
            };
            for oy in -ry..=ry {
                let Some((cy, sy, gy)) = step(1, oy) else {
                    continue;
                };
                if gx + gy > beyond {
                    continue;
                }
                for oz in -rz..=rz {
                    let Some((cz, sz, gz)) = step(2, oz) else {
                        continue;
                    };
                    if gx + gy + gz > beyond {
                        continue;
                    }
                    let c = (cx * self.n[1] + cy) * self.n[2] + cz;
                    for &b in &self.members[self.start[c]..self.start[c + 1]] {
                        let xb = self.wrapped[b];
                        let r = [xa[0] - xb[0] - sx, xa[1] - xb[1] - sy, xa[2] - xb[2] - sz];
                        let d2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
                        if d2 <= rc2 && !(b == a && d2 == 0.0) {
                            f(b, r);
                        }
                    }
                }
            }
        }
    }
}
