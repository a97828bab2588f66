//! Broken PLY, STL and glTF files give one-line errors naming the file and the line or
//! element, as broken OBJ files do; no input panics.

mod writers;

use std::path::Path;

use phosphor_mesh::{MeshError, MeshFormat, NormalOptions, load_mesh, parse_mesh_bytes};
use proptest::prelude::*;
use writers::{GltfBuffer, GltfMesh, Ply};

fn no_files(_: &str) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
}

fn parse(bytes: &[u8], name: &str) -> Result<phosphor_mesh::Mesh, MeshError> {
    let format = MeshFormat::from_path(Path::new(name));
    parse_mesh_bytes(bytes, name, format, &no_files, &NormalOptions::default()).map(|(m, _)| m)
}

/// The error of `bytes`, checked to be one line starting with `prefix` and mentioning `words`.
fn assert_error(bytes: &[u8], name: &str, prefix: &str, words: &str) -> MeshError {
    let e = match parse(bytes, name) {
        Ok(_) => panic!("{name}: expected an error starting {prefix:?}"),
        Err(e) => e,
    };
    let msg = e.to_string();
    assert!(
        msg.starts_with(prefix),
        "{msg:?} should start with {prefix:?}"
    );
    assert!(msg.contains(words), "{msg:?} should mention {words:?}");
    assert!(!msg.contains('\n'), "{msg:?} is one line");
    e
}

fn cube_ply(encoding: Ply) -> Vec<u8> {
    writers::ply(&writers::cube(), None, encoding)
}

fn cube_gltf(buffer: GltfBuffer) -> (Vec<u8>, Vec<u8>) {
    let cube = writers::cube().triangulated();
    let mesh = GltfMesh {
        shape: &cube,
        normals: None,
        extras: &[],
        material: None,
    };
    writers::gltf(&[mesh], &[], &[], buffer)
}

/// Offset of the payload (after `end_header\n`) of a PLY file.
fn payload_start(ply: &[u8]) -> usize {
    let marker = b"end_header\n";
    ply.windows(marker.len())
        .position(|w| w == marker)
        .expect("header")
        + marker.len()
}

#[test]
fn empty_files_have_no_faces() {
    for name in ["e.ply", "e.stl", "e.gltf", "e.glb"] {
        let e = parse(b"", name).expect_err(name);
        assert!(matches!(e, MeshError::NoFaces { .. }), "{name}: {e}");
        assert!(
            e.to_string().starts_with(&format!("{name}: no faces")),
            "{e}"
        );
    }
    let faceless = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n\
                    property float y\nproperty float z\nend_header\n0 0 0\n";
    assert!(matches!(
        parse(faceless.as_bytes(), "p.ply"),
        Err(MeshError::NoFaces { .. })
    ));
    let mut zero = vec![b' '; 80];
    zero.extend_from_slice(&0u32.to_le_bytes());
    assert!(matches!(
        parse(&zero, "z.stl"),
        Err(MeshError::NoFaces { .. })
    ));
    assert!(matches!(
        parse(b"solid x\nendsolid x\n", "a.stl"),
        Err(MeshError::NoFaces { .. })
    ));
    let meshless = "{\"asset\":{\"version\":\"2.0\"}}";
    assert!(matches!(
        parse(meshless.as_bytes(), "m.gltf"),
        Err(MeshError::NoFaces { .. })
    ));
}

#[test]
fn truncated_binary_files_name_the_element_where_they_end() {
    for encoding in [Ply::Little, Ply::Big] {
        let ply = cube_ply(encoding);
        let start = payload_start(&ply);
        // Vertices are 16 bytes (x y z confidence): cut inside the third.
        let cut = &ply[..start + 2 * 16 + 5];
        let e = assert_error(cut, "t.ply", "t.ply: vertex 3 of 8: ", "truncated");
        assert!(matches!(e, MeshError::Element { .. }));
        // Cut inside the last face.
        let cut = &ply[..ply.len() - 8 - 3];
        assert_error(cut, "t.ply", "t.ply: face 6 of 6: ", "truncated");
    }
    let stl = writers::stl_binary(&writers::cube());
    assert_error(
        &stl[..84 + 50 * 4 + 7],
        "t.stl",
        "t.stl: facet 5 of 12: ",
        "truncated",
    );
    let mut headless = stl.clone();
    headless[..5].copy_from_slice(b"SOLID");
    assert_error(&headless[..60], "t.stl", "t.stl: header: ", "truncated");
    let glb = cube_gltf(GltfBuffer::Glb).0;
    assert_error(
        &glb[..glb.len() - 40],
        "t.glb",
        "t.glb: BIN chunk: ",
        "truncated",
    );
}

#[test]
fn a_short_external_buffer_names_the_buffer() {
    let dir = writers::temp_dir("short-buffer");
    let (json, bin) = cube_gltf(GltfBuffer::External);
    std::fs::write(dir.join("s.gltf"), &json).expect("write");
    std::fs::write(dir.join("mesh.bin"), &bin[..bin.len() / 2]).expect("write");
    let e = load_mesh(&dir.join("s.gltf"), &NormalOptions::default()).expect_err("short");
    let msg = e.to_string();
    assert!(msg.contains("s.gltf: buffers[0]: truncated"), "{msg}");
    std::fs::remove_file(dir.join("mesh.bin")).expect("remove");
    let e = load_mesh(&dir.join("s.gltf"), &NormalOptions::default()).expect_err("missing");
    assert!(
        e.to_string().contains("buffers[0]: cannot read 'mesh.bin'"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn indices_out_of_range_are_named() {
    let ply = String::from_utf8(cube_ply(Ply::Ascii)).expect("ascii");
    // The first face line is `4 0 3 2 1 `, on line 23 (14 header lines, 8 vertices).
    let bad = ply.replacen("4 0 3 2 1 ", "4 0 3 2 8 ", 1);
    assert_error(
        bad.as_bytes(),
        "i.ply",
        "i.ply:23: face 1 of 6: ",
        "index 8 out of range",
    );
    let bad = ply.replacen("4 0 3 2 1 ", "4 0 3 2 -1 ", 1);
    assert_error(
        bad.as_bytes(),
        "i.ply",
        "i.ply:23: face 1 of 6: ",
        "index -1 out of range",
    );

    let mut ply = cube_ply(Ply::Little);
    let start = payload_start(&ply) + 8 * 16;
    ply[start + 1..start + 5].copy_from_slice(&99i32.to_le_bytes());
    assert_error(
        &ply,
        "i.ply",
        "i.ply: face 1 of 6: ",
        "index 99 out of range",
    );

    let gltf = String::from_utf8(cube_gltf(GltfBuffer::DataUri).0).expect("json");
    // Declare only 7 vertices: index 7 falls outside.
    let bad = gltf.replacen("\"count\":8", "\"count\":7", 1);
    assert_error(
        bad.as_bytes(),
        "i.gltf",
        "i.gltf: meshes[0].primitives[0]: ",
        "out of range (7 vertices)",
    );
}

#[test]
fn nan_coordinates_are_named() {
    let mut ply = cube_ply(Ply::Big);
    let start = payload_start(&ply) + 16 + 4;
    ply[start..start + 4].copy_from_slice(&f32::NAN.to_be_bytes());
    assert_error(&ply, "n.ply", "n.ply: vertex 2 of 8: ", "NaN");

    let mut stl = writers::stl_binary(&writers::cube());
    let at = 84 + 50 * 2 + 12 + 4;
    stl[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    assert_error(
        &stl,
        "n.stl",
        "n.stl: facet 3 of 12: ",
        "vertex 1: NaN or infinite",
    );

    let text = String::from_utf8(writers::stl_ascii(&writers::cube())).expect("ascii");
    let bad = text.replacen("vertex 1 1 0", "vertex 1 nan 0", 1);
    let e = assert_error(bad.as_bytes(), "n.stl", "n.stl:", "facet 1: ");
    assert!(e.line().is_some(), "{e}");

    let dir = writers::temp_dir("nan-gltf");
    let (json, mut bin) = cube_gltf(GltfBuffer::External);
    bin[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(dir.join("n.gltf"), &json).expect("write");
    std::fs::write(dir.join("mesh.bin"), &bin).expect("write");
    let e = load_mesh(&dir.join("n.gltf"), &NormalOptions::default()).expect_err("NaN");
    assert!(
        e.to_string()
            .ends_with("n.gltf: meshes[0].primitives[0]: POSITION[1]: NaN or infinite coordinate"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gltf_uris_outside_the_file_are_refused_not_fetched() {
    let gltf = String::from_utf8(cube_gltf(GltfBuffer::External).0).expect("json");
    let bad = gltf.replace(
        "\"uri\":\"mesh.bin\"",
        "\"uri\":\"https://example.invalid/mesh.bin\"",
    );
    assert_error(
        bad.as_bytes(),
        "u.gltf",
        "u.gltf: buffers[0]: ",
        "not a relative file",
    );
}

#[test]
fn malformed_gltf_accessors_are_errors_not_panics() {
    let gltf = String::from_utf8(cube_gltf(GltfBuffer::DataUri).0).expect("json");
    // Positions as unsigned bytes: a type the POSITION attribute may not have here.
    let bad = gltf.replacen("\"componentType\":5126", "\"componentType\":5121", 1);
    assert_error(
        bad.as_bytes(),
        "a.gltf",
        "a.gltf: meshes[0].primitives[0]: ",
        "POSITION",
    );
    // More elements than the buffer view holds.
    let bad = gltf.replacen("\"count\":8", "\"count\":800", 1);
    assert_error(
        bad.as_bytes(),
        "a.gltf",
        "a.gltf: meshes[0].primitives[0]: ",
        "do not fit",
    );
    // A dangling index is caught by the crate's validation.
    let bad = gltf.replacen("\"bufferView\":0", "\"bufferView\":9", 1);
    assert_error(
        bad.as_bytes(),
        "a.gltf",
        "a.gltf: invalid glTF: ",
        "accessors[0]",
    );
    assert_error(b"{ not json", "a.gltf", "a.gltf: not a readable glTF", "");
    // A POSITION naming an accessor that does not exist (the crate's own validation would
    // index past its accessor list here).
    let at = gltf.find("\"POSITION\":").expect("a POSITION attribute");
    let digits = gltf[at + 11..]
        .find(|c: char| !c.is_ascii_digit())
        .expect("digits end");
    let bad = format!(
        "{}\"POSITION\":57{}",
        &gltf[..at],
        &gltf[at + 11 + digits..]
    );
    assert_error(
        bad.as_bytes(),
        "a.gltf",
        "a.gltf: invalid glTF: meshes[0].primitives[0].attributes.POSITION: ",
        "accessor 57 does not exist",
    );
}

#[test]
fn a_missing_file_names_it() {
    for name in [
        "/nonexistent/dir/a.ply",
        "/nonexistent/dir/a.stl",
        "/nonexistent/dir/a.glb",
    ] {
        let e = load_mesh(Path::new(name), &NormalOptions::default()).expect_err(name);
        assert!(
            e.to_string().starts_with(&format!("{name}: cannot read")),
            "{e}"
        );
    }
}

/// Valid files of every format and encoding, to be damaged.
fn valid_files() -> Vec<(&'static str, Vec<u8>)> {
    let cube = writers::cube();
    vec![
        ("a.ply", cube_ply(Ply::Ascii)),
        ("l.ply", cube_ply(Ply::Little)),
        ("b.ply", cube_ply(Ply::Big)),
        ("a.stl", writers::stl_ascii(&cube)),
        ("b.stl", writers::stl_binary(&cube)),
        ("d.gltf", cube_gltf(GltfBuffer::DataUri).0),
        ("b.glb", cube_gltf(GltfBuffer::Glb).0),
    ]
}

fn check_damaged(name: &str, bytes: &[u8]) {
    for opts in [NormalOptions::default(), NormalOptions::s1()] {
        let format = MeshFormat::from_path(Path::new(name));
        match parse_mesh_bytes(bytes, name, format, &no_files, &opts) {
            Ok((m, _)) => assert!(m.is_consistent(), "{name}: inconsistent mesh"),
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.starts_with(name) && !msg.contains('\n'), "{msg:?}");
            }
        }
    }
}

#[test]
fn every_truncation_is_an_error_or_a_mesh_never_a_panic() {
    for (name, bytes) in valid_files() {
        for len in 0..bytes.len() {
            check_damaged(name, &bytes[..len]);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn damaged_bytes_are_an_error_or_a_mesh_never_a_panic(
        file in 0usize..7,
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
    ) {
        let (name, mut bytes) = valid_files().swap_remove(file);
        for (at, value) in edits {
            let i = at.index(bytes.len());
            bytes[i] = value;
        }
        check_damaged(name, &bytes);
    }
}
