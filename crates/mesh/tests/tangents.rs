//! MikkTSpace tangents: unit, perpendicular to the normals, handedness +-1, hand-computed
//! frames on a quad, split vertices at mirrored uv seams, agreement with the primitives.

use glam::{Vec2, Vec3, Vec4};
use phosphor_mesh::tangents::compute;
use phosphor_mesh::{Mesh, fallback_tangent, primitives};
use proptest::prelude::*;

/// Every tangent unit, perpendicular to its normal, handedness exactly +1 or -1.
fn assert_frames(m: &Mesh, what: &str) {
    assert!(m.is_consistent(), "{what}: consistent");
    let ts = m.tangents.as_ref().expect("tangents");
    for (i, (t, n)) in ts.iter().zip(&m.normals).enumerate() {
        assert!(
            (t.truncate().length() - 1.0).abs() < 1e-5,
            "{what}: vertex {i} tangent {t} not unit"
        );
        assert!(
            t.truncate().dot(*n).abs() < 1e-5,
            "{what}: vertex {i} tangent {t} not perpendicular to {n}"
        );
        assert!(t.w == 1.0 || t.w == -1.0, "{what}: vertex {i} w {}", t.w);
    }
}

/// A quad in the z = 0 plane from (0, 0) to (2, 1), normal +Z, with the uv of each corner
/// given by `uv`.
fn quad(uv: impl Fn(Vec3) -> Vec2) -> Mesh {
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    Mesh {
        uvs: Some(positions.iter().map(|&p| uv(p)).collect()),
        normals: vec![Vec3::Z; 4],
        positions,
        indices: vec![[0, 1, 2], [0, 2, 3]],
        surface_ids: vec![0; 2],
        material_ids: vec![0; 2],
        smoothing_groups: vec![0; 2],
        ..Mesh::default()
    }
}

#[test]
fn quad_tangents_match_the_hand_computed_uv_directions() {
    // u = x / 2, v = y: dP/du = +X, dP/dv = +Y = N x T, so w = +1.
    let mut m = quad(|p| Vec2::new(p.x / 2.0, p.y));
    m.compute_tangents();
    assert_frames(&m, "plain");
    for t in m.tangents.as_ref().expect("tangents") {
        assert!((*t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-6, "{t}");
    }
    // u = y, v = -x / 2: dP/du = +Y, dP/dv = -X = N x T (Z x Y = -X), so w = +1.
    let mut m = quad(|p| Vec2::new(p.y, -p.x / 2.0));
    m.compute_tangents();
    for t in m.tangents.as_ref().expect("tangents") {
        assert!((*t - Vec4::new(0.0, 1.0, 0.0, 1.0)).length() < 1e-6, "{t}");
    }
    // Mirrored: u = -x / 2, v = y: dP/du = -X, dP/dv = +Y = -(N x T), so w = -1.
    let mut m = quad(|p| Vec2::new(-p.x / 2.0, p.y));
    m.compute_tangents();
    for t in m.tangents.as_ref().expect("tangents") {
        assert!(
            (*t - Vec4::new(-1.0, 0.0, 0.0, -1.0)).length() < 1e-6,
            "{t}"
        );
    }
}

#[test]
fn sphere_cube_and_torus_frames_are_unit_perpendicular_and_near_the_primitives_gradient() {
    for (name, m) in [
        ("sphere", primitives::uv_sphere(1.0, 48, 24)),
        ("cube", primitives::cube(1.0)),
        ("torus", primitives::torus(1.0, 0.3, 48, 24)),
    ] {
        let mut mikk = m.clone();
        mikk.compute_tangents();
        assert_frames(&mikk, name);
        assert_eq!(mikk.positions.len(), m.positions.len(), "{name}: no split");
        // The gradient the primitive carries and MikkTSpace agree within the tessellation
        // (the sphere's pole rows aside, where the uv grid pinches to a point).
        let ts = mikk.tangents.as_ref().expect("tangents");
        let ours = m.tangents.as_ref().expect("tangents");
        for (i, (a, b)) in ts.iter().zip(ours).enumerate() {
            if m.normals[i].y.abs() > 0.95 && name == "sphere" {
                continue;
            }
            let angle = a.truncate().angle_between(b.truncate());
            assert!(angle < 0.05, "{name}: vertex {i}: {a} vs {b} ({angle} rad)");
            assert_eq!(a.w, b.w, "{name}: vertex {i} handedness");
        }
    }
}

#[test]
fn mirrored_uvs_split_the_seam_vertices_one_per_frame() {
    // Two quads sharing the edge x = 1; the uvs mirror across it (u = x on the left,
    // u = 2 - x on the right), so the seam's vertices have one uv but two frames.
    let positions: Vec<Vec3> = [0.0, 1.0, 2.0]
        .iter()
        .flat_map(|&x| [Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 0.0)])
        .collect();
    let uvs = positions
        .iter()
        .map(|p| Vec2::new(1.0 - (p.x - 1.0).abs(), p.y))
        .collect();
    let mut m = Mesh {
        normals: vec![Vec3::Z; 6],
        uvs: Some(uvs),
        positions,
        indices: vec![[0, 2, 3], [0, 3, 1], [2, 4, 5], [2, 5, 3]],
        surface_ids: vec![0; 4],
        material_ids: vec![0; 4],
        smoothing_groups: vec![0; 4],
        ..Mesh::default()
    };
    m.compute_tangents();
    assert_frames(&m, "mirrored");
    assert_eq!(m.positions.len(), 8, "the two seam vertices are split");
    let ts = m.tangents.as_ref().expect("tangents");
    for (t, tri) in m.indices.iter().enumerate() {
        let left = t < 2;
        for &i in tri {
            let want = if left {
                Vec4::new(1.0, 0.0, 0.0, 1.0)
            } else {
                Vec4::new(-1.0, 0.0, 0.0, -1.0)
            };
            assert!(
                (ts[i as usize] - want).length() < 1e-6,
                "triangle {t}: {}",
                ts[i as usize]
            );
        }
    }
    // Every split vertex copies its position, normal and uv.
    let positions: std::collections::HashSet<[u32; 3]> = m
        .positions
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect();
    assert_eq!(positions.len(), 6);
    // compute keeps one tangent per given vertex: the first corner's.
    let uvs = m.uvs.clone().expect("uvs");
    let flat = compute(&m.positions, &m.normals, &uvs, &m.indices);
    assert_eq!(flat.len(), m.positions.len());
}

#[test]
fn degenerate_uvs_nan_and_bad_indices_fall_back_without_panicking() {
    let mut same = quad(|_| Vec2::splat(0.5));
    same.compute_tangents();
    assert_frames(&same, "one uv everywhere");
    let mut nan = quad(|p| if p.x > 1.0 { Vec2::NAN } else { Vec2::ZERO });
    nan.compute_tangents();
    assert!(
        nan.tangents
            .as_ref()
            .expect("filled")
            .iter()
            .all(|t| t.is_finite())
    );
    let mut bad = quad(|p| Vec2::new(p.x, p.y));
    bad.indices.push([0, 1, 99]);
    bad.compute_tangents();
    assert_eq!(bad.tangents.as_ref().map(Vec::len), Some(4));
    let short = compute(&bad.positions, &bad.normals[..2], &[], &bad.indices);
    assert_eq!(short.len(), 4);
}

#[test]
fn ensure_tangents_keeps_tangents_already_there() {
    let mut m = quad(|p| Vec2::new(p.x, p.y));
    let authored = vec![Vec4::new(0.0, 1.0, 0.0, -1.0); 4];
    m.tangents = Some(authored.clone());
    m.ensure_tangents();
    assert_eq!(m.tangents.as_ref(), Some(&authored));
    m.tangents = Some(vec![Vec4::X; 3]);
    m.ensure_tangents();
    assert_frames(&m, "refilled");
}

#[test]
fn ensure_tangents_without_uvs_uses_the_fallback() {
    let mut m = primitives::cube(1.0);
    m.uvs = None;
    m.tangents = None;
    m.ensure_tangents();
    assert!(m.is_consistent());
    let ts = m.tangents.as_ref().expect("filled");
    assert!(
        ts.iter()
            .zip(&m.normals)
            .all(|(t, n)| t.truncate().dot(*n).abs() < 1e-6)
    );
}

proptest! {
    #[test]
    fn fallback_tangent_is_unit_and_perpendicular(x in -1.0f32..1.0, y in -1.0f32..1.0, z in -1.0f32..1.0) {
        let n = Vec3::new(x, y, z);
        prop_assume!(n.length() > 1e-3);
        let n = n.normalize();
        let t = fallback_tangent(n);
        prop_assert!((t.truncate().length() - 1.0).abs() < 1e-5);
        prop_assert!(t.truncate().dot(n).abs() < 1e-5);
    }
}

#[test]
fn fallback_tangent_handles_poles_and_garbage() {
    for n in [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::ZERO, Vec3::NAN] {
        let t = fallback_tangent(n);
        assert!(t.is_finite() && (t.truncate().length() - 1.0).abs() < 1e-6);
    }
}
