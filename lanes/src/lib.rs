//! Lanes: vectors of `f64` or `f32` that evaluate several pairs per instruction, for
//! the lane kernels that `cargo xtask gen` emits (generic over [`Lane`]).
//!
//! [`Lane`] is implemented by `f64` and `f32` (one pair: the portable fallback) and, on
//! x86-64, by AVX2 with FMA (4 `f64` or 8 `f32` lanes) and AVX-512F (8 `f64` or 16
//! `f32` lanes; types private to this crate). The element type ([`Element`]) is chosen
//! by the code ([`WithLanes::Elem`]); the instruction set by [`dispatch`], which picks
//! the widest one the processor has, detected at run time, and compiles the generic
//! code for it (`#[target_feature]`); [`dispatch_with`] forces one ([`Isa`]), for tests
//! and benchmarks. Code that the wider AVX-512 lanes do not speed up leaves their copy out
//! ([`WithLanes::AVX512`]) and runs on AVX2 lanes there. A plain `cargo build --release`
//! is therefore fast on any x86-64 and correct everywhere else. The `f32` lanes are the single-precision twins: the same
//! generated kernels (their literals rounded to `f32` by [`Lane::splat`]) with twice as
//! many pairs per instruction.
//!
//! Everything called inside [`WithLanes::run`] must be `#[inline(always)]` so that it is
//! compiled with the instruction set of the dispatching function. The intrinsics are
//! the project's only `unsafe` code, confined to `x86.rs`.

use std::ops::{Add, Div, Mul, Neg, Sub};

#[cfg(target_arch = "x86_64")]
mod x86;

mod private {
    pub trait Sealed {}
    impl Sealed for f64 {}
    impl Sealed for f32 {}
}

/// An element type of lanes: `f64` or `f32`.
pub trait Element:
    Copy + Default + PartialEq + PartialOrd + std::fmt::Debug + Send + Sync + 'static + private::Sealed
{
    /// `v` rounded to this type.
    fn from_f64(v: f64) -> Self;
    /// The value as `f64` (exact).
    fn to_f64(self) -> f64;
    /// Run `w` with lanes of this element on `isa`, or hand it back if this processor
    /// lacks `isa` (what [`dispatch_with`] calls).
    fn run_with<W: WithLanes<Elem = Self>>(isa: Isa, w: W) -> Result<W::Output, W>;
}

impl Element for f64 {
    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    fn run_with<W: WithLanes<Elem = f64>>(isa: Isa, w: W) -> Result<W::Output, W> {
        match isa {
            Isa::Scalar => Ok(w.run::<f64>()),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => x86::run_avx2_f64(w),
            #[cfg(target_arch = "x86_64")]
            // a constant per `W`: the branch not taken is not compiled
            Isa::Avx512 => match W::AVX512 {
                true => x86::run_avx512_f64(w),
                false if x86::has_avx512() => x86::run_avx2_f64(w),
                false => Err(w),
            },
            #[cfg(not(target_arch = "x86_64"))]
            _ => Err(w),
        }
    }
}

impl Element for f32 {
    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn run_with<W: WithLanes<Elem = f32>>(isa: Isa, w: W) -> Result<W::Output, W> {
        match isa {
            Isa::Scalar => Ok(w.run::<f32>()),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => x86::run_avx2_f32(w),
            #[cfg(target_arch = "x86_64")]
            // a constant per `W`: the branch not taken is not compiled
            Isa::Avx512 => match W::AVX512 {
                true => x86::run_avx512_f32(w),
                false if x86::has_avx512() => x86::run_avx2_f32(w),
                false => Err(w),
            },
            #[cfg(not(target_arch = "x86_64"))]
            _ => Err(w),
        }
    }
}

/// The most lanes of any lane type (16 `f32` lanes of AVX-512).
pub const MAX_WIDTH: usize = 16;

/// A vector of `WIDTH` lanes of [`Lane::Elem`] with IEEE arithmetic in each lane.
pub trait Lane:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Number of lanes (at most [`MAX_WIDTH`]).
    const WIDTH: usize;
    /// The element type of each lane.
    type Elem: Element;
    /// The result of a lane-wise comparison.
    type Mask: Copy;
    /// Every lane `v` (rounded to [`Lane::Elem`]).
    fn splat(v: f64) -> Self;
    /// Lanes `s[0..WIDTH]` (panics if `s` is shorter).
    fn load(s: &[Self::Elem]) -> Self;
    /// Lanes `s[0..WIDTH]` of single-precision numbers, each converted to
    /// [`Lane::Elem`] (exactly: every `f32` is an `f64`; panics if `s` is shorter).
    fn load_f32(s: &[f32]) -> Self;
    /// Write the lanes to `s[0..WIDTH]` (panics if `s` is shorter).
    fn store(self, s: &mut [Self::Elem]);
    /// Lanes `0, 1, ..., WIDTH - 1`.
    fn iota() -> Self;
    /// Lane-wise square root: correctly rounded, or within an ulp where an
    /// instruction set computes it from an approximate reciprocal square root refined
    /// by Newton's method (AVX-512: its square root and division are not pipelined).
    fn sqrt(self) -> Self;
    /// `1 / sqrt(self)`: the correctly rounded square root divided into one, or within
    /// about an ulp where an instruction set refines an approximate reciprocal square
    /// root by Newton's method.
    #[inline(always)]
    fn rsqrt(self) -> Self {
        Self::splat(1.0) / self.sqrt()
    }
    /// `sqrt(self)` where `r = self.rsqrt()` is at hand: as [`Lane::sqrt`], from `r`
    /// where the instruction set computes square roots that way (0 where `self` is 0).
    #[inline(always)]
    fn sqrt_with(self, r: Self) -> Self {
        let _ = r;
        self.sqrt()
    }
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
    /// `-(self * b) - c`, fused like [`Lane::mul_add`]: `-(self.mul_add(b, c))` to the
    /// bit (rounding is symmetric), in one instruction.
    fn neg_mul_sub(self, b: Self, c: Self) -> Self;
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
    /// The sum of the lanes in `f64`, in lane order (a fixed order: reproducible
    /// results).
    #[inline(always)]
    fn sum(self) -> f64 {
        let mut buf = [Self::Elem::default(); MAX_WIDTH];
        self.store(&mut buf[..Self::WIDTH]);
        buf[..Self::WIDTH]
            .iter()
            .fold(0.0, |acc, v| acc + v.to_f64())
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

/// The scalar fallbacks, `f64` and `f32`: one pair at a time.
macro_rules! scalar_lane {
    ($t:ident) => {
        impl Lane for $t {
            const WIDTH: usize = 1;
            type Elem = $t;
            type Mask = bool;
            #[inline(always)]
            fn splat(v: f64) -> Self {
                $t::from_f64(v)
            }
            #[inline(always)]
            fn load(s: &[$t]) -> Self {
                s[0]
            }
            #[inline(always)]
            fn load_f32(s: &[f32]) -> Self {
                $t::from(s[0])
            }
            #[inline(always)]
            fn store(self, s: &mut [$t]) {
                s[0] = self;
            }
            #[inline(always)]
            fn iota() -> Self {
                0.0
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $t::sqrt(self)
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
            fn neg_mul_sub(self, b: Self, c: Self) -> Self {
                -(self * b) - c
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
    };
}

scalar_lane!(f64);
scalar_lane!(f32);

/// Code generic over the lane type, run by [`dispatch`].
pub trait WithLanes: Sized {
    /// The element type of the lanes the code runs on (`f64` or `f32`).
    type Elem: Element;
    /// What the code returns.
    type Output;
    /// Whether the code is compiled for AVX-512 lanes: where it is `false`, AVX2 lanes run
    /// it when AVX-512 is asked for (every processor with AVX-512F here has AVX2 and FMA).
    /// Every instruction set is a copy of the code, and AVX-512's is the slowest to
    /// compile; code that the wider lanes do not speed up (a computation bound by the
    /// memory it writes) leaves it out.
    const AVX512: bool = true;
    /// The code, for lane type `L`. Mark it `#[inline(always)]`, and everything it
    /// calls with lanes too.
    fn run<L: Lane<Elem = Self::Elem>>(self) -> Self::Output;
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
    /// `f64` lanes per vector (twice as many `f32` lanes on AVX2 and AVX-512).
    pub fn width(self) -> usize {
        match self {
            Isa::Scalar => 1,
            Isa::Avx2 => 4,
            Isa::Avx512 => 8,
        }
    }

    /// Lanes per vector of elements `E`.
    pub fn width_of<E: Element>(self) -> usize {
        match self {
            Isa::Scalar => 1,
            _ => self.width() * 8 / std::mem::size_of::<E>(),
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
    W::Elem::run_with(isa, w)
}

/// Stores that bypass the caches, for large outputs written once (a dense matrix of
/// hundreds of megabytes: the processor then need not read each line before writing
/// it). [`streaming`] hands one out and orders its stores before it returns.
pub struct Streaming(std::marker::PhantomData<*const ()>);

impl Streaming {
    /// `dst = src` (non-temporal stores on x86-64, an ordinary copy elsewhere).
    #[inline(always)]
    pub fn copy(&mut self, dst: &mut [f64], src: &[f64]) {
        #[cfg(target_arch = "x86_64")]
        x86::stream_copy(dst, src);
        #[cfg(not(target_arch = "x86_64"))]
        dst.copy_from_slice(src);
    }
}

/// Run `f` with a [`Streaming`]; its stores are ordered before everything after the
/// call (a fence, also when `f` panics), so that other threads see them once they
/// synchronise with this one as usual.
#[inline]
pub fn streaming<T>(f: impl FnOnce(&mut Streaming) -> T) -> T {
    struct Fence;
    impl Drop for Fence {
        fn drop(&mut self) {
            #[cfg(target_arch = "x86_64")]
            x86::fence();
        }
    }
    let _fence = Fence;
    f(&mut Streaming(std::marker::PhantomData))
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Probe(Vec<f64>);
    impl WithLanes for Probe {
        type Elem = f64;
        type Output = Vec<f64>;
        #[inline(always)]
        fn run<L: Lane<Elem = f64>>(self) -> Vec<f64> {
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

    /// The width of the lanes a code runs on, with and without AVX-512 lanes of its own.
    struct Width<const WIDE: bool>;
    impl<const WIDE: bool> WithLanes for Width<WIDE> {
        type Elem = f64;
        type Output = usize;
        const AVX512: bool = WIDE;
        #[inline(always)]
        fn run<L: Lane<Elem = f64>>(self) -> usize {
            L::WIDTH
        }
    }

    /// Code without AVX-512 lanes runs on AVX2 lanes where AVX-512 is asked for, and is
    /// handed back like any other where the processor lacks AVX-512.
    #[test]
    fn code_without_avx512_lanes_runs_on_avx2_lanes() {
        let isa = Isa::Avx512;
        let capped = dispatch_with(isa, Width::<false>).ok();
        let wide = dispatch_with(isa, Width::<true>).ok();
        match isa.available() {
            true => assert_eq!((capped, wide), (Some(4), Some(8))),
            false => assert_eq!((capped, wide), (None, None)),
        }
        for isa in [Isa::Scalar, Isa::Avx2]
            .into_iter()
            .filter(|i| i.available())
        {
            assert_eq!(dispatch_with(isa, Width::<false>).ok(), Some(isa.width()));
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

    /// The four fused forms on triples `(a, b, c)`: `mul_add`, `mul_sub`, `neg_mul_add`,
    /// `neg_mul_sub`, one after another per triple.
    struct Fused(Vec<[f64; 3]>);
    impl WithLanes for Fused {
        type Elem = f64;
        type Output = Vec<[f64; 4]>;
        #[inline(always)]
        fn run<L: Lane<Elem = f64>>(self) -> Vec<[f64; 4]> {
            let mut out = Vec::with_capacity(self.0.len());
            for t in self.0.chunks(L::WIDTH) {
                let col = |k: usize| L::load(&t.iter().map(|x| x[k]).collect::<Vec<f64>>());
                let (a, b, c) = (col(0), col(1), col(2));
                let mut r = [[0.0; MAX_WIDTH]; 4];
                a.mul_add(b, c).store(&mut r[0]);
                a.mul_sub(b, c).store(&mut r[1]);
                a.neg_mul_add(b, c).store(&mut r[2]);
                a.neg_mul_sub(b, c).store(&mut r[3]);
                out.extend((0..L::WIDTH).map(|l| [r[0][l], r[1][l], r[2][l], r[3][l]]));
            }
            out
        }
    }

    #[test]
    fn fused_forms_are_signed_multiply_adds() {
        let t: Vec<[f64; 3]> = (0..64)
            .map(|k| {
                let x = k as f64;
                [
                    (x * 0.731).sin() * 3.0,
                    (x * 1.37).cos() + 0.1,
                    x * 0.29 - 7.0,
                ]
            })
            .collect();
        for isa in Isa::all_available() {
            let got = dispatch_with(isa, Fused(t.clone())).ok().unwrap();
            for ([a, b, c], r) in t.iter().zip(&got) {
                // the fused value (one rounding), or the fallback's two roundings
                let fused = [a.mul_add(*b, *c), a.mul_add(*b, -c)];
                let twice = [a * b + c, a * b - c];
                for k in 0..2 {
                    assert!(
                        r[k] == fused[k] || r[k] == twice[k],
                        "{isa:?} {k}: {}",
                        r[k]
                    );
                }
                // the negated forms: negation is exact and rounding symmetric, so they
                // are the others negated to the bit
                assert_eq!(r[2].to_bits(), (-r[1]).to_bits(), "{isa:?}: c - a b");
                assert_eq!(r[3].to_bits(), (-r[0]).to_bits(), "{isa:?}: -(a b) - c");
            }
        }
    }

    #[test]
    fn streamed_copies_are_copies() {
        // every length and both alignments of the destination's start
        let src: Vec<f64> = (0..40).map(|k| k as f64 * 1.25 - 3.0).collect();
        for start in 0..2 {
            for len in 0..=37 {
                let mut dst = vec![f64::NAN; 40];
                streaming(|s| s.copy(&mut dst[start..start + len], &src[..len]));
                assert_eq!(&dst[start..start + len], &src[..len], "{start} {len}");
                assert!(dst[..start]
                    .iter()
                    .chain(&dst[start + len..])
                    .all(|v| v.is_nan()));
            }
        }
    }

    /// Single-precision numbers loaded into lanes of either element.
    struct Widen<E>(Vec<f32>, std::marker::PhantomData<E>);
    impl<E: Element> WithLanes for Widen<E> {
        type Elem = E;
        type Output = Vec<E>;
        #[inline(always)]
        fn run<L: Lane<Elem = E>>(self) -> Vec<E> {
            let mut out = vec![E::from_f64(0.0); self.0.len()];
            for (x, o) in self.0.chunks(L::WIDTH).zip(out.chunks_mut(L::WIDTH)) {
                L::load_f32(x).store(o);
            }
            out
        }
    }

    /// `load_f32` converts exactly on every instruction set, into `f64` and `f32` lanes
    /// (normal, subnormal, signed zero, the extremes).
    #[test]
    fn single_precision_loads_are_exact() {
        let mut x: Vec<f32> = (0..64).map(|k| (k as f32 - 17.3) * 0.731).collect();
        x[..4].copy_from_slice(&[f32::MAX, f32::MIN_POSITIVE, 1e-45, -0.0]);
        for isa in Isa::all_available() {
            let wide = dispatch_with(isa, Widen::<f64>(x.clone(), Default::default()));
            let narrow = dispatch_with(isa, Widen::<f32>(x.clone(), Default::default()));
            let (wide, narrow) = (wide.ok().unwrap(), narrow.ok().unwrap());
            for ((&w, &n), &v) in wide.iter().zip(&narrow).zip(&x) {
                assert_eq!(w.to_bits(), f64::from(v).to_bits(), "{isa:?}");
                assert_eq!(n.to_bits(), v.to_bits(), "{isa:?}");
            }
        }
    }

    /// The probe of [`every_instruction_set_computes_the_same_lanes`] in `f32`.
    struct Probe32(Vec<f32>);
    impl WithLanes for Probe32 {
        type Elem = f32;
        type Output = Vec<f32>;
        #[inline(always)]
        fn run<L: Lane<Elem = f32>>(self) -> Vec<f32> {
            let mut out = vec![0.0; self.0.len()];
            for (x, o) in self.0.chunks(L::WIDTH).zip(out.chunks_mut(L::WIDTH)) {
                let v = L::load(x);
                let r = L::select(
                    v.gt(L::splat(0.0)),
                    v.sqrt().mul_add(L::splat(2.0), L::splat(1.0)) * v.recip(),
                    -v.powi(3) - L::iota(),
                );
                r.store(o);
            }
            out
        }
    }

    #[test]
    fn every_instruction_set_computes_the_same_f32_lanes() {
        let x: Vec<f32> = (0..64).map(|k| (k as f32 - 20.0) * 0.37).collect();
        for isa in Isa::all_available() {
            let got = dispatch_with(isa, Probe32(x.clone())).ok().unwrap();
            for (k, g) in got.iter().enumerate() {
                let v = x[k] as f64;
                let iota = (k % isa.width_of::<f32>()) as f64;
                let e = if v > 0.0 {
                    (v.sqrt() * 2.0 + 1.0) / v
                } else {
                    -(v * v * v) - iota
                };
                // each of the ~4 roundings (sqrt and recip within an ulp) costs an f32
                // ulp of the result or less: 8 ulps of f32 against the exact value
                assert!(
                    (*g as f64 - e).abs() <= 8.0 * f32::EPSILON as f64 * e.abs(),
                    "{isa:?} {k}: {g} {e}"
                );
            }
        }
    }

    /// `rsqrt` and `sqrt_with` on every instruction set, `f64` and `f32`.
    struct Roots<E>(Vec<E>);
    impl<E: Element> WithLanes for Roots<E> {
        type Elem = E;
        type Output = Vec<(f64, f64)>;
        #[inline(always)]
        fn run<L: Lane<Elem = E>>(self) -> Vec<(f64, f64)> {
            let (mut r, mut s) = (
                vec![E::default(); self.0.len()],
                vec![E::default(); self.0.len()],
            );
            for k in (0..self.0.len()).step_by(L::WIDTH) {
                let x = L::load(&self.0[k..]);
                let q = x.rsqrt();
                q.store(&mut r[k..]);
                x.sqrt_with(q).store(&mut s[k..]);
            }
            r.iter()
                .zip(&s)
                .map(|(a, b)| (a.to_f64(), b.to_f64()))
                .collect()
        }
    }

    #[test]
    fn reciprocal_square_roots_on_every_instruction_set() {
        // 0, then 63 positive numbers over 28 binades (64 values: a multiple of every width)
        let x: Vec<f64> = (0..64)
            .map(|k| if k == 0 { 0.0 } else { 1.37f64.powi(k - 30) })
            .collect();
        let x32: Vec<f32> = x.iter().map(|&v| v as f32).collect();
        for isa in Isa::all_available() {
            let got = dispatch_with(isa, Roots(x.clone())).ok().unwrap();
            let got32 = dispatch_with(isa, Roots(x32.clone())).ok().unwrap();
            assert_eq!((got[0].1, got32[0].1), (0.0, 0.0), "{isa:?}: sqrt(0)");
            for k in 1..x.len() {
                // Newton's steps from 14 bits, or a square root and a division: 2 ulps
                let (r, s) = got[k];
                let (e_r, e_s) = (1.0 / x[k].sqrt(), x[k].sqrt());
                assert!(
                    (r - e_r).abs() <= 2.0 * f64::EPSILON * e_r,
                    "{isa:?} {k}: {r} {e_r}"
                );
                assert!(
                    (s - e_s).abs() <= 2.0 * f64::EPSILON * e_s,
                    "{isa:?} {k}: {s} {e_s}"
                );
                let (r, s) = got32[k];
                let v = x32[k] as f64;
                let (e_r, e_s) = (1.0 / v.sqrt(), v.sqrt());
                let eps = f32::EPSILON as f64;
                assert!(
                    (r - e_r).abs() <= 2.0 * eps * e_r,
                    "{isa:?} f32 {k}: {r} {e_r}"
                );
                assert!(
                    (s - e_s).abs() <= 2.0 * eps * e_s,
                    "{isa:?} f32 {k}: {s} {e_s}"
                );
            }
        }
    }

    #[test]
    fn sums_are_in_lane_order() {
        struct S;
        impl WithLanes for S {
            type Elem = f64;
            type Output = f64;
            #[inline(always)]
            fn run<L: Lane<Elem = f64>>(self) -> f64 {
                (L::iota() + L::splat(1.0)).sum()
            }
        }
        struct S32;
        impl WithLanes for S32 {
            type Elem = f32;
            type Output = f64;
            #[inline(always)]
            fn run<L: Lane<Elem = f32>>(self) -> f64 {
                (L::iota() + L::splat(1.0)).sum()
            }
        }
        for isa in Isa::all_available() {
            let w = isa.width() as f64;
            assert_eq!(dispatch_with(isa, S).ok().unwrap(), w * (w + 1.0) / 2.0);
            let w = isa.width_of::<f32>() as f64;
            assert_eq!(dispatch_with(isa, S32).ok().unwrap(), w * (w + 1.0) / 2.0);
        }
    }
}
