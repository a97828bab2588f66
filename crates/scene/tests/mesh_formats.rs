//! A scene file's `mesh = "..."` and S1's `--mesh` take PLY, STL and glTF files as they take
//! OBJ files: chosen by extension, glTF buffers read next to the file, errors naming the field.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use phosphor_scene::{MeshRef, Scene, Transform};

const CORNERS: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];

fn write_files(dir: &Path) {
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n").unwrap();

    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement face 1\n\
                    property list uchar uint vertex_indices\nend_header\n"
        .to_vec();
    for c in CORNERS.iter().flatten() {
        ply.extend_from_slice(&c.to_le_bytes());
    }
    ply.push(3);
    for i in 0u32..3 {
        ply.extend_from_slice(&i.to_le_bytes());
    }
    std::fs::write(dir.join("tri.ply"), ply).unwrap();

    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&1u32.to_le_bytes());
    stl.extend_from_slice(&[0u8; 12]);
    for c in CORNERS.iter().flatten() {
        stl.extend_from_slice(&c.to_le_bytes());
    }
    stl.extend_from_slice(&[0, 0]);
    std::fs::write(dir.join("tri.stl"), stl).unwrap();

    let bin: Vec<u8> = CORNERS
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), bin).unwrap();
    let gltf = "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\
                \"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\
                \"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\
                \"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[2,2,0]}],\
                \"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\
                \"buffers\":[{\"byteLength\":36,\"uri\":\"tri.bin\"}]}";
    std::fs::write(dir.join("tri.gltf"), gltf).unwrap();
}

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "phosphor-scene-formats-{test}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The object's mesh with its positions in world space (a glTF's nodes are entities placed
/// by their transforms, the file's normalization included).
fn mesh_of(scene: &Scene, object: usize) -> phosphor_mesh::Mesh {
    let e = scene.objects()[object];
    let mut mesh = scene.world.get::<&MeshRef>(e).unwrap().0.mesh.clone();
    let m = scene.world.get::<&Transform>(e).unwrap().matrix();
    for p in &mut mesh.positions {
        *p = m.transform_point3(*p);
    }
    mesh
}

#[test]
fn scene_objects_load_every_mesh_format_by_extension() {
    let dir = temp_dir("objects");
    write_files(&dir);
    let names = ["tri.obj", "tri.ply", "tri.stl", "tri.gltf"];
    let objects: String = names
        .iter()
        .map(|n| format!("[[objects]]\nmesh = \"{n}\"\nnormalize = true\n"))
        .collect();
    let light = "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n";
    std::fs::write(dir.join("s.toml"), format!("{light}{objects}")).unwrap();
    let scene = Scene::load(&dir.join("s.toml")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let want = mesh_of(&scene, 0);
    for (i, name) in names.iter().enumerate().skip(1) {
        let got = mesh_of(&scene, i);
        assert_eq!(got.triangle_count(), 1, "{name}");
        for p in &want.positions {
            assert!(
                got.positions.iter().any(|q| (*p - *q).length() < 1e-6),
                "{name}: {p} missing from {:?}",
                got.positions
            );
        }
        assert!(got.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn s1_takes_any_mesh_format() {
    let dir = temp_dir("s1");
    write_files(&dir);
    let want = mesh_of(&Scene::s1_with_mesh(&dir.join("tri.obj")).unwrap(), 0);
    for name in ["tri.ply", "tri.stl", "tri.gltf"] {
        let got = mesh_of(&Scene::s1_with_mesh(&dir.join(name)).unwrap(), 0);
        let (got, want) = (got.bounds(), want.bounds());
        assert!(
            (got.0 - want.0).length() < 1e-6 && (got.1 - want.1).length() < 1e-6,
            "{name}: normalized alike: {got:?} vs {want:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_broken_mesh_file_names_the_field_and_the_element() {
    let dir = temp_dir("broken");
    std::fs::write(dir.join("cut.stl"), [0u8; 90]).unwrap();
    std::fs::write(dir.join("s.toml"), "[[objects]]\nmesh = \"cut.stl\"\n").unwrap();
    let e = Scene::load(&dir.join("s.toml")).unwrap_err().to_string();
    assert!(e.contains("s.toml: objects[0].mesh: "), "{e}");
    assert!(e.contains("cut.stl: "), "{e}");
    // The glTF's buffer is missing: named by the buffer, read relative to the glTF.
    write_files(&dir);
    std::fs::remove_file(dir.join("tri.bin")).unwrap();
    std::fs::write(dir.join("s.toml"), "[[objects]]\nmesh = \"tri.gltf\"\n").unwrap();
    let e = Scene::load(&dir.join("s.toml")).unwrap_err().to_string();
    assert!(
        e.contains("tri.gltf: buffers[0]: cannot read 'tri.bin'"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
