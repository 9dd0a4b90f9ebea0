//! Two f64 lanes, for the kernels' code that does the same arithmetic for two angles or two
//! elements at once ([`crate::trig::sin_cos_pair`], the line elements' loads in the fused
//! right-hand sides, the seabed's depth series of two elements in the runtime's fused load
//! path). Each operation is one IEEE operation per lane, so a lane's result equals, bit for
//! bit, the scalar code's doing the same operations (a NaN's sign and payload aside, which
//! Rust leaves unspecified); a scalar branch becomes a comparison's mask and a
//! [`F2::select`] of both sides, the lane's side taken.
//!
//! On x86-64 with SSE2 (part of every x86-64 processor, on for every x86-64 target but the
//! soft-float ones) an [`F2`] is an SSE2 register (`sse2::F2`); elsewhere, two numbers
//! (`portable::F2`). Both are compiled on x86-64, and a test there holds the portable lanes
//! to the SSE2 ones bit for bit, operation by operation, on special and random values, and
//! every operation to the scalar one it stands for: the trigonometric, seabed and load
//! tests check the SSE2 lanes against the scalar code, so the portable ones are checked
//! through them. Built with `RUSTFLAGS="--cfg
//! kanestop_portable_lanes"`, an x86-64 build puts the portable lanes in for the SSE2 ones, as
//! a target without SSE2 does: `.ci/run` runs the generated and runtime crates' own tests so,
//! which compiles and runs the other targets' wiring here. The operations built
//! on the lanes' bits (`keep`, `mask`, `keep_mask`, `select`, `copysign`, `abs`, `−x`,
//! `clamp`, the quadrant's selects) are written once for both (`derived!`), so the test
//! against the scalar operations is what checks them. The SSE2 intrinsics are `unsafe`
//! before Rust 1.87 and safe since wherever SSE2 is on, as on every x86-64 target: hence the
//! `unsafe` blocks, with `unused_unsafe` allowed. None of them reads or writes memory.
#![allow(unused_unsafe)]

#[cfg(all(target_arch = "x86_64", target_feature = "sse2", not(kanestop_portable_lanes)))]
pub use sse2::F2;

#[cfg(any(not(all(target_arch = "x86_64", target_feature = "sse2")), kanestop_portable_lanes))]
pub use portable::F2;

/// The operations built on an `F2`'s primitive ones (`new`, `lanes`, its bits and the
/// `Bits` operations), the same for both kinds of lanes.
macro_rules! derived {
    () => {
        impl F2 {
            /// `x` in both lanes.
            #[inline(always)]
            pub fn splat(x: f64) -> F2 {
                F2::new(x, x)
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

            /// |x| of each lane (as `f64::abs`: the sign bit cleared).
            #[inline(always)]
            pub fn abs(self) -> F2 {
                F2::from_bits(self.bits().andnot(Bits::splat(1 << 63)))
            }

            /// Per lane: `if_set` where `mask` (a comparison's result: all bits set or none)
            /// is set, else `self`.
            #[inline(always)]
            pub fn select(self, mask: F2, if_set: F2) -> F2 {
                let m = mask.bits();
                F2::from_bits(self.bits().andnot(m).or(if_set.bits().and(m)))
            }

            /// Per lane: `self` where `mask` is set, else +0 (with a mask for `self`, the
            /// lanes set in both).
            #[inline(always)]
            pub fn keep_mask(self, mask: F2) -> F2 {
                F2::from_bits(self.bits().and(mask.bits()))
            }

            /// The mask with lane i set where `set[i]`, as a comparison gives.
            #[inline(always)]
            pub fn mask(set: [bool; 2]) -> F2 {
                F2::splat(f64::from_bits(u64::MAX)).keep(set)
            }

            /// Each lane clamped to `[lo, hi]`, as `f64::clamp` (NaN stays NaN; unlike it, no
            /// panic for `lo > hi` or a NaN bound: the caller's bounds are ordered numbers).
            #[inline(always)]
            pub fn clamp(self, lo: F2, hi: F2) -> F2 {
                let x = self.select(self.lt(lo), lo);
                x.select(x.gt(hi), hi)
            }

            /// `f` of each lane, one scalar call per lane (a function with no lane form,
            /// such as `tanh` or `powf`).
            #[inline(always)]
            pub fn map(self, f: impl Fn(f64) -> f64) -> F2 {
                let [a, b] = self.lanes();
                F2::new(f(a), f(b))
            }

            /// `[[a₀, b₀], [a₁, b₁]]`: lane i of `a` and of `b` side by side.
            #[inline(always)]
            pub fn zip(a: F2, b: F2) -> [[f64; 2]; 2] {
                let (a, b) = (a.lanes(), b.lanes());
                [[a[0], b[0]], [a[1], b[1]]]
            }
        }

        impl core::ops::Neg for F2 {
            type Output = F2;
            /// −x of each lane (as the scalar `-x`: the sign bit flipped, so −0 of +0).
            #[inline(always)]
            fn neg(self) -> F2 {
                F2::from_bits(self.bits().xor(Bits::splat(1 << 63)))
            }
        }

        impl Bits {
            #[inline(always)]
            fn splat(x: u64) -> Bits {
                Bits::new(x, x)
            }
        }
    };
}

/// Two plain numbers: the lanes wherever SSE2 is not. Compiled on x86-64 too, where only the
/// test against the SSE2 lanes uses them (unless built with `--cfg kanestop_portable_lanes`).
#[cfg_attr(
    all(target_arch = "x86_64", target_feature = "sse2", not(test), not(kanestop_portable_lanes)),
    allow(dead_code)
)]
mod portable {
    /// Two f64 lanes, `[lane 0, lane 1]`.
    #[derive(Clone, Copy, Debug)]
    pub struct F2([f64; 2]);

    /// Two u64 lanes (an [`F2`]'s bits).
    #[derive(Clone, Copy)]
    struct Bits([u64; 2]);

    macro_rules! lanewise {
        ($($trait:ident $method:ident $op:tt),*) => {$(
            impl core::ops::$trait for F2 {
                type Output = F2;
                #[inline(always)]
                fn $method(self, o: F2) -> F2 {
                    F2([self.0[0] $op o.0[0], self.0[1] $op o.0[1]])
                }
            }
        )*};
    }
    lanewise!(Add add +, Sub sub -, Mul mul *, Div div /);

    impl F2 {
        /// `[a, b]`.
        #[inline(always)]
        pub fn new(a: f64, b: f64) -> F2 {
            F2([a, b])
        }

        /// `[lane 0, lane 1]`.
        #[inline(always)]
        pub fn lanes(self) -> [f64; 2] {
            self.0
        }

        /// √ of each lane (correctly rounded, as `f64::sqrt`).
        #[inline(always)]
        pub fn sqrt(self) -> F2 {
            F2(self.0.map(f64::sqrt))
        }

        /// Per lane, all bits set where `op` holds, else clear.
        #[inline(always)]
        fn compare(self, o: F2, op: impl Fn(f64, f64) -> bool) -> F2 {
            let m = |i: usize| if op(self.0[i], o.0[i]) { f64::from_bits(u64::MAX) } else { 0.0 };
            F2([m(0), m(1)])
        }
    }

    /// `a.lt(b)` … `a.ne(b)`: each lane all bits set where the scalar comparison holds (false
    /// with a NaN, but for `ne`), else clear: a mask for `select`.
    macro_rules! comparisons {
        ($($name:ident $op:tt),*) => {
            impl F2 {$(
                #[doc = concat!("Per lane, all bits set where `self ", stringify!($op), " o`, else clear.")]
                #[inline(always)]
                pub fn $name(self, o: F2) -> F2 {
                    self.compare(o, |a, b| a $op b)
                }
            )*}
        };
    }
    comparisons!(lt <, le <=, gt >, ge >=, eq ==, ne !=);

    impl F2 {
        #[inline(always)]
        fn bits(self) -> Bits {
            Bits(self.0.map(f64::to_bits))
        }

        #[inline(always)]
        fn from_bits(b: Bits) -> F2 {
            F2(b.0.map(f64::from_bits))
        }
    }

    impl Bits {
        #[inline(always)]
        fn new(a: u64, b: u64) -> Bits {
            Bits([a, b])
        }

        #[inline(always)]
        fn map2(self, o: Bits, f: impl Fn(u64, u64) -> u64) -> Bits {
            Bits([f(self.0[0], o.0[0]), f(self.0[1], o.0[1])])
        }

        #[inline(always)]
        fn and(self, o: Bits) -> Bits {
            self.map2(o, |a, b| a & b)
        }

        #[inline(always)]
        fn or(self, o: Bits) -> Bits {
            self.map2(o, |a, b| a | b)
        }

        #[inline(always)]
        fn xor(self, o: Bits) -> Bits {
            self.map2(o, |a, b| a ^ b)
        }

        #[inline(always)]
        fn add(self, o: Bits) -> Bits {
            self.map2(o, u64::wrapping_add)
        }

        #[inline(always)]
        fn sub(self, o: Bits) -> Bits {
            self.map2(o, u64::wrapping_sub)
        }

        /// `self & !mask`.
        #[inline(always)]
        fn andnot(self, mask: Bits) -> Bits {
            self.map2(mask, |a, m| a & !m)
        }

        /// Bit `bit` moved to bit 63 (the others of `self` are zero).
        #[inline(always)]
        fn shift_to_sign(self, bit: u32) -> Bits {
            Bits(self.0.map(|x| x << (63 - bit)))
        }
    }

    derived!();
}

/// An SSE2 register of two f64.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[cfg_attr(all(kanestop_portable_lanes, not(test)), allow(dead_code))]
mod sse2 {
    use core::arch::x86_64::*;

    /// Two f64 lanes, `[lane 0, lane 1]`.
    #[derive(Clone, Copy, Debug)]
    pub struct F2(__m128d);

    /// Two u64 lanes (an [`F2`]'s bits).
    #[derive(Clone, Copy)]
    struct Bits(__m128i);

    macro_rules! lanewise {
        ($($trait:ident $method:ident $intrinsic:ident),*) => {$(
            impl core::ops::$trait for F2 {
                type Output = F2;
                #[inline(always)]
                fn $method(self, o: F2) -> F2 {
                    F2(unsafe { $intrinsic(self.0, o.0) })
                }
            }
        )*};
    }
    lanewise!(Add add _mm_add_pd, Sub sub _mm_sub_pd, Mul mul _mm_mul_pd, Div div _mm_div_pd);

    impl F2 {
        /// `[a, b]`.
        #[inline(always)]
        pub fn new(a: f64, b: f64) -> F2 {
            F2(unsafe { _mm_set_pd(b, a) })
        }

        /// `[lane 0, lane 1]`.
        #[inline(always)]
        pub fn lanes(self) -> [f64; 2] {
            unsafe { [_mm_cvtsd_f64(self.0), _mm_cvtsd_f64(_mm_unpackhi_pd(self.0, self.0))] }
        }

        /// √ of each lane (correctly rounded, as `f64::sqrt`).
        #[inline(always)]
        pub fn sqrt(self) -> F2 {
            F2(unsafe { _mm_sqrt_pd(self.0) })
        }
    }

    /// `a.lt(b)` … `a.ne(b)`: each lane all bits set where the scalar comparison holds (false
    /// with a NaN, but for `ne`), else clear: a mask for `select`.
    macro_rules! comparisons {
        ($($name:ident $op:tt $intrinsic:ident),*) => {
            impl F2 {$(
                #[doc = concat!("Per lane, all bits set where `self ", stringify!($op), " o`, else clear.")]
                #[inline(always)]
                pub fn $name(self, o: F2) -> F2 {
                    F2(unsafe { $intrinsic(self.0, o.0) })
                }
            )*}
        };
    }
    comparisons!(
        lt < _mm_cmplt_pd,
        le <= _mm_cmple_pd,
        gt > _mm_cmpgt_pd,
        ge >= _mm_cmpge_pd,
        eq == _mm_cmpeq_pd,
        ne != _mm_cmpneq_pd
    );

    impl F2 {
        #[inline(always)]
        fn bits(self) -> Bits {
            Bits(unsafe { _mm_castpd_si128(self.0) })
        }

        #[inline(always)]
        fn from_bits(b: Bits) -> F2 {
            F2(unsafe { _mm_castsi128_pd(b.0) })
        }
    }

    macro_rules! bitwise {
        ($($method:ident $intrinsic:ident),*) => {$(
            #[inline(always)]
            fn $method(self, o: Bits) -> Bits {
                Bits(unsafe { $intrinsic(self.0, o.0) })
            }
        )*};
    }

    impl Bits {
        #[inline(always)]
        fn new(a: u64, b: u64) -> Bits {
            Bits(unsafe { _mm_set_epi64x(b as i64, a as i64) })
        }

        bitwise!(and _mm_and_si128, or _mm_or_si128, xor _mm_xor_si128, add _mm_add_epi64, sub _mm_sub_epi64);

        /// `self & !mask`.
        #[inline(always)]
        fn andnot(self, mask: Bits) -> Bits {
            Bits(unsafe { _mm_andnot_si128(mask.0, self.0) })
        }

        /// Bit `bit` moved to bit 63 (the others of `self` are zero).
        #[inline(always)]
        fn shift_to_sign(self, bit: u32) -> Bits {
            Bits(unsafe { _mm_sll_epi64(self.0, _mm_set_epi64x(0, i64::from(63 - bit))) })
        }
    }

    derived!();
}

#[cfg(all(test, target_arch = "x86_64", target_feature = "sse2"))]
mod tests {
    use super::{portable, sse2};

    /// Special values (signed zeros, subnormals, the extremes, infinities, NaN, the integers
    /// and quadrant patterns `sin_cos` feeds the selects) and seeded random bit patterns.
    fn values() -> Vec<f64> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            2.0,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            5e-324,
            -5e-324,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
            std::f64::consts::PI,
            6_755_399_441_055_744.0,
            6_755_399_441_055_745.0,
            6_755_399_441_055_746.0,
            6_755_399_441_055_747.0,
        ];
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        for i in 0..400 {
            // xorshift64*: bit patterns of every exponent, and ordinary magnitudes.
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            let r = x.wrapping_mul(0x2545_F491_4F6C_DD1D);
            v.push(if i % 2 == 0 { f64::from_bits(r) } else { (r >> 11) as f64 / (1u64 << 40) as f64 - 4096.0 });
        }
        v
    }

    #[test]
    fn the_portable_lanes_equal_the_sse2_lanes_bit_for_bit() {
        let v = values();
        let bits = |l: [f64; 2]| l.map(f64::to_bits);
        let mut compared = 0usize;
        for (i, &a) in v.iter().enumerate() {
            // Each value against a spread of partners, in both lanes.
            for &b in v.iter().skip(i % 7).step_by(7) {
                let (p, s) = (portable::F2::new(a, b), sse2::F2::new(a, b));
                let (pq, sq) = (portable::F2::new(b, a), sse2::F2::new(b, a));
                let same = |x: [f64; 2], y: [f64; 2], what: &str| {
                    assert_eq!(bits(x), bits(y), "{what} of [{a:e}, {b:e}]: portable {x:?}, sse2 {y:?}");
                };
                same(p.lanes(), s.lanes(), "lanes");
                same(portable::F2::splat(a).lanes(), sse2::F2::splat(a).lanes(), "splat");
                same((p + pq).lanes(), (s + sq).lanes(), "+");
                same((p - pq).lanes(), (s - sq).lanes(), "−");
                same((p * pq).lanes(), (s * sq).lanes(), "×");
                same((p / pq).lanes(), (s / sq).lanes(), "÷");
                same(p.sqrt().lanes(), s.sqrt().lanes(), "sqrt");
                for keep in [[false, false], [true, false], [false, true], [true, true]] {
                    same(p.keep(keep).lanes(), s.keep(keep).lanes(), "keep");
                    same(portable::F2::mask(keep).lanes(), sse2::F2::mask(keep).lanes(), "mask");
                    let set = keep.map(|k| if k { f64::from_bits(u64::MAX) } else { 0.0 });
                    same(sse2::F2::mask(keep).lanes(), set, "mask against its lanes");
                }
                same(p.copysign(pq).lanes(), s.copysign(sq).lanes(), "copysign");
                same(p.abs().lanes(), s.abs().lanes(), "abs");
                same((-p).lanes(), (-s).lanes(), "−x");
                let masks = [
                    (p.lt(pq), s.lt(sq), "<"),
                    (p.le(pq), s.le(sq), "≤"),
                    (p.gt(pq), s.gt(sq), ">"),
                    (p.ge(pq), s.ge(sq), "≥"),
                    (p.eq(pq), s.eq(sq), "="),
                    (p.ne(pq), s.ne(sq), "≠"),
                ];
                for (mp, ms, what) in masks {
                    same(mp.lanes(), ms.lanes(), what);
                    same(p.select(mp, pq).lanes(), s.select(ms, sq).lanes(), "select");
                    same(p.keep_mask(mp).lanes(), s.keep_mask(ms).lanes(), "keep_mask");
                }
                let (lo, hi) = (portable::F2::splat(-1.0), portable::F2::splat(2.0));
                same(p.clamp(lo, hi).lanes(), s.clamp(sse2::F2::splat(-1.0), sse2::F2::splat(2.0)).lanes(), "clamp");
                same(p.map(f64::tanh).lanes(), s.map(f64::tanh).lanes(), "map");
                // …and the lanes do what the scalar operations do, lane by lane.
                let scalar = |f: &dyn Fn(f64, f64) -> f64| [f(a, b), f(b, a)];
                same(s.abs().lanes(), scalar(&|x, _| x.abs()), "abs against f64::abs");
                same((-s).lanes(), scalar(&|x, _| -x), "−x against the scalar −x");
                same(
                    s.clamp(sse2::F2::splat(-1.0), sse2::F2::splat(2.0)).lanes(),
                    scalar(&|x, _| x.clamp(-1.0, 2.0)),
                    "clamp against f64::clamp",
                );
                let set = |c: bool| if c { f64::from_bits(u64::MAX) } else { 0.0 };
                same(s.lt(sq).lanes(), scalar(&|x, y| set(x < y)), "< against the scalar <");
                same(s.le(sq).lanes(), scalar(&|x, y| set(x <= y)), "≤ against the scalar ≤");
                same(s.gt(sq).lanes(), scalar(&|x, y| set(x > y)), "> against the scalar >");
                same(s.ge(sq).lanes(), scalar(&|x, y| set(x >= y)), "≥ against the scalar ≥");
                same(s.eq(sq).lanes(), scalar(&|x, y| set(x == y)), "= against the scalar =");
                same(s.ne(sq).lanes(), scalar(&|x, y| set(x != y)), "≠ against the scalar ≠");
                same(s.select(s.lt(sq), sq).lanes(), scalar(&|x, y| if x < y { y } else { x }), "select against if");
                same(
                    s.keep_mask(s.lt(sq)).lanes(),
                    scalar(&|x, y| if x < y { x } else { 0.0 }),
                    "keep_mask against if",
                );
                same(s.copysign(sq).lanes(), scalar(&f64::copysign), "copysign against f64::copysign");
                let zero = sse2::F2::splat(0.0);
                // From +0, as the current's profile clamps: −0 stays −0.
                same(
                    s.clamp(zero, sse2::F2::splat(2.0)).lanes(),
                    scalar(&|x, _| x.clamp(0.0, 2.0)),
                    "clamp from +0 against f64::clamp",
                );
                same(p.select_odd(pq, p * pq).lanes(), s.select_odd(sq, s * sq).lanes(), "select_odd");
                for (add, bit) in [(0, 0), (0, 1), (1, 1), (3, 2)] {
                    same(p.negate_if(pq, add, bit).lanes(), s.negate_if(sq, add, bit).lanes(), "negate_if");
                }
                let (zp, zs) = (portable::F2::zip(p, pq), sse2::F2::zip(s, sq));
                same(zp[0], zs[0], "zip");
                same(zp[1], zs[1], "zip");
                compared += 1;
            }
        }
        assert!(compared > 20_000, "{compared} pairs compared");
    }
}

#[cfg(test)]
mod wiring {
    /// The lanes in use are the ones the target and `--cfg kanestop_portable_lanes` call for:
    /// the run of these tests under the cfg (`.ci/run`) does exercise the portable lanes.
    #[test]
    fn the_lanes_in_use_are_the_configured_ones() {
        let portable = cfg!(kanestop_portable_lanes) || !cfg!(all(target_arch = "x86_64", target_feature = "sse2"));
        let name = std::any::type_name::<super::F2>();
        let expected = if portable { "::portable::F2" } else { "::sse2::F2" };
        assert!(name.ends_with(expected), "F2 is {name}, expected {expected}");
    }
}
