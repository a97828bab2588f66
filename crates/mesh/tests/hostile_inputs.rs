//! Inputs built to hang, abort or lose data: many faces on one edge or one vertex, huge
//! polygons, MTL files that are huge or not files at all, byte-order marks, faces with fewer
//! than three corners, very long names in warnings. Each loads, or fails with a message,
//! without losing what the file says.

use std::path::{Path, PathBuf};

use glam::Vec3;
use phosphor_mesh::{
    MAX_MTL_BYTES, MAX_WARNING_CHARS, NormalOptions, Weighting, load_obj_with_warnings, parse_obj,
    parse_obj_with_warnings,
};

/// A fresh folder under the system temp dir, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("phosphor-mesh-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        TempDir(dir)
    }

    fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).expect("write");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn forty_thousand_copies_of_one_triangle_load_as_one_surface() {
    let text = format!("{TRI}{}", "f 1 2 3\n".repeat(40_000));
    for opts in [NormalOptions::default(), NormalOptions::crease(30.0)] {
        let m = parse_obj(&text, "repeat.obj", None, &opts).expect("loads");
        assert!(m.is_consistent());
        let stats = m.stats();
        assert_eq!(
            (stats.triangles, stats.surfaces, stats.vertices),
            (40_000, 1, 3)
        );
        assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
    }
}

/// A cone of `n` triangles around the apex (0, 1, 0) over a unit circle.
fn cone(n: usize) -> String {
    let mut s = String::from("v 0 1 0\n");
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        s += &format!("v {} 0 {}\n", a.cos(), -a.sin());
    }
    for i in 0..n {
        s += &format!("f 1 {} {}\n", i + 2, (i + 1) % n + 2);
    }
    s
}

#[test]
fn cone_apex_shared_by_thousands_of_faces_gets_the_axis_with_smoothing_on() {
    // Neighbouring faces differ by under a degree: one smooth surface, and at the apex, where
    // every face meets, the uniform average is the cone's axis.
    let m = parse_obj(
        &cone(3000),
        "cone.obj",
        None,
        &NormalOptions::smooth_all(Weighting::Uniform),
    )
    .expect("loads");
    assert!(m.is_consistent());
    assert_eq!(m.stats().surfaces, 1);
    let apex: Vec<Vec3> = m
        .positions
        .iter()
        .zip(&m.normals)
        .filter(|(p, _)| (**p - Vec3::Y).length() < 1e-6)
        .map(|(_, n)| *n)
        .collect();
    assert_eq!(
        apex.len(),
        1,
        "one apex vertex: every corner there has the same normal"
    );
    assert!((apex[0] - Vec3::Y).length() < 1e-4, "{}", apex[0]);
}

#[test]
fn huge_convex_polygon_loads_with_every_triangle_facing_its_normal() {
    let n = 20_000;
    let mut s = String::new();
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        s += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    s += "f";
    for i in 1..=n {
        s += &format!(" {i}");
    }
    s += "\n";
    let m = parse_obj(&s, "disc.obj", None, &NormalOptions::default()).expect("loads");
    assert!(m.is_consistent());
    assert_eq!(m.indices.len(), n - 2);
    assert_eq!(m.stats().surfaces, 1);
    assert!(m.normals.iter().all(|v| (*v - Vec3::Z).length() < 1e-6));
    let area: f64 = (0..m.indices.len()).map(|t| m.double_area(t) * 0.5).sum();
    let exact = 0.5 * n as f64 * (std::f64::consts::TAU / n as f64).sin();
    assert!((area - exact).abs() < 1e-4 * exact, "{area} vs {exact}");
}

#[test]
fn byte_order_mark_keeps_the_first_obj_line() {
    let text = format!("\u{feff}{TRI}f 1 2 3\n");
    let m = parse_obj(&text, "bom.obj", None, &NormalOptions::default()).expect("loads");
    assert_eq!(m.indices.len(), 1);
    // Also from disk, where the bytes are decoded first.
    let dir = TempDir::new("bom");
    let path = dir.write("bom.obj", text.as_bytes());
    let (m, warnings) =
        load_obj_with_warnings(&path, &NormalOptions::default()).expect("loads from disk");
    assert_eq!(m.indices.len(), 1);
    assert!(warnings.is_empty(), "{warnings:?}");
}

#[test]
fn byte_order_mark_keeps_the_first_mtl_line() {
    let obj = format!("mtllib m.mtl\n{TRI}usemtl red\nf 1 2 3\n");
    let mtl = "\u{feff}newmtl red\nKd 1 0 0\n";
    let (m, warnings) =
        parse_obj_with_warnings(&obj, "bom.obj", Some(mtl), &NormalOptions::default())
            .expect("loads");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(m.materials.len(), 1);
    assert_eq!(m.materials[0].name, "red");
    assert_eq!(m.materials[0].kd, Vec3::X);

    let dir = TempDir::new("bom-mtl");
    dir.write("m.mtl", mtl.as_bytes());
    let path = dir.write("bom.obj", obj.as_bytes());
    let (m, warnings) = load_obj_with_warnings(&path, &NormalOptions::default()).expect("loads");
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(m.materials[0].kd, Vec3::X);
}

#[test]
fn face_with_fewer_than_three_corners_is_warned_about_with_its_line() {
    let text = format!("{TRI}f 1 2 3\nf 1 2\nf 3\nl 1 2\n");
    let (m, warnings) =
        parse_obj_with_warnings(&text, "short.obj", None, &NormalOptions::default())
            .expect("loads");
    assert_eq!(m.indices.len(), 1);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(
        warnings[0].starts_with("short.obj:5: face with 2 corners"),
        "{warnings:?}"
    );
    assert!(
        warnings[1].starts_with("short.obj:6: face with 1 corner "),
        "{warnings:?}"
    );
}

#[test]
fn many_short_faces_are_summarised_after_the_first_ten() {
    let text = format!("{TRI}f 1 2 3\n{}", "f 1 2\n".repeat(25));
    let (_, warnings) =
        parse_obj_with_warnings(&text, "short.obj", None, &NormalOptions::default())
            .expect("loads");
    assert_eq!(warnings.len(), 11, "{warnings:?}");
    assert_eq!(
        warnings[10],
        "short.obj: 15 more faces with fewer than 3 corners skipped"
    );
}

#[test]
fn warnings_are_cut_at_the_limit() {
    let name = "m".repeat(500);
    let text = format!("{TRI}usemtl {name}\nf 1 2 3\n");
    let (_, warnings) = parse_obj_with_warnings(
        &text,
        "long.obj",
        Some("newmtl a\n"),
        &NormalOptions::default(),
    )
    .expect("loads");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].chars().count(), MAX_WARNING_CHARS);
    assert!(warnings[0].starts_with("long.obj:4: material 'mmm"));
    assert!(warnings[0].contains("mmm...mmm"));
    assert!(warnings[0].ends_with("' is not defined; using the default material"));
}

#[test]
fn mtl_over_the_size_cap_is_a_warning_naming_file_and_cap_and_is_not_read() {
    let dir = TempDir::new("big-mtl");
    let big = dir.0.join("big.mtl");
    // Sparse: the length is what the cap looks at, before reading a byte.
    std::fs::File::create(&big)
        .and_then(|f| f.set_len(MAX_MTL_BYTES + 1))
        .expect("sparse file");
    let path = dir.write(
        "m.obj",
        format!("mtllib big.mtl\n{TRI}usemtl a\nf 1 2 3\n").as_bytes(),
    );
    let (m, warnings) = load_obj_with_warnings(&path, &NormalOptions::default()).expect("loads");
    assert_eq!(m.indices.len(), 1);
    let shown = big.display().to_string();
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with(&shown) && w.contains("over the 64 MiB limit")),
        "{warnings:?}"
    );
}

/// Loads `path` on another thread; `None` when it has not finished within a minute (a load
/// blocked on a FIFO never would).
fn load_or_hang(path: &Path) -> Option<Vec<String>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let path = path.to_owned();
    std::thread::spawn(move || {
        let r = load_obj_with_warnings(&path, &NormalOptions::default());
        let _ = tx.send(r.map(|(_, w)| w).unwrap_or_else(|e| vec![e.to_string()]));
    });
    rx.recv_timeout(std::time::Duration::from_secs(60)).ok()
}

#[cfg(unix)]
#[test]
fn mtl_that_is_a_fifo_is_a_warning_not_a_hang() {
    let dir = TempDir::new("fifo-mtl");
    let fifo = dir.0.join("pipe.mtl");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success(), "mkfifo failed");
    let path = dir.write(
        "m.obj",
        format!("mtllib pipe.mtl\n{TRI}f 1 2 3\n").as_bytes(),
    );
    let warnings = load_or_hang(&path).expect("a FIFO named by mtllib must not block the load");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("pipe.mtl") && w.contains("not a regular file")),
        "{warnings:?}"
    );
}

#[test]
fn mtl_that_is_a_directory_is_a_warning() {
    let dir = TempDir::new("dir-mtl");
    std::fs::create_dir_all(dir.0.join("lib.mtl")).expect("dir");
    let path = dir.write(
        "m.obj",
        format!("mtllib lib.mtl\n{TRI}f 1 2 3\n").as_bytes(),
    );
    let warnings = load_or_hang(&path).expect("finishes");
    assert!(
        warnings.iter().any(|w| w.contains("lib.mtl")),
        "{warnings:?}"
    );
}
