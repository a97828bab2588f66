//! Vertex normals from OBJ files: creases, smoothing groups, two-sided sheets, shipped meshes.

use std::path::PathBuf;

use glam::Vec3;
use phosphor_mesh::{
    Mesh, NormalOptions, NormalSource, Weighting, load_obj, parse_obj, primitives,
};

const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

fn parse(text: &str, opts: &NormalOptions) -> Mesh {
    let m = parse_obj(text, "t.obj", None, opts).expect("valid OBJ");
    assert!(m.is_consistent());
    m
}

fn assert_corners_take_face_normals(m: &Mesh) {
    for t in 0..m.indices.len() {
        let f = m.face_normal(t).expect("non-degenerate");
        for &i in &m.indices[t] {
            assert!((m.normals[i as usize] - f).length() < 1e-6);
        }
    }
}

#[test]
fn cube_with_30_degree_crease_keeps_six_flat_faces() {
    let m = parse(CUBE, &NormalOptions::crease(30.0));
    assert_eq!(m.positions.len(), 24);
    assert_eq!(m.indices.len(), 12);
    assert_eq!(m.stats().surfaces, 6);
    assert_corners_take_face_normals(&m);
    // Faces point outward (the OBJ is counter-clockwise seen from outside).
    let centre = Vec3::splat(0.5);
    for t in 0..12 {
        let [a, _, _] = m.triangle_positions(t).expect("in range");
        assert!(m.face_normal(t).expect("flat").dot(a - centre) > 0.0);
    }
}

#[test]
fn s1_options_average_over_every_face_sharing_a_position() {
    let m = parse(CUBE, &NormalOptions::s1());
    assert_eq!(m.positions.len(), 8);
    for (p, n) in m.positions.iter().zip(&m.normals) {
        let diagonal = (*p - Vec3::splat(0.5)).normalize();
        assert!((*n - diagonal).length() < 1e-6, "{n} vs {diagonal}");
    }
}

/// Cylinder OBJ: side quads in `s 1`, top cap polygon in `s 2`, bottom cap in `s 3`.
fn cylinder_obj(segments: usize) -> String {
    let mut s = String::new();
    for y in [0.0, 2.0] {
        for j in 0..segments {
            let a = j as f32 / segments as f32 * std::f32::consts::TAU;
            s += &format!("v {} {y} {}\n", a.cos(), -a.sin());
        }
    }
    s += "g side\ns 1\n";
    for j in 0..segments {
        let (a, b) = (j + 1, (j + 1) % segments + 1);
        s += &format!("f {a} {b} {} {}\n", b + segments, a + segments);
    }
    s += "g top\ns 2\nf";
    for j in 0..segments {
        s += &format!(" {}", j + 1 + segments);
    }
    s += "\ng bottom\ns 3\nf";
    for j in (0..segments).rev() {
        s += &format!(" {}", j + 1);
    }
    s + "\n"
}

#[test]
fn cylinder_smoothing_groups_smooth_the_side_and_keep_both_rims_sharp() {
    let m = parse(&cylinder_obj(16), &NormalOptions::default());
    assert_eq!(m.stats().smoothing_groups, 3);
    assert_eq!(m.stats().surfaces, 3);
    for t in 0..m.indices.len() {
        for &i in &m.indices[t] {
            let (p, n) = (m.positions[i as usize], m.normals[i as usize]);
            match m.smoothing_groups[t] {
                // Smooth side: the exact radial direction (symmetric neighbours).
                1 => assert!(
                    (n - Vec3::new(p.x, 0.0, p.z).normalize()).length() < 1e-5,
                    "{n}"
                ),
                2 => assert!((n - Vec3::Y).length() < 1e-6),
                3 => assert!((n + Vec3::Y).length() < 1e-6),
                g => panic!("unexpected group {g}"),
            }
        }
    }
    // Every rim position is split into a side vertex and a cap vertex.
    assert_eq!(m.positions.len(), 4 * 16);
}

#[test]
fn s_off_faces_are_flat_even_inside_a_smooth_file() {
    let text = CUBE.replace("f 1 4 3 2", "s off\nf 1 4 3 2\ns 1");
    let m = parse(&text, &NormalOptions::default());
    let t = 0; // first face (two triangles) is s off
    let f = m.face_normal(t).expect("flat");
    for &i in &m.indices[t] {
        assert!((m.normals[i as usize] - f).length() < 1e-6);
    }
}

#[test]
fn two_sided_sheet_yields_no_nan() {
    // The same quad twice with opposite windings: the S1 sum cancels at every corner.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 4 3 2 1\n";
    for opts in [
        NormalOptions::s1(),
        NormalOptions::smooth_all(Weighting::Area),
        NormalOptions::smooth_all(Weighting::Angle),
        NormalOptions::default(),
    ] {
        let m = parse(text, &opts);
        // Documented fallback: each corner takes its own face normal.
        assert_corners_take_face_normals(&m);
    }
}

#[test]
fn degenerate_faces_are_flagged_and_left_out_of_averaging() {
    // A zero-area triangle (collinear) shares vertex 1 with a proper one.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n";
    let m = parse(text, &NormalOptions::s1());
    assert_eq!(m.stats().degenerate, 1);
    assert!(m.face_normal(1).is_none());
    for &i in &m.indices[0] {
        assert!((m.normals[i as usize] - Vec3::Z).length() < 1e-6);
    }
}

#[test]
fn slivers_and_extreme_coordinates_keep_their_face_normal() {
    for s in [1e-30f32, 1e-3, 1.0, 1e30] {
        let text = format!("v 0 0 0\nv {s} 0 0\nv 0 {} 0\nf 1 2 3\n", s * 1e-5);
        let m = parse(&text, &NormalOptions::default());
        assert!(
            (m.face_normal(0).expect("not degenerate") - Vec3::Z).length() < 1e-6,
            "scale {s}"
        );
    }
}

#[test]
fn authored_normals_are_used_unless_computed_is_asked() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nvn 1 0 1\nf 1//1 2//2 3//1\n";
    let m = parse(text, &NormalOptions::default());
    assert!(
        m.normals
            .iter()
            .any(|n| (*n - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 1e-6)
    );
    let c = parse(
        text,
        &NormalOptions {
            source: NormalSource::Computed,
            ..NormalOptions::default()
        },
    );
    assert!(c.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
}

#[test]
fn concave_polygon_in_obj_is_ear_clipped() {
    // An L shape; a fan from corner 1 would cover the notch.
    let text = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n";
    let m = parse(text, &NormalOptions::default());
    assert_eq!(m.indices.len(), 4);
    let area: f64 = (0..4).map(|t| m.double_area(t) * 0.5).sum();
    assert!((area - 3.0).abs() < 1e-9);
    assert!((0..4).all(|t| m.face_normal(t).expect("proper") == Vec3::Z));
}

#[test]
fn uvs_give_tangents_perpendicular_to_normals() {
    let text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
    let m = parse(text, &NormalOptions::default());
    let t = m.tangents.as_ref().expect("tangents with uvs");
    assert!(
        t.iter()
            .all(|t| (t.truncate() - Vec3::X).length() < 1e-6 && t.w == 1.0)
    );
}

#[test]
fn materials_come_from_the_mtl_and_split_when_asked() {
    let text = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n";
    let mtl = "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nNs 20\n";
    let m = parse_obj(text, "t.obj", Some(mtl), &NormalOptions::s1()).expect("valid");
    assert_eq!(m.materials.len(), 2);
    assert_eq!(m.material_ids, vec![0, 1]);
    assert_eq!(m.materials[1].ns, 20.0);
    // Smoothed across the material boundary (S1), split when asked.
    assert_eq!(m.positions.len(), 4);
    let split = NormalOptions {
        split_by_material: true,
        ..NormalOptions::s1()
    };
    let m2 = parse_obj(text, "t.obj", Some(mtl), &split).expect("valid");
    assert_eq!(m2.positions.len(), 6);
}

fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/meshes")
        .join(name)
}

#[test]
fn every_normal_of_every_shipped_mesh_is_unit_and_finite() {
    for name in [
        "bunny.obj",
        "bunny_small.obj",
        "teapot.obj",
        "fandisk.obj",
        "spider.obj",
    ] {
        for opts in [NormalOptions::default(), NormalOptions::s1()] {
            let m = load_obj(&asset(name), &opts).unwrap_or_else(|e| panic!("{e}"));
            assert!(m.is_consistent(), "{name}");
            assert!(
                m.normals
                    .iter()
                    .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5)
            );
            assert!(!m.indices.is_empty());
        }
    }
    let spider = load_obj(&asset("spider.obj"), &NormalOptions::default()).expect("spider");
    let s = spider.stats();
    assert_eq!(s.materials, 5);
    assert!(s.smoothing_groups >= 1);
    assert_eq!(s.triangles, 1368);
}

#[test]
fn normalize_unit_centres_and_scales_to_the_unit_sphere() {
    let mut m = primitives::cube(3.0);
    for p in &mut m.positions {
        *p += Vec3::new(10.0, -4.0, 2.0);
    }
    m.normalize_unit();
    let far = m.positions.iter().map(|p| p.length()).fold(0.0, f32::max);
    assert!((far - 1.0).abs() < 1e-6);
    let (lo, hi) = m.bounds();
    assert!(((lo + hi) * 0.5).length() < 1e-6);
}

#[test]
fn vertex_normal_at_an_asymmetric_vertex_follows_each_weighting() {
    // Three faces around the origin with different areas and angles there:
    // (O, (2,0,0), (0,1,0)): normal +z, area 1, angle 90 deg;
    // (O, (0,1,0), (0,0,1)): normal +x, area 1/2, angle 90 deg;
    // (O, (0,0,1), (1,0,1)): normal +y, area 1/2, angle 45 deg.
    let text = "v 0 0 0\nv 2 0 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 5\n";
    let expected = [
        // The notes' N_v = sum N_k / |sum N_k|.
        (Weighting::Uniform, Vec3::new(1.0, 1.0, 1.0)),
        // Areas 1/2, 1/2, 1 on +x, +y, +z.
        (Weighting::Area, Vec3::new(0.5, 0.5, 1.0)),
        // Angles pi/2, pi/4, pi/2 on +x, +y, +z.
        (Weighting::Angle, Vec3::new(2.0, 1.0, 2.0)),
    ];
    for (weighting, direction) in expected {
        let m = parse(text, &NormalOptions::smooth_all(weighting));
        let at_origin: Vec<Vec3> = m
            .positions
            .iter()
            .zip(&m.normals)
            .filter(|(p, _)| **p == Vec3::ZERO)
            .map(|(_, n)| *n)
            .collect();
        assert!(!at_origin.is_empty(), "{weighting:?}");
        for n in at_origin {
            assert!(
                (n - direction.normalize()).length() < 1e-6,
                "{weighting:?}: {n} against {}",
                direction.normalize()
            );
        }
    }
}
