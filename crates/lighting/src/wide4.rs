//! The illumination model four pixels at a time: [`shade_x4`] over [`Vec3x4`] (three
//! [`f32x4`] lanes-of-four, structure of arrays), for the rasterizer's 2x2 quads and spans.
//!
//! Contract: in every lane `i`, `shade_x4::<FX>(set, mat, p, n, eye)` has exactly the bits of
//! `shade::<FX>(set, mat, p[i], n[i], eye)`. The scalar model is mirrored operation by operation
//! in the same order (IEEE add, mul, div and sqrt are correctly rounded in both), its branches
//! become per-lane selects, and its rare paths (an overflowing squared length in
//! `safe_normalize`, a non-integer or large shininess taking `powf`) call the scalar functions
//! for the lanes that need them.
//!
//! Why the selects are bit-exact where the scalar code branches:
//!
//! * `x.max(c)` / `x.min(c)` with a constant `c` map NaN to `c`, as SSE's `maxps(x, c)` /
//!   `minps(x, c)` do (they return the second operand when either is NaN). The one case they
//!   may differ in, `max(-0.0, 0.0)`, cannot change a result: the sums the guards see start at
//!   `+0.0` and `x + y` is `-0.0` only when both are, and a `-0.0` lobe or cone factor only ever
//!   ends up added to such a sum.
//! * A light that the scalar code skips (`N.L <= 0`, or a zero normal's early return) leaves
//!   the lane's sums untouched: its term is masked to `+0.0` before the add, and a sum is
//!   never `-0.0` (it starts at `+0.0`, and `+0.0 + -0.0` is `+0.0`), so adding `+0.0` returns
//!   it bit for bit, NaN and infinity included.
//! * Negation flips the sign bit (wide's `-x` is `0 - x`, which turns `-(+0)` into `+0`).
//!
//! Cost: the lights' constants are splatted once per light per call and the Phong lobe
//! `(V.R)^n` of an integer `n` is the scalar code's repeated squaring on four lanes, so the
//! common path (directional and point lights, Phong or Blinn, integer shininess, any
//! attenuation, Fresnel or spot cone) has no per-lane scalar code at all. On S1 (three point
//! lights with `1/(1+d)`, Phong `n_s = 32`, the rasterizer's `BASE | SPECULAR | ATTENUATION`
//! instantiation, x86-64 baseline SSE2) one `shade_x4` call retires 214 instructions per
//! pixel against 634 for `shade` (callgrind), and takes 77-104 ns against 300-308 ns for four
//! `shade` calls (`cargo bench --bench lighting -- x4/ --quick`, 2-core machine under load:
//! 2.9x to 4.0x). A light's terms are added masked to `+0.0` in the lanes that skip it (one AND
//! per component) rather than selected against the old sums (three SSE2 operations per
//! component without SSE4.1): 877 -> 836 instructions per call in S1's phong frame.

use std::ops::{Add, Mul, Sub};

use glam::Vec3;
use phosphor_math::{
    MAX_SQUARING_EXPONENT, MIN_NORMALIZABLE_LENGTH_SQUARED, clamped_pow, safe_normalize,
};
pub use wide::f32x4;
use wide::{CmpEq, CmpGe, CmpLe};

use crate::attenuation::{MAX_LIGHT_DISTANCE, MIN_ATTENUATION_DENOMINATOR};
use crate::effects::Effects;
use crate::fresnel::Fresnel;
use crate::lightset::{LightSet, PreparedPoint};
use crate::lobe::MIRROR_COS_TOLERANCE;
use crate::material::{Material, SpecularModel};
use crate::shade::{ShadeTerms, UNIT_NORMAL_TOLERANCE, finite_intensity};

/// Four 3-vectors as three lanes of four: `x[i], y[i], z[i]` is vector `i`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Vec3x4 {
    /// The four x components.
    pub x: f32x4,
    /// The four y components.
    pub y: f32x4,
    /// The four z components.
    pub z: f32x4,
}

impl Vec3x4 {
    /// All lanes zero.
    pub const ZERO: Vec3x4 = Vec3x4::splat(Vec3::ZERO);

    /// From the three component lanes.
    #[inline]
    #[must_use]
    pub const fn new(x: f32x4, y: f32x4, z: f32x4) -> Vec3x4 {
        Vec3x4 { x, y, z }
    }

    /// `v` in all four lanes.
    #[inline]
    #[must_use]
    pub const fn splat(v: Vec3) -> Vec3x4 {
        Vec3x4 {
            x: f32x4::new([v.x; 4]),
            y: f32x4::new([v.y; 4]),
            z: f32x4::new([v.z; 4]),
        }
    }

    /// Lane `i` holds `v[i]`.
    #[inline]
    #[must_use]
    pub const fn from_array(v: [Vec3; 4]) -> Vec3x4 {
        Vec3x4 {
            x: f32x4::new([v[0].x, v[1].x, v[2].x, v[3].x]),
            y: f32x4::new([v[0].y, v[1].y, v[2].y, v[3].y]),
            z: f32x4::new([v[0].z, v[1].z, v[2].z, v[3].z]),
        }
    }

    /// The four vectors, lane `i` at index `i`.
    #[inline]
    #[must_use]
    pub fn to_array(self) -> [Vec3; 4] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        [0, 1, 2, 3].map(|i| Vec3::new(x[i], y[i], z[i]))
    }

    /// Lane `i` (`i < 4`) as a `Vec3`.
    ///
    /// # Panics
    /// When `i >= 4`.
    #[inline]
    #[must_use]
    pub fn lane(self, i: usize) -> Vec3 {
        Vec3::new(
            self.x.to_array()[i],
            self.y.to_array()[i],
            self.z.to_array()[i],
        )
    }

    /// Per-lane dot product, `x x' + y y' + z z'` left to right (as glam's `Vec3::dot`).
    #[inline]
    #[must_use]
    pub fn dot(self, rhs: Vec3x4) -> f32x4 {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    /// Per-lane squared length (`self.dot(self)`).
    #[inline]
    #[must_use]
    pub fn length_squared(self) -> f32x4 {
        self.dot(self)
    }

    /// Lane by lane: `t` where `mask` is all ones, `f` where it is all zeros (masks come from
    /// `f32x4` comparisons).
    #[inline]
    #[must_use]
    pub fn select(mask: f32x4, t: Vec3x4, f: Vec3x4) -> Vec3x4 {
        Vec3x4 {
            x: mask.blend(t.x, f.x),
            y: mask.blend(t.y, f.y),
            z: mask.blend(t.z, f.z),
        }
    }
}

impl From<[Vec3; 4]> for Vec3x4 {
    #[inline]
    fn from(v: [Vec3; 4]) -> Vec3x4 {
        Vec3x4::from_array(v)
    }
}

impl From<Vec3x4> for [Vec3; 4] {
    #[inline]
    fn from(v: Vec3x4) -> [Vec3; 4] {
        v.to_array()
    }
}

impl Add for Vec3x4 {
    type Output = Vec3x4;
    #[inline]
    fn add(self, rhs: Vec3x4) -> Vec3x4 {
        Vec3x4::new(self.x + rhs.x, self.y + rhs.y, self.z + rhs.z)
    }
}

impl Sub for Vec3x4 {
    type Output = Vec3x4;
    #[inline]
    fn sub(self, rhs: Vec3x4) -> Vec3x4 {
        Vec3x4::new(self.x - rhs.x, self.y - rhs.y, self.z - rhs.z)
    }
}

/// Component-wise product (glam's `Vec3 * Vec3`).
impl Mul for Vec3x4 {
    type Output = Vec3x4;
    #[inline]
    fn mul(self, rhs: Vec3x4) -> Vec3x4 {
        Vec3x4::new(self.x * rhs.x, self.y * rhs.y, self.z * rhs.z)
    }
}

/// Each component times the lane's scalar (glam's `Vec3 * f32`).
impl Mul<f32x4> for Vec3x4 {
    type Output = Vec3x4;
    #[inline]
    fn mul(self, rhs: f32x4) -> Vec3x4 {
        Vec3x4::new(self.x * rhs, self.y * rhs, self.z * rhs)
    }
}

/// The lane's scalar times each component (glam's `f32 * Vec3`).
impl Mul<Vec3x4> for f32x4 {
    type Output = Vec3x4;
    #[inline]
    fn mul(self, rhs: Vec3x4) -> Vec3x4 {
        Vec3x4::new(self * rhs.x, self * rhs.y, self * rhs.z)
    }
}

const ZERO: f32x4 = f32x4::ZERO;
const ONE: f32x4 = f32x4::ONE;

/// Scalar `x.max(c)` for a non-NaN `c` on each lane: NaN lanes give `c` (see the module docs
/// for the `-0.0` tie). SSE's `maxps(x, c)` is exactly that; elsewhere compare and select.
#[inline(always)]
fn max_c(x: f32x4, c: f32x4) -> f32x4 {
    #[cfg(target_feature = "sse")]
    {
        x.fast_max(c)
    }
    #[cfg(not(target_feature = "sse"))]
    {
        use wide::CmpGt;
        x.cmp_gt(c).blend(x, c)
    }
}

/// Scalar `x.min(c)` for a non-NaN `c` on each lane: NaN lanes give `c`.
#[inline(always)]
fn min_c(x: f32x4, c: f32x4) -> f32x4 {
    #[cfg(target_feature = "sse")]
    {
        x.fast_min(c)
    }
    #[cfg(not(target_feature = "sse"))]
    {
        use wide::CmpLt;
        x.cmp_lt(c).blend(x, c)
    }
}

/// Every bit set: a lane mask of all lanes.
const ALL_ONES: f32x4 = f32x4::new([f32::from_bits(u32::MAX); 4]);

/// `v` in the lanes set in `mask`, `+0.0` in the others: one AND per component. Adding it to
/// a sum is exactly [`Vec3x4::select`] of the sum and the new sum, because the sums here start
/// at `+0.0` and so are never `-0.0`, and `x + (+0.0)` is `x` for every other `x` (NaN
/// payloads and infinities included), where a select costs three SSE2 operations per
/// component.
#[inline(always)]
fn masked(mask: f32x4, v: Vec3x4) -> Vec3x4 {
    Vec3x4::new(v.x & mask, v.y & mask, v.z & mask)
}

/// `-x` by flipping the sign bit (`-(+0) = -0`, unlike `0 - x`).
#[inline(always)]
fn neg(x: f32x4) -> f32x4 {
    x ^ f32x4::splat(-0.0)
}

/// [`finite_intensity`] per lane.
#[inline(always)]
fn finite_x4(v: Vec3x4) -> Vec3x4 {
    let (lo, hi) = (ZERO, f32x4::splat(f32::MAX));
    Vec3x4::new(
        min_c(max_c(v.x, lo), hi),
        min_c(max_c(v.y, lo), hi),
        min_c(max_c(v.z, lo), hi),
    )
}

/// `safe_normalize(v[i], fallback[i])` per lane, with `sqrt(|v|^2)` per lane (the `d` of
/// `towards`, whichever branch it takes).
#[inline(always)]
fn safe_normalize_x4(v: Vec3x4, fallback: Vec3x4) -> (Vec3x4, f32x4) {
    let len_sq = v.length_squared();
    let len = len_sq.sqrt();
    let unit = v * (ONE / len);
    // A finite squared length means finite components; NaN fails both comparisons.
    let plain = len_sq.cmp_ge(f32x4::splat(MIN_NORMALIZABLE_LENGTH_SQUARED))
        & len_sq.cmp_le(f32x4::splat(f32::MAX));
    if plain.all() {
        return (unit, len);
    }
    let out = Vec3x4::select(plain, unit, fallback);
    // An infinite squared length is either an infinite component (fallback) or an overflow
    // that safe_normalize rescales: both rare, both left to the scalar function.
    let overflow = len_sq.cmp_eq(f32x4::splat(f32::INFINITY));
    if overflow.any() {
        return (scalar_lanes(overflow, v, fallback, out), len);
    }
    (out, len)
}

/// `out` with the lanes set in `mask` replaced by the scalar `safe_normalize`.
#[cold]
#[inline(never)]
fn scalar_lanes(mask: f32x4, v: Vec3x4, fallback: Vec3x4, out: Vec3x4) -> Vec3x4 {
    let bits = mask.move_mask();
    let (v, fallback, mut out) = (v.to_array(), fallback.to_array(), out.to_array());
    for i in 0..4 {
        if bits & (1 << i) != 0 {
            out[i] = safe_normalize(v[i], fallback[i]);
        }
    }
    Vec3x4::from_array(out)
}

/// `unit_normal` of the scalar model per lane: `n` where `| |n|^2 - 1 | <= tolerance`, else
/// `safe_normalize(n, 0)`.
#[inline(always)]
fn unit_normal_x4(n: Vec3x4) -> Vec3x4 {
    let given = (n.length_squared() - ONE)
        .abs()
        .cmp_le(f32x4::splat(UNIT_NORMAL_TOLERANCE));
    if given.all() {
        return n;
    }
    Vec3x4::select(given, n, safe_normalize_x4(n, Vec3x4::ZERO).0)
}

/// How `specular_lobe(base, shininess)` evaluates, decided once per call.
#[derive(Clone, Copy)]
enum Power {
    /// Integer exponent up to `MAX_SQUARING_EXPONENT`: repeated squaring.
    Squaring(u32),
    /// Any other finite exponent: the scalar `clamped_pow` (powf) per lane.
    Powf(f32),
    /// `+inf`, the perfect mirror: 1 where the base is within `MIRROR_COS_TOLERANCE` of 1.
    Mirror,
}

impl Power {
    #[inline(always)]
    fn of(shininess: f32) -> Power {
        if shininess == f32::INFINITY {
            return Power::Mirror;
        }
        let e = shininess.max(0.0);
        if e > MAX_SQUARING_EXPONENT {
            return Power::Powf(shininess);
        }
        // `e` is in [0, 256] (NaN became 0): it is an integer (`fract() == 0`) exactly when it
        // survives the round trip through u32, without the libm call `fract` makes.
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            reason = "e is in [0, 256]"
        )]
        let n = e as u32;
        #[allow(clippy::cast_precision_loss, reason = "n <= 256")]
        if n as f32 != e {
            return Power::Powf(shininess);
        }
        Power::Squaring(n)
    }

    /// `specular_lobe(base[i], shininess)` per lane.
    #[inline(always)]
    fn pow(self, base: f32x4) -> f32x4 {
        match self {
            Power::Squaring(0) => ONE,
            Power::Squaring(n) => {
                // The scalar loop squares `b` while bits remain and multiplies the accumulator
                // (from 1.0) by `b` at each set bit. Its first product is 1.0 * b, exactly b:
                // square up to the lowest set bit, take b, then run the same loop on the rest.
                let mut b = min_c(max_c(base, ZERO), ONE);
                for _ in 0..n.trailing_zeros() {
                    b *= b;
                }
                let mut acc = b;
                let mut rest = n >> n.trailing_zeros() >> 1;
                while rest > 0 {
                    b *= b;
                    if rest & 1 == 1 {
                        acc *= b;
                    }
                    rest >>= 1;
                }
                acc
            }
            Power::Powf(e) => powf_lanes(base, e),
            // `mirror_lobe`'s `>=` per lane: false for NaN, as in the scalar code.
            Power::Mirror => base
                .cmp_ge(f32x4::splat(1.0 - MIRROR_COS_TOLERANCE))
                .blend(ONE, ZERO),
        }
    }
}

/// `clamped_pow(base[i], e)` per lane (the non-integer shininess path).
#[inline(never)]
fn powf_lanes(base: f32x4, e: f32) -> f32x4 {
    f32x4::new(base.to_array().map(|b| clamped_pow(b, e)))
}

/// `W(theta)` of the material, prepared once per call.
#[derive(Clone, Copy)]
enum FresnelX4 {
    /// `W = 1` (no multiplication: `1.0 * lobe` is `lobe`).
    One,
    /// `W = w`.
    Constant(f32x4),
    /// Schlick with `f0` and `1 - f0`.
    Schlick(f32x4, f32x4),
}

impl FresnelX4 {
    #[inline(always)]
    fn of<const FX: u32>(mat: &Material) -> FresnelX4 {
        if !has(FX, Effects::FRESNEL) {
            return FresnelX4::One;
        }
        match mat.fresnel {
            // `Fresnel::w` returns 1.0 here and the scalar code multiplies by it: exact.
            Fresnel::None => FresnelX4::One,
            Fresnel::Constant { w } => FresnelX4::Constant(f32x4::splat(w)),
            Fresnel::Schlick { f0 } => FresnelX4::Schlick(f32x4::splat(f0), f32x4::splat(1.0 - f0)),
        }
    }

    /// `W(n_dot_l) * lobe` per lane.
    #[inline(always)]
    fn times(self, n_dot_l: f32x4, lobe: f32x4) -> f32x4 {
        match self {
            FresnelX4::One => lobe,
            FresnelX4::Constant(w) => w * lobe,
            FresnelX4::Schlick(f0, one_minus_f0) => {
                let m = ONE - min_c(max_c(n_dot_l, ZERO), ONE);
                let m2 = m * m;
                (f0 + one_minus_f0 * (m2 * m2 * m)) * lobe
            }
        }
    }
}

#[inline(always)]
const fn has(fx: u32, effect: Effects) -> bool {
    fx & effect.bits() != 0
}

/// The per-call constants of the light loop and the running sums.
struct Sums {
    n: Vec3x4,
    v: Vec3x4,
    /// Lanes whose normal is zero: the scalar model returned before the lights.
    dark: f32x4,
    kd: Vec3x4,
    ks: Vec3x4,
    specular_model: SpecularModel,
    power: Power,
    fresnel: FresnelX4,
    diffuse: Vec3x4,
    specular: Vec3x4,
}

impl Sums {
    /// One light's `kd Il (N.L) + ks W Il_spec lobe^n` per lane, `il` already attenuated;
    /// lanes with `N.L <= 0` (or a zero normal) keep their sums.
    #[inline(always)]
    fn add<const FX: u32>(&mut self, l: Vec3x4, il: Vec3x4, il_s: Vec3x4) {
        let n_dot_l = self.n.dot(l);
        // `<=` is false for NaN, which the scalar code does not skip either.
        let skip = n_dot_l.cmp_le(ZERO) | self.dark;
        if skip.all() {
            return;
        }
        let keep = skip ^ ALL_ONES;
        if has(FX, Effects::DIFFUSE) {
            let term = Vec3x4::new(
                (self.kd.x * n_dot_l) * il.x,
                (self.kd.y * n_dot_l) * il.y,
                (self.kd.z * n_dot_l) * il.z,
            );
            self.diffuse = self.diffuse + masked(keep, term);
        }
        if has(FX, Effects::SPECULAR) {
            let base = match self.specular_model {
                SpecularModel::Phong => {
                    // reflect(n, l) = 2 (N.L) N - L, then R.V.
                    let r = ((f32x4::splat(2.0) * n_dot_l) * self.n) - l;
                    r.dot(self.v)
                }
                SpecularModel::Blinn => self.n.dot(safe_normalize_x4(l + self.v, self.n).0),
            };
            let lobe = self.power.pow(base);
            let w_lobe = self.fresnel.times(n_dot_l, lobe);
            let term = Vec3x4::new(
                (self.ks.x * w_lobe) * il_s.x,
                (self.ks.y * w_lobe) * il_s.y,
                (self.ks.z * w_lobe) * il_s.z,
            );
            self.specular = self.specular + masked(keep, term);
        }
    }

    /// A positional light: direction and attenuated intensities as `towards` gives them,
    /// times `cone` (the spot factor) when given.
    #[inline(always)]
    fn add_point<const FX: u32>(&mut self, light: &PreparedPoint, p: Vec3x4, cone: Cone) {
        let delta = Vec3x4::splat(light.position) - p;
        let (l, d) = safe_normalize_x4(delta, self.n);
        let mut f = has(FX, Effects::ATTENUATION).then(|| attenuation_x4(light.attenuation, d));
        if let Cone::Spot {
            axis,
            cos_outer,
            inv_cos_width,
        } = cone
        {
            // cos_angle = -(L.axis); smoothstep as in `spot_cone`.
            let cos_angle = neg(l.dot(Vec3x4::splat(axis)));
            let t = (cos_angle - f32x4::splat(cos_outer)) * f32x4::splat(inv_cos_width);
            let t = min_c(max_c(t, ZERO), ONE);
            let cone = t * t * (f32x4::splat(3.0) - f32x4::splat(2.0) * t);
            // Without attenuation the scalar factor is 1.0, and 1.0 * cone is cone.
            f = Some(f.map_or(cone, |f| f * cone));
        }
        let (il, il_s) = (Vec3x4::splat(light.il), Vec3x4::splat(light.il_specular));
        match f {
            Some(f) => self.add::<FX>(l, il * f, il_s * f),
            // `il * 1.0` is `il`.
            None => self.add::<FX>(l, il, il_s),
        }
    }
}

/// The spot factor of a positional light, or none.
#[derive(Clone, Copy)]
enum Cone {
    None,
    Spot {
        axis: Vec3,
        cos_outer: f32,
        inv_cos_width: f32,
    },
}

/// `factor_from_coefficients([c, l, q], d[i])` per lane.
#[inline(always)]
fn attenuation_x4([c, l, q]: [f32; 3], d: f32x4) -> f32x4 {
    let d = max_c(min_c(d, f32x4::splat(MAX_LIGHT_DISTANCE)), ZERO);
    let denominator = f32x4::splat(c) + f32x4::splat(l) * d + f32x4::splat(q) * (d * d);
    ONE / max_c(denominator, f32x4::splat(MIN_ATTENUATION_DENOMINATOR))
}

/// [`shade`](crate::shade()) at four surface points at once: lane `i` of the result has exactly
/// the bits of `shade::<FX>(set, mat, p[i], n[i], eye)` (see the module docs for how).
///
/// ```
/// use glam::Vec3;
/// use phosphor_lighting::{Effects, LightSet, Material, Vec3x4, shade, shade_x4};
///
/// const FX: u32 = Effects::AMBIENT.bits() | Effects::DIFFUSE.bits() | Effects::SPECULAR.bits()
///     | Effects::ATTENUATION.bits();
/// let (set, mat, eye) = (LightSet::s1(), Material::s1(), Vec3::new(0.0, 0.0, 3.0));
/// let n = [Vec3::Z, Vec3::new(0.6, 0.0, 0.8), Vec3::ZERO, Vec3::new(0.0, 3.0, 4.0)];
/// let p = n.map(|n| n * 0.5);
/// let lit = shade_x4::<FX>(&set, &mat, Vec3x4::from(p), Vec3x4::from(n), eye).to_array();
/// for i in 0..4 {
///     let one = shade::<FX>(&set, &mat, p[i], n[i], eye);
///     assert_eq!(lit[i].to_array().map(f32::to_bits), one.to_array().map(f32::to_bits));
/// }
/// ```
#[inline]
#[must_use]
pub fn shade_x4<const FX: u32>(
    set: &LightSet,
    mat: &Material,
    p: Vec3x4,
    n: Vec3x4,
    eye: Vec3,
) -> Vec3x4 {
    // The ambient terms do not depend on the lane: the scalar code's, splatted.
    let mut ambient = Vec3::ZERO;
    if has(FX, Effects::EMISSION) {
        ambient += mat.emission;
    }
    if has(FX, Effects::AMBIENT) {
        ambient += mat.ka * set.ambient();
    }
    let ambient = finite_intensity(ambient);
    let unlit = ShadeTerms {
        ambient,
        ..ShadeTerms::default()
    }
    .total();
    if !has(FX, Effects::DIFFUSE) && !has(FX, Effects::SPECULAR) {
        return Vec3x4::splat(unlit);
    }
    let n = unit_normal_x4(n);
    let dark = n.x.cmp_eq(ZERO) & n.y.cmp_eq(ZERO) & n.z.cmp_eq(ZERO);
    if dark.all() {
        return Vec3x4::splat(unlit);
    }
    let (v, _) = safe_normalize_x4(Vec3x4::splat(eye) - p, n);
    let mut acc = Sums {
        n,
        v,
        dark,
        kd: Vec3x4::splat(mat.kd),
        ks: Vec3x4::splat(mat.ks),
        specular_model: mat.specular,
        power: Power::of(mat.shininess),
        fresnel: FresnelX4::of::<FX>(mat),
        diffuse: Vec3x4::ZERO,
        specular: Vec3x4::ZERO,
    };
    for light in set.directional() {
        acc.add::<FX>(
            Vec3x4::splat(light.to_light),
            Vec3x4::splat(light.il),
            Vec3x4::splat(light.il_specular),
        );
    }
    for light in set.points() {
        acc.add_point::<FX>(light, p, Cone::None);
    }
    if has(FX, Effects::SPOT) {
        for spot in set.spots() {
            let cone = Cone::Spot {
                axis: spot.axis,
                cos_outer: spot.cos_outer,
                inv_cos_width: spot.inv_cos_width,
            };
            acc.add_point::<FX>(&spot.point, p, cone);
        }
    }
    if has(FX, Effects::DISTRIBUTED) {
        for light in set.distributed_samples() {
            acc.add_point::<FX>(light, p, Cone::None);
        }
    }
    let ambient = Vec3x4::splat(ambient);
    finite_x4(ambient + finite_x4(acc.diffuse) + finite_x4(acc.specular))
}

#[cfg(test)]
mod tests {
    use crate::lobe::specular_lobe;

    use super::*;

    #[test]
    fn power_matches_specular_lobe_for_every_squaring_exponent_and_the_powf_and_mirror_paths() {
        let bases = [
            0.0,
            -0.0,
            1e-30,
            f32::MIN_POSITIVE / 8.0,
            0.1,
            0.5,
            0.6,
            0.999_999,
            0.999_99,
            1.0 - MIRROR_COS_TOLERANCE,
            1.0,
            1.000_000_1,
            1.5,
            -0.25,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        let mut exponents: Vec<f32> = (0..=300).map(|n| n as f32).collect();
        exponents.extend([
            0.5,
            2.5,
            255.5,
            1e6,
            f32::MAX,
            f32::INFINITY,
            -3.0,
            f32::NAN,
        ]);
        for e in exponents {
            let power = Power::of(e);
            for quad in bases.chunks(4) {
                let mut lanes = [0.3; 4];
                lanes[..quad.len()].copy_from_slice(quad);
                let got = power.pow(f32x4::new(lanes)).to_array();
                for (b, g) in lanes.iter().zip(got) {
                    assert_eq!(g.to_bits(), specular_lobe(*b, e).to_bits(), "{b}^{e}");
                }
            }
        }
    }

    #[test]
    fn min_max_and_neg_follow_the_scalar_semantics() {
        let x = f32x4::new([f32::NAN, -1.0, 2.0, f32::INFINITY]);
        let one = f32x4::splat(1.0);
        assert_eq!(max_c(x, one).to_array(), [1.0, 1.0, 2.0, f32::INFINITY]);
        assert_eq!(min_c(x, one).to_array(), [1.0, -1.0, 1.0, 1.0]);
        let z = neg(f32x4::new([0.0, -0.0, 1.0, -2.0])).to_array();
        assert_eq!(
            z.map(f32::to_bits),
            [-0.0f32, 0.0, -1.0, 2.0].map(f32::to_bits)
        );
    }
}
