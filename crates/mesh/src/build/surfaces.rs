//! Surfaces: the connected sets of triangles smoothed together, found across shared edges.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::normals::{self, FaceData, SmoothRule};

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
pub(super) fn surface_ids(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normals::NormalOptions;

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
