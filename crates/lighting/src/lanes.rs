//! Lane types the illumination model is generic over: [`F32x1`] (one value, the scalar
//! model), [`f32x4`] (SSE2, the x86-64 baseline,
//! and whatever `wide` maps it to elsewhere) and, on x86-64 CPUs that have it, [`F32x8`]
//! (AVX2, eight lanes), chosen at run time through [`Avx2`].
//!
//! Contract: every operation is the IEEE single-precision one lane by lane (correctly rounded
//! add, sub, mul, div and sqrt; no fused multiply-add), so a computation written once over
//! [`Lanes`] gives the same bits in lane `i` at every width. The comparisons are ordered (false
//! for NaN), `max_c` / `min_c` return their second operand when either is NaN (SSE and AVX
//! `max`/`min`), and masks are all ones or all zeros per lane.
//!
//! Why a token: an AVX2 instruction may only run on a CPU that has it. [`Avx2::detect`] checks
//! the CPU once; every [`F32x8`] carries the (zero-sized) proof, so its operations are safe to
//! call, and [`Avx2::run`] compiles a closure (and everything it inlines) with AVX2 enabled.
//! The intrinsics come from `pulp`'s safe wrappers: this crate has no `unsafe`.

use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Sub};

pub use wide::f32x4;
use wide::{CmpEq, CmpGe, CmpLe};

/// A vector of `N` f32 lanes with the operations the illumination model uses (see the module
/// docs for their exact semantics). Constants come from an existing value ([`Lanes::splat`]),
/// so that a lane type may carry a CPU-feature token.
pub trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
{
    /// The number of lanes (at most 8).
    const N: usize;
    /// `x` in every lane (of a vector of the same kind as `self`).
    fn splat(self, x: f32) -> Self;
    /// Lane `i` is `a[i]`, for `i < N` (of a vector of the same kind as `self`).
    fn with_lanes(self, a: [f32; 8]) -> Self;
    /// The lanes, `N` of them, then zeros.
    fn to_lanes(self) -> [f32; 8];
    /// Square root per lane.
    fn sqrt(self) -> Self;
    /// `|x|` per lane (the sign bit cleared).
    fn abs(self) -> Self;
    /// Scalar `x.max(c)` for a non-NaN `c`: NaN lanes give `c`.
    fn max_c(self, c: Self) -> Self;
    /// Scalar `x.min(c)` for a non-NaN `c`: NaN lanes give `c`.
    fn min_c(self, c: Self) -> Self;
    /// `self >= o` per lane as a mask (false for NaN).
    fn cmp_ge(self, o: Self) -> Self;
    /// `self <= o` per lane as a mask (false for NaN).
    fn cmp_le(self, o: Self) -> Self;
    /// `self == o` per lane as a mask (false for NaN).
    fn cmp_eq(self, o: Self) -> Self;
    /// With `self` a mask: `t` where it is set, `f` where it is clear.
    fn blend(self, t: Self, f: Self) -> Self;
    /// With `self` a mask: bit `i` set when lane `i` is.
    fn mask_bits(self) -> u32;
    /// The eight columns of the first `N` rows of `rows` (lane `i` of column `j` is
    /// `rows[i][j]`), of the kind of `self`: a transpose, so that values stored one item after
    /// another (a pixel's attributes) become lanes.
    fn columns(self, rows: &[[f32; 8]; 8]) -> [Self; 8];
    /// With `self` a mask: every lane set.
    #[inline(always)]
    fn all(self) -> bool {
        self.mask_bits() == (1 << Self::N) - 1
    }
    /// With `self` a mask: some lane set.
    #[inline(always)]
    fn any(self) -> bool {
        self.mask_bits() != 0
    }
}

impl Lanes for f32x4 {
    const N: usize = 4;
    #[inline(always)]
    fn splat(self, x: f32) -> f32x4 {
        f32x4::splat(x)
    }
    #[inline(always)]
    fn with_lanes(self, a: [f32; 8]) -> f32x4 {
        f32x4::new([a[0], a[1], a[2], a[3]])
    }
    #[inline(always)]
    fn to_lanes(self) -> [f32; 8] {
        let a = self.to_array();
        [a[0], a[1], a[2], a[3], 0.0, 0.0, 0.0, 0.0]
    }
    #[inline(always)]
    fn sqrt(self) -> f32x4 {
        f32x4::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f32x4 {
        f32x4::abs(self)
    }
    #[inline(always)]
    fn max_c(self, c: f32x4) -> f32x4 {
        #[cfg(target_feature = "sse")]
        {
            self.fast_max(c)
        }
        #[cfg(not(target_feature = "sse"))]
        {
            use wide::CmpGt;
            self.cmp_gt(c).blend(self, c)
        }
    }
    #[inline(always)]
    fn min_c(self, c: f32x4) -> f32x4 {
        #[cfg(target_feature = "sse")]
        {
            self.fast_min(c)
        }
        #[cfg(not(target_feature = "sse"))]
        {
            use wide::CmpLt;
            self.cmp_lt(c).blend(self, c)
        }
    }
    #[inline(always)]
    fn cmp_ge(self, o: f32x4) -> f32x4 {
        CmpGe::cmp_ge(self, o)
    }
    #[inline(always)]
    fn cmp_le(self, o: f32x4) -> f32x4 {
        CmpLe::cmp_le(self, o)
    }
    #[inline(always)]
    fn cmp_eq(self, o: f32x4) -> f32x4 {
        CmpEq::cmp_eq(self, o)
    }
    #[inline(always)]
    fn blend(self, t: f32x4, f: f32x4) -> f32x4 {
        f32x4::blend(self, t, f)
    }
    #[inline(always)]
    fn mask_bits(self) -> u32 {
        self.move_mask().cast_unsigned()
    }
    #[inline(always)]
    fn columns(self, rows: &[[f32; 8]; 8]) -> [f32x4; 8] {
        // Two 4 x 4 transposes (eight shuffles each), where gathering the lanes one float at
        // a time takes a move per float.
        let quad = |at: usize| {
            f32x4::transpose(std::array::from_fn(|i| {
                f32x4::new([
                    rows[i][at],
                    rows[i][at + 1],
                    rows[i][at + 2],
                    rows[i][at + 3],
                ])
            }))
        };
        let (lo, hi) = (quad(0), quad(4));
        [lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]]
    }
}

/// One f32 lane: the scalar model as a [`Lanes`] type, so that code written once over lanes
/// also runs one value at a time (a pixel, a triangle) with the same bits as every wider
/// lane type. Masks are all ones or all zeros in the one lane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct F32x1(pub f32);

impl F32x1 {
    #[inline(always)]
    fn bits(self) -> u32 {
        self.0.to_bits()
    }

    #[inline(always)]
    fn from_bits(b: u32) -> F32x1 {
        F32x1(f32::from_bits(b))
    }

    #[inline(always)]
    fn mask(c: bool) -> F32x1 {
        F32x1::from_bits(if c { u32::MAX } else { 0 })
    }
}

macro_rules! scalar_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F32x1 {
            type Output = F32x1;
            #[inline(always)]
            fn $method(self, rhs: F32x1) -> F32x1 {
                F32x1(self.0 $op rhs.0)
            }
        }
    };
}
scalar_op!(Add, add, +);
scalar_op!(Sub, sub, -);
scalar_op!(Mul, mul, *);
scalar_op!(Div, div, /);

macro_rules! scalar_bits {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F32x1 {
            type Output = F32x1;
            #[inline(always)]
            fn $method(self, rhs: F32x1) -> F32x1 {
                F32x1::from_bits(self.bits() $op rhs.bits())
            }
        }
    };
}
scalar_bits!(BitAnd, bitand, &);
scalar_bits!(BitOr, bitor, |);
scalar_bits!(BitXor, bitxor, ^);

impl Lanes for F32x1 {
    const N: usize = 1;
    #[inline(always)]
    fn splat(self, x: f32) -> F32x1 {
        F32x1(x)
    }
    #[inline(always)]
    fn with_lanes(self, a: [f32; 8]) -> F32x1 {
        F32x1(a[0])
    }
    #[inline(always)]
    fn to_lanes(self) -> [f32; 8] {
        [self.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    }
    #[inline(always)]
    fn sqrt(self) -> F32x1 {
        F32x1(self.0.sqrt())
    }
    #[inline(always)]
    fn abs(self) -> F32x1 {
        F32x1::from_bits(self.bits() & 0x7fff_ffff)
    }
    #[inline(always)]
    fn max_c(self, c: F32x1) -> F32x1 {
        // SSE's `maxps(x, c)`: x where x > c, else c (NaN gives c).
        if self.0 > c.0 { self } else { c }
    }
    #[inline(always)]
    fn min_c(self, c: F32x1) -> F32x1 {
        if self.0 < c.0 { self } else { c }
    }
    #[inline(always)]
    fn cmp_ge(self, o: F32x1) -> F32x1 {
        F32x1::mask(self.0 >= o.0)
    }
    #[inline(always)]
    fn cmp_le(self, o: F32x1) -> F32x1 {
        F32x1::mask(self.0 <= o.0)
    }
    #[inline(always)]
    fn cmp_eq(self, o: F32x1) -> F32x1 {
        F32x1::mask(self.0 == o.0)
    }
    #[inline(always)]
    fn blend(self, t: F32x1, f: F32x1) -> F32x1 {
        if self.bits() >> 31 != 0 { t } else { f }
    }
    #[inline(always)]
    fn mask_bits(self) -> u32 {
        self.bits() >> 31
    }
    #[inline(always)]
    fn columns(self, rows: &[[f32; 8]; 8]) -> [F32x1; 8] {
        rows[0].map(F32x1)
    }
}

#[cfg(target_arch = "x86_64")]
pub use avx2::{Avx2, Avx2Task, F32x8};

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::__m256;
    use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Sub};

    use pulp::x86::V3;

    use super::Lanes;

    /// Proof that the CPU runs AVX2 (and the rest of x86-64-v3), found at run time.
    #[derive(Debug, Clone, Copy)]
    pub struct Avx2(V3);

    impl Avx2 {
        /// The token when this CPU has AVX2, else `None` (the answer is cached).
        #[must_use]
        pub fn detect() -> Option<Avx2> {
            V3::try_new().map(Avx2)
        }

        /// Runs `task` inside a function compiled for AVX2. What is inlined into it uses
        /// 256-bit instructions; anything it calls that is not inlined runs at the baseline,
        /// correct but slow (each intrinsic then becomes a call). A closure works, but rustc
        /// may leave its body out of line, so hot code implements [`Avx2Task`] with an
        /// `#[inline(always)]` `run`.
        #[inline(always)]
        pub fn run<T: Avx2Task>(self, task: T) -> T::Output {
            self.0.vectorize(Call(task, self))
        }

        /// The `pulp` token this proof wraps, for a caller's own AVX2 intrinsics (the
        /// rasterizer's integer coverage masks).
        #[inline(always)]
        #[must_use]
        pub fn v3(self) -> V3 {
            self.0
        }

        /// `x` in all eight lanes.
        #[inline(always)]
        #[must_use]
        pub fn splat(self, x: f32) -> F32x8 {
            F32x8 {
                t: self.0,
                v: self.0.avx._mm256_set1_ps(x),
            }
        }

        /// Lane `i` is `a[i]`.
        #[inline(always)]
        #[must_use]
        pub fn load(self, a: [f32; 8]) -> F32x8 {
            F32x8 {
                t: self.0,
                v: pulp::cast(a),
            }
        }

        /// Column `j` of the eight rows `r` (an 8 x 8 transpose in 24 shuffles): lane `i` of
        /// output `j` is `r[i][j]`.
        #[inline(always)]
        #[must_use]
        pub fn transpose(self, r: [[f32; 8]; 8]) -> [F32x8; 8] {
            let a = self.0.avx;
            let r = r.map(pulp::cast::<[f32; 8], __m256>);
            // Pairs of rows interleaved within each 128-bit half ...
            let t = [
                a._mm256_unpacklo_ps(r[0], r[1]),
                a._mm256_unpackhi_ps(r[0], r[1]),
                a._mm256_unpacklo_ps(r[2], r[3]),
                a._mm256_unpackhi_ps(r[2], r[3]),
                a._mm256_unpacklo_ps(r[4], r[5]),
                a._mm256_unpackhi_ps(r[4], r[5]),
                a._mm256_unpacklo_ps(r[6], r[7]),
                a._mm256_unpackhi_ps(r[6], r[7]),
            ];
            // ... then four rows per half: columns j and j + 4 of rows 0-3 (or 4-7) ...
            let q = [
                a._mm256_shuffle_ps::<0x44>(t[0], t[2]),
                a._mm256_shuffle_ps::<0xEE>(t[0], t[2]),
                a._mm256_shuffle_ps::<0x44>(t[1], t[3]),
                a._mm256_shuffle_ps::<0xEE>(t[1], t[3]),
                a._mm256_shuffle_ps::<0x44>(t[4], t[6]),
                a._mm256_shuffle_ps::<0xEE>(t[4], t[6]),
                a._mm256_shuffle_ps::<0x44>(t[5], t[7]),
                a._mm256_shuffle_ps::<0xEE>(t[5], t[7]),
            ];
            // ... and the halves recombined.
            let col = |j: usize| {
                let (lo, hi) = (q[j % 4], q[4 + j % 4]);
                if j < 4 {
                    a._mm256_permute2f128_ps::<0x20>(lo, hi)
                } else {
                    a._mm256_permute2f128_ps::<0x31>(lo, hi)
                }
            };
            std::array::from_fn(|j| F32x8 {
                t: self.0,
                v: col(j),
            })
        }
    }

    /// Work for [`Avx2::run`]; `run` should be `#[inline(always)]`, and so should the lane
    /// code it calls.
    pub trait Avx2Task {
        /// What the task returns.
        type Output;
        /// Does the work, with `s` to make [`F32x8`] values.
        fn run(self, s: Avx2) -> Self::Output;
    }

    /// A closure as a task (for tests and cold paths: it may not be inlined).
    impl<R, F: FnOnce(Avx2) -> R> Avx2Task for F {
        type Output = R;
        #[inline(always)]
        fn run(self, s: Avx2) -> R {
            self(s)
        }
    }

    /// `pulp`'s entry point for a task: inlined into its AVX2 function.
    struct Call<T>(T, Avx2);

    impl<T: Avx2Task> pulp::NullaryFnOnce for Call<T> {
        type Output = T::Output;
        #[inline(always)]
        fn call(self) -> T::Output {
            self.0.run(self.1)
        }
    }

    /// Eight f32 lanes in one AVX register, carrying the [`Avx2`] proof that makes its
    /// operations safe.
    #[derive(Debug, Clone, Copy)]
    pub struct F32x8 {
        t: V3,
        v: __m256,
    }

    impl F32x8 {
        /// The eight lanes.
        #[inline(always)]
        #[must_use]
        pub fn to_array(self) -> [f32; 8] {
            pulp::cast(self.v)
        }

        #[inline(always)]
        fn with(self, v: __m256) -> F32x8 {
            F32x8 { t: self.t, v }
        }
    }

    macro_rules! binary {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for F32x8 {
                type Output = F32x8;
                #[inline(always)]
                fn $method(self, rhs: F32x8) -> F32x8 {
                    self.with(self.t.avx.$intrinsic(self.v, rhs.v))
                }
            }
        };
    }
    binary!(Add, add, _mm256_add_ps);
    binary!(Sub, sub, _mm256_sub_ps);
    binary!(Mul, mul, _mm256_mul_ps);
    binary!(Div, div, _mm256_div_ps);
    binary!(BitAnd, bitand, _mm256_and_ps);
    binary!(BitOr, bitor, _mm256_or_ps);
    binary!(BitXor, bitxor, _mm256_xor_ps);

    /// `_mm256_cmp_ps` predicates: ordered and quiet, as the SSE comparisons `wide` uses.
    const EQ_OQ: i32 = 0x00;
    const LE_OQ: i32 = 0x12;
    const GE_OQ: i32 = 0x1D;

    impl Lanes for F32x8 {
        const N: usize = 8;
        #[inline(always)]
        fn splat(self, x: f32) -> F32x8 {
            self.with(self.t.avx._mm256_set1_ps(x))
        }
        #[inline(always)]
        fn with_lanes(self, a: [f32; 8]) -> F32x8 {
            self.with(pulp::cast(a))
        }
        #[inline(always)]
        fn to_lanes(self) -> [f32; 8] {
            self.to_array()
        }
        #[inline(always)]
        fn sqrt(self) -> F32x8 {
            self.with(self.t.avx._mm256_sqrt_ps(self.v))
        }
        #[inline(always)]
        fn abs(self) -> F32x8 {
            self & self.splat(f32::from_bits(0x7fff_ffff))
        }
        #[inline(always)]
        fn max_c(self, c: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_max_ps(self.v, c.v))
        }
        #[inline(always)]
        fn min_c(self, c: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_min_ps(self.v, c.v))
        }
        #[inline(always)]
        fn cmp_ge(self, o: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_cmp_ps::<GE_OQ>(self.v, o.v))
        }
        #[inline(always)]
        fn cmp_le(self, o: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_cmp_ps::<LE_OQ>(self.v, o.v))
        }
        #[inline(always)]
        fn cmp_eq(self, o: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_cmp_ps::<EQ_OQ>(self.v, o.v))
        }
        #[inline(always)]
        fn blend(self, t: F32x8, f: F32x8) -> F32x8 {
            self.with(self.t.avx._mm256_blendv_ps(f.v, t.v, self.v))
        }
        #[inline(always)]
        fn mask_bits(self) -> u32 {
            self.t.avx._mm256_movemask_ps(self.v).cast_unsigned()
        }
        #[inline(always)]
        fn columns(self, rows: &[[f32; 8]; 8]) -> [F32x8; 8] {
            Avx2(self.t).transpose(*rows)
        }
    }
}
