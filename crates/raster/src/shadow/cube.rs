//! Cube maps: a point light whose casters surround it (no single cone of at most
//! [`super::MAX_POINT_HALF_ANGLE_DEG`] holds them) gets one perspective map per face of a cube
//! centred on it, along the world axes. Only the faces through which a caster can shadow a
//! receiver are made ([`fit_cube`]); a point on a face that was not made is lit.
//!
//! * **Which face.** A point `p` is looked up in the face of the major axis of `p - light`
//!   (ties go to x, then y), on the side of its sign: exactly one face per point, the same in
//!   every lane width.
//! * **Seams.** Each face's frustum is a little wider than the cube's 90 degrees
//!   ([`face_tan_half`]): the filter's footprint of a point near a face's edge reaches up to
//!   three texels past it, and those texels hold that face's own casters, so a shadow crossing
//!   a seam stays continuous instead of leaking light along the cube's edges.
//! * **Depth range.** The map holds distances along the face's axis, which are shorter than
//!   the distances to the light off the axis (down to `1 / sqrt(1 + 2 t^2)` of them at the
//!   frustum's corners, `t` the half-width's tangent); the near plane is put that much closer,
//!   so no caster inside the frustum is clipped.

use std::fmt;

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s};

use super::fit::{NoMap, Sphere};
use super::{LightView, Projection, ShadowMap};

/// Texels past the cube's edge that a face's map also covers: the lookup's footprint reaches
/// under three texels from a point.
pub const SEAM_TEXELS: f32 = 3.0;

/// One face of a cube map, named by the axis it looks along.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CubeFace {
    /// Along +x.
    PosX,
    /// Along -x.
    NegX,
    /// Along +y.
    PosY,
    /// Along -y.
    NegY,
    /// Along +z.
    PosZ,
    /// Along -z.
    NegZ,
}

impl CubeFace {
    /// The six faces, in the order of [`CubeFace::index`].
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    /// Position in [`CubeFace::ALL`].
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The unit axis the face looks along.
    #[must_use]
    pub const fn axis(self) -> Vec3 {
        match self {
            CubeFace::PosX => Vec3::X,
            CubeFace::NegX => Vec3::NEG_X,
            CubeFace::PosY => Vec3::Y,
            CubeFace::NegY => Vec3::NEG_Y,
            CubeFace::PosZ => Vec3::Z,
            CubeFace::NegZ => Vec3::NEG_Z,
        }
    }

    /// The face that looks up the direction `d` (from the light): the major axis of `d`, ties
    /// to x, then y.
    #[must_use]
    pub fn of(d: Vec3) -> CubeFace {
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            if d.x >= 0.0 {
                CubeFace::PosX
            } else {
                CubeFace::NegX
            }
        } else if a.y >= a.z {
            if d.y >= 0.0 {
                CubeFace::PosY
            } else {
                CubeFace::NegY
            }
        } else if d.z >= 0.0 {
            CubeFace::PosZ
        } else {
            CubeFace::NegZ
        }
    }
}

impl fmt::Display for CubeFace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CubeFace::PosX => "+x",
            CubeFace::NegX => "-x",
            CubeFace::PosY => "+y",
            CubeFace::NegY => "-y",
            CubeFace::PosZ => "+z",
            CubeFace::NegZ => "-z",
        })
    }
}

/// `tan` of a face's half-angle for maps of side `size`: the cube's 45 degrees widened so that
/// [`SEAM_TEXELS`] texels lie past the edge on every side (`t = 1 + 2 SEAM_TEXELS t / size`).
#[must_use]
pub fn face_tan_half(size: u32) -> f32 {
    let size = (size as f32).max(4.0 * SEAM_TEXELS);
    1.0 / (1.0 - 2.0 * SEAM_TEXELS / size)
}

/// Whether sphere `s` can reach into the frustum of `face` from `position`: the angle from the
/// axis to the sphere's centre, less the sphere's half-angle, is under the frustum's corner
/// angle (a cone around the square frustum, so this may say yes for a sphere just outside it).
fn touches(face: CubeFace, position: Vec3, s: &Sphere, tan_half: f32) -> bool {
    let v = s.center - position;
    let d = v.length();
    if d <= s.radius {
        return true;
    }
    let corner = (tan_half * std::f32::consts::SQRT_2).atan();
    let off_axis = face.axis().dot(v / d).clamp(-1.0, 1.0).acos();
    off_axis - (s.radius / d).asin() < corner
}

/// Whether the world box `[lo, hi]` can reach into the frustum of `face` from `position`:
/// it is not wholly behind the light along the face's axis, nor wholly outside one of the
/// frustum's four side planes (a box may pass that lies outside near a corner, as in any
/// plane-by-plane cull). Tighter than the bounding
/// sphere for flat and long objects: a floor below the light never reaches the upward face.
fn box_touches(face: CubeFace, position: Vec3, (lo, hi): (Vec3, Vec3), tan_half: f32) -> bool {
    let (lo, hi) = (lo - position, hi - position);
    let a = face.axis();
    // Inside is `m . q >= 0` for `m = a` (in front of the light) and for the side planes'
    // normals `m = t a -+ w`: outside when even the box's farthest corner along one `m` is
    // below.
    let reaches = |m: Vec3| m.dot(Vec3::select(m.cmpgt(Vec3::ZERO), hi, lo)) >= 0.0;
    let across = [Vec3::X, Vec3::Y, Vec3::Z]
        .into_iter()
        .filter(|w| w.dot(a) == 0.0);
    reaches(a)
        && across
            .flat_map(|w| [w, -w])
            .all(|w| reaches(a * tan_half - w))
}

/// A caster or a receiver as [`fit_cube`] sees it: its bounding sphere and, where known, its
/// world-space box (lowest and highest corner).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// The bounding sphere.
    pub sphere: Sphere,
    /// The world box, if known.
    pub aabb: Option<(Vec3, Vec3)>,
}

impl From<Sphere> for Extent {
    fn from(sphere: Sphere) -> Extent {
        Extent { sphere, aabb: None }
    }
}

impl Extent {
    /// Whether it can reach into the frustum of `face`: by its sphere, and by its box.
    fn touches(&self, face: CubeFace, position: Vec3, tan_half: f32) -> bool {
        touches(face, position, &self.sphere, tan_half)
            && self
                .aabb
                .is_none_or(|b| box_touches(face, position, b, tan_half))
    }
}

/// One face of a cube map worth making: its view and which casters and receivers reach
/// into its frustum (indices into the slices given to [`fit_cube`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FaceFit {
    /// The face.
    pub face: CubeFace,
    /// Its view from the light.
    pub view: LightView,
    /// The casters that reach into it (and, given pairs, can shadow a receiver there).
    pub casters: Vec<usize>,
    /// The receivers that reach into it (and, given pairs, some caster there can shadow).
    pub receivers: Vec<usize>,
}

/// The faces of a cube map at `position` worth making for maps of side `size`: those whose
/// frustum some caster of `casters` and some receiver of `receivers` both reach. With
/// `pairs` (`(caster, receiver)` indices: which caster can shadow which receiver), a face
/// needs a pair that both reach it, so a flat object that shadows another only elsewhere
/// makes no face of its own. Near and far are fitted per face (near from its casters, far
/// from its receivers).
///
/// # Errors
/// [`NoMap::NothingBetween`] when no face has both, [`NoMap::Degenerate`] for a position or
/// bounds that are not finite.
pub fn fit_cube(
    position: Vec3,
    casters: &[Extent],
    receivers: &[Extent],
    pairs: Option<&[(usize, usize)]>,
    size: u32,
) -> Result<Vec<FaceFit>, NoMap> {
    let all = || casters.iter().chain(receivers).map(|e| &e.sphere);
    if !position.is_finite()
        || all().any(|s| !s.center.is_finite() || !s.radius.is_finite() || s.radius < 0.0)
    {
        return Err(NoMap::Degenerate);
    }
    let tan_half = face_tan_half(size);
    // Distances along the axis are at least this share of the distance to the light.
    let corner_cos = 1.0 / (1.0 + 2.0 * tan_half * tan_half).sqrt();
    let mut faces = Vec::new();
    for face in CubeFace::ALL {
        let reaching = |set: &[Extent]| -> Vec<bool> {
            set.iter()
                .map(|e| e.touches(face, position, tan_half))
                .collect()
        };
        let (ct, rt) = (reaching(casters), reaching(receivers));
        let (mut cs, mut rs): (Vec<usize>, Vec<usize>) = match pairs {
            None => (
                (0..casters.len()).filter(|&i| ct[i]).collect(),
                (0..receivers.len()).filter(|&i| rt[i]).collect(),
            ),
            Some(pairs) => pairs
                .iter()
                .filter(|&&(c, r)| ct.get(c) == Some(&true) && rt.get(r) == Some(&true))
                .copied()
                .unzip(),
        };
        cs.sort_unstable();
        cs.dedup();
        rs.sort_unstable();
        rs.dedup();
        if cs.is_empty() || rs.is_empty() {
            continue;
        }
        let near = cs
            .iter()
            .map(|&i| casters[i].sphere.center.distance(position) - casters[i].sphere.radius)
            .fold(f32::MAX, f32::min);
        let far = rs
            .iter()
            .map(|&i| receivers[i].sphere.center.distance(position) + receivers[i].sphere.radius)
            .fold(f32::MIN, f32::max);
        let near = (near * corner_cos * 0.99).max(far * 1e-3).max(1e-4);
        if near >= far {
            continue;
        }
        let axis = face.axis();
        let up = if axis.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
        let view = LightView {
            view: glam::camera::rh::view::look_at_mat4(position, position + axis, up),
            projection: Projection::Perspective { tan_half },
            near,
            far: far * 1.01,
            toward: position,
        };
        if !view.is_valid() {
            return Err(NoMap::Degenerate);
        }
        faces.push(FaceFit {
            face,
            view,
            casters: cs,
            receivers: rs,
        });
    }
    if faces.is_empty() {
        Err(NoMap::NothingBetween)
    } else {
        Ok(faces)
    }
}

/// A point light's cube map as a receiver looks it up: the light's position and the faces
/// that were made (by [`CubeFace::index`]).
#[derive(Debug, Clone, Copy)]
pub struct CubeShadow<'a> {
    /// Where the light is.
    pub position: Vec3,
    /// The faces made; a point on a missing face is lit.
    pub faces: [Option<&'a ShadowMap>; 6],
}

impl CubeShadow<'_> {
    /// How much of the light reaches `p` with normal `n`: the visibility in the map of
    /// [`CubeFace::of`]`(p - position)`, 1 where that face was not made.
    #[must_use]
    pub fn visibility(&self, p: Vec3, n: Vec3) -> f32 {
        let like = phosphor_lighting::F32x1(0.0);
        self.visibility_lanes(Vec3s::broadcast(like, p), Vec3s::broadcast(like, n))
            .0
    }

    /// [`CubeShadow::visibility`] per lane: each face present among the lanes is looked up
    /// once, and each lane keeps its own face's value (the one-lane bits at every width).
    #[inline(always)]
    #[must_use]
    pub fn visibility_lanes<L: Lanes>(&self, p: Vec3s<L>, n: Vec3s<L>) -> L {
        let like = p.x;
        let zero = like.splat(0.0);
        let d = p - Vec3s::broadcast(like, self.position);
        let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
        let major_x = ax.cmp_ge(ay) & ax.cmp_ge(az);
        let major_y = major_x.blend(zero, ay.cmp_ge(az));
        let major_z = major_x.blend(zero, major_y.blend(zero, zero.cmp_eq(zero)));
        let sides = [
            (major_x, d.x.cmp_ge(zero)),
            (major_y, d.y.cmp_ge(zero)),
            (major_z, d.z.cmp_ge(zero)),
        ];
        let mut seen = like.splat(1.0);
        for (face, map) in CubeFace::ALL.iter().zip(self.faces) {
            let Some(map) = map else { continue };
            let (major, positive) = sides[face.index() / 2];
            let on = if face.index() % 2 == 0 {
                major & positive
            } else {
                positive.blend(zero, major)
            };
            if on.any() {
                seen = on.blend(map.visibility_lanes(p, n), seen);
            }
        }
        seen
    }
}
