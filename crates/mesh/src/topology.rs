//! Whether a triangle mesh bounds a solid seen from outside: closed, consistently oriented and
//! oriented outwards. A renderer may then skip the triangles facing away from an eye outside
//! the solid, since every ray from that eye meets a front face before any back face.

use glam::{DVec3, Vec3};

/// True when `indices` over `positions` form a closed, consistently and outwardly oriented
/// surface:
/// - corners are compared by position (bit-identical coordinates are one vertex), so meshes
///   split at creases or uv seams still count as closed;
/// - every directed edge `a -> b` occurs exactly once and its reverse `b -> a` exactly once
///   (each edge shared by exactly two faces, in opposite directions);
/// - the enclosed signed volume is positive (counter-clockwise seen from outside, the
///   front-face convention).
///
/// Triangles with two equal corners have no area; their edges cancel in pairs and they are
/// ignored. An index out of range, a non-finite position or an empty mesh gives `false`.
/// Runs in `O(n log n)` for `n` triangles (a sort of the directed edges).
#[must_use]
pub fn is_closed_solid(positions: &[Vec3], indices: &[[u32; 3]]) -> bool {
    if indices.is_empty() || positions.iter().any(|p| !p.is_finite()) {
        return false;
    }
    // Weld by exact position: ids in first-seen order.
    let mut keyed: Vec<([u32; 3], u32)> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // +0.0 and -0.0 are one position.
            let p = *p + Vec3::ZERO;
            (p.to_array().map(f32::to_bits), i as u32)
        })
        .collect();
    keyed.sort_unstable();
    let mut weld = vec![0u32; positions.len()];
    let mut id = 0u32;
    for (k, &(key, i)) in keyed.iter().enumerate() {
        if k > 0 && keyed[k - 1].0 != key {
            id += 1;
        }
        weld[i as usize] = id;
    }
    let mut edges: Vec<u64> = Vec::with_capacity(indices.len() * 3);
    let mut volume6 = 0.0f64;
    for tri in indices {
        let Some(w) = tri
            .iter()
            .map(|&i| weld.get(i as usize).copied())
            .collect::<Option<Vec<u32>>>()
        else {
            return false;
        };
        if w[0] == w[1] || w[1] == w[2] || w[2] == w[0] {
            continue;
        }
        for k in 0..3 {
            edges.push(u64::from(w[k]) << 32 | u64::from(w[(k + 1) % 3]));
        }
        let [a, b, c] = tri.map(|i| positions[i as usize].as_dvec3());
        volume6 += a.dot(b.cross(c));
    }
    if edges.is_empty() {
        return false;
    }
    edges.sort_unstable();
    if edges.windows(2).any(|p| p[0] == p[1]) {
        return false;
    }
    let paired = edges.iter().all(|&e| {
        let reverse = e.rotate_right(32);
        edges.binary_search(&reverse).is_ok()
    });
    paired && volume6 > 0.0 && volume6.is_finite()
}

/// The signed volume enclosed by a closed surface, for tests and reports: positive when it is
/// oriented outwards.
#[must_use]
pub fn signed_volume(positions: &[Vec3], indices: &[[u32; 3]]) -> f64 {
    let at = |i: u32| {
        positions
            .get(i as usize)
            .map_or(DVec3::ZERO, |p| p.as_dvec3())
    };
    indices
        .iter()
        .map(|t| at(t[0]).dot(at(t[1]).cross(at(t[2]))) / 6.0)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    fn tetra() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        // Counter-clockwise seen from outside.
        let t = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        (p, t)
    }

    #[test]
    fn outward_tetrahedron_is_a_closed_solid() {
        let (p, t) = tetra();
        assert!(signed_volume(&p, &t) > 0.0);
        assert!(is_closed_solid(&p, &t));
    }

    #[test]
    fn inward_orientation_is_not_a_solid_seen_from_outside() {
        let (p, mut t) = tetra();
        for tri in &mut t {
            tri.swap(1, 2);
        }
        assert!(!is_closed_solid(&p, &t));
    }

    #[test]
    fn an_open_or_inconsistent_surface_is_not_closed() {
        let (p, mut t) = tetra();
        assert!(!is_closed_solid(&p, &t[..3]));
        t[3].swap(1, 2); // one face flipped
        assert!(!is_closed_solid(&p, &t));
        let (p, mut t) = tetra();
        t.push(t[0]); // an edge used by three faces
        assert!(!is_closed_solid(&p, &t));
    }

    #[test]
    fn bad_input_is_not_closed() {
        let (mut p, t) = tetra();
        assert!(!is_closed_solid(&p, &[]));
        assert!(!is_closed_solid(&p, &[[0, 1, 9]]));
        p[0].x = f32::NAN;
        assert!(!is_closed_solid(&p, &t));
    }

    #[test]
    fn split_vertices_are_welded_by_position() {
        // The cube primitive splits every corner into one vertex per face normal.
        let cube = primitives::cube(1.0);
        assert!(cube.positions.len() > 8);
        assert!(is_closed_solid(&cube.positions, &cube.indices));
        let sphere = primitives::uv_sphere(1.0, 32, 16);
        assert!(is_closed_solid(&sphere.positions, &sphere.indices));
        let plane = primitives::plane(1.0, 4);
        assert!(!is_closed_solid(&plane.positions, &plane.indices));
    }
}
