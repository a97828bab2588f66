//! The illumination model several pixels at a time, written once over [`Lanes`]:
//! [`shade_lanes`] over [`Vec3s`] (three lane vectors, structure of arrays), with
//! [`shade_x4`] on [`f32x4`] for the rasterizer's quads and spans and, on x86-64 CPUs with
//! AVX2, eight lanes of [`F32x8`](crate::F32x8) inside [`Avx2::run`](crate::Avx2::run).
//!
//! Contract: in every lane `i`, `shade_lanes::<FX, L>(set, mat, p, n, eye)` has exactly the
//! bits of `shade::<FX>(set, mat, p[i], n[i], eye)`, at every width. The scalar model is
//! mirrored operation by operation in the same order (IEEE add, mul, div and sqrt are
//! correctly rounded in both, and no lane type fuses a multiply-add), its branches become
//! per-lane selects, and its rare paths (an overflowing squared length in `safe_normalize`, a
//! non-integer or large shininess taking `powf`) call the scalar functions for the lanes that
//! need them.
//!
//! Why the selects are bit-exact where the scalar code branches:
//!
//! * `x.max(c)` / `x.min(c)` with a constant `c` map NaN to `c`, as SSE's and AVX's
//!   `maxps(x, c)` / `minps(x, c)` do (they return the second operand when either is NaN). The one case they
//!   may differ in, `max(-0.0, 0.0)`, cannot change a result: the sums the guards see start at
//!   `+0.0` and `x + y` is `-0.0` only when both are, and a `-0.0` lobe or cone factor only ever
//!   ends up added to such a sum.
//! * A light that the scalar code skips (`N.L <= 0`, or a zero normal's early return) leaves
//!   the lane's sums untouched: its term is masked to `+0.0` before the add, and a sum is
//!   never `-0.0` (it starts at `+0.0`, and `+0.0 + -0.0` is `+0.0`), so adding `+0.0` returns
//!   it bit for bit, NaN and infinity included.
//! * Negation flips the sign bit (`0 - x` would turn `-(+0)` into `+0`).
//!
//! Cost: the lights' constants are splatted once per light per call and the Phong lobe
//! `(V.R)^n` of an integer `n` is the scalar code's repeated squaring across the lanes, so the
//! common path (directional and point lights, Phong or Blinn, integer shininess, any
//! attenuation, Fresnel or spot cone) has no per-lane scalar code at all. A light's terms are
//! added masked to `+0.0` in the lanes that skip it (one AND per component) rather than
//! selected against the old sums. Measured costs per width are in `docs/speed.md`.

use std::ops::{Add, Mul, Sub};

use glam::Vec3;
use phosphor_math::{
    MAX_SQUARING_EXPONENT, MIN_NORMALIZABLE_LENGTH_SQUARED, clamped_pow, safe_normalize,
};

use crate::attenuation::{MAX_LIGHT_DISTANCE, MIN_ATTENUATION_DENOMINATOR};
use crate::effects::Effects;
use crate::fresnel::Fresnel;
use crate::lanes::{Lanes, f32x4};
use crate::lightset::{LightSet, PreparedPoint};
use crate::lobe::MIRROR_COS_TOLERANCE;
use crate::material::{Material, SpecularModel};
use crate::shade::{UNIT_NORMAL_TOLERANCE, finite_intensity};

/// `L::N` 3-vectors as three lane vectors: `x[i], y[i], z[i]` is vector `i`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Vec3s<L> {
    /// The x components.
    pub x: L,
    /// The y components.
    pub y: L,
    /// The z components.
    pub z: L,
}

/// Four 3-vectors in [`f32x4`] lanes.
pub type Vec3x4 = Vec3s<f32x4>;

/// Eight 3-vectors in AVX2 lanes.
#[cfg(target_arch = "x86_64")]
pub type Vec3x8 = Vec3s<crate::F32x8>;

impl<L: Lanes> Vec3s<L> {
    /// From the three component lanes.
    #[inline(always)]
    #[must_use]
    pub const fn new(x: L, y: L, z: L) -> Vec3s<L> {
        Vec3s { x, y, z }
    }

    /// `v` in every lane, lanes of the kind of `like`.
    #[inline(always)]
    #[must_use]
    pub fn broadcast(like: L, v: Vec3) -> Vec3s<L> {
        Vec3s::new(like.splat(v.x), like.splat(v.y), like.splat(v.z))
    }

    /// Lane `i` of each component as a `Vec3`, `L::N` of them then zeros.
    #[inline(always)]
    #[must_use]
    pub fn to_vecs(self) -> [Vec3; 8] {
        let (x, y, z) = (self.x.to_lanes(), self.y.to_lanes(), self.z.to_lanes());
        std::array::from_fn(|i| Vec3::new(x[i], y[i], z[i]))
    }

    /// Lane `i` holds `v[i]` (`i < L::N`), lanes of the kind of `like`.
    #[inline(always)]
    #[must_use]
    pub fn from_vecs(like: L, v: [Vec3; 8]) -> Vec3s<L> {
        Vec3s::new(
            like.with_lanes(v.map(|v| v.x)),
            like.with_lanes(v.map(|v| v.y)),
            like.with_lanes(v.map(|v| v.z)),
        )
    }

    /// Per-lane dot product, `x x' + y y' + z z'` left to right (as glam's `Vec3::dot`).
    #[inline(always)]
    #[must_use]
    pub fn dot(self, rhs: Vec3s<L>) -> L {
        self.x * rhs.x + self.y * rhs.y + self.z * rhs.z
    }

    /// Per-lane cross product, in the order of glam's `Vec3::cross` (the same bits).
    #[inline(always)]
    #[must_use]
    pub fn cross(self, rhs: Vec3s<L>) -> Vec3s<L> {
        Vec3s::new(
            self.y * rhs.z - rhs.y * self.z,
            self.z * rhs.x - rhs.z * self.x,
            self.x * rhs.y - rhs.x * self.y,
        )
    }

    /// `phosphor_math::safe_normalize(self[i], fallback[i])` per lane, bit for bit: the unit
    /// vector, or `fallback` for a zero, tiny or non-finite one.
    #[inline(always)]
    #[must_use]
    pub fn safe_normalize(self, fallback: Vec3s<L>) -> Vec3s<L> {
        safe_normalize_lanes(self, fallback).0
    }

    /// Per-lane squared length (`self.dot(self)`).
    #[inline(always)]
    #[must_use]
    pub fn length_squared(self) -> L {
        self.dot(self)
    }

    /// Lane by lane: `t` where `mask` is all ones, `f` where it is all zeros (masks come from
    /// lane comparisons).
    #[inline(always)]
    #[must_use]
    pub fn select(mask: L, t: Vec3s<L>, f: Vec3s<L>) -> Vec3s<L> {
        Vec3s::new(
            mask.blend(t.x, f.x),
            mask.blend(t.y, f.y),
            mask.blend(t.z, f.z),
        )
    }
}

impl Vec3x4 {
    /// All lanes zero.
    pub const ZERO: Vec3x4 = Vec3x4::splat(Vec3::ZERO);

    /// `v` in all four lanes.
    #[inline]
    #[must_use]
    pub const fn splat(v: Vec3) -> Vec3x4 {
        Vec3s {
            x: f32x4::new([v.x; 4]),
            y: f32x4::new([v.y; 4]),
            z: f32x4::new([v.z; 4]),
        }
    }

    /// Lane `i` holds `v[i]`.
    #[inline]
    #[must_use]
    pub const fn from_array(v: [Vec3; 4]) -> Vec3x4 {
        Vec3s {
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

impl<L: Lanes> Add for Vec3s<L> {
    type Output = Vec3s<L>;
    #[inline(always)]
    fn add(self, rhs: Vec3s<L>) -> Vec3s<L> {
        Vec3s::new(self.x + rhs.x, self.y + rhs.y, self.z + rhs.z)
    }
}

impl<L: Lanes> Sub for Vec3s<L> {
    type Output = Vec3s<L>;
    #[inline(always)]
    fn sub(self, rhs: Vec3s<L>) -> Vec3s<L> {
        Vec3s::new(self.x - rhs.x, self.y - rhs.y, self.z - rhs.z)
    }
}

/// Component-wise product (glam's `Vec3 * Vec3`).
impl<L: Lanes> Mul for Vec3s<L> {
    type Output = Vec3s<L>;
    #[inline(always)]
    fn mul(self, rhs: Vec3s<L>) -> Vec3s<L> {
        Vec3s::new(self.x * rhs.x, self.y * rhs.y, self.z * rhs.z)
    }
}

/// Each component times the lane's scalar (glam's `Vec3 * f32`; IEEE products commute, so
/// this is also `f32 * Vec3`).
impl<L: Lanes> Mul<L> for Vec3s<L> {
    type Output = Vec3s<L>;
    #[inline(always)]
    fn mul(self, rhs: L) -> Vec3s<L> {
        Vec3s::new(self.x * rhs, self.y * rhs, self.z * rhs)
    }
}

/// The lane's scalar times each component (glam's `f32 * Vec3`).
impl Mul<Vec3x4> for f32x4 {
    type Output = Vec3x4;
    #[inline]
    fn mul(self, rhs: Vec3x4) -> Vec3x4 {
        Vec3s::new(self * rhs.x, self * rhs.y, self * rhs.z)
    }
}

/// `v` in the lanes set in `mask`, `+0.0` in the others: one AND per component. Adding it to
/// a sum is exactly [`Vec3s::select`] of the sum and the new sum, because the sums here start
/// at `+0.0` and so are never `-0.0`, and `x + (+0.0)` is `x` for every other `x` (NaN
/// payloads and infinities included), where a select costs three SSE2 operations per
/// component.
#[inline(always)]
fn masked<L: Lanes>(mask: L, v: Vec3s<L>) -> Vec3s<L> {
    Vec3s::new(v.x & mask, v.y & mask, v.z & mask)
}

/// `-x` by flipping the sign bit (`-(+0) = -0`, unlike `0 - x`).
#[inline(always)]
fn neg<L: Lanes>(x: L) -> L {
    x ^ x.splat(-0.0)
}

/// [`finite_intensity`] per lane.
#[inline(always)]
fn finite_lanes<L: Lanes>(v: Vec3s<L>) -> Vec3s<L> {
    let (lo, hi) = (v.x.splat(0.0), v.x.splat(f32::MAX));
    Vec3s::new(
        v.x.max_c(lo).min_c(hi),
        v.y.max_c(lo).min_c(hi),
        v.z.max_c(lo).min_c(hi),
    )
}

/// `safe_normalize(v[i], fallback[i])` per lane, with `sqrt(|v|^2)` per lane (the `d` of
/// `towards`, whichever branch it takes).
#[inline(always)]
fn safe_normalize_lanes<L: Lanes>(v: Vec3s<L>, fallback: Vec3s<L>) -> (Vec3s<L>, L) {
    let len_sq = v.length_squared();
    let len = len_sq.sqrt();
    let unit = v * (len.splat(1.0) / len);
    // A finite squared length means finite components; NaN fails both comparisons.
    let plain = len_sq.cmp_ge(len.splat(MIN_NORMALIZABLE_LENGTH_SQUARED))
        & len_sq.cmp_le(len.splat(f32::MAX));
    if plain.all() {
        return (unit, len);
    }
    let out = Vec3s::select(plain, unit, fallback);
    // An infinite squared length is either an infinite component (fallback) or an overflow
    // that safe_normalize rescales: both rare, both left to the scalar function.
    let overflow = len_sq.cmp_eq(len.splat(f32::INFINITY));
    if overflow.any() {
        let fixed = scalar_lanes(
            overflow.mask_bits(),
            v.to_vecs(),
            fallback.to_vecs(),
            out.to_vecs(),
        );
        return (Vec3s::from_vecs(len, fixed), len);
    }
    (out, len)
}

/// `out` with the lanes set in `bits` replaced by the scalar `safe_normalize`.
#[cold]
#[inline(never)]
fn scalar_lanes(bits: u32, v: [Vec3; 8], fallback: [Vec3; 8], mut out: [Vec3; 8]) -> [Vec3; 8] {
    for i in 0..8 {
        if bits & (1 << i) != 0 {
            out[i] = safe_normalize(v[i], fallback[i]);
        }
    }
    out
}

/// `unit_normal` of the scalar model per lane: `n` where `| |n|^2 - 1 | <= tolerance`, else
/// `safe_normalize(n, 0)`.
#[inline(always)]
fn unit_normal_lanes<L: Lanes>(n: Vec3s<L>) -> Vec3s<L> {
    let w = n.x;
    let given = (n.length_squared() - w.splat(1.0))
        .abs()
        .cmp_le(w.splat(UNIT_NORMAL_TOLERANCE));
    if given.all() {
        return n;
    }
    let zero = Vec3s::broadcast(w, Vec3::ZERO);
    Vec3s::select(given, n, safe_normalize_lanes(n, zero).0)
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
    fn pow<L: Lanes>(self, base: L) -> L {
        match self {
            Power::Squaring(0) => base.splat(1.0),
            Power::Squaring(n) => {
                // The scalar loop squares `b` while bits remain and multiplies the accumulator
                // (from 1.0) by `b` at each set bit. Its first product is 1.0 * b, exactly b:
                // square up to the lowest set bit, take b, then run the same loop on the rest.
                let mut b = base.max_c(base.splat(0.0)).min_c(base.splat(1.0));
                for _ in 0..n.trailing_zeros() {
                    b = b * b;
                }
                let mut acc = b;
                let mut rest = n >> n.trailing_zeros() >> 1;
                while rest > 0 {
                    b = b * b;
                    if rest & 1 == 1 {
                        acc = acc * b;
                    }
                    rest >>= 1;
                }
                acc
            }
            Power::Powf(e) => powf_lanes(base, e),
            // `mirror_lobe`'s `>=` per lane: false for NaN, as in the scalar code.
            Power::Mirror => base
                .cmp_ge(base.splat(1.0 - MIRROR_COS_TOLERANCE))
                .blend(base.splat(1.0), base.splat(0.0)),
        }
    }
}

/// `clamped_pow(base[i], e)` per lane (the non-integer shininess path).
#[inline(never)]
fn powf_lanes<L: Lanes>(base: L, e: f32) -> L {
    base.with_lanes(base.to_lanes().map(|b| clamped_pow(b, e)))
}

/// `W(theta)` of the material, prepared once per call.
#[derive(Clone, Copy)]
enum FresnelLanes<L> {
    /// `W = 1` (no multiplication: `1.0 * lobe` is `lobe`).
    One,
    /// `W = w`.
    Constant(L),
    /// Schlick with `f0` and `1 - f0`.
    Schlick(L, L),
}

impl<L: Lanes> FresnelLanes<L> {
    #[inline(always)]
    fn of<const FX: u32>(like: L, mat: &Material) -> FresnelLanes<L> {
        if !has(FX, Effects::FRESNEL) {
            return FresnelLanes::One;
        }
        match mat.fresnel {
            // `Fresnel::w` returns 1.0 here and the scalar code multiplies by it: exact.
            Fresnel::None => FresnelLanes::One,
            Fresnel::Constant { w } => FresnelLanes::Constant(like.splat(w)),
            Fresnel::Schlick { f0 } => FresnelLanes::Schlick(like.splat(f0), like.splat(1.0 - f0)),
        }
    }

    /// `W(n_dot_l) * lobe` per lane.
    #[inline(always)]
    fn times(self, n_dot_l: L, lobe: L) -> L {
        match self {
            FresnelLanes::One => lobe,
            FresnelLanes::Constant(w) => w * lobe,
            FresnelLanes::Schlick(f0, one_minus_f0) => {
                let one = lobe.splat(1.0);
                let m = one - n_dot_l.max_c(lobe.splat(0.0)).min_c(one);
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
struct Sums<L> {
    n: Vec3s<L>,
    v: Vec3s<L>,
    /// Lanes whose normal is zero: the scalar model returned before the lights.
    dark: L,
    kd: Vec3s<L>,
    ks: Vec3s<L>,
    specular_model: SpecularModel,
    power: Power,
    fresnel: FresnelLanes<L>,
    diffuse: Vec3s<L>,
    specular: Vec3s<L>,
}

impl<L: Lanes> Sums<L> {
    /// One light's `kd Il (N.L) + ks W Il_spec lobe^n` per lane, `il` already attenuated;
    /// lanes with `N.L <= 0` (or a zero normal) keep their sums.
    #[inline(always)]
    fn add<const FX: u32>(&mut self, l: Vec3s<L>, il: Vec3s<L>, il_s: Vec3s<L>) {
        let n_dot_l = self.n.dot(l);
        // `<=` is false for NaN, which the scalar code does not skip either.
        let skip = n_dot_l.cmp_le(n_dot_l.splat(0.0)) | self.dark;
        if skip.all() {
            return;
        }
        let keep = skip ^ skip.splat(f32::from_bits(u32::MAX));
        if has(FX, Effects::DIFFUSE) {
            let term = Vec3s::new(
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
                    let r = (self.n * (n_dot_l.splat(2.0) * n_dot_l)) - l;
                    r.dot(self.v)
                }
                SpecularModel::Blinn => self.n.dot(safe_normalize_lanes(l + self.v, self.n).0),
            };
            let lobe = self.power.pow(base);
            let w_lobe = self.fresnel.times(n_dot_l, lobe);
            let term = Vec3s::new(
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
    fn add_point<const FX: u32>(&mut self, light: &PreparedPoint, p: Vec3s<L>, cone: Cone) {
        let delta = Vec3s::broadcast(p.x, light.position) - p;
        let (l, d) = safe_normalize_lanes(delta, self.n);
        let mut f = has(FX, Effects::ATTENUATION).then(|| attenuation_lanes(light.attenuation, d));
        if let Cone::Spot {
            axis,
            cos_outer,
            inv_cos_width,
        } = cone
        {
            // cos_angle = -(L.axis); smoothstep as in `spot_cone`.
            let cos_angle = neg(l.dot(Vec3s::broadcast(d, axis)));
            let t = (cos_angle - d.splat(cos_outer)) * d.splat(inv_cos_width);
            let t = t.max_c(d.splat(0.0)).min_c(d.splat(1.0));
            let cone = t * t * (d.splat(3.0) - d.splat(2.0) * t);
            // Without attenuation the scalar factor is 1.0, and 1.0 * cone is cone.
            f = Some(f.map_or(cone, |f| f * cone));
        }
        let (il, il_s) = (
            Vec3s::broadcast(d, light.il),
            Vec3s::broadcast(d, light.il_specular),
        );
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
fn attenuation_lanes<L: Lanes>([c, l, q]: [f32; 3], d: L) -> L {
    let d = d.min_c(d.splat(MAX_LIGHT_DISTANCE)).max_c(d.splat(0.0));
    let denominator = d.splat(c) + d.splat(l) * d + d.splat(q) * (d * d);
    d.splat(1.0) / denominator.max_c(d.splat(MIN_ATTENUATION_DENOMINATOR))
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
    shade_lanes::<FX, f32x4>(set, mat, p, n, eye)
}

/// [`shade`](crate::shade()) at `L::N` surface points at once: lane `i` of the result has
/// exactly the bits of `shade::<FX>(set, mat, p[i], n[i], eye)`, at every lane width (see the
/// module docs for how). Inlined always, so that inside [`Avx2::run`](crate::Avx2::run) it
/// compiles to AVX2.
///
/// ```
/// use glam::Vec3;
/// use phosphor_lighting::{Effects, LightSet, Material, Vec3s, shade, shade_lanes};
///
/// const FX: u32 = Effects::AMBIENT.bits() | Effects::DIFFUSE.bits() | Effects::SPECULAR.bits();
/// let (set, mat, eye) = (LightSet::s1(), Material::s1(), Vec3::new(0.0, 0.0, 3.0));
/// let n: [Vec3; 8] = std::array::from_fn(|i| Vec3::new(i as f32 * 0.1, 0.2, 1.0).normalize());
/// let p = n.map(|n| n * 0.5);
/// # #[cfg(target_arch = "x86_64")]
/// if let Some(avx2) = phosphor_lighting::Avx2::detect() {
///     let lit = avx2.run(|s: phosphor_lighting::Avx2| {
///         let w = s.splat(0.0);
///         let (p, n) = (Vec3s::from_vecs(w, p), Vec3s::from_vecs(w, n));
///         shade_lanes::<FX, _>(&set, &mat, p, n, eye).to_vecs()
///     });
///     for i in 0..8 {
///         assert_eq!(lit[i], shade::<FX>(&set, &mat, p[i], n[i], eye));
///     }
/// }
/// ```
#[inline(always)]
#[must_use]
pub fn shade_lanes<const FX: u32, L: Lanes>(
    set: &LightSet,
    mat: &Material,
    p: Vec3s<L>,
    n: Vec3s<L>,
    eye: Vec3,
) -> Vec3s<L> {
    shade_terms_lanes::<FX, L>(set, mat, p, n, eye).total()
}

/// The three sums of [`shade_lanes`] kept apart, each finite and non-negative per lane (the
/// lane form of [`shade_split`](crate::shade_split)): for a renderer that scales the
/// ambient and diffuse light by a per-pixel colour (a texture, a vertex colour) and adds the
/// specular highlight untinted, as fixed-function OpenGL's "separate specular" does.
#[derive(Debug, Clone, Copy)]
pub struct TermsLanes<L> {
    /// `emission + ka Ia`, the same in every lane.
    pub ambient: Vec3s<L>,
    /// `sum f(d) Il kd max(N.L, 0)`.
    pub diffuse: Vec3s<L>,
    /// `sum f(d) Il_spec ks W(theta) max(V.R, 0)^n_s`.
    pub specular: Vec3s<L>,
}

impl<L: Lanes> TermsLanes<L> {
    /// `ambient + diffuse + specular`, finite per lane: [`shade_lanes`] bit for bit.
    #[inline(always)]
    #[must_use]
    pub fn total(self) -> Vec3s<L> {
        finite_lanes(self.ambient + self.diffuse + self.specular)
    }

    /// `(ambient + diffuse) * m + specular`, finite per lane: the light scaled by the
    /// surface colour `m` with the highlight added after.
    #[inline(always)]
    #[must_use]
    pub fn modulated(self, m: Vec3s<L>) -> Vec3s<L> {
        finite_lanes((self.ambient + self.diffuse) * m + self.specular)
    }
}

/// [`shade_lanes`] split into its three sums ([`TermsLanes`]).
#[inline(always)]
#[must_use]
pub fn shade_terms_lanes<const FX: u32, L: Lanes>(
    set: &LightSet,
    mat: &Material,
    p: Vec3s<L>,
    n: Vec3s<L>,
    eye: Vec3,
) -> TermsLanes<L> {
    shade_terms_lanes_seen::<FX, L, NoneSeen>(set, &NoneSeen, mat, (p, n, eye))
}

/// Lights whose light reaches each lane only in part (shadows): for [`shade_terms_lanes_seen`].
/// Implementations should mark both methods `#[inline(always)]`: the lane code they run must
/// be inlined into the caller's SIMD context.
pub trait SeenLights<L: Lanes> {
    /// How many lights (or sets of lights) there are.
    fn count(&self) -> usize;
    /// The lights of entry `k` (their ambient is ignored).
    fn lights(&self, k: usize) -> &LightSet;
    /// The share of entry `k`'s light that reaches each lane's point, in `[0, 1]`.
    fn seen(&self, k: usize) -> L;
}

/// No lights with shadows.
#[derive(Debug, Clone, Copy)]
pub struct NoneSeen;

impl<L: Lanes> SeenLights<L> for NoneSeen {
    #[inline(always)]
    fn count(&self) -> usize {
        0
    }
    #[inline(always)]
    fn lights(&self, _: usize) -> &LightSet {
        unreachable!("NoneSeen has no lights")
    }
    #[inline(always)]
    fn seen(&self, _: usize) -> L {
        unreachable!("NoneSeen has no lights")
    }
}

/// [`shade_terms_lanes`] of `set`, plus, for each entry `k` of `shadowed`, the lights of
/// `shadowed.lights(k)` (their ambient ignored) with their diffuse and specular sums scaled per
/// lane by `shadowed.seen(k)` (a shadow's visibility), added in order. Bit for bit
/// `shade_terms_lanes(set)` followed, per entry, by `diffuse += shade_terms_lanes(lights(k)).
/// diffuse * seen(k)` (and the same for the specular), but the normal, the view vector and the
/// material's lane constants are made once for all of them.
#[inline(always)]
#[must_use]
pub fn shade_terms_lanes_seen<const FX: u32, L: Lanes, S: SeenLights<L>>(
    set: &LightSet,
    shadowed: &S,
    mat: &Material,
    (p, n, eye): (Vec3s<L>, Vec3s<L>, Vec3),
) -> TermsLanes<L> {
    let w = p.x;
    // The ambient terms do not depend on the lane: the scalar code's, splatted.
    let mut ambient = Vec3::ZERO;
    if has(FX, Effects::EMISSION) {
        ambient += mat.emission;
    }
    if has(FX, Effects::AMBIENT) {
        ambient += mat.ka * set.ambient();
    }
    let ambient = finite_intensity(ambient);
    let none = Vec3s::broadcast(w, Vec3::ZERO);
    let unlit = TermsLanes {
        ambient: Vec3s::broadcast(w, ambient),
        diffuse: none,
        specular: none,
    };
    if !has(FX, Effects::DIFFUSE) && !has(FX, Effects::SPECULAR) {
        return unlit;
    }
    let n = unit_normal_lanes(n);
    let zero = w.splat(0.0);
    let dark = n.x.cmp_eq(zero) & n.y.cmp_eq(zero) & n.z.cmp_eq(zero);
    if dark.all() {
        return unlit;
    }
    let (v, _) = safe_normalize_lanes(Vec3s::broadcast(w, eye) - p, n);
    let mut acc = Sums {
        n,
        v,
        dark,
        kd: Vec3s::broadcast(w, mat.kd),
        ks: Vec3s::broadcast(w, mat.ks),
        specular_model: mat.specular,
        power: Power::of(mat.shininess),
        fresnel: FresnelLanes::of::<FX>(w, mat),
        diffuse: none,
        specular: none,
    };
    acc.add_set::<FX>(set, p);
    let mut terms = TermsLanes {
        ambient: unlit.ambient,
        diffuse: finite_lanes(acc.diffuse),
        specular: finite_lanes(acc.specular),
    };
    for k in 0..shadowed.count() {
        acc.diffuse = none;
        acc.specular = none;
        acc.add_set::<FX>(shadowed.lights(k), p);
        let seen = shadowed.seen(k);
        terms.diffuse = terms.diffuse + finite_lanes(acc.diffuse) * seen;
        terms.specular = terms.specular + finite_lanes(acc.specular) * seen;
    }
    terms
}

impl<L: Lanes> Sums<L> {
    /// Adds every light of `set` at the points `p`.
    #[inline(always)]
    fn add_set<const FX: u32>(&mut self, set: &LightSet, p: Vec3s<L>) {
        let w = p.x;
        for light in set.directional() {
            self.add::<FX>(
                Vec3s::broadcast(w, light.to_light),
                Vec3s::broadcast(w, light.il),
                Vec3s::broadcast(w, light.il_specular),
            );
        }
        for light in set.points() {
            self.add_point::<FX>(light, p, Cone::None);
        }
        if has(FX, Effects::SPOT) {
            for spot in set.spots() {
                let cone = Cone::Spot {
                    axis: spot.axis,
                    cos_outer: spot.cos_outer,
                    inv_cos_width: spot.inv_cos_width,
                };
                self.add_point::<FX>(&spot.point, p, cone);
            }
        }
        if has(FX, Effects::DISTRIBUTED) {
            for light in set.distributed_samples() {
                self.add_point::<FX>(light, p, Cone::None);
            }
        }
    }
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
    fn shadowed_lights_in_one_pass_are_the_separate_passes_bit_for_bit() {
        use crate::{Attenuation, F32x1, Light};
        let mat = Material {
            ks: Vec3::splat(0.6),
            shininess: 24.0,
            emission: Vec3::new(0.05, 0.0, 0.02),
            ..Material::s1()
        };
        let mut direct = mat;
        direct.ka = Vec3::ZERO;
        direct.emission = Vec3::ZERO;
        let mut key = Light::point(Vec3::new(2.0, 3.0, 1.0), Vec3::new(1.5, 1.2, 1.0)).unwrap();
        key.attenuation = Attenuation::Offset { k: 1.0 };
        let sun = Light::directional(Vec3::new(-0.3, -1.0, 0.2), Vec3::splat(0.7)).unwrap();
        let fill = Light::point(Vec3::new(-2.0, 0.5, 2.0), Vec3::splat(0.4)).unwrap();
        let rest = LightSet::new(Vec3::splat(0.3), &[fill]);
        let alone = [
            LightSet::new(Vec3::ZERO, &[key]),
            LightSet::new(Vec3::ZERO, &[sun]),
        ];
        let eye = Vec3::new(0.0, 1.0, 4.0);
        let like = F32x1(0.0);
        // Normals lit, grazing, facing away and zero; visibilities 0, between and 1.
        let normals = [
            Vec3::Y,
            Vec3::new(1.0, 0.01, 0.0),
            -Vec3::Y,
            Vec3::ZERO,
            Vec3::new(0.3, 0.8, 0.5),
        ];
        for (i, n) in normals.into_iter().enumerate() {
            let p = Vec3::new(0.1 * i as f32, -0.2, 0.3);
            let (pl, nl) = (Vec3s::broadcast(like, p), Vec3s::broadcast(like, n));
            let seen = [F32x1(0.25 * i as f32 % 1.0), F32x1(1.0 - 0.2 * i as f32)];
            let mut want =
                shade_terms_lanes::<{ Effects::ALL.bits() }, F32x1>(&rest, &mat, pl, nl, eye);
            for (set, k) in alone.iter().zip(seen) {
                let t =
                    shade_terms_lanes::<{ Effects::ALL.bits() }, F32x1>(set, &direct, pl, nl, eye);
                want.diffuse = want.diffuse + t.diffuse * k;
                want.specular = want.specular + t.specular * k;
            }
            struct Two<'a>(&'a [LightSet; 2], [F32x1; 2]);
            impl SeenLights<F32x1> for Two<'_> {
                fn count(&self) -> usize {
                    2
                }
                fn lights(&self, k: usize) -> &LightSet {
                    &self.0[k]
                }
                fn seen(&self, k: usize) -> F32x1 {
                    self.1[k]
                }
            }
            let got = shade_terms_lanes_seen::<{ Effects::ALL.bits() }, F32x1, _>(
                &rest,
                &Two(&alone, seen),
                &mat,
                (pl, nl, eye),
            );
            let bits = |t: &TermsLanes<F32x1>| {
                [t.ambient, t.diffuse, t.specular].map(|v| [v.x.0, v.y.0, v.z.0].map(f32::to_bits))
            };
            assert_eq!(bits(&got), bits(&want), "normal {n}");
        }
    }

    #[test]
    fn min_max_and_neg_follow_the_scalar_semantics() {
        let x = f32x4::new([f32::NAN, -1.0, 2.0, f32::INFINITY]);
        let one = f32x4::splat(1.0);
        assert_eq!(x.max_c(one).to_array(), [1.0, 1.0, 2.0, f32::INFINITY]);
        assert_eq!(x.min_c(one).to_array(), [1.0, -1.0, 1.0, 1.0]);
        let z = neg(f32x4::new([0.0, -0.0, 1.0, -2.0])).to_array();
        assert_eq!(
            z.map(f32::to_bits),
            [-0.0f32, 0.0, -1.0, 2.0].map(f32::to_bits)
        );
    }
}
