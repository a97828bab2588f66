//! Exact shadow rays in `f64`, the ground truth a shadow map is measured against: `reference`
//! traces, from each pixel's surface point, one ray to each light with shadows and tests it
//! against the light's casters' triangles (the same casters its map was made from). The
//! answer is 0 or 1, a hard shadow: the map's filtered penumbra and its texels both count as
//! its error.
//!
//! The triangles are held in world space in `f64` in a bounding volume hierarchy (boxes
//! split at the median centroid of their longest axis, leaves of at most [`LEAF`] triangles),
//! so a ray visits a few dozen boxes instead of every triangle. The ray test is Moller and
//! Trumbore's (1997). A hit counts only beyond [`SELF_HIT`] of the ray's length from its
//! origin (the receiver's own surface, where it is a caster too) and before the light.
//!
//! A receiver that cannot shadow itself (a convex solid: its own `N.L <= 0` darkens what faces
//! away) passes its own triangles by: a ray from a point just lit by its smooth normal would
//! otherwise cross the neighbouring facets of the tessellation and draw their jagged outline
//! along the terminator, which no smooth surface has.

use glam::{DMat4, DVec3};

use super::Caster;

/// Most triangles in a leaf.
pub const LEAF: usize = 4;
/// Hits nearer the ray's origin than this share of its length (or, towards a directional
/// light, than this many units times the point's scale) are the receiver's own surface.
pub const SELF_HIT: f64 = 1e-7;

/// Where a light is, for its shadow rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RayTarget {
    /// A light at this position (point, spot).
    Position(DVec3),
    /// A light infinitely far in this unit direction (directional).
    Direction(DVec3),
}

#[derive(Debug, Clone, Copy)]
struct Node {
    min: DVec3,
    max: DVec3,
    /// A leaf: its first triangle; an inner node: its first child (the second follows it).
    first: u32,
    /// Triangles of a leaf; 0 for an inner node.
    count: u32,
}

/// The triangles that can block a light, in `f64` world space, with their hierarchy.
#[derive(Debug, Clone, Default)]
pub struct Occluders {
    tris: Vec<[DVec3; 3]>,
    /// The caster (index in the list given to [`Occluders::new`]) of each triangle.
    owner: Vec<u32>,
    nodes: Vec<Node>,
}

/// The box around `tris`.
fn bounds(tris: &[[DVec3; 3]]) -> (DVec3, DVec3) {
    tris.iter().flatten().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

impl Occluders {
    /// The casters' triangles placed in the world; triangles with a non-finite corner or no
    /// area are left out (they block nothing).
    #[must_use]
    pub fn new(casters: &[Caster]) -> Occluders {
        let mut tris = Vec::new();
        for (id, c) in casters.iter().enumerate() {
            let model: DMat4 = c.model.as_dmat4();
            let p = c.mesh.positions;
            for t in c.mesh.indices {
                let Some(corners) = t
                    .iter()
                    .map(|&i| {
                        p.get(i as usize)
                            .map(|v| model.transform_point3(v.as_dvec3()))
                    })
                    .collect::<Option<Vec<DVec3>>>()
                else {
                    continue;
                };
                let [a, b, c] = [corners[0], corners[1], corners[2]];
                let area = (b - a).cross(c - a).length_squared();
                if a.is_finite() && b.is_finite() && c.is_finite() && area > 0.0 {
                    tris.push(([a, b, c], id as u32));
                }
            }
        }
        let (tris, owner) = tris.into_iter().unzip();
        let mut out = Occluders {
            tris,
            owner,
            nodes: Vec::new(),
        };
        if !out.tris.is_empty() {
            out.nodes.push(Node {
                min: DVec3::ZERO,
                max: DVec3::ZERO,
                first: 0,
                count: 0,
            });
            out.build(0, 0, out.tris.len());
        }
        out
    }

    /// Triangles held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether no triangle is held.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Fills node `at` with triangles `start..end`, splitting it below [`LEAF`].
    fn build(&mut self, at: usize, start: usize, end: usize) {
        let (min, max) = bounds(&self.tris[start..end]);
        if end - start <= LEAF {
            self.nodes[at] = Node {
                min,
                max,
                first: start as u32,
                count: (end - start) as u32,
            };
            return;
        }
        let centroid = |t: &[DVec3; 3]| (t[0] + t[1] + t[2]) / 3.0;
        let (lo, hi) = self.tris[start..end].iter().fold(
            (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
            |(lo, hi), t| (lo.min(centroid(t)), hi.max(centroid(t))),
        );
        let extent = hi - lo;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mid = start + (end - start) / 2;
        let mut pairs: Vec<([DVec3; 3], u32)> = self.tris[start..end]
            .iter()
            .copied()
            .zip(self.owner[start..end].iter().copied())
            .collect();
        pairs.select_nth_unstable_by(mid - start, |a, b| {
            centroid(&a.0)[axis].total_cmp(&centroid(&b.0)[axis])
        });
        for (k, (t, o)) in pairs.into_iter().enumerate() {
            self.tris[start + k] = t;
            self.owner[start + k] = o;
        }
        let first = self.nodes.len();
        let empty = Node {
            min,
            max,
            first: 0,
            count: 0,
        };
        self.nodes.push(empty);
        self.nodes.push(empty);
        self.nodes[at] = Node {
            min,
            max,
            first: first as u32,
            count: 0,
        };
        self.build(first, start, mid);
        self.build(first + 1, mid, end);
    }

    /// 1 when nothing stands between `p` and the light `target`, 0 when a triangle does (a
    /// point that is not finite is lit); the triangles of caster `skip` never block.
    #[must_use]
    pub fn visibility(&self, p: DVec3, target: RayTarget, skip: Option<usize>) -> f64 {
        if !p.is_finite() || self.tris.is_empty() {
            return 1.0;
        }
        let own = skip.map_or(u32::MAX, |s| s as u32);
        let (dir, length, skip) = match target {
            RayTarget::Position(q) => {
                let d = q - p;
                let len = d.length();
                if len <= 0.0 || !len.is_finite() {
                    return 1.0;
                }
                (d / len, len, SELF_HIT * len)
            }
            RayTarget::Direction(d) => {
                let len = d.length();
                if len <= 0.0 || !len.is_finite() {
                    return 1.0;
                }
                (d / len, f64::MAX, SELF_HIT * (1.0 + p.abs().max_element()))
            }
        };
        if self.blocked(p, dir, (skip, length), own) {
            0.0
        } else {
            1.0
        }
    }

    /// Whether the ray `origin + t dir`, `t` in `(t_min, t_max)`, hits a triangle not of
    /// caster `own`.
    fn blocked(&self, origin: DVec3, dir: DVec3, (t_min, t_max): (f64, f64), own: u32) -> bool {
        let inv = dir.recip();
        let mut stack = [0u32; 64];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let node = self.nodes[stack[depth] as usize];
            // Slabs: `f64::min`/`max` skip the NaN of a zero direction on a box face.
            let t1 = (node.min - origin) * inv;
            let t2 = (node.max - origin) * inv;
            let near = t1.min(t2).max_element().max(t_min);
            let far = t1.max(t2).min_element().min(t_max);
            if near > far {
                continue;
            }
            if node.count == 0 {
                if depth + 2 > stack.len() {
                    // Deeper than any median split of 2^62 triangles: not reached.
                    return false;
                }
                stack[depth] = node.first;
                stack[depth + 1] = node.first + 1;
                depth += 2;
                continue;
            }
            let first = node.first as usize;
            let range = first..first + node.count as usize;
            for (t, &o) in self.tris[range.clone()].iter().zip(&self.owner[range]) {
                if o == own {
                    continue;
                }
                if let Some(t_hit) = hit(origin, dir, t)
                    && t_hit > t_min
                    && t_hit < t_max
                {
                    return true;
                }
            }
        }
        false
    }
}

/// Moller and Trumbore (1997): the ray parameter where `origin + t dir` meets triangle `t`,
/// if it does (edges included).
fn hit(origin: DVec3, dir: DVec3, t: &[DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = dir.cross(e2);
    let det = e1.dot(h);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let f = 1.0 / det;
    let s = origin - t[0];
    let u = f * s.dot(h);
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = f * dir.dot(q);
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(f * e2.dot(q))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeshView;
    use glam::{Mat4, Vec3};

    /// A unit square in the plane y = 0, as two triangles.
    fn square() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        (
            vec![
                Vec3::new(-0.5, 0.0, -0.5),
                Vec3::new(0.5, 0.0, -0.5),
                Vec3::new(0.5, 0.0, 0.5),
                Vec3::new(-0.5, 0.0, 0.5),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn a_square_blocks_exactly_what_is_behind_it() {
        let (p, i) = square();
        let n = vec![Vec3::Y; 4];
        let mesh = MeshView {
            positions: &p,
            normals: &n,
            uvs: None,
            tangents: None,
            colors: None,
            indices: &i,
        };
        // Many copies, so that the hierarchy has inner nodes: squares at y = 1, 2, ... 40
        // shifted far along x, and the one that matters at y = 1 over the origin.
        let mut casters = vec![Caster {
            mesh,
            model: Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
        }];
        for k in 0..40 {
            casters.push(Caster {
                mesh,
                model: Mat4::from_translation(Vec3::new(5.0 + k as f32, 1.0 + k as f32, 0.0)),
            });
        }
        let occ = Occluders::new(&casters);
        assert_eq!(occ.len(), 82);
        let up = RayTarget::Direction(DVec3::Y);
        // Under the square: dark; just past its edge: lit.
        assert_eq!(occ.visibility(DVec3::ZERO, up, None), 0.0);
        assert_eq!(occ.visibility(DVec3::new(0.4999, 0.0, 0.0), up, None), 0.0);
        assert_eq!(occ.visibility(DVec3::new(0.5001, 0.0, 0.0), up, None), 1.0);
        // Above it, or a light below the square: lit.
        assert_eq!(occ.visibility(DVec3::new(0.0, 1.5, 0.0), up, None), 1.0);
        let lamp = RayTarget::Position(DVec3::new(0.0, 0.5, 0.0));
        assert_eq!(occ.visibility(DVec3::ZERO, lamp, None), 1.0);
        // A point light above: the shadow widens with the distance below.
        let high = RayTarget::Position(DVec3::new(0.0, 2.0, 0.0));
        // The square's edge at x = 0.5 projects from y = 2 through y = 1 to x = 1 at y = 0.
        assert_eq!(occ.visibility(DVec3::new(0.99, 0.0, 0.0), high, None), 0.0);
        assert_eq!(occ.visibility(DVec3::new(1.01, 0.0, 0.0), high, None), 1.0);
        // On the square itself (its own surface): lit; and on one of the far copies.
        assert_eq!(occ.visibility(DVec3::new(0.1, 1.0, 0.1), up, None), 1.0);
        assert_eq!(occ.visibility(DVec3::new(20.0, 16.0, 0.0), up, None), 1.0);
        assert_eq!(occ.visibility(DVec3::new(20.0, 15.5, 0.0), up, None), 0.0);
        // Not finite, or a light at the point: lit, never NaN.
        assert_eq!(occ.visibility(DVec3::NAN, up, None), 1.0);
        assert_eq!(
            occ.visibility(DVec3::ZERO, RayTarget::Position(DVec3::ZERO), None),
            1.0
        );
        assert_eq!(
            occ.visibility(DVec3::ZERO, RayTarget::Direction(DVec3::ZERO), None),
            1.0
        );
        // A ray in the squares' own plane meets no face of them.
        let side = RayTarget::Direction(DVec3::X);
        assert_eq!(occ.visibility(DVec3::new(-3.0, 1.0, 0.0), side, None), 1.0);
        // A receiver's own triangles let its rays by; the others still block them.
        assert_eq!(occ.visibility(DVec3::ZERO, up, Some(0)), 1.0);
        assert_eq!(
            occ.visibility(DVec3::new(20.0, 15.5, 0.0), up, Some(0)),
            0.0
        );
        assert_eq!(
            occ.visibility(DVec3::new(20.0, 15.5, 0.0), up, Some(16)),
            1.0
        );
    }
}
