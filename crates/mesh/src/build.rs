//! From a welded triangle soup (what the OBJ loader produces) to a [`Mesh`] whose vertices are
//! split where surfaces meet.

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};

use crate::mesh::Mesh;
use crate::normals::{self, NormalOptions, NormalSource, SmoothRule};

mod surfaces;

use surfaces::surface_ids;

/// Triangles over shared (welded) positions, before vertex normals exist.
///
/// Build one by hand, or get one from a [`Mesh`] with [`Mesh::to_soup`], then turn it into a
/// mesh with [`TriangleSoup::build`].
#[derive(Clone, Debug, Default)]
pub struct TriangleSoup {
    /// Unique positions: faces that share a position share an index here.
    pub positions: Vec<Vec3>,
    /// Triangles (counter-clockwise = front) indexing `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates and, per triangle, the uv index of each corner.
    pub uvs: Option<(Vec<Vec2>, Vec<[u32; 3]>)>,
    /// Authored normals (`vn`) and, per triangle, the normal index of each corner.
    pub normals: Option<(Vec<Vec3>, Vec<[u32; 3]>)>,
    /// Vertex colours (linear RGB in `[0, 1]`) and, per triangle, the colour index of each
    /// corner.
    pub colors: Option<(Vec<Vec3>, Vec<[u32; 3]>)>,
    /// Authored tangents (glTF `TANGENT`: `xyz` and handedness `w`) and, per triangle, the
    /// tangent index of each corner. Used only with the authored normals (they are a frame
    /// around them); otherwise tangents are computed from the uvs.
    pub tangents: Option<(Vec<Vec4>, Vec<[u32; 3]>)>,
    /// Per triangle smoothing group (0 = off), or `None` when the source had no `s` lines.
    pub smoothing_groups: Option<Vec<u32>>,
    /// Per triangle material id (empty = all 0).
    pub material_ids: Vec<u32>,
    /// Per triangle: the source polygon it was triangulated from (empty = each triangle is its own
    /// polygon). Uniform weighting counts a polygon once per vertex, as the lecture notes' `N_v`
    /// counts faces, and triangles of one polygon are always smoothed together.
    pub polygon_ids: Vec<u32>,
}

impl TriangleSoup {
    /// Drops triangles with an index out of range (so `build` never panics on hand-made soups);
    /// a per-corner attribute whose index list is not one per triangle is dropped.
    fn sanitized(&self) -> TriangleSoup {
        let np = self.positions.len() as u32;
        let t = self.triangles.len();
        let uvs = Attribute::new(&self.uvs, t);
        let normals = Attribute::new(&self.normals, t);
        let colors = Attribute::new(&self.colors, t);
        let tangents = Attribute::new(&self.tangents, t);
        let keep: Vec<usize> = (0..t)
            .filter(|&i| {
                self.triangles[i].iter().all(|&v| v < np)
                    && uvs.in_range(i)
                    && normals.in_range(i)
                    && colors.in_range(i)
                    && tangents.in_range(i)
            })
            .collect();
        let pick = |v: &Vec<[u32; 3]>| keep.iter().map(|&i| v[i]).collect::<Vec<_>>();
        TriangleSoup {
            positions: self.positions.clone(),
            triangles: pick(&self.triangles),
            uvs: uvs.pick(&keep),
            normals: normals.pick(&keep),
            colors: colors.pick(&keep),
            tangents: tangents.pick(&keep),
            smoothing_groups: self
                .smoothing_groups
                .as_ref()
                .filter(|g| g.len() == t)
                .map(|g| keep.iter().map(|&i| g[i]).collect()),
            material_ids: if self.material_ids.len() == t {
                keep.iter().map(|&i| self.material_ids[i]).collect()
            } else {
                vec![0; keep.len()]
            },
            polygon_ids: if self.polygon_ids.len() == t {
                keep.iter().map(|&i| self.polygon_ids[i]).collect()
            } else {
                (0..keep.len() as u32).collect()
            },
        }
    }

    /// Builds the mesh: vertex normals per `opts` (see [`crate::normals`]), vertices split where
    /// surfaces, normals, uvs, colours or authored tangents differ, surface ids, and tangents
    /// (the authored ones with authored normals, else MikkTSpace's where uvs exist).
    /// Non-finite positions are not expected (the loader rejects them); triangles with an
    /// index out of range are dropped.
    #[must_use]
    pub fn build(&self, opts: &NormalOptions) -> Mesh {
        let soup = self.sanitized();
        let tris = &soup.triangles;
        let t = tris.len();
        let groups = soup.smoothing_groups.clone().unwrap_or_else(|| vec![0; t]);
        let rule = SmoothRule::resolve(opts, soup.smoothing_groups.is_some());
        let faces = normals::face_data(&soup.positions, tris);
        let labels = normals::FaceLabels {
            groups: &groups,
            materials: &soup.material_ids,
            polygons: &soup.polygon_ids,
        };
        let surfaces = surface_ids(&soup.positions, tris, &faces, &labels, &rule);

        let authored = match (&soup.normals, opts.source) {
            (Some(n), NormalSource::Authored) => Some(n),
            _ => None,
        };
        let corner_normal: Vec<Vec3> = match authored {
            Some((vn, idx)) => {
                let mut out = Vec::with_capacity(t * 3);
                for (ti, corners) in idx.iter().enumerate() {
                    let own = faces.normal[ti].map_or(Vec3::Z, |n| n.as_vec3());
                    for &i in corners {
                        out.push(phosphor_math::safe_normalize(vn[i as usize], own));
                    }
                }
                out
            }
            None => normals::corner_normals(
                &soup.positions,
                tris,
                &faces,
                &labels,
                opts.weighting,
                &rule,
                &surfaces,
            ),
        };

        let tangents = soup
            .tangents
            .as_ref()
            .filter(|_| authored.is_some() && soup.uvs.is_some());
        // One vertex per distinct (position, surface, normal, uv, colour, tangent).
        let mut map: HashMap<VertexKey, u32> = HashMap::new();
        let mut mesh = Mesh::default();
        let mut uvs_out = soup.uvs.as_ref().map(|_| Vec::new());
        let mut colors_out = soup.colors.as_ref().map(|_| Vec::new());
        let mut tangents_out = tangents.map(|_| Vec::new());
        for (ti, tri) in tris.iter().enumerate() {
            let mut out = [0u32; 3];
            for k in 0..3 {
                let n = corner_normal[ti * 3 + k];
                let uv = soup.uvs.as_ref().map_or(u32::MAX, |(_, ix)| ix[ti][k]);
                let color = soup
                    .colors
                    .as_ref()
                    .map_or(Vec3::NAN, |(c, ix)| c[ix[ti][k] as usize]);
                let tangent = tangents.map_or(u32::MAX, |(_, ix)| ix[ti][k]);
                let key = VertexKey {
                    position: tri[k],
                    surface: surfaces[ti],
                    normal: n.to_array().map(f32::to_bits),
                    uv,
                    color: color.to_array().map(f32::to_bits),
                    tangent,
                };
                out[k] = *map.entry(key).or_insert_with(|| {
                    mesh.positions.push(soup.positions[tri[k] as usize]);
                    mesh.normals.push(n);
                    if let (Some(dst), Some((src, _))) = (uvs_out.as_mut(), soup.uvs.as_ref()) {
                        dst.push(src[uv as usize]);
                    }
                    if let Some(dst) = colors_out.as_mut() {
                        dst.push(color);
                    }
                    if let (Some(dst), Some((src, _))) = (tangents_out.as_mut(), tangents) {
                        dst.push(authored_tangent(src[tangent as usize], n));
                    }
                    (mesh.positions.len() - 1) as u32
                });
            }
            mesh.indices.push(out);
        }
        mesh.uvs = uvs_out;
        mesh.colors = colors_out;
        mesh.tangents = tangents_out;
        mesh.surface_ids = surfaces;
        mesh.material_ids = soup.material_ids.clone();
        mesh.smoothing_groups = groups;
        if mesh.uvs.is_some() && mesh.tangents.is_none() {
            mesh.compute_tangents();
        }
        mesh
    }
}

/// What makes a vertex distinct when the soup is split into vertices.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct VertexKey {
    position: u32,
    surface: u32,
    normal: [u32; 3],
    /// Index into the soup's uvs (`u32::MAX`: none).
    uv: u32,
    /// The colour's bits (NaN: none): a colour given per corner (glTF) or per model (OBJ)
    /// splits a vertex only where the values differ.
    color: [u32; 3],
    /// Index into the soup's authored tangents (`u32::MAX`: none).
    tangent: u32,
}

/// An authored tangent as the mesh keeps it: `xyz` unit, `w` +1 or -1 (negative `w` is -1);
/// one that is zero or not finite is replaced by [`crate::fallback_tangent`] of `normal`.
fn authored_tangent(t: Vec4, normal: Vec3) -> Vec4 {
    let xyz = t.truncate();
    let len = xyz.length();
    if !(len > 1e-12 && len.is_finite() && t.w.is_finite()) {
        return crate::tangents::fallback_tangent(normal);
    }
    let w = if t.w < 0.0 { -1.0 } else { 1.0 };
    phosphor_math::safe_normalize(xyz / len, Vec3::X).extend(w)
}

/// A per-corner attribute of a soup while it is sanitized.
struct Attribute<'a, T> {
    /// The values and their per-triangle indices, when the indices are one per triangle.
    data: Option<&'a (Vec<T>, Vec<[u32; 3]>)>,
}

impl<'a, T: Clone> Attribute<'a, T> {
    fn new(data: &'a Option<(Vec<T>, Vec<[u32; 3]>)>, triangles: usize) -> Self {
        Attribute {
            data: data.as_ref().filter(|(_, ix)| ix.len() == triangles),
        }
    }

    /// Whether triangle `t`'s corners index existing values (true when there are none).
    fn in_range(&self, t: usize) -> bool {
        self.data
            .is_none_or(|(v, ix)| ix[t].iter().all(|&i| (i as usize) < v.len()))
    }

    /// The attribute for the kept triangles.
    fn pick(&self, keep: &[usize]) -> Option<(Vec<T>, Vec<[u32; 3]>)> {
        self.data
            .map(|(v, ix)| (v.clone(), keep.iter().map(|&i| ix[i]).collect()))
    }
}

impl Mesh {
    /// The mesh as a soup with positions welded by exact equality (`-0.0 == 0.0`), keeping
    /// uvs, colours, smoothing groups and material ids, without normals (nor tangents, a frame
    /// around them): the input to recompute normals.
    #[must_use]
    pub fn to_soup(&self) -> TriangleSoup {
        let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
        let mut positions = Vec::new();
        let remap: Vec<u32> = self
            .positions
            .iter()
            .map(|p| {
                *weld.entry(weld_key(*p)).or_insert_with(|| {
                    positions.push(*p);
                    (positions.len() - 1) as u32
                })
            })
            .collect();
        let n = self.positions.len() as u32;
        let valid: Vec<[u32; 3]> = self
            .indices
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| i < n))
            .collect();
        let t = valid.len();
        TriangleSoup {
            triangles: valid.iter().map(|t| t.map(|i| remap[i as usize])).collect(),
            positions,
            uvs: self
                .uvs
                .clone()
                .filter(|u| u.len() == self.positions.len())
                .map(|u| (u, valid.clone())),
            colors: self
                .colors
                .clone()
                .filter(|c| c.len() == self.positions.len())
                .map(|c| (c, valid.clone())),
            normals: None,
            tangents: None,
            smoothing_groups: (self.smoothing_groups.len() == t
                && self.smoothing_groups.iter().any(|&g| g != 0))
            .then(|| self.smoothing_groups.clone()),
            material_ids: if self.material_ids.len() == t {
                self.material_ids.clone()
            } else {
                vec![0; t]
            },
            polygon_ids: Vec::new(),
        }
    }

    /// This mesh with vertex normals recomputed from its positions (welded by exact equality)
    /// per `opts`; materials and group names are kept.
    #[must_use]
    pub fn with_computed_normals(&self, opts: &NormalOptions) -> Mesh {
        let opts = NormalOptions {
            source: NormalSource::Computed,
            ..*opts
        };
        let mut m = self.to_soup().build(&opts);
        m.materials = self.materials.clone();
        m.groups = self.groups.clone();
        m
    }
}

/// A colour as the mesh keeps it: each component clamped to `[0, 1]` (NaN becomes 0).
pub(crate) fn unit_color(c: Vec3) -> Vec3 {
    Vec3::from_array(
        c.to_array()
            .map(|x| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) }),
    )
}

/// Bit pattern of a position for welding; `-0.0` and `0.0` weld together.
pub(crate) fn weld_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO)
        .to_array()
        .map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}
