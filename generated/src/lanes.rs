//! Two f64 lanes, for the kernels' code that does the same arithmetic for two angles or two
//! elements at once ([`crate::trig::sin_cos_pair`], the seabed's depth series of two
//! elements in the runtime's fused load path). Each operation is one IEEE operation per lane,
//! so a lane's result equals, bit for bit, the scalar code's doing the same operations.
//!
//! On x86-64 with SSE2 (part of every x86-64 processor, on for every x86-64 target but the
//! soft-float ones) an [`F2`] is an SSE2 register; elsewhere, two numbers. The SSE2 intrinsics are `unsafe` before Rust 1.87 and safe since
//! wherever SSE2 is on, as on every x86-64 target: hence the `unsafe` blocks, with
//! `unused_unsafe` allowed. None of them reads or writes memory.
#![allow(unused_unsafe)]

#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
use core::arch::x86_64::*;

/// Two f64 lanes, `[lane 0, lane 1]`.
#[derive(Clone, Copy, Debug)]
pub struct F2(
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))] __m128d,
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))] [f64; 2],
);

macro_rules! lanewise {
    ($($trait:ident $method:ident $intrinsic:ident $op:tt),*) => {$(
        impl core::ops::$trait for F2 {
            type Output = F2;
            #[inline(always)]
            fn $method(self, o: F2) -> F2 {
                #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
                return F2(unsafe { $intrinsic(self.0, o.0) });
                #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
                return F2([self.0[0] $op o.0[0], self.0[1] $op o.0[1]]);
            }
        }
    )*};
}

// Each arm names the SSE2 intrinsic and the scalar operator; only one of the two is compiled.
lanewise!(Add add _mm_add_pd +, Sub sub _mm_sub_pd -, Mul mul _mm_mul_pd *, Div div _mm_div_pd /);

impl F2 {
    /// `[a, b]`.
    #[inline(always)]
    pub fn new(a: f64, b: f64) -> F2 {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return F2(unsafe { _mm_set_pd(b, a) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return F2([a, b]);
    }

    /// `x` in both lanes.
    #[inline(always)]
    pub fn splat(x: f64) -> F2 {
        F2::new(x, x)
    }

    /// `[lane 0, lane 1]`.
    #[inline(always)]
    pub fn lanes(self) -> [f64; 2] {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return unsafe { [_mm_cvtsd_f64(self.0), _mm_cvtsd_f64(_mm_unpackhi_pd(self.0, self.0))] };
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return self.0;
    }

    /// √ of each lane (correctly rounded, as `f64::sqrt`).
    #[inline(always)]
    pub fn sqrt(self) -> F2 {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return F2(unsafe { _mm_sqrt_pd(self.0) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return F2(self.0.map(f64::sqrt));
    }

    /// Each lane's bits.
    #[inline(always)]
    fn bits(self) -> Bits {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return Bits(unsafe { _mm_castpd_si128(self.0) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return Bits(self.0.map(f64::to_bits));
    }

    /// The lanes of these bits.
    #[inline(always)]
    fn from_bits(b: Bits) -> F2 {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return F2(unsafe { _mm_castsi128_pd(b.0) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return F2(b.0.map(f64::from_bits));
    }

    /// Lane i where `keep[i]`, else +0 (all bits clear).
    #[inline(always)]
    pub fn keep(self, keep: [bool; 2]) -> F2 {
        let mask = |k: bool| if k { u64::MAX } else { 0 };
        F2::from_bits(self.bits().and(Bits::new(mask(keep[0]), mask(keep[1]))))
    }

    /// |x| with the sign of `sign`, lane by lane (as `f64::copysign`).
    #[inline(always)]
    pub fn copysign(self, sign: F2) -> F2 {
        let s = Bits::splat(1 << 63);
        F2::from_bits(self.bits().andnot(s).or(sign.bits().and(s)))
    }

    /// Per lane: `if_set` where bit 0 of `mask` (an integer's bits) is set, else `self`.
    #[inline(always)]
    pub fn select_odd(self, mask: F2, if_set: F2) -> F2 {
        let odd = Bits::splat(0).sub(mask.bits().and(Bits::splat(1)));
        F2::from_bits(self.bits().andnot(odd).or(if_set.bits().and(odd)))
    }

    /// Per lane: −x where bit `bit` of `mask`'s bits (plus `add`) is set, else x.
    #[inline(always)]
    pub fn negate_if(self, mask: F2, add: u64, bit: u32) -> F2 {
        let b = mask.bits().add(Bits::splat(add)).and(Bits::splat(1 << bit)).shift_to_sign(bit);
        F2::from_bits(self.bits().xor(b))
    }

    /// `[[a₀, b₀], [a₁, b₁]]`: lane i of `a` and of `b` side by side.
    #[inline(always)]
    pub fn zip(a: F2, b: F2) -> [[f64; 2]; 2] {
        let (a, b) = (a.lanes(), b.lanes());
        [[a[0], b[0]], [a[1], b[1]]]
    }
}

/// Two u64 lanes (an [`F2`]'s bits).
#[derive(Clone, Copy)]
struct Bits(
    #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))] __m128i,
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))] [u64; 2],
);

macro_rules! bitwise {
    ($($method:ident $intrinsic:ident $op:expr),*) => {$(
        #[inline(always)]
        fn $method(self, o: Bits) -> Bits {
            #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
            return Bits(unsafe { $intrinsic(self.0, o.0) });
            #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
            return Bits([$op(self.0[0], o.0[0]), $op(self.0[1], o.0[1])]);
        }
    )*};
}

impl Bits {
    /// `[a, b]`.
    #[inline(always)]
    fn new(a: u64, b: u64) -> Bits {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return Bits(unsafe { _mm_set_epi64x(b as i64, a as i64) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return Bits([a, b]);
    }

    #[inline(always)]
    fn splat(x: u64) -> Bits {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return Bits(unsafe { _mm_set1_epi64x(x as i64) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return Bits([x, x]);
    }

    bitwise!(
        and _mm_and_si128 |a: u64, b: u64| a & b,
        or _mm_or_si128 |a: u64, b: u64| a | b,
        xor _mm_xor_si128 |a: u64, b: u64| a ^ b,
        add _mm_add_epi64 u64::wrapping_add,
        sub _mm_sub_epi64 u64::wrapping_sub
    );

    /// `self & !mask`.
    #[inline(always)]
    fn andnot(self, mask: Bits) -> Bits {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return Bits(unsafe { _mm_andnot_si128(mask.0, self.0) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return Bits([self.0[0] & !mask.0[0], self.0[1] & !mask.0[1]]);
    }

    /// Bit `bit` moved to bit 63 (the others of `self` are zero).
    #[inline(always)]
    fn shift_to_sign(self, bit: u32) -> Bits {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        return Bits(unsafe { _mm_sll_epi64(self.0, _mm_set_epi64x(0, i64::from(63 - bit))) });
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        return Bits(self.0.map(|x| x << (63 - bit)));
    }
}
