//! Face normals and vertex normals averaged within a surface.
//!
//! The lecture notes: the vertex normal is `N_v = sum N_k / |sum N_k|` over the faces `k` around
//! the vertex ([`Weighting::Uniform`]), and the average is taken only over faces of the same
//! surface. Here a corner of a face averages the faces around its position that are *compatible*
//! with its own face: same smoothing group (when the file has `s` lines and the options use them;
//! group 0 / `s off` means flat), same material (when asked), and a dihedral angle between the two
//! face normals no larger than the crease angle (when one applies). Degenerate (zero-area) faces
//! never contribute.
//!
//! Uniform weighting counts each source polygon once per vertex (an OBJ quad split into two
//! triangles is one face, as in the notes' `N_v`); area and angle weights are per triangle (the
//! angles of a polygon's triangles at a vertex add up to the polygon's angle). Triangles of one
//! polygon are always smoothed together.
//!
//! At a vertex where more than 256 corners meet, each corner averages the faces of its own
//! surface there instead (surfaces are the faces joined edge to edge by the same tests), which
//! keeps the work linear; it is the same average wherever every two faces of a surface at that
//! vertex pass the tests, as on smooth and flat regions.
//!
//! Fallbacks, so no corner is ever NaN: where the weighted sum cancels or points away from the
//! corner's own face (a two-sided sheet with the crease test off), the corner takes its own
//! face normal; a corner of a degenerate face takes
//! the average of the compatible faces around its position, else of all faces there, else +Z.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

/// How the face normals around a vertex are weighted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Weighting {
    /// Every face counts once: the lecture notes' `N_v = sum N_k / |sum N_k|`.
    #[default]
    Uniform,
    /// Faces weighted by their area.
    Area,
    /// Faces weighted by their interior angle at the vertex (Thürmer & Wüthrich 1998).
    Angle,
}

/// Where vertex normals come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalSource {
    /// Use the file's `vn` when every face corner has one; compute them otherwise.
    #[default]
    Authored,
    /// Always compute normals from the geometry, ignoring `vn`.
    Computed,
}

/// Options for vertex normals (docs/conventions.md, "Normals").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalOptions {
    /// Weighting of the face normals around a vertex.
    pub weighting: Weighting,
    /// Faces meeting at a sharper angle than this (degrees, between face normals) are not
    /// averaged. `None` = the convention: no crease angle when the file has `s` lines (and
    /// `use_smoothing_groups` is on), 60 degrees otherwise. `Some(180.0)` smooths every edge.
    pub crease_angle_deg: Option<f32>,
    /// Use the file's smoothing groups (`s N`, `s off`) when it has any.
    pub use_smoothing_groups: bool,
    /// Never average across faces of different materials.
    pub split_by_material: bool,
    /// Authored `vn` or computed normals.
    pub source: NormalSource,
}

/// Crease angle used when the file has no smoothing groups and the caller set none.
pub const DEFAULT_CREASE_ANGLE_DEG: f32 = 60.0;

impl Default for NormalOptions {
    /// The conventions of docs/conventions.md: `vn` as authored; smoothing groups when the file has
    /// them; otherwise a 60-degree crease angle; uniform weights (the lecture notes' `N_v`).
    fn default() -> Self {
        NormalOptions {
            weighting: Weighting::Uniform,
            crease_angle_deg: None,
            use_smoothing_groups: true,
            split_by_material: false,
            source: NormalSource::Authored,
        }
    }
}

impl NormalOptions {
    /// Standard scene S1: as the default, except that every face sharing a position is averaged
    /// (crease angle 180 degrees) with uniform weights, the lecture notes' `N_v`. Smoothing groups
    /// and authored `vn` still win where the file has them.
    #[must_use]
    pub fn s1() -> Self {
        NormalOptions {
            crease_angle_deg: Some(180.0),
            ..NormalOptions::default()
        }
    }

    /// Computed normals averaged over every face sharing a position (crease 180, no smoothing
    /// groups, no material split) with the given weighting.
    #[must_use]
    pub fn smooth_all(weighting: Weighting) -> Self {
        NormalOptions {
            weighting,
            crease_angle_deg: Some(180.0),
            use_smoothing_groups: false,
            split_by_material: false,
            source: NormalSource::Computed,
        }
    }

    /// Computed normals with a crease angle and no smoothing groups.
    #[must_use]
    pub fn crease(angle_deg: f32) -> Self {
        NormalOptions {
            crease_angle_deg: Some(angle_deg),
            use_smoothing_groups: false,
            source: NormalSource::Computed,
            ..NormalOptions::default()
        }
    }
}

/// The options resolved against one file: which tests decide that two faces are smoothed together.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SmoothRule {
    pub groups: bool,
    pub split_by_material: bool,
    /// `cos(crease)`; `None` when no crease test applies (crease >= 180 or none).
    pub cos_crease: Option<f64>,
}

impl SmoothRule {
    pub fn resolve(opts: &NormalOptions, file_has_groups: bool) -> SmoothRule {
        let groups = opts.use_smoothing_groups && file_has_groups;
        let crease = match opts.crease_angle_deg {
            Some(c) if !c.is_nan() => Some(c),
            _ if groups => None,
            _ => Some(DEFAULT_CREASE_ANGLE_DEG),
        };
        let cos_crease = crease
            .filter(|&c| c < 180.0)
            .map(|c| f64::from(c.max(0.0)).to_radians().cos());
        SmoothRule {
            groups,
            split_by_material: opts.split_by_material,
            cos_crease,
        }
    }

    /// Group and material test (no angle).
    fn same_kind(&self, ga: u32, gb: u32, ma: u32, mb: u32) -> bool {
        (!self.groups || (ga == gb && ga != 0)) && (!self.split_by_material || ma == mb)
    }
}

/// Unit normal and twice the area of triangle `abc` (counter-clockwise = front), in f64.
///
/// f64 holds the products of any two f32 differences without overflow or underflow (f32
/// spans 1e±38, f64 1e±308), so slivers and huge or tiny coordinates keep their direction.
/// `None` when the area is zero (collinear or coincident corners; also sin(angle) below 1e-12
/// relative to the edges) or a coordinate is not finite.
#[must_use]
pub fn triangle_normal_f64(a: Vec3, b: Vec3, c: Vec3) -> Option<(DVec3, f64)> {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let e1 = b - a;
    let e2 = c - a;
    let cross = e1.cross(e2);
    let len = cross.length();
    let scale = e1.length() * e2.length();
    if !len.is_finite() || len <= 1e-12 * scale || len == 0.0 {
        return None;
    }
    Some((cross / len, len))
}

/// Interior angle at corner `a` of triangle `abc`, in radians (0 when an edge is zero).
fn corner_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let u = b - a;
    let v = c - a;
    // atan2 of |u x v| and u.v is accurate for every angle, unlike acos.
    let s = u.cross(v).length();
    let d = u.dot(v);
    if s == 0.0 && d == 0.0 {
        0.0
    } else {
        s.atan2(d)
    }
}

/// Per-triangle data the corner averaging needs.
pub(crate) struct FaceData {
    /// Unit face normal, `None` for degenerate faces.
    pub normal: Vec<Option<DVec3>>,
    /// Twice the area.
    pub area2: Vec<f64>,
}

pub(crate) fn face_data(positions: &[Vec3], tris: &[[u32; 3]]) -> FaceData {
    let mut normal = Vec::with_capacity(tris.len());
    let mut area2 = Vec::with_capacity(tris.len());
    for t in tris {
        let p = t.map(|i| positions[i as usize]);
        match triangle_normal_f64(p[0], p[1], p[2]) {
            Some((n, a)) => {
                normal.push(Some(n));
                area2.push(a);
            }
            None => {
                normal.push(None);
                area2.push(0.0);
            }
        }
    }
    FaceData { normal, area2 }
}

/// Corners (as `tri * 3 + k`) grouped by position, in compressed rows.
pub(crate) struct CornersByPosition {
    pub offsets: Vec<usize>,
    pub corners: Vec<u32>,
}

impl CornersByPosition {
    pub fn new(position_count: usize, tris: &[[u32; 3]]) -> Self {
        let mut offsets = vec![0usize; position_count + 1];
        for t in tris {
            for &i in t {
                offsets[i as usize + 1] += 1;
            }
        }
        for i in 0..position_count {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut corners = vec![0u32; offsets[position_count]];
        for (ti, t) in tris.iter().enumerate() {
            for (k, &i) in t.iter().enumerate() {
                corners[fill[i as usize]] = (ti * 3 + k) as u32;
                fill[i as usize] += 1;
            }
        }
        CornersByPosition { offsets, corners }
    }

    pub fn at(&self, position: usize) -> &[u32] {
        &self.corners[self.offsets[position]..self.offsets[position + 1]]
    }
}

/// Per-triangle labels that decide which faces are smoothed together.
#[derive(Clone, Copy)]
pub(crate) struct FaceLabels<'a> {
    /// Smoothing group (0 = off).
    pub groups: &'a [u32],
    /// Material id.
    pub materials: &'a [u32],
    /// Source polygon id.
    pub polygons: &'a [u32],
}

/// Vertices where more corners than this meet average each corner over its surface there
/// rather than testing every pair of faces (see [`corner_normals`]).
pub(crate) const MAX_PAIRWISE_VALENCE: usize = 256;

/// Computes one unit normal per corner (`tri * 3 + k`).
///
/// At a vertex where at most [`MAX_PAIRWISE_VALENCE`] corners meet, each corner averages the
/// faces there that are compatible with its own face (the module docs' rule, tested pair by
/// pair). Where more meet (the apex of a fine cone, the centre of a fanned polygon, a face
/// repeated thousands of times), pair tests would be quadratic in the valence, so each corner
/// averages the faces of its own surface there (`surfaces`, the components of faces joined
/// across edges by the same rule): the same faces whenever the rule holds between every two
/// faces of a surface at that vertex, as on smooth or flat regions.
pub(crate) fn corner_normals(
    positions: &[Vec3],
    tris: &[[u32; 3]],
    faces: &FaceData,
    labels: &FaceLabels<'_>,
    weighting: Weighting,
    rule: &SmoothRule,
    surfaces: &[u32],
) -> Vec<Vec3> {
    let FaceLabels {
        groups,
        materials,
        polygons,
    } = *labels;
    let by_pos = CornersByPosition::new(positions.len(), tris);
    let weight = |c: u32| -> f64 {
        let t = (c / 3) as usize;
        match weighting {
            Weighting::Uniform => 1.0,
            Weighting::Area => faces.area2[t] * 0.5,
            Weighting::Angle => {
                let k = (c % 3) as usize;
                let p = tris[t].map(|i| positions[i as usize].as_dvec3());
                corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3])
            }
        }
    };
    let mut out = vec![Vec3::Z; tris.len() * 3];
    let mut around: Vec<(u32, DVec3, f64)> = Vec::new();
    let mut polys: Vec<u32> = Vec::new();
    let mut by_surface: HashMap<u32, (DVec3, f64)> = HashMap::new();
    for pos in 0..positions.len() {
        let corners = by_pos.at(pos);
        around.clear();
        around.extend(corners.iter().filter_map(|&c| {
            let t = (c / 3) as usize;
            faces.normal[t].map(|n| (c, n, weight(c)))
        }));
        if weighting == Weighting::Uniform {
            // Count each source polygon once at this vertex (the notes' N_v: one N_k per face).
            polys.clear();
            polys.extend(around.iter().map(|&(c, _, _)| polygons[(c / 3) as usize]));
            polys.sort_unstable();
            for entry in &mut around {
                let p = polygons[(entry.0 / 3) as usize];
                let count = polys.partition_point(|&q| q <= p) - polys.partition_point(|&q| q < p);
                entry.2 /= count as f64;
            }
        }
        // Degenerate face with no compatible neighbour: any face here, else +Z.
        let any_face = || {
            let any: DVec3 = around.iter().map(|&(_, n2, _)| n2).sum();
            let l = any.length();
            (l > 0.0).then(|| any / l)
        };
        let mut any_here: Option<Option<DVec3>> = None;
        let pairwise = corners.len() <= MAX_PAIRWISE_VALENCE;
        if !pairwise {
            by_surface.clear();
            for &(c2, n2, w2) in &around {
                let entry = by_surface
                    .entry(surfaces[(c2 / 3) as usize])
                    .or_insert((DVec3::ZERO, 0.0));
                entry.0 += n2 * w2;
                entry.1 += w2.abs();
            }
        }
        for &c in corners {
            let t = (c / 3) as usize;
            let own = faces.normal[t];
            let (sum, total) = if pairwise {
                let (g, m) = (groups[t], materials[t]);
                let mut sum = DVec3::ZERO;
                let mut total = 0.0;
                for &(c2, n2, w2) in &around {
                    let t2 = (c2 / 3) as usize;
                    let same_polygon = polygons[t2] == polygons[t];
                    if !same_polygon && !rule.same_kind(g, groups[t2], m, materials[t2]) {
                        continue;
                    }
                    if let (false, Some(n), Some(cos)) = (same_polygon, own, rule.cos_crease) {
                        // Small tolerance so that exactly-at-threshold and coplanar faces merge.
                        if n.dot(n2) < cos - 1e-9 {
                            continue;
                        }
                    }
                    sum += n2 * w2;
                    total += w2.abs();
                }
                (sum, total)
            } else {
                by_surface
                    .get(&surfaces[t])
                    .copied()
                    .unwrap_or((DVec3::ZERO, 0.0))
            };
            let len = sum.length();
            // A corner never takes a normal facing away from its own face (two-sided sheets).
            let facing = own.is_none_or(|n| n.dot(sum) > 0.0);
            let n = if len > 1e-9 * total && len > 0.0 && facing {
                Some(sum / len)
            } else {
                own.or_else(|| *any_here.get_or_insert_with(any_face))
            };
            out[c as usize] = n.map_or(Vec3::Z, |n| {
                phosphor_math::safe_normalize(n.as_vec3(), Vec3::Z)
            });
        }
    }
    out
}
