//! From a welded triangle soup (what the OBJ loader produces) to a [`Mesh`] whose vertices are
//! split where surfaces meet.

use std::collections::HashMap;

use glam::{DVec3, Vec2, Vec3};

use crate::mesh::Mesh;
use crate::normals::{self, FaceData, NormalOptions, NormalSource, SmoothRule};

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

/// Union-find over triangles.
struct Components(Vec<u32>);

impl Components {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb) as usize] = ra.min(rb);
        }
    }
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

/// Triangles on one edge beyond which [`surface_ids`] stops testing every pair.
const MAX_PAIRWISE_EDGE: usize = 16;

/// Surface id per triangle: connected components of triangles joined across shared edges
/// when the smoothing rule joins them (group, material, crease), numbered from 0 in order.
///
/// An edge shared by at most [`MAX_PAIRWISE_EDGE`] triangles tests every pair. On a busier
/// edge (a face repeated thousands of times, a "book" of pages on one spine) the same
/// components come from near-linear work: triangles of one polygon are joined in a run;
/// within one group and material, a degenerate triangle (no normal) joins all, and otherwise
/// every normal is perpendicular to the edge, so sorted by their angle around it, two normals
/// are within the crease exactly when every step between them is: only neighbours in that
/// circular order need the crease test.
fn surface_ids(
    positions: &[Vec3],
    tris: &[[u32; 3]],
    faces: &FaceData,
    labels: &normals::FaceLabels<'_>,
    rule: &SmoothRule,
) -> Vec<u32> {
    let mut edges: Vec<(u64, u32)> = Vec::with_capacity(tris.len() * 3);
    for (ti, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                edges.push((key, ti as u32));
            }
        }
    }
    edges.sort_unstable();
    let mut comp = Components((0..tris.len() as u32).collect());
    let mut list: Vec<u32> = Vec::new();
    let mut start = 0;
    while start < edges.len() {
        let key = edges[start].0;
        let end = start + edges[start..].partition_point(|e| e.0 == key);
        list.clear();
        list.extend(edges[start..end].iter().map(|e| e.1));
        // A triangle listing the same edge twice (two corners welded) joins itself: harmless.
        let edge = [(key >> 32) as u32, key as u32].map(|i| positions[i as usize]);
        join_across_edge(&mut comp, &list, edge, faces, labels, rule);
        start = end;
    }
    let mut number: HashMap<u32, u32> = HashMap::new();
    (0..tris.len() as u32)
        .map(|t| {
            let root = comp.find(t);
            let next = number.len() as u32;
            *number.entry(root).or_insert(next)
        })
        .collect()
}

/// Joins the triangles of `list` (all sharing the edge between the positions `edge`) that
/// the smoothing rule joins; see [`surface_ids`].
fn join_across_edge(
    comp: &mut Components,
    list: &[u32],
    edge: [Vec3; 2],
    faces: &FaceData,
    labels: &normals::FaceLabels<'_>,
    rule: &SmoothRule,
) {
    let normals::FaceLabels {
        groups,
        materials,
        polygons,
    } = *labels;
    let angle_ok =
        |au: usize, bu: usize| match (faces.normal[au], faces.normal[bu], rule.cos_crease) {
            (Some(na), Some(nb), Some(cos)) => na.dot(nb) >= cos - 1e-9,
            _ => true,
        };
    if list.len() <= MAX_PAIRWISE_EDGE {
        for (i, &a) in list.iter().enumerate() {
            for &b in &list[i + 1..] {
                let (au, bu) = (a as usize, b as usize);
                let kind = (!rule.groups || (groups[au] == groups[bu] && groups[au] != 0))
                    && (!rule.split_by_material || materials[au] == materials[bu]);
                if (kind && angle_ok(au, bu)) || polygons[au] == polygons[bu] {
                    comp.union(a, b);
                }
            }
        }
        return;
    }
    // Triangles of one polygon: joined whatever their labels.
    let mut sorted: Vec<(u64, u32)> = list
        .iter()
        .map(|&t| (u64::from(polygons[t as usize]), t))
        .collect();
    sorted.sort_unstable();
    for w in sorted.windows(2) {
        if w[0].0 == w[1].0 {
            comp.union(w[0].1, w[1].1);
        }
    }
    // Classes of the group and material test; group 0 joins nothing when groups apply.
    sorted.clear();
    sorted.extend(list.iter().filter_map(|&t| {
        let t_us = t as usize;
        let g = if rule.groups { groups[t_us] } else { 0 };
        if rule.groups && g == 0 {
            return None;
        }
        let m = if rule.split_by_material {
            materials[t_us]
        } else {
            0
        };
        Some(((u64::from(g) << 32) | u64::from(m), t))
    }));
    sorted.sort_unstable();
    // Basis of the plane perpendicular to the edge, where every face normal on it lies.
    let axis = (edge[1].as_dvec3() - edge[0].as_dvec3())
        .try_normalize()
        .unwrap_or(DVec3::Z);
    let (u, v) = axis.any_orthonormal_pair();
    let mut class: Vec<(f64, u32)> = Vec::new();
    let mut start = 0;
    while start < sorted.len() {
        let key = sorted[start].0;
        let end = start + sorted[start..].partition_point(|e| e.0 == key);
        let members = &sorted[start..end];
        start = end;
        let join_all = rule.cos_crease.is_none()
            || members
                .iter()
                .any(|&(_, t)| faces.normal[t as usize].is_none());
        if join_all {
            for w in members.windows(2) {
                comp.union(w[0].1, w[1].1);
            }
            continue;
        }
        class.clear();
        class.extend(members.iter().map(|&(_, t)| {
            let n = faces.normal[t as usize].unwrap_or(DVec3::Z);
            (n.dot(v).atan2(n.dot(u)), t)
        }));
        class.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let len = class.len();
        for i in 0..len {
            let (a, b) = (class[i].1, class[(i + 1) % len].1);
            if a != b && angle_ok(a as usize, b as usize) {
                comp.union(a, b);
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The rule applied to every pair of triangles sharing an edge: the reference that the
    /// busy-edge path must match.
    fn pairwise_components(
        tris: &[[u32; 3]],
        faces: &FaceData,
        labels: &normals::FaceLabels<'_>,
        rule: &SmoothRule,
    ) -> Vec<u32> {
        let mut comp = Components((0..tris.len() as u32).collect());
        for a in 0..tris.len() {
            for b in a + 1..tris.len() {
                let shared = tris[a].iter().filter(|v| tris[b].contains(v)).count();
                if shared < 2 {
                    continue;
                }
                let kind = (!rule.groups
                    || (labels.groups[a] == labels.groups[b] && labels.groups[a] != 0))
                    && (!rule.split_by_material || labels.materials[a] == labels.materials[b]);
                let angle_ok = match (faces.normal[a], faces.normal[b], rule.cos_crease) {
                    (Some(na), Some(nb), Some(cos)) => na.dot(nb) >= cos - 1e-9,
                    _ => true,
                };
                if (kind && angle_ok) || labels.polygons[a] == labels.polygons[b] {
                    comp.union(a as u32, b as u32);
                }
            }
        }
        (0..tris.len() as u32).map(|t| comp.find(t)).collect()
    }

    /// Whether two labelings split the triangles into the same sets.
    fn same_partition(a: &[u32], b: &[u32]) -> bool {
        let mut map_ab = HashMap::new();
        let mut map_ba = HashMap::new();
        a.iter().zip(b).all(|(&x, &y)| {
            *map_ab.entry(x).or_insert(y) == y && *map_ba.entry(y).or_insert(x) == x
        })
    }

    #[test]
    fn busy_edge_joins_exactly_the_pages_the_pairwise_rule_joins() {
        // A "book": 60 pages on the spine from (0,0,0) to (0,0,1), at scattered angles, some
        // repeated, one degenerate, in two materials and with two pages of one polygon.
        let mut positions = vec![Vec3::ZERO, Vec3::Z];
        let mut tris = Vec::new();
        let mut seed = 12345u32;
        for k in 0..60 {
            seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
            let angle = f64::from(seed >> 8) / f64::from(1u32 << 24) * std::f64::consts::TAU;
            let angle = if k % 7 == 0 { 1.0 } else { angle };
            let r = if k == 30 { 0.0 } else { 1.0 };
            positions.push(Vec3::new(
                (r * angle.cos()) as f32,
                (r * angle.sin()) as f32,
                if k == 30 { 0.25 } else { 0.5 },
            ));
            tris.push([0, 1, k + 2]);
        }
        let faces = normals::face_data(&positions, &tris);
        assert!(faces.normal[30].is_none(), "page 30 lies on the spine");
        let t = tris.len();
        let groups: Vec<u32> = (0..t as u32).map(|i| 1 + i % 3).collect();
        let materials: Vec<u32> = (0..t as u32).map(|i| i % 2).collect();
        let mut polygons: Vec<u32> = (0..t as u32).collect();
        polygons[5] = 4;
        let labels = normals::FaceLabels {
            groups: &groups,
            materials: &materials,
            polygons: &polygons,
        };
        for (crease, use_groups, split) in [
            (Some(20.0), false, false),
            (Some(45.0), false, true),
            (Some(90.0), true, false),
            (Some(180.0), true, true),
            (None, true, false),
        ] {
            let opts = NormalOptions {
                crease_angle_deg: crease,
                use_smoothing_groups: use_groups,
                split_by_material: split,
                ..NormalOptions::default()
            };
            let rule = SmoothRule::resolve(&opts, true);
            let fast = surface_ids(&positions, &tris, &faces, &labels, &rule);
            let slow = pairwise_components(&tris, &faces, &labels, &rule);
            assert!(
                same_partition(&fast, &slow),
                "crease {crease:?}, groups {use_groups}, split {split}: {fast:?} vs {slow:?}"
            );
        }
    }
}
