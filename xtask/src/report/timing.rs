//! The timing loop: one warm-up pass over a fixed set of inputs, then whole passes
//! until a minimum wall time has elapsed; the result is wall time per evaluation.
//! Callers pass inputs and results through `std::hint::black_box`.

use std::time::{Duration, Instant};

/// Nanoseconds per evaluation of `pass`, which evaluates `per_pass` times. At least
/// three timed passes, and at least `min_time` in total.
pub fn ns_per_eval(min_time: Duration, per_pass: usize, mut pass: impl FnMut()) -> f64 {
    pass(); // warm-up
    let t0 = Instant::now();
    let mut passes = 0usize;
    while passes < 3 || t0.elapsed() < min_time {
        pass();
        passes += 1;
    }
    t0.elapsed().as_secs_f64() * 1e9 / (passes * per_pass.max(1)) as f64
}
