//! The Mach-band measure of `phosphor accuracy`: how sharply a picture changes across the
//! interior edges of its meshes (docs/conventions.md, "The Mach-band measure").
//!
//! The eye turns a jump in intensity, and a jump in the intensity's slope, into a light or dark
//! band along the edge where it happens (the Mach band effect). The lecture notes say flat shading
//! shows such bands at every edge, Gouraud 1971 still shows them, and Phong 1975 "greatly
//! reduces" them. This module measures it:
//!
//! - [`triangle_ids`] renders, with the public raster API, which triangle each pixel shows;
//! - [`edge_jumps`] takes the pixel pairs that straddle an edge shared by two triangles of one
//!   mesh, and measures there the jump of the value (for flat shading) or of the one-pixel slope
//!   (every other mode), averaged per edge, then over edges;
//! - [`jump_map`] paints the jumps as a false-colour image.
//!
//! Values are the mean of the three channels of the clamped framebuffer, so a jump is in the
//! framebuffer's units (1 = the whole display range).

use std::collections::{HashMap, HashSet};

use phosphor_lighting::{Effects, Light, LightSet, Material};
use phosphor_math::glam::{Mat3, Vec3};
use phosphor_raster::{DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode, render};
use phosphor_scene::{FrameOptions, Scene, draw_items, plan_frame, raster_options};

use crate::accuracy::{heat_colour, scale_bar_image};
use crate::rgb8::Rgb8Image;

/// No triangle (background, or a colour that did not decode to an id).
pub const NO_ID: u32 = u32::MAX;

/// The colour of [`jump_map`] for mesh pixels outside every measured pair.
pub const MESH_GREY: [u8; 3] = [48, 48, 48];

/// Which triangle each pixel shows, and which triangles share an edge.
#[derive(Clone, Debug, Default)]
pub struct TriangleIds {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major ids, [`NO_ID`] where no triangle was decoded.
    pub ids: Vec<u32>,
    /// Unordered pairs `(a, b)`, `a < b`, of triangles of one mesh sharing an edge (both corner
    /// positions bit-identical).
    pub adjacent: HashSet<(u32, u32)>,
    /// Pixels that showed a triangle but whose colour did not decode to a valid id.
    pub undecoded: usize,
}

/// Grid size of the id encoding for `count` triangles: `k * k >= count`.
fn grid_side(count: usize) -> u32 {
    let mut k = (count as f64).sqrt().ceil() as u32;
    while (k as usize) * (k as usize) < count {
        k += 1;
    }
    k.max(1)
}

/// The unit normal that encodes `id` on a `k` x `k` grid: the direction of
/// `(1, (i + 0.5)/k, (j + 0.5)/k)` with `i = id mod k`, `j = id div k`. Lit by unit lights along
/// +X, +Y, +Z with `kd = 1` it shows as that colour; [`decode_id`] reads it back from the
/// ratios green/red and blue/red, which keep half a grid cell of margin against rounding.
#[must_use]
pub fn encode_id(id: u32, k: u32) -> Vec3 {
    let (i, j) = (id % k, id / k);
    let k = k as f32;
    Vec3::new(1.0, (i as f32 + 0.5) / k, (j as f32 + 0.5) / k).normalize()
}

/// The id a colour encodes on a `k` x `k` grid, if it is one: red above `1/sqrt(3)` (every
/// encoding's is), both ratios within a quarter cell of a cell centre, the id below `count`.
#[must_use]
pub fn decode_id(c: Vec3, k: u32, count: usize) -> Option<u32> {
    if !c.is_finite() || c.x < 0.5 {
        return None;
    }
    let cell = |ratio: f32| -> Option<u32> {
        let t = f64::from(ratio) * f64::from(k);
        let index = t.floor();
        let off_centre = (t - index - 0.5).abs();
        (off_centre < 0.25 && index >= 0.0 && index < f64::from(k)).then_some(index as u32)
    };
    let i = cell(c.y / c.x)?;
    let j = cell(c.z / c.x)?;
    let id = j.checked_mul(k)?.checked_add(i)?;
    ((id as usize) < count).then_some(id)
}

/// Bit patterns of a position, for exact comparison and hashing.
fn key(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// Which triangle each pixel of `scene`'s frame at `width` x `height` shows.
///
/// Renders the frame's draws once more (same plan, positions, model matrices, camera and raster
/// options, so the same depth test picks the same triangle) with every triangle on three vertices
/// of its own whose normals encode its id ([`encode_id`], pre-multiplied by the inverse of the
/// normal matrix the rasterizer applies), `kd = 1` under three unit directional lights along +X,
/// +Y, +Z, nothing else, in `gouraud`: each pixel's colour is its triangle's normal, and
/// [`decode_id`] reads it back. The ids number the draws' triangles in order.
#[must_use]
pub fn triangle_ids(scene: &Scene, width: u32, height: u32, opts: &FrameOptions) -> TriangleIds {
    let camera = scene.camera();
    let plan = plan_frame(scene, &camera, (width, height), opts);
    let draws = draw_items(&plan);
    let count: usize = draws.iter().map(|d| d.mesh.indices.len()).sum();
    let k = grid_side(count);
    let mut adjacent = HashSet::new();
    let mut meshes = Vec::with_capacity(draws.len());
    let mut first_id = 0u32;
    for d in &draws {
        meshes.push(id_mesh(d, first_id, k));
        collect_adjacency(d.mesh, first_id, &mut adjacent);
        first_id = first_id.saturating_add(u32::try_from(d.mesh.indices.len()).unwrap_or(u32::MAX));
    }
    let lights = LightSet::new(Vec3::ZERO, &id_lights());
    let material = Material {
        ka: Vec3::ZERO,
        kd: Vec3::ONE,
        ks: Vec3::ZERO,
        ..Material::default()
    };
    let id_draws: Vec<DrawItem> = draws
        .iter()
        .zip(&meshes)
        .map(|(d, m)| DrawItem {
            mesh: MeshView {
                positions: &m.0,
                normals: &m.1,
                uvs: None,
                tangents: None,
                colors: None,
                indices: &m.2,
            },
            model: d.model,
            material: &material,
            lights: &lights,
            effects: Effects::DIFFUSE,
            mode: ShadingMode::Gouraud,
            bump: None,
            texture: None,
            // The same triangles as the picture's draw: culling hides no visible pixel.
            cull_backfaces: d.cull_backfaces,
        })
        .collect();
    let options = RenderOptions {
        background: Vec3::ZERO,
        ..raster_options(scene, opts)
    };
    let mut ids = TriangleIds {
        width,
        height,
        adjacent,
        ..TriangleIds::default()
    };
    let Ok(mut fb) = Framebuffer::new(width, height) else {
        return ids;
    };
    render(&mut fb, &camera, &id_draws, &options);
    ids.ids = fb
        .color()
        .iter()
        .map(|&c| {
            if c == Vec3::ZERO {
                return NO_ID;
            }
            decode_id(c, k, count).unwrap_or_else(|| {
                ids.undecoded += 1;
                NO_ID
            })
        })
        .collect();
    ids
}

/// Unit lights along +X, +Y and +Z, one colour channel each.
fn id_lights() -> Vec<Light> {
    [Vec3::X, Vec3::Y, Vec3::Z]
        .into_iter()
        // A directional light's direction is where its light travels: away from the axis.
        .filter_map(|axis| Light::directional(-axis, axis).ok())
        .collect()
}

/// The draw's triangles, each on three vertices of its own with the normal that encodes its id
/// (in object space: the rasterizer multiplies normals by the inverse transpose of the model's
/// 3x3 part, so the object-space normal is that matrix's inverse, the transpose, times the
/// wanted world normal).
fn id_mesh(d: &DrawItem, first_id: u32, k: u32) -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
    let m3 = Mat3::from_mat4(d.model);
    let to_object = if m3.inverse().is_finite() {
        m3.transpose()
    } else {
        Mat3::IDENTITY
    };
    let tris = d.mesh.indices;
    let mut positions = Vec::with_capacity(tris.len() * 3);
    let mut normals = Vec::with_capacity(tris.len() * 3);
    let mut indices = Vec::with_capacity(tris.len());
    for (t, tri) in tris.iter().enumerate() {
        let Some(corners) = tri
            .iter()
            .map(|&i| d.mesh.positions.get(i as usize).copied())
            .collect::<Option<Vec<Vec3>>>()
        else {
            // Out-of-range indices: the rasterizer skips the triangle; so does the id render.
            continue;
        };
        let id = first_id.saturating_add(u32::try_from(t).unwrap_or(u32::MAX));
        let n = (to_object * encode_id(id, k)).normalize_or_zero();
        let base = u32::try_from(positions.len()).unwrap_or(u32::MAX);
        positions.extend(corners);
        normals.extend([n; 3]);
        indices.push([base, base + 1, base + 2]);
    }
    (positions, normals, indices)
}

/// Adds the pairs of the mesh's triangles that share an edge (by corner positions).
fn collect_adjacency(mesh: MeshView, first_id: u32, adjacent: &mut HashSet<(u32, u32)>) {
    let mut by_edge: HashMap<([u32; 3], [u32; 3]), Vec<u32>> = HashMap::new();
    for (t, tri) in mesh.indices.iter().enumerate() {
        let Some(p) = tri
            .iter()
            .map(|&i| mesh.positions.get(i as usize).map(|&p| key(p)))
            .collect::<Option<Vec<[u32; 3]>>>()
        else {
            continue;
        };
        let id = first_id.saturating_add(u32::try_from(t).unwrap_or(u32::MAX));
        for (a, b) in [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])] {
            if a != b {
                by_edge.entry((a.min(b), a.max(b))).or_default().push(id);
            }
        }
    }
    for tris in by_edge.values() {
        for (n, &a) in tris.iter().enumerate() {
            for &b in &tris[n + 1..] {
                if a != b {
                    adjacent.insert((a.min(b), a.max(b)));
                }
            }
        }
    }
}

/// What is measured across an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JumpKind {
    /// `|s(q) - s(p)|` for the pixels `p | q` on either side.
    Value,
    /// `|(s(q+1) - s(q)) - (s(p) - s(p-1))|`, the change of the one-pixel slope, with `p-1` on
    /// `p`'s triangle and `q+1` on `q`'s.
    Slope,
}

impl JumpKind {
    /// The kind a shading mode is judged by: the value for flat shading (constant per
    /// triangle, so its slope is 0 on both sides), the slope for every other mode.
    #[must_use]
    pub fn for_mode(mode: Option<ShadingMode>) -> JumpKind {
        if mode == Some(ShadingMode::Flat) {
            JumpKind::Value
        } else {
            JumpKind::Slope
        }
    }
}

/// The jumps of one image across the interior edges.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EdgeJumps {
    /// Mean over edges of each edge's mean jump; NaN when no edge was measured.
    pub mean: f64,
    /// Edges (triangle pairs) with at least one measured pixel pair.
    pub edges: usize,
    /// Pixel pairs measured.
    pub pairs: usize,
    /// Per pixel, the largest jump of a pair it belongs to (0 elsewhere).
    pub per_pixel: Vec<f32>,
    /// Per pixel, whether it belongs to a measured pair.
    pub measured: Vec<bool>,
}

/// The value the measure reads: the mean of the three channels.
fn value(c: Vec3) -> f64 {
    (f64::from(c.x) + f64::from(c.y) + f64::from(c.z)) / 3.0
}

/// Measures `image` (row-major, `ids.width` x `ids.height`) across the interior edges of
/// `ids`: every horizontally or vertically adjacent pixel pair whose triangles differ and share
/// an edge. Returns zero edges when the sizes differ.
#[must_use]
pub fn edge_jumps(image: &[Vec3], ids: &TriangleIds, kind: JumpKind) -> EdgeJumps {
    let (w, h) = (ids.width as usize, ids.height as usize);
    let mut out = EdgeJumps {
        mean: f64::NAN,
        per_pixel: vec![0.0; image.len()],
        measured: vec![false; image.len()],
        ..EdgeJumps::default()
    };
    if image.len() != w * h || ids.ids.len() != w * h || w == 0 || h == 0 {
        return out;
    }
    let id = |x: usize, y: usize| ids.ids[y * w + x];
    let s = |x: usize, y: usize| value(image[y * w + x]);
    let mut per_edge: HashMap<(u32, u32), (f64, u32)> = HashMap::new();
    // (dx, dy): the step from p to q.
    for (dx, dy) in [(1usize, 0usize), (0, 1)] {
        for y in 0..h - dy {
            for x in 0..w - dx {
                let (a, b) = (id(x, y), id(x + dx, y + dy));
                if a == NO_ID
                    || b == NO_ID
                    || a == b
                    || !ids.adjacent.contains(&(a.min(b), a.max(b)))
                {
                    continue;
                }
                let (qx, qy) = (x + dx, y + dy);
                let jump = match kind {
                    JumpKind::Value => (s(qx, qy) - s(x, y)).abs(),
                    JumpKind::Slope => {
                        // p - 1 and q + 1 must lie inside the image and on p's and q's
                        // triangles.
                        if x < dx || y < dy || qx + dx >= w || qy + dy >= h {
                            continue;
                        }
                        let (px0, py0) = (x - dx, y - dy);
                        let (qx1, qy1) = (qx + dx, qy + dy);
                        if id(px0, py0) != a || id(qx1, qy1) != b {
                            continue;
                        }
                        let before = s(x, y) - s(px0, py0);
                        let after = s(qx1, qy1) - s(qx, qy);
                        (after - before).abs()
                    }
                };
                let e = per_edge.entry((a.min(b), a.max(b))).or_insert((0.0, 0));
                e.0 += jump;
                e.1 += 1;
                out.pairs += 1;
                for i in [y * w + x, qy * w + qx] {
                    out.per_pixel[i] = out.per_pixel[i].max(jump as f32);
                    out.measured[i] = true;
                }
            }
        }
    }
    out.edges = per_edge.len();
    if out.edges > 0 {
        let sum: f64 = per_edge.values().map(|&(s, n)| s / f64::from(n)).sum();
        out.mean = sum / out.edges as f64;
    }
    out
}

/// The jumps as a false-colour image over `[0, scale]` (labelled scale bar on the right):
/// measured pixels in heat colours, the rest of the meshes dark grey, the background black.
#[must_use]
pub fn jump_map(jumps: &EdgeJumps, ids: &TriangleIds, scale: f32) -> Option<Rgb8Image> {
    if jumps.per_pixel.len() != ids.ids.len() {
        return None;
    }
    let scale = if scale.is_finite() && scale > 0.0 {
        scale
    } else {
        1.0
    };
    scale_bar_image(ids.width, ids.height, |i| {
        if jumps.measured[i] {
            heat_colour(jumps.per_pixel[i] / scale)
        } else if ids.ids[i] != NO_ID {
            MESH_GREY
        } else {
            [0, 0, 0]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_survive_the_encoding_and_other_colours_do_not_decode() {
        for count in [1usize, 2, 5, 100, 69_451, 1 << 20] {
            let k = grid_side(count);
            let ids = [0u32, 1, (count / 2) as u32, (count - 1) as u32];
            for id in ids.into_iter().filter(|&id| (id as usize) < count) {
                let c = encode_id(id, k);
                assert!((c.length() - 1.0).abs() < 1e-6);
                // Rounding of a few units of f32 in each channel changes nothing.
                let off = c * (1.0 + 4.0 * f32::EPSILON);
                assert_eq!(decode_id(off, k, count), Some(id), "{id} of {count}");
            }
        }
        let k = grid_side(100);
        assert_eq!(decode_id(Vec3::ZERO, k, 100), None);
        assert_eq!(decode_id(Vec3::new(f32::NAN, 0.5, 0.5), k, 100), None);
        // Half-way between two cells (a blend of two ids) is rejected.
        let blend = (encode_id(3, k) + encode_id(4, k)) * 0.5;
        assert_eq!(decode_id(blend, k, 100), None);
        // An id past the count is rejected.
        assert_eq!(decode_id(encode_id(99, k), k, 50), None);
    }

    /// A 6x1 strip: triangles 0 | 1 | 2, two pixels each, 0 and 1 adjacent, 1 and 2 not.
    fn strip() -> TriangleIds {
        TriangleIds {
            width: 6,
            height: 1,
            ids: vec![0, 0, 1, 1, 2, 2],
            adjacent: HashSet::from([(0, 1)]),
            undecoded: 0,
        }
    }

    #[test]
    fn value_jumps_are_measured_only_across_shared_edges() {
        // Grey levels 0.1 0.1 | 0.4 0.4 | 0.9 0.9: one shared edge, jump 0.3.
        let image: Vec<Vec3> = [0.1, 0.1, 0.4, 0.4, 0.9, 0.9].map(Vec3::splat).to_vec();
        let j = edge_jumps(&image, &strip(), JumpKind::Value);
        assert_eq!((j.edges, j.pairs), (1, 1));
        assert!((j.mean - 0.3).abs() < 1e-6, "{}", j.mean);
        assert!(j.measured[1] && j.measured[2] && !j.measured[4]);
        // The mean of the channels: (0, 0, 0.3) to (0.3, 0, 0.3) is a jump of 0.1.
        let mut colour = image.clone();
        colour[1] = Vec3::new(0.0, 0.0, 0.3);
        colour[2] = Vec3::new(0.3, 0.0, 0.3);
        let j = edge_jumps(&colour, &strip(), JumpKind::Value);
        assert!((j.mean - 0.1).abs() < 1e-6, "{}", j.mean);
    }

    #[test]
    fn slope_jumps_compare_the_slopes_on_either_side() {
        // 0.1 0.2 | 0.5 0.9: slope 0.1 before the edge, 0.4 after: a kink of 0.3.
        let image: Vec<Vec3> = [0.1, 0.2, 0.5, 0.9, 0.0, 0.0].map(Vec3::splat).to_vec();
        let j = edge_jumps(&image, &strip(), JumpKind::Slope);
        assert_eq!((j.edges, j.pairs), (1, 1));
        assert!((j.mean - 0.3).abs() < 1e-6, "{}", j.mean);
        // A straight ramp across the edge has no kink.
        let ramp: Vec<Vec3> = (0..6).map(|i| Vec3::splat(i as f32 * 0.1)).collect();
        let j = edge_jumps(&ramp, &strip(), JumpKind::Slope);
        assert!(j.mean.abs() < 1e-6, "{}", j.mean);
        // A triangle one pixel wide gives no slope on its side: nothing measured.
        let narrow = TriangleIds {
            ids: vec![0, 1, 1, 1, 2, 2],
            ..strip()
        };
        let j = edge_jumps(&image, &narrow, JumpKind::Slope);
        assert_eq!(j.edges, 0);
        assert!(j.mean.is_nan());
    }

    #[test]
    fn the_mean_is_over_edges_not_over_pixel_pairs() {
        // 4x3: triangles 0 | 1 on every row (three pairs, jump 0.1 each); 1 and 2 meet across
        // the top right (one horizontal and one vertical pair, jump 0.5 each). Per edge:
        // (0.1 + 0.5)/2 = 0.3; per pair it would be (3 * 0.1 + 2 * 0.5)/5 = 0.26.
        let ids = TriangleIds {
            width: 4,
            height: 3,
            ids: vec![0, 0, 1, 2, 0, 0, 1, 1, 0, 0, 1, 1],
            adjacent: HashSet::from([(0, 1), (1, 2)]),
            undecoded: 0,
        };
        let image: Vec<Vec3> = [
            0.0, 0.0, 0.1, 0.6, //
            0.0, 0.0, 0.1, 0.1, //
            0.0, 0.0, 0.1, 0.1,
        ]
        .map(Vec3::splat)
        .to_vec();
        let j = edge_jumps(&image, &ids, JumpKind::Value);
        assert_eq!((j.edges, j.pairs), (2, 5));
        assert!((j.mean - 0.3).abs() < 1e-6, "{}", j.mean);
    }

    /// Flat shading is constant over each triangle: every pixel of one id must have the same
    /// flat colour, whatever the object's transform (rotated and scaled unevenly here, which
    /// the id normals must undo).
    #[test]
    fn ids_partition_the_frame_into_the_flat_render_triangles() {
        let scene = Scene::parse(
            "[[lights]]\ntype = \"point\"\nposition = [2, 2, 2]\nintensity = 3\n\
             [materials.m]\nkd = [0.8, 0.6, 0.4]\nks = 0.5\nshininess = 16\n\
             [[objects]]\nprimitive = { shape = \"sphere\", segments = 24, rings = 12 }\n\
             material = \"m\"\n\
             transform = { rotate_deg = [30, 50, 10], scale = [1.2, 0.7, 0.9] }\n",
            "ids.toml",
        )
        .expect("valid scene");
        let (w, h) = (160, 120);
        let opts = FrameOptions {
            shading: Some(phosphor_scene::ShadingChoice::Mode(ShadingMode::Flat)),
            ..FrameOptions::default()
        };
        let ids = triangle_ids(&scene, w, h, &opts);
        assert_eq!(ids.undecoded, 0);
        let mut fb = Framebuffer::new(w, h).expect("size");
        phosphor_scene::render_frame(&scene, &mut fb, &opts);
        let mut colour_of: HashMap<u32, Vec3> = HashMap::new();
        for (&id, &c) in ids.ids.iter().zip(fb.color()) {
            if id == NO_ID {
                assert_eq!(c, Vec3::ZERO, "background where no triangle is");
                continue;
            }
            let first = *colour_of.entry(id).or_insert(c);
            assert_eq!(first, c, "triangle {id} has two flat colours");
        }
        // Most of the front half's 24 * 12 * 2 triangles are seen, and they have neighbours.
        assert!(colour_of.len() > 150, "{} triangles seen", colour_of.len());
        assert!(
            ids.adjacent.len() > 400,
            "{} adjacent pairs",
            ids.adjacent.len()
        );
        let flat: Vec<Vec3> = fb.color().to_vec();
        let j = edge_jumps(&flat, &ids, JumpKind::Value);
        assert!(
            j.edges > 100 && j.mean > 0.0,
            "{} edges, mean {}",
            j.edges,
            j.mean
        );
    }

    #[test]
    fn the_jump_map_paints_measured_pixels_grey_meshes_and_black_background() {
        let mut ids = strip();
        ids.ids[5] = NO_ID;
        let image: Vec<Vec3> = [0.1, 0.1, 0.4, 0.4, 0.9, 0.0].map(Vec3::splat).to_vec();
        let j = edge_jumps(&image, &ids, JumpKind::Value);
        let map = jump_map(&j, &ids, 0.3).expect("sizes match");
        let at = |x: usize| &map.data[x * 3..x * 3 + 3];
        assert_eq!(at(1), heat_colour(1.0));
        assert_eq!(at(0), MESH_GREY);
        assert_eq!(at(5), [0, 0, 0]);
    }
}
