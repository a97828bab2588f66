//! The wireframe: triangle edges drawn over the frame, all or only the creases.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::LineStyle;
use super::line::{Depth, draw_clipped};
use crate::{Camera, DrawItem, Framebuffer, MeshView};

/// Which edges [`wireframe`] draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Edges {
    /// Every triangle edge.
    All,
    /// Edges where two faces meet at more than `angle_deg` degrees between their normals
    /// (a crease), edges of one face (the border of an open surface) and edges of more than
    /// two faces: the outline a smooth shading keeps, without the triangles of its curves.
    /// Triangles without a normal (zero area, or a vertex that is not finite) take no part.
    /// A NaN angle counts as 0 (every edge between faces that are not coplanar).
    Creases {
        /// The angle between neighbouring face normals above which an edge is drawn.
        angle_deg: f32,
    },
}

/// Draws the edges of every triangle of `draws` chosen by `edges`, each once, as seen by
/// `camera`, depth-tested against the frame in `fb`. Returns the pixels written.
///
/// Vertices are told apart by position, not by index: a mesh splits a vertex where its
/// normals or texture coordinates differ, and the edge along such a seam is still one edge,
/// between its two faces. Triangles with an index out of range or a repeated corner are
/// left out, and so are edges with a vertex that is not finite. Crease angles are measured
/// in object space (exact under the rotations and uniform scales of a model matrix).
pub fn wireframe(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    edges: Edges,
    style: LineStyle,
) -> u64 {
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let mut written = 0;
    for d in draws {
        let mvp = vp * d.model;
        for (a, b) in edge_list(&d.mesh, edges) {
            let p = mvp * d.mesh.positions[a as usize].extend(1.0);
            let q = mvp * d.mesh.positions[b as usize].extend(1.0);
            written += draw_clipped(fb, p, q, style, Depth::Tested);
        }
    }
    written
}

/// What is known of an edge while the faces are read.
struct EdgeFaces {
    /// Faces that have it.
    count: u32,
    /// The first face's normal (not unit).
    normal: DVec3,
    /// Two of its faces meet at more than the crease angle.
    creased: bool,
}

/// The edges of `mesh` that `edges` asks for, each once, as pairs of vertex indices (the
/// first index holding each position, smaller first), in the order the triangles first name
/// them; [`wireframe`] draws these. Vertices are matched by position (see [`wireframe`]).
#[must_use]
pub fn edge_list(mesh: &MeshView, edges: Edges) -> Vec<(u32, u32)> {
    let n = mesh.positions.len();
    // The first index holding each position (`-0.0` and `0.0` are one position).
    let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(n);
    let canonical: Vec<u32> = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            *first.entry(key).or_insert(i as u32)
        })
        .collect();
    let cos_limit = match edges {
        Edges::All => None,
        Edges::Creases { angle_deg } => {
            let a = if angle_deg.is_nan() { 0.0 } else { angle_deg };
            Some(f64::from(a.clamp(0.0, 180.0)).to_radians().cos())
        }
    };
    let mut seen: HashMap<(u32, u32), EdgeFaces> = HashMap::new();
    let mut order = Vec::new();
    for t in mesh.indices {
        if t.iter().any(|&i| i as usize >= n) {
            continue;
        }
        let [a, b, c] = t.map(|i| canonical[i as usize]);
        if a == b || b == c || c == a {
            continue;
        }
        let at = |i: u32| mesh.positions[i as usize].as_dvec3();
        let normal = (at(b) - at(a)).cross(at(c) - at(a));
        // A face without a normal (zero area, or a vertex that is not finite) meets its
        // neighbours at no defined angle: the crease test leaves it out, so an edge it shares
        // with one real face is that face's border.
        let length = normal.length();
        if cos_limit.is_some() && !(length > 0.0 && length.is_finite()) {
            continue;
        }
        for (p, q) in [(a, b), (b, c), (c, a)] {
            let key = (p.min(q), p.max(q));
            match seen.get_mut(&key) {
                Some(e) => {
                    e.count += 1;
                    if let Some(cos_limit) = cos_limit {
                        let len = e.normal.length() * length;
                        if e.normal.dot(normal) < cos_limit * len {
                            e.creased = true;
                        }
                    }
                }
                None => {
                    seen.insert(
                        key,
                        EdgeFaces {
                            count: 1,
                            normal,
                            creased: false,
                        },
                    );
                    order.push(key);
                }
            }
        }
    }
    order
        .into_iter()
        .filter(|key| {
            cos_limit.is_none() || {
                let e = &seen[key];
                e.count != 2 || e.creased
            }
        })
        .collect()
}
