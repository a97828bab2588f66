//! Texture references from hostile files: glTF image URIs that climb out of the asset's
//! folder (confined as buffer URIs are), image files that are FIFOs (read through the same
//! opener as every input), one image named by many materials (resolved and copied once), MTL
//! map lines without an end (the line cap holds for the map scan too), and terminal control
//! characters in map options, image URIs and extension names (escaped in warnings).

mod writers;

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use phosphor_mesh::{
    MAX_LINE_BYTES, Mesh, MeshFormat, NormalOptions, TextureSource, load_mesh_with_warnings,
    parse_mesh_bytes, parse_obj_with_warnings,
};
use writers::{GltfBuffer, GltfDoc, GltfImage, GltfMesh, Shape};

fn triangle() -> Shape {
    Shape {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        faces: vec![vec![0, 1, 2]],
    }
}

/// A triangle whose material `k` uses texture `k`, texture `k` image `sources[k]`, and whose
/// images are `images`.
fn textured(materials: usize, sources: &[usize], images: &[GltfImage], ext: &[&str]) -> Vec<u8> {
    let shape = triangle();
    let mesh = GltfMesh {
        shape: &shape,
        normals: None,
        extras: &[],
        material: Some(0),
    };
    let materials: Vec<String> = (0..materials)
        .map(|k| format!("{{\"pbrMetallicRoughness\":{{\"baseColorTexture\":{{\"index\":{k}}}}}}}"))
        .collect();
    let textures: Vec<String> = sources
        .iter()
        .map(|s| format!("{{\"source\":{s}}}"))
        .collect();
    writers::gltf_doc(&GltfDoc {
        meshes: &[mesh],
        node_extras: &[],
        base_colours: &[],
        buffer: GltfBuffer::DataUri,
        materials: &materials,
        textures: &textures,
        samplers: &[],
        images,
        extensions_used: ext,
    })
    .0
}

fn parse(bytes: &[u8], name: &str) -> (Mesh, Vec<String>) {
    let never = |uri: &str| -> std::io::Result<Vec<u8>> { panic!("{uri} must not be read") };
    let format = MeshFormat::from_path(Path::new(name));
    parse_mesh_bytes(bytes, name, format, &never, &NormalOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn gltf_image_uris_stay_in_the_folder_as_buffer_uris_do() {
    let dir = writers::temp_dir("image-escape");
    std::fs::create_dir_all(dir.join("model")).expect("dir");
    std::fs::write(dir.join("secret.png"), b"secret").expect("write");
    std::fs::write(dir.join("model/ok.png"), b"png").expect("write");
    let gltf = dir.join("model/m.gltf");
    for uri in ["../secret.png", "a/../../secret.png", "..%2Fsecret.png"] {
        let json = textured(1, &[0], &[GltfImage::Uri(uri.to_owned())], &[]);
        std::fs::write(&gltf, json).expect("write");
        let (m, warnings) =
            load_mesh_with_warnings(&gltf, &NormalOptions::default()).expect("the mesh loads");
        assert!(m.materials[0].kd_map.is_none(), "{uri}: not used");
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let w = &warnings[0];
        assert!(w.contains("materials[0].pbrMetallicRoughness.baseColorTexture: images[0]: uri '"));
        assert!(w.contains("leads outside the glTF file's folder"), "{w}");
        assert!(w.ends_with("; texture not used"), "{w}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("../secret.png", dir.join("model/link.png")).expect("link");
        let json = textured(1, &[0], &[GltfImage::Uri("link.png".to_owned())], &[]);
        std::fs::write(&gltf, json).expect("write");
        let (m, warnings) =
            load_mesh_with_warnings(&gltf, &NormalOptions::default()).expect("mesh");
        assert!(m.materials[0].kd_map.is_none());
        assert!(warnings[0].contains("leads outside"), "{warnings:?}");
    }
    let json = textured(1, &[0], &[GltfImage::Uri("ok.png".to_owned())], &[]);
    std::fs::write(&gltf, json).expect("write");
    let (m, warnings) = load_mesh_with_warnings(&gltf, &NormalOptions::default()).expect("mesh");
    assert!(warnings.is_empty(), "{warnings:?}");
    let kd = m.materials[0].kd_map.as_ref().expect("inside the folder");
    assert_eq!(kd.written, "ok.png");
    assert_eq!(&kd.source.bytes().expect("read")[..], b"png");
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn an_image_file_that_is_a_fifo_is_refused_without_blocking() {
    let dir = writers::temp_dir("image-fifo");
    let fifo = dir.join("t.png");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let (tx, rx) = std::sync::mpsc::channel();
    let source = TextureSource::File(fifo);
    std::thread::spawn(move || {
        let _ = tx.send(source.bytes().map_err(|e| e.to_string()));
    });
    let e = rx
        .recv_timeout(std::time::Duration::from_secs(30))
        .expect("a FIFO must not block the read")
        .expect_err("refused");
    assert_eq!(e, "a FIFO, not a regular file");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_image_named_by_many_textures_is_decoded_once_and_shared() {
    let image = GltfImage::Uri(format!(
        "data:image/png;base64,{}",
        writers::base64(&[7u8; 300])
    ));
    let (m, warnings) = parse(&textured(3, &[0, 0, 0], &[image], &[]), "many.gltf");
    assert!(warnings.is_empty(), "{warnings:?}");
    let bytes: Vec<Arc<[u8]>> = m
        .materials
        .iter()
        .take(3)
        .map(|mat| match &mat.kd_map.as_ref().expect("map").source {
            TextureSource::Embedded { bytes, .. } => bytes.clone(),
            other => panic!("embedded: {other:?}"),
        })
        .collect();
    assert!(Arc::ptr_eq(&bytes[0], &bytes[1]) && Arc::ptr_eq(&bytes[0], &bytes[2]));
    // A bad image is refused for the same reason by every material naming it.
    let bad = GltfImage::Uri("data:image/png;base64,%%%%".to_owned());
    let (_, warnings) = parse(&textured(2, &[0, 0], &[bad], &[]), "bad.gltf");
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings.iter().all(|w| w.contains("malformed base64")));
}

#[test]
fn terminal_control_in_texture_text_is_escaped_in_warnings() {
    let image = GltfImage::Uri("http://x/\\u001b[2J".to_owned());
    let (_, warnings) = parse(&textured(1, &[0], &[image], &["E\\u001b[31m"]), "t.gltf");
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    for w in &warnings {
        assert!(!w.contains('\u{1b}'), "{w:?}");
    }
    assert!(warnings.iter().any(|w| w.contains("extension E\\e[31m")));
    assert!(warnings.iter().any(|w| w.contains("uri 'http://x/\\e[2J'")));
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let mtl = "newmtl a\nmap_Kd -clamp \u{1b}[2J t.png\nmap_Ks -zz\u{202e} s.png\n";
    let (m, warnings) =
        parse_obj_with_warnings(obj, "m.obj", Some(mtl), &NormalOptions::default()).expect("obj");
    assert!(m.materials[0].kd_map.is_some());
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].contains("found '\\e[2J'"), "{warnings:?}");
    assert!(warnings[1].contains("'-zz\\u{202e}'"), "{warnings:?}");
}

#[test]
fn an_mtl_map_line_over_the_line_cap_costs_the_material_only() {
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let mut mtl = "newmtl a\nKd 1 0 0\nmap_Kd ".to_owned();
    mtl.push_str(&"x".repeat(MAX_LINE_BYTES + 1));
    let (m, warnings) =
        parse_obj_with_warnings(obj, "m.obj", Some(&mtl), &NormalOptions::default()).expect("obj");
    assert!(m.materials.iter().all(|x| x.kd_map.is_none()));
    assert!(
        warnings[0].starts_with("m.obj: MTL: line 3: line longer than 1 MiB"),
        "{warnings:?}"
    );
    let dir = writers::temp_dir("mtl-long-map");
    std::fs::write(dir.join("m.obj"), obj).expect("obj");
    std::fs::write(dir.join("m.mtl"), &mtl).expect("mtl");
    let (m, warnings) =
        load_mesh_with_warnings(&dir.join("m.obj"), &NormalOptions::default()).expect("obj");
    assert!(m.materials.iter().all(|x| x.kd_map.is_none()));
    assert!(
        warnings[0].contains("line 3: line longer than 1 MiB"),
        "{warnings:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
