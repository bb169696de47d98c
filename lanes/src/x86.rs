//! The x86-64 lanes: AVX2 with FMA ([`F64x4`], [`F32x8`]) and AVX-512F ([`F64x8`],
//! [`F32x16`]), and the dispatch into code compiled for them.
//!
//! Soundness rests on one fact: a value of these private types exists only inside
//! [`WithLanes::run`] as called by the `run_*` functions below, which check with
//! `is_x86_feature_detected!` that this processor has the instructions first. Every
//! intrinsic below is therefore executed on a processor that has it. The streaming
//! stores at the end ([`stream_copy`], [`fence`]) use SSE2 only, which every x86-64
//! processor has.
#![allow(unsafe_code)]

use crate::{Lane, WithLanes};
use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

pub(crate) fn has_avx2() -> bool {
    is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
}

pub(crate) fn has_avx512() -> bool {
    is_x86_feature_detected!("avx512f") && has_avx2()
}

/// The dispatch into code compiled for one instruction set and lane type: a body
/// with the target features, and the run-time check before it.
macro_rules! runner {
    ($run:ident, $body:ident, $features:literal, $has:ident, $lane:ident, $elem:ty) => {
        #[target_feature(enable = $features)]
        fn $body<W: WithLanes<Elem = $elem>>(w: W) -> W::Output {
            w.run::<$lane>()
        }

        pub(crate) fn $run<W: WithLanes<Elem = $elem>>(w: W) -> Result<W::Output, W> {
            if !$has() {
                return Err(w);
            }
            // SAFETY: this processor has the features the body is compiled with,
            // checked on the line above (`has_avx2`: AVX2 and FMA; `has_avx512`:
            // AVX-512F as well).
            Ok(unsafe { $body(w) })
        }
    };
}

runner!(
    run_avx2_f64,
    avx2_f64_body,
    "avx2,fma",
    has_avx2,
    F64x4,
    f64
);
runner!(
    run_avx512_f64,
    avx512_body,
    "avx512f,avx2,fma",
    has_avx512,
    F64x8,
    f64
);
runner!(
    run_avx2_f32,
    avx2_f32_body,
    "avx2,fma",
    has_avx2,
    F32x8,
    f32
);
runner!(
    run_avx512_f32,
    avx512_f32_body,
    "avx512f,avx2,fma",
    has_avx512,
    F32x16,
    f32
);

/// Four `f64` lanes in an AVX register.
#[derive(Clone, Copy)]
pub struct F64x4(__m256d);

/// Eight `f64` lanes in an AVX-512 register.
#[derive(Clone, Copy)]
pub struct F64x8(__m512d);

/// Eight `f32` lanes in an AVX register.
#[derive(Clone, Copy)]
pub struct F32x8(__m256);

/// Sixteen `f32` lanes in an AVX-512 register.
#[derive(Clone, Copy)]
pub struct F32x16(__m512);

/// The binary operators of one lane type from one intrinsic each.
macro_rules! binary {
    ($t:ident, $($tr:ident $f:ident $intr:ident),*) => {$(
        impl $tr for $t {
            type Output = $t;
            #[inline(always)]
            fn $f(self, o: $t) -> $t {
                // SAFETY: values of this type exist only after run-time detection of
                // its instruction set (module documentation).
                $t(unsafe { $intr(self.0, o.0) })
            }
        }
    )*};
}

binary!(F64x4, Add add _mm256_add_pd, Sub sub _mm256_sub_pd, Mul mul _mm256_mul_pd, Div div _mm256_div_pd);
binary!(F64x8, Add add _mm512_add_pd, Sub sub _mm512_sub_pd, Mul mul _mm512_mul_pd, Div div _mm512_div_pd);
binary!(F32x8, Add add _mm256_add_ps, Sub sub _mm256_sub_ps, Mul mul _mm256_mul_ps, Div div _mm256_div_ps);
binary!(F32x16, Add add _mm512_add_ps, Sub sub _mm512_sub_ps, Mul mul _mm512_mul_ps, Div div _mm512_div_ps);

impl Neg for F64x4 {
    type Output = F64x4;
    #[inline(always)]
    fn neg(self) -> F64x4 {
        // SAFETY: AVX was detected before this value existed (module documentation).
        F64x4(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
}

impl Neg for F64x8 {
    type Output = F64x8;
    #[inline(always)]
    fn neg(self) -> F64x8 {
        // SAFETY: AVX-512F was detected before this value existed (module
        // documentation); the sign bit is flipped by an integer xor (AVX-512F has no
        // `f64` xor without AVX-512DQ).
        F64x8(unsafe {
            _mm512_castsi512_pd(_mm512_xor_si512(
                _mm512_castpd_si512(self.0),
                _mm512_set1_epi64(i64::MIN),
            ))
        })
    }
}

impl Lane for F64x4 {
    const WIDTH: usize = 4;
    type Elem = f64;
    type Mask = __m256d;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: called only inside code dispatched after detection (module docs).
        F64x4(unsafe { _mm256_set1_pd(v) })
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        let s = &s[..4];
        // SAFETY: `s` holds 4 f64 (the slice above is bounds-checked); unaligned load;
        // AVX detected before (module docs).
        F64x4(unsafe { _mm256_loadu_pd(s.as_ptr()) })
    }
    #[inline(always)]
    fn load_f32(s: &[f32]) -> Self {
        let s = &s[..4];
        // SAFETY: `s` holds 4 f32 (bounds-checked above); unaligned load, widened
        // exactly; AVX detected before (module docs).
        F64x4(unsafe { _mm256_cvtps_pd(_mm_loadu_ps(s.as_ptr())) })
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        let s = &mut s[..4];
        // SAFETY: `s` has room for 4 f64 (bounds-checked above); unaligned store.
        unsafe { _mm256_storeu_pd(s.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn iota() -> Self {
        // SAFETY: as `splat`.
        F64x4(unsafe { _mm256_setr_pd(0.0, 1.0, 2.0, 3.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as `splat`.
        F64x4(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: FMA is part of the detected set (module docs).
        F64x4(unsafe { _mm256_fmadd_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x4(unsafe { _mm256_fmsub_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x4(unsafe { _mm256_fnmadd_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x4(unsafe { _mm256_fnmsub_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __m256d {
        // SAFETY: as `splat`.
        unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn and(m1: __m256d, m2: __m256d) -> __m256d {
        // SAFETY: as `splat`.
        unsafe { _mm256_and_pd(m1, m2) }
    }
    #[inline(always)]
    fn select(m: __m256d, a: Self, b: Self) -> Self {
        // SAFETY: as `splat`.
        F64x4(unsafe { _mm256_blendv_pd(b.0, a.0, m) })
    }
    #[inline(always)]
    fn any(m: __m256d) -> bool {
        // SAFETY: as `splat`.
        unsafe { _mm256_movemask_pd(m) != 0 }
    }
    #[inline(always)]
    fn all(m: __m256d) -> bool {
        // SAFETY: as `splat`.
        unsafe { _mm256_movemask_pd(m) == 0xF }
    }
}

impl Lane for F64x8 {
    const WIDTH: usize = 8;
    type Elem = f64;
    type Mask = __mmask8;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: called only inside code dispatched after detection (module docs).
        F64x8(unsafe { _mm512_set1_pd(v) })
    }
    #[inline(always)]
    fn load(s: &[f64]) -> Self {
        let s = &s[..8];
        // SAFETY: `s` holds 8 f64 (bounds-checked above); unaligned load.
        F64x8(unsafe { _mm512_loadu_pd(s.as_ptr()) })
    }
    #[inline(always)]
    fn load_f32(s: &[f32]) -> Self {
        let s = &s[..8];
        // SAFETY: `s` holds 8 f32 (bounds-checked above); unaligned load, widened
        // exactly; AVX-512F detected before (module docs).
        F64x8(unsafe { _mm512_cvtps_pd(_mm256_loadu_ps(s.as_ptr())) })
    }
    #[inline(always)]
    fn store(self, s: &mut [f64]) {
        let s = &mut s[..8];
        // SAFETY: `s` has room for 8 f64 (bounds-checked above); unaligned store.
        unsafe { _mm512_storeu_pd(s.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn iota() -> Self {
        // SAFETY: as `splat`.
        F64x8(unsafe { _mm512_setr_pd(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0) })
    }
    /// `x r` with `r` the reciprocal square root from `vrsqrt14pd` (14 bits) after two
    /// Newton steps (56 bits), then one correction `s + (r/2) (x - s^2)`: within an
    /// ulp, on the multiply-add ports instead of the square-root unit (which accepts
    /// one `zmm` operation every 16 or more cycles). `sqrt(0) = 0`; no negative or
    /// infinite arguments occur in the kernels.
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.sqrt_with(self.rsqrt())
    }
    /// `vrsqrt14pd` (14 bits) after two Newton steps `r (3/2 - x r^2 / 2)`.
    #[inline(always)]
    fn rsqrt(self) -> Self {
        // SAFETY: as `splat` (AVX-512F has `vrsqrt14pd`).
        unsafe {
            let x = self.0;
            let hx = _mm512_mul_pd(_mm512_set1_pd(0.5), x);
            let three_halves = _mm512_set1_pd(1.5);
            let mut r = _mm512_rsqrt14_pd(x);
            for _ in 0..2 {
                let rr = _mm512_mul_pd(r, r);
                r = _mm512_mul_pd(r, _mm512_fnmadd_pd(hx, rr, three_halves));
            }
            F64x8(r)
        }
    }
    /// `s = x r` corrected by one step `s + (r/2)(x - s^2)`: within an ulp.
    #[inline(always)]
    fn sqrt_with(self, r: Self) -> Self {
        // SAFETY: as `splat`.
        unsafe {
            let (x, r) = (self.0, r.0);
            let s = _mm512_mul_pd(x, r);
            let d = _mm512_fnmadd_pd(s, s, x);
            let s = _mm512_fmadd_pd(_mm512_mul_pd(_mm512_set1_pd(0.5), r), d, s);
            let positive = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(x, _mm512_setzero_pd());
            F64x8(_mm512_mask_blend_pd(positive, _mm512_setzero_pd(), s))
        }
    }
    /// `vrcp14pd` (14 bits) after two Newton steps `y + y (1 - x y)`: within an ulp.
    #[inline(always)]
    fn recip(self) -> Self {
        // SAFETY: as `splat` (AVX-512F has `vrcp14pd`).
        unsafe {
            let x = self.0;
            let one = _mm512_set1_pd(1.0);
            let mut y = _mm512_rcp14_pd(x);
            for _ in 0..2 {
                let e = _mm512_fnmadd_pd(x, y, one);
                y = _mm512_fmadd_pd(y, e, y);
            }
            F64x8(y)
        }
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `splat`.
        F64x8(unsafe { _mm512_fmadd_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x8(unsafe { _mm512_fmsub_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x8(unsafe { _mm512_fnmadd_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F64x8(unsafe { _mm512_fnmsub_pd(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __mmask8 {
        // SAFETY: as `splat`.
        unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn and(m1: __mmask8, m2: __mmask8) -> __mmask8 {
        m1 & m2
    }
    #[inline(always)]
    fn select(m: __mmask8, a: Self, b: Self) -> Self {
        // SAFETY: as `splat`.
        F64x8(unsafe { _mm512_mask_blend_pd(m, b.0, a.0) })
    }
    #[inline(always)]
    fn any(m: __mmask8) -> bool {
        m != 0
    }
    #[inline(always)]
    fn all(m: __mmask8) -> bool {
        m == 0xFF
    }
}

impl Neg for F32x8 {
    type Output = F32x8;
    #[inline(always)]
    fn neg(self) -> F32x8 {
        // SAFETY: AVX was detected before this value existed (module documentation).
        F32x8(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
    }
}

impl Neg for F32x16 {
    type Output = F32x16;
    #[inline(always)]
    fn neg(self) -> F32x16 {
        // SAFETY: AVX-512F was detected before this value existed (module
        // documentation); the sign bit is flipped by an integer xor, as for `F64x8`.
        F32x16(unsafe {
            _mm512_castsi512_ps(_mm512_xor_si512(
                _mm512_castps_si512(self.0),
                _mm512_set1_epi32(i32::MIN),
            ))
        })
    }
}

impl Lane for F32x8 {
    const WIDTH: usize = 8;
    type Elem = f32;
    type Mask = __m256;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: called only inside code dispatched after detection (module docs).
        F32x8(unsafe { _mm256_set1_ps(v as f32) })
    }
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        let s = &s[..8];
        // SAFETY: `s` holds 8 f32 (bounds-checked above); unaligned load.
        F32x8(unsafe { _mm256_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn load_f32(s: &[f32]) -> Self {
        Self::load(s)
    }
    #[inline(always)]
    fn store(self, s: &mut [f32]) {
        let s = &mut s[..8];
        // SAFETY: `s` has room for 8 f32 (bounds-checked above); unaligned store.
        unsafe { _mm256_storeu_ps(s.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn iota() -> Self {
        // SAFETY: as `splat`.
        F32x8(unsafe { _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: as `splat`.
        F32x8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: FMA is part of the detected set (module docs).
        F32x8(unsafe { _mm256_fmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x8(unsafe { _mm256_fmsub_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x8(unsafe { _mm256_fnmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x8(unsafe { _mm256_fnmsub_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __m256 {
        // SAFETY: as `splat`.
        unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn and(m1: __m256, m2: __m256) -> __m256 {
        // SAFETY: as `splat`.
        unsafe { _mm256_and_ps(m1, m2) }
    }
    #[inline(always)]
    fn select(m: __m256, a: Self, b: Self) -> Self {
        // SAFETY: as `splat`.
        F32x8(unsafe { _mm256_blendv_ps(b.0, a.0, m) })
    }
    #[inline(always)]
    fn any(m: __m256) -> bool {
        // SAFETY: as `splat`.
        unsafe { _mm256_movemask_ps(m) != 0 }
    }
    #[inline(always)]
    fn all(m: __m256) -> bool {
        // SAFETY: as `splat`.
        unsafe { _mm256_movemask_ps(m) == 0xFF }
    }
}

impl Lane for F32x16 {
    const WIDTH: usize = 16;
    type Elem = f32;
    type Mask = __mmask16;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: called only inside code dispatched after detection (module docs).
        F32x16(unsafe { _mm512_set1_ps(v as f32) })
    }
    #[inline(always)]
    fn load(s: &[f32]) -> Self {
        let s = &s[..16];
        // SAFETY: `s` holds 16 f32 (bounds-checked above); unaligned load.
        F32x16(unsafe { _mm512_loadu_ps(s.as_ptr()) })
    }
    #[inline(always)]
    fn load_f32(s: &[f32]) -> Self {
        Self::load(s)
    }
    #[inline(always)]
    fn store(self, s: &mut [f32]) {
        let s = &mut s[..16];
        // SAFETY: `s` has room for 16 f32 (bounds-checked above); unaligned store.
        unsafe { _mm512_storeu_ps(s.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn iota() -> Self {
        // SAFETY: as `splat`.
        F32x16(unsafe {
            _mm512_setr_ps(
                0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0,
                15.0,
            )
        })
    }
    /// `x r` with `r` the reciprocal square root from `vrsqrt14ps` (14 bits) after one
    /// Newton step (28 bits), then one correction `s + (r/2) (x - s^2)`: within an ulp
    /// of `f32`, on the multiply-add ports, as for `F64x8`. `sqrt(0) = 0`.
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.sqrt_with(self.rsqrt())
    }
    /// `vrsqrt14ps` (14 bits) after one Newton step `r (3/2 - x r^2 / 2)`.
    #[inline(always)]
    fn rsqrt(self) -> Self {
        // SAFETY: as `splat` (AVX-512F has `vrsqrt14ps`).
        unsafe {
            let x = self.0;
            let hx = _mm512_mul_ps(_mm512_set1_ps(0.5), x);
            let r = _mm512_rsqrt14_ps(x);
            let rr = _mm512_mul_ps(r, r);
            F32x16(_mm512_mul_ps(
                r,
                _mm512_fnmadd_ps(hx, rr, _mm512_set1_ps(1.5)),
            ))
        }
    }
    /// `s = x r` corrected by one step `s + (r/2)(x - s^2)`: within an ulp of `f32`.
    #[inline(always)]
    fn sqrt_with(self, r: Self) -> Self {
        // SAFETY: as `splat`.
        unsafe {
            let (x, r) = (self.0, r.0);
            let s = _mm512_mul_ps(x, r);
            let d = _mm512_fnmadd_ps(s, s, x);
            let s = _mm512_fmadd_ps(_mm512_mul_ps(_mm512_set1_ps(0.5), r), d, s);
            let positive = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(x, _mm512_setzero_ps());
            F32x16(_mm512_mask_blend_ps(positive, _mm512_setzero_ps(), s))
        }
    }
    /// `vrcp14ps` (14 bits) after one Newton step `y + y (1 - x y)`: within an ulp of
    /// `f32`.
    #[inline(always)]
    fn recip(self) -> Self {
        // SAFETY: as `splat` (AVX-512F has `vrcp14ps`).
        unsafe {
            let x = self.0;
            let y = _mm512_rcp14_ps(x);
            let e = _mm512_fnmadd_ps(x, y, _mm512_set1_ps(1.0));
            F32x16(_mm512_fmadd_ps(y, e, y))
        }
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `splat`.
        F32x16(unsafe { _mm512_fmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x16(unsafe { _mm512_fmsub_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_add(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x16(unsafe { _mm512_fnmadd_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn neg_mul_sub(self, b: Self, c: Self) -> Self {
        // SAFETY: as `mul_add`.
        F32x16(unsafe { _mm512_fnmsub_ps(self.0, b.0, c.0) })
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __mmask16 {
        // SAFETY: as `splat`.
        unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn and(m1: __mmask16, m2: __mmask16) -> __mmask16 {
        m1 & m2
    }
    #[inline(always)]
    fn select(m: __mmask16, a: Self, b: Self) -> Self {
        // SAFETY: as `splat`.
        F32x16(unsafe { _mm512_mask_blend_ps(m, b.0, a.0) })
    }
    #[inline(always)]
    fn any(m: __mmask16) -> bool {
        m != 0
    }
    #[inline(always)]
    fn all(m: __mmask16) -> bool {
        m == 0xFFFF
    }
}

/// `dst = src` with non-temporal stores (SSE2, part of every x86-64) for the 16-byte
/// aligned pairs of `dst`, ordinary stores for an unaligned first or last value. The
/// caller fences ([`fence`]) before another thread may read `dst`.
#[inline(always)]
pub(crate) fn stream_copy(dst: &mut [f64], src: &[f64]) {
    assert_eq!(dst.len(), src.len(), "stream_copy of unequal lengths");
    // the aligned middle: `dst[head..head + 2 m]` starts on a 16-byte boundary
    let head = dst.as_ptr().align_offset(16).min(dst.len());
    let pairs = (dst.len() - head) / 2;
    dst[..head].copy_from_slice(&src[..head]);
    for p in 0..pairs {
        let k = head + 2 * p;
        let (d, s) = (&mut dst[k..k + 2], &src[k..k + 2]);
        // SAFETY: SSE2 is part of the x86-64 baseline; `d` is two writable `f64` at a
        // 16-byte boundary (`align_offset` above) and `s` two readable ones
        // (`loadu` needs no alignment), both bounds-checked by the slicing above.
        unsafe { _mm_stream_pd(d.as_mut_ptr(), _mm_loadu_pd(s.as_ptr())) }
    }
    let tail = head + 2 * pairs;
    dst[tail..].copy_from_slice(&src[tail..]);
}

/// Orders every earlier non-temporal store before the stores after it (`sfence`).
#[inline(always)]
pub(crate) fn fence() {
    // SAFETY: SSE (part of the x86-64 baseline) has `sfence`; it has no operands.
    unsafe { _mm_sfence() }
}
