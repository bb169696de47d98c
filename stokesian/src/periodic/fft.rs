//! Three-dimensional discrete Fourier transforms of a stack of complex grids, by
//! `rustfft` along each axis in turn. A stack of `g` grids of `mx x my x mz` points is
//! laid out `[ix][grid][iy][iz]` (`iz` fastest): an x-plane of every grid is one
//! contiguous chunk, which is what spreading, the symbols and interpolation share out
//! between threads. Every line is transformed on its own, so the result does not
//! depend on the number of threads.
//!
//! Unnormalised in both directions (`rustfft`'s convention): the forward transform is
//! `sum_j c_j exp(-i k.x_j)`, the inverse `sum_k c_k exp(+i k.x_j)`.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftDirection, FftPlanner};
use std::sync::Arc;

/// Columns of the x-transform handed to one task.
const COLUMNS: usize = 64;

/// The plans of one grid shape, in one direction.
pub(crate) struct Fft3 {
    m: [usize; 3],
    grids: usize,
    plans: [Arc<dyn Fft<f64>>; 3],
}

impl Fft3 {
    /// Plans for `grids` grids of `m` points in `direction`.
    pub(crate) fn new(m: [usize; 3], grids: usize, direction: FftDirection) -> Fft3 {
        let mut planner = FftPlanner::new();
        let plans = m.map(|len| planner.plan_fft(len, direction));
        Fft3 { m, grids, plans }
    }

    /// Transform the stack `data` in place.
    pub(crate) fn process(&self, data: &mut [Complex64]) {
        let [mx, my, mz] = self.m;
        let plane = my * mz;
        assert_eq!(data.len(), mx * self.grids * plane);
        // z: every run of mz points is a line
        let fz = &self.plans[2];
        data.par_chunks_mut(plane).for_each(|chunk| {
            let mut scratch = vec![Complex64::default(); fz.get_inplace_scratch_len()];
            fz.process_with_scratch(chunk, &mut scratch);
        });
        // y: each plane turned to (z, y), its lines transformed, turned back
        let fy = &self.plans[1];
        data.par_chunks_mut(plane).for_each(|chunk| {
            let mut turned = vec![Complex64::default(); plane];
            let mut scratch = vec![Complex64::default(); fy.get_inplace_scratch_len()];
            for iy in 0..my {
                for iz in 0..mz {
                    turned[iz * my + iy] = chunk[iy * mz + iz];
                }
            }
            fy.process_with_scratch(&mut turned, &mut scratch);
            for iy in 0..my {
                for iz in 0..mz {
                    chunk[iy * mz + iz] = turned[iz * my + iy];
                }
            }
        });
        // x: columns of the (mx) x (grids my mz) matrix gathered in blocks, transformed,
        // then written back plane by plane
        let fx = &self.plans[0];
        let row = self.grids * plane;
        let blocks: Vec<Vec<Complex64>> = (0..row.div_ceil(COLUMNS))
            .into_par_iter()
            .map(|b| {
                let (c0, c1) = (b * COLUMNS, ((b + 1) * COLUMNS).min(row));
                let mut lines = vec![Complex64::default(); (c1 - c0) * mx];
                for ix in 0..mx {
                    for c in c0..c1 {
                        lines[(c - c0) * mx + ix] = data[ix * row + c];
                    }
                }
                let mut scratch = vec![Complex64::default(); fx.get_inplace_scratch_len()];
                fx.process_with_scratch(&mut lines, &mut scratch);
                lines
            })
            .collect();
        data.par_chunks_mut(row)
            .enumerate()
            .for_each(|(ix, chunk)| {
                for (b, lines) in blocks.iter().enumerate() {
                    let c0 = b * COLUMNS;
                    for (c, v) in chunk[c0..(c0 + COLUMNS).min(row)].iter_mut().enumerate() {
                        *v = lines[c * mx + ix];
                    }
                }
            });
    }
}
