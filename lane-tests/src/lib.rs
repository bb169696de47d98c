//! Checks of the lane kernels (the generated kernels over `lanes::Lane`) against the
//! scalar kernels, generic over the lanes' element: [`lane_checks`] for every confinement,
//! [`ewald_lanes`] for the building block `ewald_real`. The tests are two binaries,
//! `tests/lanes` (`f64` lanes) and `tests/lanes_single` (`f32` lanes), which compile in
//! parallel.
//!
//! The package is compiled without optimisation (Cargo.toml), and unoptimised lane
//! kernels keep every intermediate of their thousands of statements in its own stack
//! slot: the checks run on a thread with a stack of their own ([`on_a_large_stack`]).

pub mod ewald_lanes;
pub mod lane_checks;

/// The stack of the threads that run unoptimised lane kernels. The checks overflowed 8 MiB
/// and passed in 16 MiB on AVX2 (the `f64` and `f32` binaries); an AVX-512 vector's stack
/// slot is twice an AVX2 one, so 128 MiB (address space, touched only as far as used)
/// leaves a factor of four.
const STACK: usize = 128 << 20;

/// `f()` on a thread with a stack of [`STACK`] bytes (a panic in `f` is passed on).
pub fn on_a_large_stack<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|s| {
        match std::thread::Builder::new()
            .stack_size(STACK)
            .spawn_scoped(s, f)
            .expect("a thread can be started")
            .join()
        {
            Ok(v) => v,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}
