//! Lanes: `f64` vectors that evaluate several pairs per instruction, for the lane
//! kernels that `cargo xtask gen` emits (generic over [`Lane`]).
//!
//! [`Lane`] is implemented by `f64` (one pair: the portable fallback) and, on x86-64,
//! by 4 lanes of AVX2 with FMA and 8 lanes of AVX-512F (types private to this crate).
//! Code generic over [`Lane`] runs through [`dispatch`], which picks the widest
//! instruction set the processor has, detected at run time, and compiles the generic
//! code for it (`#[target_feature]`); [`dispatch_with`] forces one ([`Isa`]), for tests
//! and benchmarks. A plain `cargo build --release` is therefore fast on any x86-64 and
//! correct everywhere else.
//!
//! Everything called inside [`WithLanes::run`] must be `#[inline(always)]` so that it is
//! compiled with the instruction set of the dispatching function. The intrinsics are
//! the project's only `unsafe` code, confined to `x86.rs`.

use std::ops::{Add, Div, Mul, Neg, Sub};

#[cfg(target_arch = "x86_64")]
mod x86;

/// A vector of `WIDTH` `f64` lanes with IEEE arithmetic in each lane.
pub trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Number of lanes.
    const WIDTH: usize;
    /// The result of a lane-wise comparison.
    type Mask: Copy;
    /// Every lane `v`.
    fn splat(v: f64) -> Self;
    /// Lanes `s[0..WIDTH]` (panics if `s` is shorter).
    fn load(s: &[f64]) -> Self;
    /// Write the lanes to `s[0..WIDTH]` (panics if `s` is shorter).
    fn store(self, s: &mut [f64]);
    /// Lanes `0, 1, ..., WIDTH - 1`.
    fn iota() -> Self;
    /// Lane-wise square root: correctly rounded, or within an ulp where an
    /// instruction set computes it from an approximate reciprocal square root refined
    /// by Newton's method (AVX-512: its square root and division are not pipelined).
    fn sqrt(self) -> Self;
    /// `1 / self`: correctly rounded, or within an ulp as for [`Lane::sqrt`].
    #[inline(always)]
    fn recip(self) -> Self {
        Self::splat(1.0) / self
    }
    /// `self * b + c`: fused (one rounding) where the instruction set has FMA, two
    /// roundings in the scalar fallback.
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// `self * b - c`, fused like [`Lane::mul_add`].
    fn mul_sub(self, b: Self, c: Self) -> Self;
    /// `c - self * b`, fused like [`Lane::mul_add`].
    fn neg_mul_add(self, b: Self, c: Self) -> Self;
    /// Lane-wise `self > o` (false where either is NaN).
    fn gt(self, o: Self) -> Self::Mask;
    /// Lane-wise `m1 && m2`.
    fn and(m1: Self::Mask, m2: Self::Mask) -> Self::Mask;
    /// `a` where `m`, `b` elsewhere.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether `m` holds in some lane.
    fn any(m: Self::Mask) -> bool;
    /// Whether `m` holds in every lane.
    fn all(m: Self::Mask) -> bool;
    /// The sum of the lanes, in lane order (a fixed order: reproducible results).
    #[inline(always)]
    fn sum(self) -> f64 {
        let mut buf = [0.0; 8];
        self.store(&mut buf[..Self::WIDTH]);
        buf[..Self::WIDTH].iter().fold(0.0, |acc, v| acc + v)
    }
    /// `self^n` by repeated squaring (`1 / self^|n|` for negative `n`).
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        let mut base = self;
        let mut e = n.unsigned_abs();
        let mut acc: Option<Self> = None;
        while e > 0 {
            if e & 1 == 1 {
                acc = Some(match acc {
                    None => base,
                    Some(a) => a * base,
                });
            }
            e >>= 1;
            if e > 0 {
                base = base * base;
            }
        }
        let p = acc.unwrap_or(Self::splat(1.0));
        if n < 0 {
            Self::splat(1.0) / p
        } else {
            p
        }
    }
}

/// `[a[k]` where `m`, `b[k]` elsewhere`]` for arrays of lanes.
#[inline(always)]
pub fn select_array<L: Lane, const N: usize>(m: L::Mask, a: [L; N], b: [L; N]) -> [L; N] {
    std::array::from_fn(|k| L::select(m, a[k], b[k]))
}

impl Lane for f64 {
    const WIDTH: usize = 1;
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        s[0]
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        s[0] = self;
    }
    #[inline(always)]
    fn iota() -> Self {
        0.0
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        // Without a guaranteed FMA unit `f64::mul_add` may be a slow library call.
        self * b + c
    }
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        self * b - c
    }
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        c - self * b
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn and(m1: bool, m2: bool) -> bool {
        m1 && m2
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn any(m: bool) -> bool {
        m
    }
    #[inline(always)]
    fn all(m: bool) -> bool {
        m
    }
}

/// Code generic over the lane type, run by [`dispatch`].
pub trait WithLanes {
    /// What the code returns.
    type Output;
    /// The code, for lane type `L`. Mark it `#[inline(always)]`, and everything it
    /// calls with lanes too.
    fn run<L: Lane>(self) -> Self::Output;
}

/// An instruction set for the lanes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Isa {
    /// One `f64` at a time (any processor).
    Scalar,
    /// 4 lanes, AVX2 and FMA (x86-64).
    Avx2,
    /// 8 lanes, AVX-512F (x86-64).
    Avx512,
}

impl Isa {
    /// Lanes per vector.
    pub fn width(self) -> usize {
        match self {
            Isa::Scalar => 1,
            Isa::Avx2 => 4,
            Isa::Avx512 => 8,
        }
    }

    /// Lower-case name (`scalar`, `avx2`, `avx512`).
    pub fn name(self) -> &'static str {
        match self {
            Isa::Scalar => "scalar",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }

    /// Whether this processor has the instruction set.
    pub fn available(self) -> bool {
        match self {
            Isa::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => x86::has_avx2(),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => x86::has_avx512(),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// Every instruction set this processor has, narrowest first.
    pub fn all_available() -> Vec<Isa> {
        [Isa::Scalar, Isa::Avx2, Isa::Avx512]
            .into_iter()
            .filter(|i| i.available())
            .collect()
    }

    /// The widest instruction set this processor has. The environment variable
    /// `STOKESIAN_ISA` (`scalar`, `avx2`, `avx512`) caps it; both are read once per
    /// process (every product asks).
    pub fn best() -> Isa {
        static BEST: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *BEST.get_or_init(|| {
            let cap = match std::env::var("STOKESIAN_ISA").as_deref() {
                Ok("scalar") => Isa::Scalar,
                Ok("avx2") => Isa::Avx2,
                _ => Isa::Avx512,
            };
            Isa::all_available()
                .into_iter()
                .filter(|&i| i <= cap)
                .max()
                .unwrap_or(Isa::Scalar)
        })
    }
}

/// Run `w` with the widest lanes this processor has ([`Isa::best`]).
pub fn dispatch<W: WithLanes>(w: W) -> W::Output {
    match dispatch_with(Isa::best(), w) {
        Ok(out) => out,
        Err(_) => unreachable!("the best instruction set is available"),
    }
}

/// Run `w` with the lanes of `isa`, or hand it back if this processor lacks `isa`.
pub fn dispatch_with<W: WithLanes>(isa: Isa, w: W) -> Result<W::Output, W> {
    match isa {
        Isa::Scalar => Ok(w.run::<f64>()),
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => x86::run_avx2(w),
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => x86::run_avx512(w),
        #[cfg(not(target_arch = "x86_64"))]
        _ => Err(w),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Probe(Vec<f64>);
    impl WithLanes for Probe {
        type Output = Vec<f64>;
        #[inline(always)]
        fn run<L: Lane>(self) -> Vec<f64> {
            let mut out = vec![0.0; self.0.len()];
            for (x, o) in self.0.chunks(L::WIDTH).zip(out.chunks_mut(L::WIDTH)) {
                let v = L::load(x);
                let r = L::select(
                    v.gt(L::splat(0.0)),
                    v.sqrt().mul_add(L::splat(2.0), L::splat(1.0)) / v,
                    -v.powi(3) - L::iota(),
                );
                r.store(o);
            }
            out
        }
    }

    #[test]
    fn every_instruction_set_computes_the_same_lanes() {
        let x: Vec<f64> = (0..64).map(|k| (k as f64 - 20.0) * 0.37).collect();
        let expect: Vec<f64> = x
            .iter()
            .map(|&v| {
                if v > 0.0 {
                    (v.sqrt() * 2.0 + 1.0) / v
                } else {
                    -(v * v * v)
                }
            })
            .collect();
        for isa in Isa::all_available() {
            let got = dispatch_with(isa, Probe(x.clone())).ok().unwrap();
            for (k, (g, e)) in got.iter().zip(&expect).enumerate() {
                let iota = (k % isa.width()) as f64;
                let e = if x[k] > 0.0 { *e } else { e - iota };
                // an FMA rounds once where the fallback rounds twice: 2 ulps apart
                assert!(
                    (g - e).abs() <= 4.0 * f64::EPSILON * e.abs(),
                    "{isa:?} {k}: {g} {e}"
                );
            }
        }
    }

    #[test]
    fn sums_are_in_lane_order() {
        struct S;
        impl WithLanes for S {
            type Output = f64;
            #[inline(always)]
            fn run<L: Lane>(self) -> f64 {
                (L::iota() + L::splat(1.0)).sum()
            }
        }
        for isa in Isa::all_available() {
            let w = isa.width() as f64;
            assert_eq!(dispatch_with(isa, S).ok().unwrap(), w * (w + 1.0) / 2.0);
        }
    }
}
