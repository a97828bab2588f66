use super::*;

fn error(text: &str) -> String {
    match parse(text.as_bytes(), "t.ply", &NormalOptions::default()) {
        Ok(_) => panic!("expected an error for {text:?}"),
        Err(e) => e.to_string(),
    }
}

const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
                      property float y\nproperty float z\nelement face 1\n\
                      property list uchar int vertex_indices\nend_header\n";

#[test]
fn ascii_triangle_loads() {
    let text = format!("{HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    let (m, w) = parse(text.as_bytes(), "t.ply", &NormalOptions::default()).expect("loads");
    assert_eq!(m.indices.len(), 1);
    assert!(w.is_empty());
    assert!(m.is_consistent());
}

#[test]
fn ascii_errors_name_the_line() {
    let e = error(&format!("{HEADER}0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n"));
    assert!(
        e.starts_with("t.ply:11: vertex 2 of 3: cannot read '1 x 0'"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
    let e = error(&format!("{HEADER}0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"));
    assert!(
        e.starts_with("t.ply:13: face 1 of 1: vertex index 3 out of range"),
        "{e}"
    );
    let e = error(&format!("{HEADER}0 0 0\n1 1e39 0\n0 1 0\n3 0 1 2\n"));
    assert!(
        e.starts_with("t.ply:11: vertex 2 of 3: NaN or infinite"),
        "{e}"
    );
    let e = error(&format!("{HEADER}0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"));
    assert!(e.starts_with("t.ply:11: vertex 2 of 3: cannot read"), "{e}");
    let e = error(&format!("{HEADER}0 0 0\n1 0 0\n"));
    assert!(
        e.starts_with("t.ply:12: vertex 3 of 3: the file ends"),
        "{e}"
    );
}

#[test]
fn header_problems_are_named() {
    let e = error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n");
    assert!(
        e.starts_with("t.ply: header: vertex has no property `y`"),
        "{e}"
    );
    let e = error("plx\n");
    assert!(e.starts_with("t.ply"), "{e}");
    let e = error(&HEADER.replace("list uchar int", "list uchar float"));
    assert!(e.contains("floating-point"), "{e}");
}
