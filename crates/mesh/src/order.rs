//! Memory order for rendering: triangles along a Morton (Z-order) curve through their
//! centroids, vertices in order of first use.
//!
//! A scan's triangles come in the order the scanner or an editor wrote them, which can jump all
//! over the surface. A rasterizer that bins triangles into screen bands then fetches each band's
//! vertices from everywhere in the vertex arrays, and waits on memory for most of them. Along a
//! Morton curve, triangles that follow each other are near each other in space, hence on screen
//! from any viewpoint, and share vertices that are still in cache. The surface is unchanged:
//! the same triangles with the same winding, normals, uvs, colours and tangents, only stored in another
//! order.

use crate::mesh::Mesh;
use glam::Vec3;

/// Bits per axis of the Morton key (a 1024^3 grid over the bounding box).
const BITS: u32 = 10;

/// Spreads the low [`BITS`] bits of `v` so that bit `i` moves to bit `3 i`.
fn spread(v: u32) -> u32 {
    let mut x = v & ((1 << BITS) - 1);
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

/// The 30-bit Morton key of `p` in the box `lo + [0, extent]`, with `scale` = cells per unit
/// along each axis (0 for a flat axis). Non-finite input lands in cell 0, never a panic.
fn morton(p: Vec3, lo: Vec3, scale: Vec3) -> u32 {
    let top = ((1 << BITS) - 1) as f32;
    let cell = |v: f32, lo: f32, s: f32| {
        let c = ((v - lo) * s).clamp(0.0, top);
        // NaN compares false everywhere: cell 0.
        if c.is_nan() { 0 } else { c as u32 }
    };
    spread(cell(p.x, lo.x, scale.x))
        | (spread(cell(p.y, lo.y, scale.y)) << 1)
        | (spread(cell(p.z, lo.z, scale.z)) << 2)
}

impl Mesh {
    /// Reorders the triangles along a Morton curve through their centroids (ties keep their
    /// order) and renumbers the vertices in order of first use, for memory locality when
    /// rendering (see the module docs). Per-triangle data (surface, material and smoothing ids)
    /// and per-vertex data (normals, uvs, colours, tangents) move with their triangles and vertices;
    /// vertices no triangle uses go to the end, in their old order. Deterministic.
    pub fn sort_spatially(&mut self) {
        let n = self.positions.len();
        let tris = self.indices.len();
        if self.indices.iter().flatten().any(|&i| i as usize >= n) {
            // Out of range indices break the crate's invariants; leave such a mesh alone.
            return;
        }
        let (lo, hi) = self.bounds();
        let top = ((1 << BITS) - 1) as f32;
        let extent = hi - lo;
        let scale = Vec3::select(
            extent.cmpgt(Vec3::ZERO) & extent.is_finite_mask(),
            Vec3::splat(top) / extent,
            Vec3::ZERO,
        );
        let key = |t: &[u32; 3]| {
            let c = t.iter().map(|&i| self.positions[i as usize]).sum::<Vec3>() / 3.0;
            morton(c, lo, scale)
        };
        let mut order: Vec<(u32, u32)> = self
            .indices
            .iter()
            .enumerate()
            .map(|(k, t)| (key(t), k as u32))
            .collect();
        order.sort_unstable();
        let take = |v: &[u32]| -> Vec<u32> {
            if v.len() == tris {
                order.iter().map(|&(_, k)| v[k as usize]).collect()
            } else {
                v.to_vec()
            }
        };
        self.surface_ids = take(&self.surface_ids);
        self.material_ids = take(&self.material_ids);
        self.smoothing_groups = take(&self.smoothing_groups);
        let old = std::mem::take(&mut self.indices);
        // New vertex number of each old vertex, by first use in the new triangle order.
        let mut new_of = vec![u32::MAX; n];
        let mut old_of = Vec::with_capacity(n);
        self.indices = order
            .iter()
            .map(|&(_, k)| {
                old[k as usize].map(|i| {
                    let slot = &mut new_of[i as usize];
                    if *slot == u32::MAX {
                        *slot = old_of.len() as u32;
                        old_of.push(i);
                    }
                    *slot
                })
            })
            .collect();
        old_of.extend((0..n as u32).filter(|&i| new_of[i as usize] == u32::MAX));
        fn permute<T: Copy>(v: &mut Vec<T>, old_of: &[u32]) {
            if v.len() == old_of.len() {
                *v = old_of.iter().map(|&i| v[i as usize]).collect();
            }
        }
        permute(&mut self.positions, &old_of);
        permute(&mut self.normals, &old_of);
        if let Some(uvs) = &mut self.uvs {
            permute(uvs, &old_of);
        }
        if let Some(colors) = &mut self.colors {
            permute(colors, &old_of);
        }
        if let Some(tangents) = &mut self.tangents {
            permute(tangents, &old_of);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    /// Each triangle as its three corners (position, normal), rotated so the smallest
    /// position comes first (the winding is kept), the list sorted: the surface, whatever
    /// the storage order.
    fn surface(m: &Mesh) -> Vec<[[u32; 6]; 3]> {
        let corner = |i: u32| {
            let (p, n) = (m.positions[i as usize], m.normals[i as usize]);
            [p.x, p.y, p.z, n.x, n.y, n.z].map(f32::to_bits)
        };
        let mut s: Vec<[[u32; 6]; 3]> = m
            .indices
            .iter()
            .map(|t| {
                let c = t.map(corner);
                let first = (0..3).min_by_key(|&k| c[k]).unwrap_or(0);
                [c[first], c[(first + 1) % 3], c[(first + 2) % 3]]
            })
            .collect();
        s.sort_unstable();
        s
    }

    /// Mean distance between the centroids of successive triangles.
    fn mean_step(m: &Mesh) -> f32 {
        let c: Vec<Vec3> = m
            .indices
            .iter()
            .map(|t| t.iter().map(|&i| m.positions[i as usize]).sum::<Vec3>() / 3.0)
            .collect();
        c.windows(2).map(|w| w[0].distance(w[1])).sum::<f32>() / (c.len() - 1) as f32
    }

    /// A sphere whose triangles are shuffled by a fixed permutation (a scan's order).
    fn shuffled_sphere() -> Mesh {
        let mut m = primitives::uv_sphere(1.0, 48, 24);
        let tris = m.indices.len();
        let mut k = 0usize;
        let perm: Vec<usize> = (0..tris)
            .map(|_| {
                k = (k + 7919) % tris;
                k
            })
            .collect();
        m.indices = perm.iter().map(|&k| m.indices[k]).collect();
        m.surface_ids = perm.iter().map(|&k| k as u32).collect();
        m
    }

    #[test]
    fn keeps_the_surface_and_brings_neighbours_together() {
        let mut m = shuffled_sphere();
        let before = (surface(&m), mean_step(&m));
        // Surface ids are a permutation of the triangles here: the old triangle of each id.
        let mut by_id = vec![[0u32; 3]; m.indices.len()];
        for (id, t) in m.surface_ids.iter().zip(&m.indices) {
            by_id[*id as usize] = *t;
        }
        let positions = m.positions.clone();
        m.sort_spatially();
        assert_eq!(
            surface(&m),
            before.0,
            "same triangles, windings and normals"
        );
        // Per-triangle data moved with its triangle.
        for (id, t) in m.surface_ids.iter().zip(&m.indices) {
            let now = t.map(|i| m.positions[i as usize]);
            let then = by_id[*id as usize].map(|i| positions[i as usize]);
            assert_eq!(now, then, "surface id {id}");
        }
        // Vertices in order of first use.
        let mut seen = 0;
        for &i in m.indices.iter().flatten() {
            assert!(i <= seen, "vertex {i} before {seen}");
            seen = seen.max(i + 1);
        }
        let after = mean_step(&m);
        assert!(after < before.1 * 0.25, "step {} -> {after}", before.1);
    }

    #[test]
    fn unused_vertices_stay_and_odd_input_is_left_whole() {
        let mut m = primitives::uv_sphere(1.0, 8, 4);
        m.positions.push(Vec3::splat(9.0));
        m.normals.push(Vec3::X);
        m.indices.reverse();
        let n = m.positions.len();
        m.sort_spatially();
        assert_eq!(m.positions.len(), n);
        assert_eq!(
            m.positions[n - 1],
            Vec3::splat(9.0),
            "unused vertex kept, last"
        );
        // A flat mesh (zero extent on an axis) and a NaN position: no panic, same sizes.
        let mut flat = primitives::uv_sphere(1.0, 8, 4);
        for p in &mut flat.positions {
            p.z = 0.0;
        }
        flat.positions[3] = Vec3::NAN;
        let tris = flat.indices.len();
        flat.sort_spatially();
        assert_eq!(flat.indices.len(), tris);
        // An index out of range: left as it was.
        let mut bad = primitives::uv_sphere(1.0, 8, 4);
        bad.indices[0][1] = 10_000;
        let copy = bad.clone();
        bad.sort_spatially();
        assert_eq!(bad, copy);
    }
}
