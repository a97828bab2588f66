//! Every malformed OBJ gives an error naming the file and, where there is one, the line.

use std::path::Path;

use phosphor_mesh::{MeshError, NormalOptions, load_obj, parse_obj};

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

fn error_of(text: &str) -> MeshError {
    match parse_obj(text, "case.obj", None, &NormalOptions::default()) {
        Ok(_) => panic!("expected an error for {text:?}"),
        Err(e) => e,
    }
}

fn assert_line(text: &str, line: usize, words: &str) {
    let e = error_of(text);
    let msg = e.to_string();
    assert_eq!(e.line(), Some(line), "{msg}");
    assert!(msg.starts_with(&format!("case.obj:{line}: ")), "{msg}");
    assert!(msg.contains(words), "{msg} should mention {words}");
}

#[test]
fn bad_number_names_its_line() {
    assert_line(
        "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n",
        2,
        "malformed number",
    );
    assert_line(
        &format!("{TRI}vn 0 0 abc\nf 1 2 3\n"),
        4,
        "malformed number",
    );
    assert_line(&format!("{TRI}vt 0.5\nf 1 2 3\n"), 4, "expected 2 numbers");
    assert_line(&format!("{TRI}f 1 2 three\n"), 4, "malformed vertex index");
}

#[test]
fn zero_index_names_its_line() {
    assert_line(&format!("{TRI}f 0 1 2\n"), 4, "index 0");
    assert_line(
        &format!("{TRI}vt 0 0\nf 1/0 2/1 3/1\n"),
        5,
        "texture index 0",
    );
}

#[test]
fn out_of_range_index_names_its_line() {
    assert_line(&format!("{TRI}f 1 2 4\n"), 4, "out of range");
    assert_line(&format!("{TRI}f -4 1 2\n"), 4, "out of range");
    assert_line(
        &format!("{TRI}vn 0 0 1\nf 1//2 2//1 3//1\n"),
        5,
        "normal index 2 out of range",
    );
}

#[test]
fn negative_texture_index_past_the_start_is_an_error_not_a_panic() {
    // tobj 4.0.5 overflows on this in debug builds (docs/conventions.md, "Dependency facts"); our
    // scan rejects it first.
    assert_line(
        &format!("{TRI}vt 0 0\nf 1/-5 2/1 3/1\n"),
        5,
        "texture index -5 out of range",
    );
}

#[test]
fn nan_or_infinite_coordinate_names_its_line() {
    assert_line(
        "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n",
        2,
        "NaN or infinite",
    );
    assert_line(
        "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n",
        3,
        "NaN or infinite",
    );
    assert_line(
        "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n",
        2,
        "NaN or infinite",
    );
    assert_line(
        "v 0 0 0\nv 1e30 0 0 1e-30\nv 0 1 0\nf 1 2 3\n",
        2,
        "infinite",
    );
    assert_line("v 0 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1, "w is 0");
}

#[test]
fn file_without_faces_is_an_error_naming_the_file() {
    for text in ["", TRI, &format!("{TRI}l 1 2\np 1\n")] {
        let e = error_of(text);
        assert!(matches!(e, MeshError::NoFaces { .. }), "{e}");
        assert!(e.to_string().starts_with("case.obj: no faces"), "{e}");
    }
}

#[test]
fn file_whose_faces_all_have_zero_area_is_an_error_naming_the_file() {
    // A mesh with no drawable face is an error (docs/conventions.md) (it would render nothing).
    for text in [
        format!("{TRI}f 1 1 1\nf 1 2 2\n"),
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n".to_owned(),
        "v 0 0 0\nv 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3 4\n".to_owned(),
    ] {
        let e = error_of(&text);
        assert!(
            e.to_string().starts_with("case.obj: no drawable face"),
            "{e}"
        );
    }
    // One good face among degenerate ones loads.
    let text = format!("{TRI}f 1 1 1\nf 1 2 3\n");
    assert!(parse_obj(&text, "case.obj", None, &NormalOptions::default()).is_ok());
}

#[test]
fn huge_and_malformed_indices_name_their_line() {
    assert_line(
        &format!("{TRI}f 1 2 99999999999999999999\n"),
        4,
        "malformed vertex index",
    );
    assert_line(&format!("{TRI}f 1 2 4294967296\n"), 4, "out of range");
    assert_line(
        &format!("{TRI}f 1 2 -99999999999999999999\n"),
        4,
        "malformed vertex index",
    );
    assert_line(&format!("{TRI}f 1x 2 3\n"), 4, "malformed vertex index");
    // A face before any vertex refers to nothing yet.
    assert_line("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", 1, "out of range");
}

#[test]
fn negative_normal_index_past_the_start_names_its_line() {
    assert_line(
        &format!("{TRI}vn 0 0 1\nf 1//-2 2//1 3//1\n"),
        5,
        "normal index -2 out of range",
    );
}

#[test]
fn non_finite_normals_and_texture_coordinates_name_their_line() {
    assert_line(
        &format!("{TRI}vn nan 0 1\nf 1//1 2//1 3//1\n"),
        4,
        "NaN or infinite",
    );
    assert_line(
        &format!("{TRI}vt inf 0\nf 1/1 2/1 3/1\n"),
        4,
        "NaN or infinite",
    );
}

#[test]
fn wrong_number_of_coordinates_names_its_line() {
    assert_line(
        "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        1,
        "expected 3 numbers",
    );
    assert_line("v 0 0 0 1 5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1, "5 values");
    assert_line(
        "v 0x1p3 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        1,
        "malformed number",
    );
}

#[test]
fn blank_comment_only_and_two_corner_files_have_no_faces() {
    for text in ["   \n\t\n", "# a\n# b\n", &format!("{TRI}f 1 2\n")] {
        let e = error_of(text);
        assert!(matches!(e, MeshError::NoFaces { .. }), "{e}");
    }
}

#[test]
fn missing_file_is_an_error_naming_the_file() {
    let e = load_obj(
        Path::new("/nonexistent/dir/mesh.obj"),
        &NormalOptions::default(),
    )
    .expect_err("missing file");
    assert!(
        e.to_string()
            .starts_with("/nonexistent/dir/mesh.obj: cannot read"),
        "{e}"
    );
}

#[test]
fn other_malformed_statements_name_their_line() {
    assert_line(&format!("{TRI}s on\nf 1 2 3\n"), 4, "smoothing group");
    assert_line(&format!("{TRI}usemtl\nf 1 2 3\n"), 4, "usemtl");
    assert_line(&format!("{TRI}f\n"), 4, "no vertices");
    assert_line(&format!("{TRI}f 1/1/1/1 2 3\n"), 4, "more than 3");
}

#[test]
fn invalid_utf8_names_its_line() {
    let dir = std::env::temp_dir().join(format!("phosphor-mesh-utf8-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("bad.obj");
    std::fs::write(&path, b"v 0 0 0\nv 1 0 0\nv 0 \xff 0\nf 1 2 3\n").expect("write");
    let e = load_obj(&path, &NormalOptions::default()).expect_err("invalid UTF-8");
    assert_eq!(e.line(), Some(3), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
