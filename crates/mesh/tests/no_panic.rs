//! No input may panic, and whatever loads satisfies the mesh invariants (unit finite normals).

use phosphor_mesh::{NormalOptions, Weighting, parse_obj};
use proptest::prelude::*;

fn check(text: &str) {
    for opts in [
        NormalOptions::default(),
        NormalOptions::s1(),
        NormalOptions::crease(30.0),
    ] {
        if let Ok(m) = parse_obj(text, "fuzz.obj", Some("newmtl a\nKd 1 0 0\n"), &opts) {
            assert!(m.is_consistent(), "inconsistent mesh from {text:?}");
        }
    }
    let opts = NormalOptions::smooth_all(Weighting::Angle);
    if let Ok(m) = parse_obj(text, "fuzz.obj", None, &opts) {
        assert!(m.is_consistent());
    }
}

fn line() -> impl Strategy<Value = String> {
    let num = prop_oneof![
        Just("0".to_owned()),
        Just("1".to_owned()),
        Just("-1".to_owned()),
        Just("nan".to_owned()),
        Just("inf".to_owned()),
        Just("1e38".to_owned()),
        Just("1e-40".to_owned()),
        Just("x".to_owned()),
        (-3.0f32..3.0).prop_map(|f| f.to_string()),
    ];
    let idx = prop_oneof![
        (-6i32..8).prop_map(|i| i.to_string()),
        (-6i32..8, -6i32..8).prop_map(|(a, b)| format!("{a}/{b}")),
        (-6i32..8, -6i32..8).prop_map(|(a, b)| format!("{a}//{b}")),
        (-6i32..8, -6i32..8, -6i32..8).prop_map(|(a, b, c)| format!("{a}/{b}/{c}")),
        Just("/".to_owned()),
        Just("1/2/3/4".to_owned()),
        Just("99999999999999999999".to_owned()),
    ];
    prop_oneof![
        3 => prop::collection::vec(num.clone(), 0..5).prop_map(|v| format!("v {}", v.join(" "))),
        1 => prop::collection::vec(num.clone(), 0..4).prop_map(|v| format!("vt {}", v.join(" "))),
        1 => prop::collection::vec(num, 0..4).prop_map(|v| format!("vn {}", v.join(" "))),
        3 => prop::collection::vec(idx.clone(), 0..7).prop_map(|v| format!("f {}", v.join(" "))),
        1 => prop::collection::vec(idx, 0..4).prop_map(|v| format!("l {}", v.join(" "))),
        1 => prop_oneof![Just("s 1"), Just("s off"), Just("s 2"), Just("s"), Just("s x")].prop_map(str::to_owned),
        1 => prop_oneof![Just("g a"), Just("o"), Just("  g b"), Just("usemtl a"), Just("usemtl zz"),
                         Just("usemtl"), Just("mtllib m.mtl"), Just("mtllib"), Just("# c"), Just("")]
            .prop_map(str::to_owned),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        check(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn random_obj_lines_never_panic_and_load_consistently(lines in prop::collection::vec(line(), 0..40)) {
        check(&lines.join("\n"));
        // With valid vertices first, many random faces load: exercise the whole pipeline.
        check(&format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nvt 0 0\nvn 0 0 1\n{}", lines.join("\n")));
    }
}

#[test]
fn known_tobj_debug_overflow_input_returns_an_error() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-5 2/1 3/1\n";
    assert!(parse_obj(text, "t.obj", None, &NormalOptions::default()).is_err());
}
