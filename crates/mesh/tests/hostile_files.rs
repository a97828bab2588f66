//! Files built to hang, abort or leak: FIFOs and devices where a mesh or buffer should be,
//! buffer URIs that climb out of the asset's folder, instancing and buffer counts that ask for
//! more memory than there is, lines without an end, terminal control in a file's text, and
//! the STL, PLY and GLB shapes a hostile-input campaign found misread. Each is refused on one
//! line before anything large is read, or read correctly.

mod writers;

use std::cell::Cell;
use std::path::Path;

use phosphor_mesh::{
    MAX_LINE_BYTES, MeshError, MeshFormat, NormalOptions, load_mesh, parse_mesh_bytes,
};
use writers::{GltfBuffer, GltfMesh};

fn parse_with(
    bytes: &[u8],
    name: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
) -> Result<phosphor_mesh::Mesh, MeshError> {
    let format = MeshFormat::from_path(Path::new(name));
    parse_mesh_bytes(
        bytes,
        name,
        format,
        read_relative,
        &NormalOptions::default(),
    )
    .map(|(m, _)| m)
}

fn parse(bytes: &[u8], name: &str) -> Result<phosphor_mesh::Mesh, MeshError> {
    let never = |uri: &str| -> std::io::Result<Vec<u8>> { panic!("{uri} must not be read") };
    parse_with(bytes, name, &never)
}

fn error(bytes: &[u8], name: &str) -> String {
    match parse(bytes, name) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(e) => e.to_string(),
    }
}

/// Loads `path` on another thread; `None` when it has not finished within 30 s (a load
/// blocked on a FIFO never would).
fn load_or_hang(path: &Path) -> Option<Result<usize, String>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let path = path.to_owned();
    std::thread::spawn(move || {
        let r = load_mesh(&path, &NormalOptions::default());
        let _ = tx.send(r.map(|m| m.indices.len()).map_err(|e| e.to_string()));
    });
    rx.recv_timeout(std::time::Duration::from_secs(30)).ok()
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let made = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(made.success(), "mkfifo failed");
}

fn cube_gltf_json() -> (String, Vec<u8>) {
    let cube = writers::cube().triangulated();
    let mesh = GltfMesh {
        shape: &cube,
        normals: None,
        extras: &[],
        material: None,
    };
    let (json, bin) = writers::gltf(&[mesh], &[], &[], GltfBuffer::External);
    (String::from_utf8(json).expect("json"), bin)
}

#[cfg(unix)]
#[test]
fn fifo_as_mesh_is_refused_without_blocking() {
    let dir = writers::temp_dir("fifo-mesh");
    for ext in ["stl", "ply", "glb", "gltf", "obj"] {
        let fifo = dir.join(format!("pipe.{ext}"));
        mkfifo(&fifo);
        let e = load_or_hang(&fifo)
            .unwrap_or_else(|| panic!(".{ext}: a FIFO must not block the load"))
            .expect_err("refused");
        assert!(e.contains("a FIFO, not a regular file"), "{e}");
        assert!(e.starts_with(&fifo.display().to_string()), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn fifo_as_gltf_buffer_is_refused_without_blocking() {
    let dir = writers::temp_dir("fifo-buffer");
    let (json, _) = cube_gltf_json();
    std::fs::write(dir.join("m.gltf"), json).expect("write");
    mkfifo(&dir.join("mesh.bin"));
    let e = load_or_hang(&dir.join("m.gltf"))
        .expect("a FIFO buffer must not block the load")
        .expect_err("refused");
    assert!(e.contains("buffers[0]: cannot read 'mesh.bin'"), "{e}");
    assert!(e.contains("a FIFO, not a regular file"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn dev_zero_as_mesh_is_refused_before_a_byte_is_read() {
    let dir = writers::temp_dir("dev-zero");
    for ext in ["stl", "glb"] {
        let link = dir.join(format!("zero.{ext}"));
        std::os::unix::fs::symlink("/dev/zero", &link).expect("link");
        let e = load_or_hang(&link).expect("finishes").expect_err("refused");
        assert!(e.contains("a character device, not a regular file"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gltf_buffer_uri_climbing_out_of_the_folder_is_not_read() {
    let dir = writers::temp_dir("escape");
    std::fs::create_dir_all(dir.join("model")).expect("dir");
    std::fs::write(dir.join("secret.bin"), [0u8; 4096]).expect("write");
    let (json, _) = cube_gltf_json();
    for uri in [
        "../secret.bin",
        "../../../../../../../../etc/passwd",
        "a/../../secret.bin",
    ] {
        let escaping = json.replace("\"uri\":\"mesh.bin\"", &format!("\"uri\":\"{uri}\""));
        std::fs::write(dir.join("model/m.gltf"), &escaping).expect("write");
        let e = load_mesh(&dir.join("model/m.gltf"), &NormalOptions::default())
            .expect_err("refused")
            .to_string();
        assert!(e.contains("buffers[0]: cannot read"), "{e}");
        assert!(e.contains("leads outside the glTF file's folder"), "{e}");
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("../secret.bin", dir.join("model/mesh.bin")).expect("link");
        std::fs::write(dir.join("model/m.gltf"), &json).expect("write");
        let e = load_mesh(&dir.join("model/m.gltf"), &NormalOptions::default())
            .expect_err("refused")
            .to_string();
        assert!(e.contains("leads outside the glTF file's folder"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn terminal_control_characters_from_a_file_are_escaped_in_messages() {
    let header = "ply\nformat ascii 1.0\n\u{1b}[2J \u{1b}[31m\0\nend_header\n";
    let e = error(header.as_bytes(), "t.ply");
    assert!(e.starts_with("t.ply:3: header: "), "{e}");
    assert!(e.contains("\\e[2J \\e[31m\\0"), "{e}");
    assert!(!e.contains(['\u{1b}', '\0']), "{e:?}");
    let uri = "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":4,\
               \"uri\":\"http://x/\\u001b[2J\"}]}";
    let e = error(uri.as_bytes(), "t.gltf");
    assert!(e.contains("\\e[2J") && !e.contains('\u{1b}'), "{e:?}");
    let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 \u{1b}[2J\n";
    let e = error(stl.as_bytes(), "t.stl");
    assert!(e.contains("\\e[2J") && !e.contains('\u{1b}'), "{e:?}");
}

#[test]
fn lines_without_an_end_are_refused_by_their_length() {
    let mut ply = b"ply\n".to_vec();
    ply.resize(MAX_LINE_BYTES + 64, b'x');
    let e = error(&ply, "t.ply");
    assert_eq!(
        e,
        "t.ply:2: header: line longer than 1 MiB (no text format needs one)"
    );
    let mut obj = b"v 0 0 0\nv".to_vec();
    obj.resize(MAX_LINE_BYTES + 64, b' ');
    assert!(error(&obj, "t.obj").starts_with("t.obj:2: line longer than 1 MiB"));
    let mut stl = b"solid x\nfacet normal ".to_vec();
    stl.resize(MAX_LINE_BYTES + 64, b'0');
    assert!(error(&stl, "t.stl").starts_with("t.stl:2: line longer than 1 MiB"));
    let header = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n";
    let mut body = header.as_bytes().to_vec();
    body.resize(header.len() + MAX_LINE_BYTES + 64, b'1');
    assert!(error(&body, "t.ply").starts_with("t.ply:8: line longer than 1 MiB"));
}

/// A glTF whose one mesh of `corners` unindexed corners (all at the origin) is placed by
/// `nodes` nodes; its buffer `b.bin` is never written.
fn instanced(corners: usize, nodes: usize) -> String {
    let bytes = corners * 12;
    let node_list: Vec<&str> = vec!["{\"mesh\":0}"; nodes];
    let roots: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
    format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[{}]}}],\
         \"nodes\":[{}],\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0}}}}]}}],\
         \"accessors\":[{{\"bufferView\":0,\"componentType\":5126,\"count\":{corners},\
         \"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[0,0,0]}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteLength\":{bytes}}}],\
         \"buffers\":[{{\"byteLength\":{bytes},\"uri\":\"b.bin\"}}]}}",
        roots.join(","),
        node_list.join(",")
    )
}

#[test]
fn instanced_triangles_over_the_memory_budget_are_refused_before_any_buffer_is_read() {
    // 10,000 triangles placed by 2,000 nodes: 20 million triangles, 6.2 GB once built.
    let e = error(instanced(30_000, 2_000).as_bytes(), "i.gltf");
    assert!(
        e.starts_with("i.gltf: nodes: 2000 nodes place meshes: "),
        "{e}"
    );
    assert!(
        e.contains("60000000 vertices, 20000000 triangles), over the 4.0 GB limit"),
        "{e}"
    );
}

#[test]
fn many_buffers_naming_one_file_read_it_once() {
    let (json, bin) = cube_gltf_json();
    let one = format!("{{\"byteLength\":{},\"uri\":\"mesh.bin\"}}", bin.len());
    let hundred = vec![one.as_str(); 100].join(",");
    let json = json.replace(
        &format!("\"buffers\":[{one}]"),
        &format!("\"buffers\":[{hundred}]"),
    );
    assert!(json.matches("mesh.bin").count() == 100);
    let reads = Cell::new(0);
    let read = |uri: &str| {
        assert_eq!(uri, "mesh.bin");
        reads.set(reads.get() + 1);
        Ok(bin.clone())
    };
    let mesh = parse_with(json.as_bytes(), "c.gltf", &read).expect("loads");
    assert_eq!(mesh.indices.len(), 12);
    assert_eq!(reads.get(), 1);
}

#[test]
fn buffers_declaring_more_than_the_cap_together_are_refused_before_reading() {
    let buffers: Vec<String> = (0..3)
        .map(|i| format!("{{\"byteLength\":1000000000,\"uri\":\"b{i}.bin\"}}"))
        .collect();
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"buffers\":[{}]}}",
        buffers.join(",")
    );
    let e = error(json.as_bytes(), "b.gltf");
    assert_eq!(
        e,
        "b.gltf: buffers: 3 files and data: URIs declare 3000000000 bytes together, over the \
         2 GiB limit"
    );
}

const FACET: &str = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                     vertex 0 1 0\nendloop\nendfacet\n";

fn triangles(text: &[u8]) -> usize {
    match parse(text, "t.stl") {
        Ok(m) => m.indices.len(),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn every_solid_of_an_ascii_stl_is_read() {
    let two = FACET.replace("vertex 0 1 0", "vertex 0 0 1");
    let text = format!("solid a\n{FACET}endsolid a\nsolid b\n{two}endsolid b\n");
    assert_eq!(triangles(text.as_bytes()), 2);
}

#[test]
fn ascii_stl_facet_normals_are_ignored_as_in_binary() {
    let text = format!(
        "solid a\n{}endsolid a\n",
        FACET.replace("0 0 1", "nan nan nan")
    );
    assert_eq!(triangles(text.as_bytes()), 1);
    let text = format!(
        "solid a\n{}endsolid a\n",
        FACET.replace(" normal 0 0 1", "")
    );
    assert_eq!(triangles(text.as_bytes()), 1);
}

#[test]
fn ascii_stl_accepts_latin1_names_blank_lines_and_any_case() {
    let mut latin1 = b"solid caf\xe9\n".to_vec();
    latin1.extend_from_slice(FACET.as_bytes());
    latin1.extend_from_slice(b"endsolid caf\xe9\n");
    assert_eq!(triangles(&latin1), 1);
    assert_eq!(
        triangles(format!("\n\n  \nsolid a\n{FACET}endsolid a\n").as_bytes()),
        1
    );
    let upper = format!("SOLID A\n{}ENDSOLID A\n", FACET.to_uppercase());
    assert_eq!(triangles(upper.as_bytes()), 1);
}

#[test]
fn a_nul_byte_in_an_ascii_stl_is_a_line_error_not_a_binary_count() {
    let text = format!(
        "solid a\n{}endsolid a\n",
        FACET.replace("vertex 1 0 0", "vertex 1 \u{0}0 0")
    );
    let e = error(text.as_bytes(), "t.stl");
    assert!(
        e.starts_with("t.stl:5: facet 1: vertex 2: '\\00' is not a number"),
        "{e}"
    );
}

#[test]
fn ply_errors_say_what_is_wrong_in_words() {
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                  end_header\n";
    for (body, words) in [
        ("0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", "not a line of numbers"),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n",
            "list value 3 is not a whole number",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999\n",
            "list value 3 is out of range for its type",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
            "the list announces 3 values, the line has 2",
        ),
        (
            "0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
            "fewer values than the element has properties",
        ),
    ] {
        let e = error(format!("{header}{body}").as_bytes(), "t.ply");
        assert!(e.contains(words), "{words} in {e}");
        assert!(!e.contains("Error") && !e.contains('{'), "{e}");
    }
    let e = error(
        b"ply\nformat ascii 1.0\nelement vertex abc\nend_header\n",
        "t.ply",
    );
    assert!(
        e.starts_with("t.ply:3: header: not a PLY header line"),
        "{e}"
    );
    assert!(!e.contains("ParseError") && !e.contains('{'), "{e}");
}

#[test]
fn every_truncated_glb_names_the_part_it_ends_in() {
    let cube = writers::cube().triangulated();
    let mesh = GltfMesh {
        shape: &cube,
        normals: None,
        extras: &[],
        material: None,
    };
    let glb = writers::gltf(&[mesh], &[], &[], GltfBuffer::Glb).0;
    for cut in 4..glb.len() {
        let e = error(&glb[..cut], "t.glb");
        assert!(!e.contains("could not completely read"), "{cut}: {e}");
        let part = [
            "header: ",
            "JSON chunk: ",
            "JSON chunk header: ",
            "BIN chunk",
            "BIN chunk header: ",
        ]
        .iter()
        .any(|p| e.starts_with(&format!("t.glb: {p}")));
        assert!(part && e.contains("truncated"), "{cut}: {e}");
    }
}

#[test]
fn a_gltf_version_is_escaped_in_messages() {
    let version = "{\"asset\":{\"version\":\"3\\u001b[2J\"}}";
    let e = error(version.as_bytes(), "v.gltf");
    assert!(
        e.contains("version 3\\e[2J is not") && !e.contains('\u{1b}'),
        "{e:?}"
    );
}
