//! `phosphor info` and `--mesh` take PLY, STL and glTF files by extension, with the error
//! contract of OBJ files (exit 1, one `error:` line naming the file and element).

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::{Command, Output};

fn phosphor(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .args(args)
        .output()
        .unwrap()
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "phosphor-cli-formats-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A binary STL of the unit cube: 12 triangles, 36 stored corners on 8 positions.
fn cube_stl() -> Vec<u8> {
    let p = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let quads = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&12u32.to_le_bytes());
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            out.extend_from_slice(&[0u8; 12]);
            for i in t {
                for c in p[i] {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            out.extend_from_slice(&[0, 0]);
        }
    }
    out
}

#[test]
fn info_names_the_format_and_counts_welded_positions() {
    let d = temp("info");
    let stl = d.join("cube.stl");
    std::fs::write(&stl, cube_stl()).unwrap();
    let o = phosphor(&["info", stl.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "format:           STL",
        "positions:        8 (distinct, welded)",
        "vertices:         24 (split where surfaces meet)",
        "triangles:        12",
        "surfaces:         6",
    ] {
        assert!(s.contains(needle), "{needle} in {s}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn render_takes_a_stl_mesh_and_a_broken_one_is_an_input_error() {
    let d = temp("render");
    let stl = d.join("cube.stl");
    std::fs::write(&stl, cube_stl()).unwrap();
    let out = d.join("out.png");
    let o = phosphor(&[
        "render",
        "--mesh",
        stl.to_str().unwrap(),
        "--size",
        "32x24",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());

    let cut = d.join("cut.stl");
    std::fs::write(&cut, &cube_stl()[..300]).unwrap();
    let out2 = d.join("out2.png");
    let o = phosphor(&[
        "render",
        "--mesh",
        cut.to_str().unwrap(),
        "--size",
        "32x24",
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let e = String::from_utf8_lossy(&o.stderr);
    let errors: Vec<&str> = e.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{e}");
    assert!(
        errors[0].contains("cut.stl: facet 5 of 12: truncated"),
        "{e}"
    );
    assert!(!out2.exists());
    let _ = std::fs::remove_dir_all(&d);
}
