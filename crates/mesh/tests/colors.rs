//! Vertex colours from PLY, glTF and OBJ arrive on the vertices of their positions, through
//! welding, vertex splitting, normal recomputation and spatial sorting.

mod writers;

use std::path::Path;

use glam::Vec3;
use phosphor_mesh::{Mesh, MeshFormat, NormalOptions, parse_mesh_bytes, parse_obj};
use writers::{GltfAttribute, GltfBuffer, GltfMesh, Ply, PlyColor, Shape};

fn no_files(_: &str) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
}

fn load(bytes: &[u8], name: &str) -> (Mesh, Vec<String>) {
    let format = MeshFormat::from_path(Path::new(name));
    let (mesh, warnings) =
        parse_mesh_bytes(bytes, name, format, &no_files, &NormalOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(mesh.is_consistent(), "{name}");
    (mesh, warnings)
}

/// The colour the tests give the vertex at `p` (cube corners at 0 and 1): distinct per corner,
/// inside `(0, 1)`.
fn colour_of(p: Vec3) -> Vec3 {
    (p * 4.0 + Vec3::new(1.0, 2.0, 3.0)) / 8.0
}

/// Every vertex carries the colour of its position, within `tol`.
fn assert_colours_follow_positions(m: &Mesh, tol: f32, what: &str) {
    let colors = m
        .colors
        .as_ref()
        .unwrap_or_else(|| panic!("{what}: colours"));
    assert_eq!(colors.len(), m.positions.len(), "{what}");
    for (p, c) in m.positions.iter().zip(colors) {
        let want = colour_of(*p);
        assert!(
            (*c - want).abs().max_element() <= tol,
            "{what}: vertex at {p} has {c}, want {want}"
        );
    }
}

fn cube_colours(shape: &Shape) -> Vec<Vec3> {
    shape.positions.iter().map(|&p| colour_of(p)).collect()
}

#[test]
fn ply_uchar_and_float_colours_stay_on_their_positions_after_splitting() {
    let cube = writers::cube();
    let colours = cube_colours(&cube);
    for encoding in [Ply::Ascii, Ply::Little, Ply::Big] {
        for (kind, tol) in [
            (PlyColor::UChar, 0.5 / 255.0 + 1e-6),
            (PlyColor::Float, 0.0),
        ] {
            let bytes = writers::ply_with(&cube, None, Some((&colours, kind)), encoding);
            let (m, warnings) = load(&bytes, "c.ply");
            assert!(warnings.is_empty(), "{warnings:?}");
            // 8 positions, split into 24 vertices by the 60-degree crease.
            assert_eq!(m.positions.len(), 24);
            assert_colours_follow_positions(&m, tol, &format!("{encoding:?} {kind:?}"));
            assert!(m.stats().colors);
        }
    }
}

#[test]
fn ply_colours_of_a_signed_type_are_a_warning_not_an_error() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nproperty short red\nproperty short green\nproperty short blue\n\
                element face 1\nproperty list uchar int vertex_indices\nend_header\n\
                0 0 0 1 2 3\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n";
    let (m, warnings) = load(text.as_bytes(), "s.ply");
    assert!(m.colors.is_none());
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].starts_with("s.ply: header: vertex colour `red green blue`"));
}

#[test]
fn ply_without_colours_has_none_and_info_says_so() {
    let (m, _) = load(&writers::ply(&writers::cube(), None, Ply::Ascii), "c.ply");
    assert!(m.colors.is_none());
    assert!(m.stats().to_string().contains("vertex colours:   no"));
}

#[test]
fn gltf_float_vec3_and_normalized_ubyte_vec4_colours_stay_on_their_positions() {
    let cube = writers::cube();
    let colours = cube_colours(&cube);
    let floats: Vec<f32> = colours.iter().flat_map(|c| c.to_array()).collect();
    let bytes: Vec<[u8; 4]> = colours
        .iter()
        .map(|c| {
            let b = (*c * 255.0).round().to_array().map(|x| x as u8);
            [b[0], b[1], b[2], 128]
        })
        .collect();
    for (attribute, tol) in [
        (GltfAttribute::f32("COLOR_0", 3, &floats), 1e-6),
        (
            GltfAttribute::u8_vec4("COLOR_0", &bytes),
            0.5 / 255.0 + 1e-6,
        ),
    ] {
        let extras = [attribute];
        let mesh = GltfMesh {
            shape: &cube,
            normals: None,
            extras: &extras,
            material: None,
        };
        for buffer in [GltfBuffer::DataUri, GltfBuffer::Glb] {
            let (file, _) = writers::gltf(&[mesh_ref(&mesh)], &[], &[], buffer);
            let (m, warnings) = load(&file, "c.glb");
            assert!(warnings.is_empty(), "{warnings:?}");
            assert_colours_follow_positions(&m, tol, &format!("{} {buffer:?}", extras[0].kind));
        }
    }
}

/// A copy of `m` that borrows the same data (GltfMesh is not Clone).
fn mesh_ref<'a>(m: &GltfMesh<'a>) -> GltfMesh<'a> {
    GltfMesh {
        shape: m.shape,
        normals: m.normals,
        extras: m.extras,
        material: m.material,
    }
}

#[test]
fn gltf_primitive_without_colours_is_white_next_to_one_with_them() {
    let cube = writers::cube();
    let colours = cube_colours(&cube);
    let floats: Vec<f32> = colours.iter().flat_map(|c| c.to_array()).collect();
    let extras = [GltfAttribute::f32("COLOR_0", 3, &floats)];
    let meshes = [
        GltfMesh {
            shape: &cube,
            normals: None,
            extras: &extras,
            material: None,
        },
        GltfMesh {
            shape: &cube,
            normals: None,
            extras: &[],
            material: None,
        },
    ];
    let (file, _) = writers::gltf(
        &meshes,
        &["", "\"translation\":[5,0,0]"],
        &[],
        GltfBuffer::DataUri,
    );
    let (m, _) = load(&file, "two.gltf");
    let colors = m.colors.as_ref().expect("colours");
    for (p, c) in m.positions.iter().zip(colors) {
        let want = if p.x >= 4.0 { Vec3::ONE } else { colour_of(*p) };
        assert!((*c - want).length() < 1e-6, "{p}: {c}");
    }
}

const OBJ_CUBE: &str = "v 0 0 0 0.125 0.25 0.375\nv 1 0 0 0.625 0.25 0.375\n\
v 1 1 0 0.625 0.75 0.375\nv 0 1 0 0.125 0.75 0.375\nv 0 0 1 0.125 0.25 0.875\n\
v 1 0 1 0.625 0.25 0.875\nv 1 1 1 0.625 0.75 0.875\nv 0 1 1 0.125 0.75 0.875\n\
g a\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\ng b\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

#[test]
fn obj_vertex_colours_stay_on_their_positions_across_groups() {
    let m = parse_obj(OBJ_CUBE, "c.obj", None, &NormalOptions::default()).expect("valid");
    assert!(m.is_consistent());
    assert_eq!(m.positions.len(), 24);
    assert_colours_follow_positions(&m, 0.0, "obj");
    // Smoothed over every edge: one vertex per position, the groups welded, the colours too.
    let smooth = parse_obj(OBJ_CUBE, "c.obj", None, &NormalOptions::s1()).expect("valid");
    assert_eq!(smooth.positions.len(), 8);
    assert_colours_follow_positions(&smooth, 0.0, "obj s1");
}

#[test]
fn obj_colours_out_of_range_are_clamped() {
    let text = "v 0 0 0 2 -1 0.5\nv 1 0 0 0 0 0\nv 0 1 0 1 1 1\nf 1 2 3\n";
    let m = parse_obj(text, "c.obj", None, &NormalOptions::default()).expect("valid");
    assert!(m.is_consistent());
    let c = m.colors.as_ref().expect("colours");
    let at_origin = m
        .positions
        .iter()
        .position(|p| *p == Vec3::ZERO)
        .expect("origin");
    assert_eq!(c[at_origin], Vec3::new(1.0, 0.0, 0.5));
}

#[test]
fn colours_survive_sorting_normal_recomputation_and_tangent_splits() {
    let mut m = parse_obj(OBJ_CUBE, "c.obj", None, &NormalOptions::default()).expect("valid");
    m.sort_spatially();
    assert!(m.is_consistent());
    assert_colours_follow_positions(&m, 0.0, "sorted");
    let smooth = m.with_computed_normals(&NormalOptions::s1());
    assert_eq!(smooth.positions.len(), 8);
    assert_colours_follow_positions(&smooth, 0.0, "recomputed");
    // Mirrored uvs on a quad strip split vertices for tangents: the copies keep the colour.
    let text = "v 0 0 0 0.125 0.25 0.375\nv 1 0 0 0.625 0.25 0.375\nv 1 1 0 0.625 0.75 0.375\n\
                v 0 1 0 0.125 0.75 0.375\nv 2 0 0 1.125 0.25 0.375\nv 2 1 0 1.125 0.75 0.375\n\
                vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\nf 2/2 5/1 6/4 3/3\n";
    let m = parse_obj(text, "m.obj", None, &NormalOptions::default()).expect("valid");
    assert!(m.is_consistent());
    assert_eq!(m.positions.len(), 8, "the seam's two vertices are split");
    let c = m.colors.as_ref().expect("colours");
    for (p, c) in m.positions.iter().zip(c) {
        assert_eq!(c.x, (p.x * 4.0 + 1.0).min(8.0) / 8.0, "{p}");
    }
}
