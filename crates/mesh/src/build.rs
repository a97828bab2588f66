//! From a welded triangle soup (what the OBJ loader produces) to a [`Mesh`] whose vertices are
//! split where surfaces meet.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

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
    /// Drops triangles with an index out of range (so `build` never panics on hand-made soups).
    fn sanitized(&self) -> TriangleSoup {
        let np = self.positions.len() as u32;
        let nuv = self.uvs.as_ref().map_or(0, |u| u.0.len() as u32);
        let nn = self.normals.as_ref().map_or(0, |n| n.0.len() as u32);
        let t = self.triangles.len();
        let uv_ok = self.uvs.as_ref().is_some_and(|u| u.1.len() == t);
        let n_ok = self.normals.as_ref().is_some_and(|n| n.1.len() == t);
        let mut keep = Vec::with_capacity(t);
        for (i, tri) in self.triangles.iter().enumerate() {
            let ok = tri.iter().all(|&v| v < np)
                && (!uv_ok
                    || self
                        .uvs
                        .as_ref()
                        .is_some_and(|u| u.1[i].iter().all(|&v| v < nuv)))
                && (!n_ok
                    || self
                        .normals
                        .as_ref()
                        .is_some_and(|n| n.1[i].iter().all(|&v| v < nn)));
            if ok {
                keep.push(i);
            }
        }
        let pick = |v: &Vec<[u32; 3]>| keep.iter().map(|&i| v[i]).collect::<Vec<_>>();
        TriangleSoup {
            positions: self.positions.clone(),
            triangles: pick(&self.triangles),
            uvs: self
                .uvs
                .as_ref()
                .filter(|_| uv_ok)
                .map(|(u, ix)| (u.clone(), pick(ix))),
            normals: self
                .normals
                .as_ref()
                .filter(|_| n_ok)
                .map(|(n, ix)| (n.clone(), pick(ix))),
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
    /// surfaces, normals or uvs differ, surface ids, and tangents where uvs exist.
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

        // One vertex per distinct (position, surface, normal, uv).
        let mut map: HashMap<(u32, u32, [u32; 3], u32), u32> = HashMap::new();
        let mut mesh = Mesh::default();
        let mut uvs_out = soup.uvs.as_ref().map(|_| Vec::new());
        for (ti, tri) in tris.iter().enumerate() {
            let mut out = [0u32; 3];
            for k in 0..3 {
                let n = corner_normal[ti * 3 + k];
                let uv = soup.uvs.as_ref().map_or(u32::MAX, |(_, ix)| ix[ti][k]);
                let key = (tri[k], surfaces[ti], n.to_array().map(f32::to_bits), uv);
                out[k] = *map.entry(key).or_insert_with(|| {
                    mesh.positions.push(soup.positions[tri[k] as usize]);
                    mesh.normals.push(n);
                    if let (Some(dst), Some((src, _))) = (uvs_out.as_mut(), soup.uvs.as_ref()) {
                        dst.push(src[uv as usize]);
                    }
                    (mesh.positions.len() - 1) as u32
                });
            }
            mesh.indices.push(out);
        }
        mesh.uvs = uvs_out;
        mesh.surface_ids = surfaces;
        mesh.material_ids = soup.material_ids.clone();
        mesh.smoothing_groups = groups;
        if mesh.uvs.is_some() {
            mesh.compute_tangents();
        }
        mesh
    }
}

impl Mesh {
    /// The mesh as a soup with positions welded by exact equality (`-0.0 == 0.0`), keeping
    /// uvs, smoothing groups and material ids, without normals: the input to recompute normals.
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
            normals: None,
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

/// Bit pattern of a position for welding; `-0.0` and `0.0` weld together.
pub(crate) fn weld_key(p: Vec3) -> [u32; 3] {
    (p + Vec3::ZERO)
        .to_array()
        .map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}
