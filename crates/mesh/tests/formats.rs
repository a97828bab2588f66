//! PLY, STL and glTF files load as the same geometry written as OBJ loads: same triangles,
//! same vertex normals under the same options (60-degree crease by default), and each
//! format's own data (authored normals, node transforms, base colours) where it has some.

mod writers;

use std::path::Path;

use glam::Vec3;
use phosphor_mesh::{
    Mesh, MeshFormat, NormalOptions, NormalSource, load_mesh, parse_mesh_bytes, parse_obj,
    primitives,
};
use writers::{GltfBuffer, GltfMesh, Ply, Shape};

const TOL: f32 = 1e-5;

fn no_files(_: &str) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
}

fn load(bytes: &[u8], name: &str, opts: &NormalOptions) -> Mesh {
    let format = MeshFormat::from_path(Path::new(name));
    let (mesh, warnings) = parse_mesh_bytes(bytes, name, format, &no_files, opts)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(warnings.is_empty(), "{name}: {warnings:?}");
    assert!(mesh.is_consistent(), "{name}");
    mesh
}

/// The mesh's vertices as (position, normal), sorted: independent of vertex and triangle
/// order, which differ between formats (STL and glTF store triangles, not quads).
fn vertices(m: &Mesh) -> Vec<[f32; 6]> {
    let mut v: Vec<[f32; 6]> = m
        .positions
        .iter()
        .zip(&m.normals)
        .map(|(p, n)| [p.x, p.y, p.z, n.x, n.y, n.z])
        .collect();
    v.sort_by(|a, b| {
        a.iter()
            .zip(b)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    v
}

fn total_area(m: &Mesh) -> f64 {
    (0..m.triangle_count())
        .map(|t| m.double_area(t) / 2.0)
        .sum()
}

fn assert_same_surface(name: &str, got: &Mesh, want: &Mesh) {
    assert_eq!(got.triangle_count(), want.triangle_count(), "{name}");
    assert_eq!(got.stats().surfaces, want.stats().surfaces, "{name}");
    assert!((total_area(got) - total_area(want)).abs() < 1e-5, "{name}");
    let (g, w) = (vertices(got), vertices(want));
    assert_eq!(g.len(), w.len(), "{name}: vertex count");
    for (a, b) in g.iter().zip(&w) {
        assert!(
            a.iter().zip(b).all(|(x, y)| (x - y).abs() < TOL),
            "{name}: vertex {a:?} vs {b:?}"
        );
    }
}

/// Every encoding of `shape` in every format, named with its extension.
fn every_encoding(shape: &Shape) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![
        (
            "ascii.ply".to_owned(),
            writers::ply(shape, None, Ply::Ascii),
        ),
        (
            "little.ply".to_owned(),
            writers::ply(shape, None, Ply::Little),
        ),
        ("big.ply".to_owned(), writers::ply(shape, None, Ply::Big)),
        ("ascii.stl".to_owned(), writers::stl_ascii(shape)),
        ("binary.stl".to_owned(), writers::stl_binary(shape)),
    ];
    for (name, buffer) in [
        ("data.gltf", GltfBuffer::DataUri),
        ("bin.glb", GltfBuffer::Glb),
    ] {
        let mesh = GltfMesh {
            shape,
            normals: None,
            extras: &[],
            material: None,
        };
        out.push((name.to_owned(), writers::gltf(&[mesh], &[], &[], buffer).0));
    }
    out
}

#[test]
fn every_format_loads_the_cube_as_its_obj_does() {
    let cube = writers::cube();
    let opts = NormalOptions::default();
    let want = parse_obj(&cube.obj(), "cube.obj", None, &opts).expect("obj");
    assert_eq!(want.positions.len(), 24, "60-degree crease: flat faces");
    for (name, bytes) in every_encoding(&cube) {
        assert_same_surface(&name, &load(&bytes, &name, &opts), &want);
    }
}

#[test]
fn every_format_smooths_a_sphere_as_its_obj_does() {
    // A closed sphere, positions shared: smooth under the default 60-degree crease, and under
    // S1's options (crease 180); any difference in welding or defaults shows in the normals.
    let soup = primitives::uv_sphere(1.0, 24, 12).to_soup();
    let sphere = Shape {
        positions: soup.positions.clone(),
        faces: soup.triangles.iter().map(|t| t.to_vec()).collect(),
    };
    for opts in [NormalOptions::default(), NormalOptions::s1()] {
        let want = parse_obj(&sphere.obj(), "sphere.obj", None, &opts).expect("obj");
        assert_eq!(want.stats().surfaces, 1);
        for (name, bytes) in every_encoding(&sphere) {
            let got = load(&bytes, &name, &opts);
            assert_same_surface(&name, &got, &want);
            let mut a = got.clone();
            let mut b = want.clone();
            a.normalize_unit();
            b.normalize_unit();
            assert!(
                (a.bounds().1 - b.bounds().1).abs().max_element() < TOL,
                "{name}"
            );
        }
    }
}

#[test]
fn ply_normals_are_used_as_authored_unless_computed_is_asked() {
    let cube = writers::cube();
    // Deliberately not the geometric normals: every vertex says +Z.
    let authored = vec![Vec3::Z; cube.positions.len()];
    for encoding in [Ply::Ascii, Ply::Little, Ply::Big] {
        let bytes = writers::ply(&cube, Some(&authored), encoding);
        let m = load(&bytes, "n.ply", &NormalOptions::default());
        assert!(
            m.normals.iter().all(|n| (*n - Vec3::Z).length() < TOL),
            "{encoding:?}"
        );
        let computed = NormalOptions {
            source: NormalSource::Computed,
            ..NormalOptions::default()
        };
        let m = load(&bytes, "n.ply", &computed);
        assert_eq!(m.positions.len(), 24, "{encoding:?}");
    }
}

#[test]
fn ply_reads_narrow_index_types_and_the_vertex_index_name() {
    let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n\
                property double z\nproperty uchar red\nelement face 1\n\
                property list uchar ushort vertex_index\nend_header\n\
                0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 9\n4 0 1 2 3\n";
    let m = load(text.as_bytes(), "q.ply", &NormalOptions::default());
    assert_eq!(m.triangle_count(), 2);
    assert_eq!(m.stats().surfaces, 1);
    assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < TOL));
}

#[test]
fn stl_corners_are_welded_into_shared_positions() {
    let cube = writers::cube();
    for (name, bytes) in [
        ("a.stl", writers::stl_ascii(&cube)),
        ("b.stl", writers::stl_binary(&cube)),
    ] {
        // 36 stored corners weld to the cube's 8 positions, so the whole cube is one
        // connected mesh under crease 180, with one normal per position.
        let m = load(&bytes, name, &NormalOptions::smooth_all(Default::default()));
        assert_eq!(m.stats().positions, 8, "{name}");
        assert_eq!(m.positions.len(), 8, "{name}");
        assert_eq!(m.stats().surfaces, 1, "{name}");
    }
}

fn cube_gltf(node: &str, colours: &[[f32; 4]], material: Option<usize>) -> Mesh {
    let cube = writers::cube().triangulated();
    let mesh = GltfMesh {
        shape: &cube,
        normals: None,
        extras: &[],
        material,
    };
    let (bytes, _) = writers::gltf(&[mesh], &[node], colours, GltfBuffer::DataUri);
    load(&bytes, "c.gltf", &NormalOptions::default())
}

#[test]
fn gltf_node_transforms_place_the_mesh() {
    let m = cube_gltf("\"translation\":[10,0,0],\"scale\":[2,3,4]", &[], None);
    let (lo, hi) = m.bounds();
    assert!((lo - Vec3::new(10.0, 0.0, 0.0)).length() < TOL, "{lo}");
    assert!((hi - Vec3::new(12.0, 3.0, 4.0)).length() < TOL, "{hi}");
    // A child inherits its parent's transform.
    let cube = writers::cube().triangulated();
    let mesh = GltfMesh {
        shape: &cube,
        normals: None,
        extras: &[],
        material: None,
    };
    let (bytes, _) = writers::gltf(&[mesh], &["\"children\":[1]"], &[], GltfBuffer::DataUri);
    let text = String::from_utf8(bytes).expect("utf8").replace(
        "\"nodes\":[{\"mesh\":0,\"children\":[1]}]",
        "\"nodes\":[{\"children\":[1],\"translation\":[0,5,0]},{\"mesh\":0,\"scale\":[2,2,2]}]",
    );
    let m = load(text.as_bytes(), "c.gltf", &NormalOptions::default());
    let (lo, hi) = m.bounds();
    assert!((lo - Vec3::new(0.0, 5.0, 0.0)).length() < TOL, "{lo}");
    assert!((hi - Vec3::new(2.0, 7.0, 2.0)).length() < TOL, "{hi}");
}

#[test]
fn gltf_mirroring_node_keeps_faces_facing_out() {
    let m = cube_gltf("\"scale\":[-1,1,1]", &[], None);
    let centre = (m.bounds().0 + m.bounds().1) / 2.0;
    for t in 0..m.triangle_count() {
        let [a, b, c] = m.triangle_positions(t).expect("in range");
        let n = m.face_normal(t).expect("not degenerate");
        assert!(
            n.dot((a + b + c) / 3.0 - centre) > 0.0,
            "triangle {t} faces in"
        );
    }
}

#[test]
fn gltf_base_colour_becomes_kd() {
    let m = cube_gltf("", &[[0.2, 0.4, 0.6, 1.0]], Some(0));
    assert_eq!(m.materials.len(), 1);
    assert_eq!(m.materials[0].name, "paint0");
    assert!((m.materials[0].kd - Vec3::new(0.2, 0.4, 0.6)).length() < TOL);
    assert!(m.material_ids.iter().all(|&i| i == 0));

    // Two meshes, one without a material: it gets glTF's default (white), appended.
    let cube = writers::cube().triangulated();
    let meshes = [
        GltfMesh {
            shape: &cube,
            normals: None,
            extras: &[],
            material: Some(0),
        },
        GltfMesh {
            shape: &cube,
            normals: None,
            extras: &[],
            material: None,
        },
    ];
    let (bytes, _) = writers::gltf(
        &meshes,
        &["", "\"translation\":[3,0,0]"],
        &[[1.0, 0.0, 0.0, 1.0]],
        GltfBuffer::DataUri,
    );
    let m = load(&bytes, "two.gltf", &NormalOptions::default());
    assert_eq!(m.materials.len(), 2);
    assert_eq!(m.materials[1].kd, Vec3::ONE);
    assert_eq!(m.material_ids.iter().filter(|&&i| i == 0).count(), 12);
    assert_eq!(m.material_ids.iter().filter(|&&i| i == 1).count(), 12);
    assert_eq!(m.groups, vec!["mesh0".to_owned(), "mesh1".to_owned()]);
}

#[test]
fn gltf_normals_are_used_as_authored_and_turned_with_the_node() {
    let cube = writers::cube().triangulated();
    let authored = vec![Vec3::Z; cube.positions.len()];
    let mesh = GltfMesh {
        shape: &cube,
        normals: Some(&authored),
        extras: &[],
        material: None,
    };
    // A quarter turn about X takes +Z to -Y.
    let (bytes, _) = writers::gltf(
        &[mesh],
        &["\"rotation\":[0.70710678,0,0,0.70710678]"],
        &[],
        GltfBuffer::DataUri,
    );
    let m = load(&bytes, "n.gltf", &NormalOptions::default());
    assert!(
        m.normals.iter().all(|n| (*n - Vec3::NEG_Y).length() < 1e-5),
        "{:?}",
        &m.normals[..3]
    );
}

#[test]
fn gltf_buffers_load_from_a_data_uri_a_glb_chunk_and_a_relative_file() {
    let dir = writers::temp_dir("gltf-buffers");
    let cube = writers::cube().triangulated();
    let make = |buffer| {
        let mesh = GltfMesh {
            shape: &cube,
            normals: None,
            extras: &[],
            material: None,
        };
        writers::gltf(&[mesh], &[], &[], buffer)
    };
    let (json, bin) = make(GltfBuffer::External);
    std::fs::write(dir.join("ext.gltf"), json).expect("write");
    std::fs::write(dir.join("mesh.bin"), bin).expect("write");
    std::fs::write(dir.join("data.gltf"), make(GltfBuffer::DataUri).0).expect("write");
    std::fs::write(dir.join("bin.GLB"), make(GltfBuffer::Glb).0).expect("write");
    let opts = NormalOptions::default();
    let want = load_mesh(&dir.join("data.gltf"), &opts).expect("data URI");
    for name in ["ext.gltf", "bin.GLB"] {
        let got = load_mesh(&dir.join(name), &opts).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(got, want, "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn load_mesh_picks_the_reader_by_extension() {
    let dir = writers::temp_dir("dispatch");
    let cube = writers::cube();
    let opts = NormalOptions::default();
    let want = parse_obj(&cube.obj(), "cube.obj", None, &opts).expect("obj");
    std::fs::write(dir.join("cube.obj"), cube.obj()).expect("write");
    std::fs::write(dir.join("cube.PLY"), writers::ply(&cube, None, Ply::Little)).expect("write");
    std::fs::write(dir.join("cube.stl"), writers::stl_binary(&cube)).expect("write");
    for name in ["cube.obj", "cube.PLY", "cube.stl"] {
        let got = load_mesh(&dir.join(name), &opts).unwrap_or_else(|e| panic!("{e}"));
        assert_same_surface(name, &got, &want);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
