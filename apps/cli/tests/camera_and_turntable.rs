//! `phosphor` end to end for how a scene is looked at: the camera flags and their errors, the
//! framing and normals of `--mesh`, turntable sequences split across runs, and `-o -`.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn phosphor(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_phosphor"))
        .current_dir(root())
        .args(args)
        .output()
        .unwrap()
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh temporary folder for one test.
fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("phosphor-view-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `args` and expects success.
fn ok(args: &[&str]) -> Output {
    let o = phosphor(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    o
}

/// The usage-error contract: exit 2, one `error:` line, naming `flag` and containing `needle`.
fn assert_usage(args: &[&str], flag: &str, needle: &str) {
    let o = phosphor(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line: {e}");
    assert!(lines[0].starts_with("error: "), "{e}");
    assert!(lines[0].contains(flag), "{args:?}: names {flag}: {e}");
    assert!(lines[0].contains(needle), "{args:?}: {needle}: {e}");
}

/// `a` then `b`.
fn cat<'a>(a: &[&'a str], b: &[&'a str]) -> Vec<&'a str> {
    [a, b].concat()
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A unit cube without normals or smoothing groups, faces wound outwards.
const CUBE_OBJ: &str = "\
v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1
f 5 6 7 8\nf 2 1 4 3\nf 1 5 8 4\nf 6 2 3 7\nf 8 7 3 4\nf 1 2 6 5
";

/// The same cube with authored normals pointing out of its corners (a rounded look).
const CUBE_VN_OBJ: &str = "\
v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1
vn -1 -1 -1\nvn 1 -1 -1\nvn 1 1 -1\nvn -1 1 -1\nvn -1 -1 1\nvn 1 -1 1\nvn 1 1 1\nvn -1 1 1
f 5//5 6//6 7//7 8//8\nf 2//2 1//1 4//4 3//3\nf 1//1 5//5 8//8 4//4
f 6//6 2//2 3//3 7//7\nf 8//8 7//7 3//3 4//4\nf 1//1 2//2 6//6 5//5
";

fn cube(dir: &Path) -> PathBuf {
    let p = dir.join("cube.obj");
    std::fs::write(&p, CUBE_OBJ).unwrap();
    p
}

#[test]
fn orbit_and_explicit_forms_reproduce_the_scene_camera_exactly() {
    let d = temp("same-camera");
    let plain = d.join("plain.png");
    let orbit = d.join("orbit.png");
    let eye = d.join("eye.png");
    let base = ["render", "assets/scenes/s1.toml", "--size", "64x36", "-o"];
    ok(&[&base[..], &[plain.to_str().unwrap()]].concat());
    ok(&[
        &base[..],
        &[
            orbit.to_str().unwrap(),
            "--azimuth",
            "0",
            "--elevation",
            "0",
            "--distance",
            "3",
        ],
    ]
    .concat());
    ok(&[
        &base[..],
        &[
            eye.to_str().unwrap(),
            "--eye",
            "0,0,3",
            "--target",
            "0,0,0",
            "--up",
            "0,1,0",
            "--fov",
            "45",
        ],
    ]
    .concat());
    assert_eq!(read(&plain), read(&orbit));
    assert_eq!(read(&plain), read(&eye));
}

#[test]
fn camera_flags_change_the_view_in_render_bench_and_accuracy() {
    let d = temp("moved");
    let front = d.join("front.png");
    let side = d.join("side.png");
    let base = ["render", "assets/scenes/s1.toml", "--size", "64x36", "-o"];
    ok(&[&base[..], &[front.to_str().unwrap()]].concat());
    ok(&[
        &base[..],
        &[side.to_str().unwrap(), "--azimuth", "-90", "--fov", "30"],
    ]
    .concat());
    assert_ne!(read(&front), read(&side));
    ok(&[
        "bench",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--shading",
        "flat",
        "--size",
        "32x18",
        "--frames",
        "1",
        "--eye",
        "-2,1,2",
    ]);
    ok(&[
        "accuracy",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--size",
        "32x18",
        "--frames",
        "1",
        "--elevation=-30",
    ]);
}

#[test]
fn bad_camera_values_are_one_line_usage_errors_naming_the_flag() {
    // S1's camera (no [camera] table) around a small sphere.
    let d = temp("bad-camera");
    let scene = d.join("ball.toml");
    std::fs::write(
        &scene,
        "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nintensity = 1\n\
         [[objects]]\nprimitive = { shape = \"sphere\", segments = 8, rings = 4 }\n",
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    for cmd in ["render", "bench", "accuracy"] {
        let base = [cmd, scene, "--size", "16x16", "-o", "never.png"];
        let base: &[&str] = if cmd == "render" { &base } else { &base[..4] };
        assert_usage(&cat(base, &["--fov", "nan"]), "--fov", "finite");
        assert_usage(&cat(base, &["--fov", "180"]), "--fov", "between 0 and 180");
        assert_usage(&cat(base, &["--fov", "0"]), "--fov", "between 0 and 180");
        assert_usage(&cat(base, &["--eye", "1,2"]), "--eye", "X,Y,Z");
        assert_usage(&cat(base, &["--eye", "nan,0,1"]), "--eye", "finite");
        assert_usage(
            &cat(base, &["--eye", "0,0,3", "--target", "0,0,3"]),
            "--target",
            "eye",
        );
        assert_usage(&cat(base, &["--up", "0,0,-1"]), "--up", "parallel");
        assert_usage(&cat(base, &["--eye", "0,5,0"]), "--eye", "parallel");
        assert_usage(
            &cat(base, &["--elevation", "90"]),
            "--elevation",
            "-90 and 90",
        );
        assert_usage(&cat(base, &["--distance", "-1"]), "--distance", "> 0");
        assert_usage(
            &cat(base, &["--eye", "1,1,1", "--azimuth", "3"]),
            "--eye",
            "--azimuth",
        );
    }
    assert!(!root().join("never.png").exists());
}

#[test]
fn mesh_keeps_a_cubes_edges_by_default_and_takes_the_normal_flags() {
    let d = temp("cube");
    let obj = cube(&d);
    let obj = obj.to_str().unwrap();
    let render = |name: &str, extra: &[&str]| -> Vec<u8> {
        let out = d.join(name);
        let args = [
            &[
                "render",
                "--mesh",
                obj,
                "--size",
                "96x72",
                "--shading",
                "gouraud",
                "-o",
            ][..],
            &[out.to_str().unwrap()],
            extra,
        ]
        .concat();
        ok(&args);
        read(&out)
    };
    let default = render("default.png", &[]);
    assert_eq!(default, render("60.png", &["--crease-angle", "60"]));
    let smooth = render("180.png", &["--crease-angle", "180"]);
    assert_ne!(default, smooth, "a crease angle of 180 rounds the cube off");
    // The weighting reaches the mesh: area weights count a quad's two triangles apart.
    let area = render(
        "area.png",
        &["--crease-angle", "180", "--weighting", "area"],
    );
    assert_ne!(smooth, area);
    // A file with neither smoothing groups nor materials is the same mesh under these.
    assert_eq!(
        default,
        render(
            "flags.png",
            &["--no-smoothing-groups", "--split-by-material"]
        )
    );
    // Authored normals are used unless computed ones are asked for.
    let vn = d.join("cube_vn.obj");
    std::fs::write(&vn, CUBE_VN_OBJ).unwrap();
    let vn = vn.to_str().unwrap();
    let with_vn = |name: &str, extra: &[&str]| -> Vec<u8> {
        let out = d.join(name);
        ok(&[
            &[
                "render",
                "--mesh",
                vn,
                "--size",
                "96x72",
                "--shading",
                "gouraud",
                "-o",
            ][..],
            &[out.to_str().unwrap()],
            extra,
        ]
        .concat());
        read(&out)
    };
    let authored = with_vn("vn.png", &[]);
    assert_eq!(
        authored,
        with_vn("vn-authored.png", &["--normals", "authored"])
    );
    assert_ne!(
        authored,
        with_vn("vn-computed.png", &["--normals", "computed"])
    );
    assert_usage(
        &[
            "render",
            "--mesh",
            obj,
            "--crease-angle",
            "200",
            "-o",
            "never.png",
        ],
        "--crease-angle",
        "between 0 and 180",
    );
    let never = d.join("never.png");
    let never = never.to_str().unwrap();
    for flag in [
        &["--crease-angle", "30"][..],
        &["--normals", "computed"],
        &["--weighting", "angle"],
        &["--no-smoothing-groups"],
        &["--split-by-material"],
    ] {
        assert_usage(
            &cat(&["render", "assets/scenes/s1.toml", "-o", never], flag),
            flag[0],
            "--mesh",
        );
        assert_usage(&cat(&["render", "-o", never], flag), flag[0], "--mesh");
    }
    assert!(!Path::new(never).exists());
}

/// The smallest rectangle holding every pixel that differs from the corner's colour.
fn covered(png: &[u8]) -> (u32, u32, u32, u32, u32, u32) {
    let img = image::load_from_memory(png).unwrap().to_rgb8();
    let bg = *img.get_pixel(0, 0);
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if *p != bg {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    (x0, y0, x1, y1, img.width(), img.height())
}

#[test]
fn mesh_is_framed_to_fill_the_view_without_touching_the_border() {
    let d = temp("framed");
    for (size, name) in [
        ("120x120", "square.png"),
        ("160x90", "wide.png"),
        ("60x120", "tall.png"),
    ] {
        let out = d.join(name);
        ok(&[
            "render",
            "--mesh",
            "assets/meshes/teapot.obj",
            "--size",
            size,
            "-o",
            out.to_str().unwrap(),
        ]);
        let (x0, y0, x1, y1, w, h) = covered(&read(&out));
        assert!(
            x0 > 0 && y0 > 0 && x1 < w - 1 && y1 < h - 1,
            "{size}: touches the border"
        );
        let (cw, ch) = (x1 - x0 + 1, y1 - y0 + 1);
        // The bounding sphere spans the narrower side; the teapot's longest extent (spout to
        // handle) is most of the sphere's diameter.
        assert!(
            cw.max(ch) * 3 > w.min(h) * 2,
            "{size}: the mesh covers only {cw}x{ch}"
        );
    }
}

#[test]
fn a_turntable_rendered_in_two_halves_equals_one_run_byte_for_byte() {
    let d = temp("turntable");
    let whole = d.join("whole");
    let split = d.join("split");
    std::fs::create_dir_all(&whole).unwrap();
    std::fs::create_dir_all(&split).unwrap();
    let pattern = |dir: &Path| dir.join("frame_%03d.png").to_str().unwrap().to_owned();
    let base = [
        "render",
        "--mesh",
        "assets/meshes/bunny_small.obj",
        "--size",
        "48x32",
        "--turntable",
        "6",
    ];
    ok(&[&base[..], &["-o", &pattern(&whole)]].concat());
    ok(&[&base[..], &["--frames", "0..3", "-o", &pattern(&split)]].concat());
    ok(&[&base[..], &["--frames", "3..=5", "-o", &pattern(&split)]].concat());
    let mut names: Vec<String> = std::fs::read_dir(&whole)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let expected: Vec<String> = (0..6).map(|k| format!("frame_{k:03}.png")).collect();
    assert_eq!(names, expected);
    for name in &names {
        assert_eq!(read(&whole.join(name)), read(&split.join(name)), "{name}");
    }
    assert_eq!(std::fs::read_dir(&split).unwrap().count(), 6);
    // The table turns: frames differ, and the half turn is the view from behind.
    assert_ne!(
        read(&whole.join("frame_000.png")),
        read(&whole.join("frame_001.png"))
    );
    let behind = d.join("behind.png");
    ok(&[
        &base[..2],
        &[
            "assets/meshes/bunny_small.obj",
            "--size",
            "48x32",
            "--azimuth",
            "210",
            "-o",
            behind.to_str().unwrap(),
        ],
    ]
    .concat());
    let (a, b) = (
        covered(&read(&behind)),
        covered(&read(&whole.join("frame_003.png"))),
    );
    let near = |p: u32, q: u32| p.abs_diff(q) <= 1;
    assert!(
        near(a.0, b.0) && near(a.1, b.1) && near(a.2, b.2) && near(a.3, b.3),
        "frame 3 of 6 is the camera turned by 180 degrees: {a:?} vs {b:?}"
    );
    // One frame by number.
    let single = d.join("single_%d.png");
    ok(&[
        &base[..],
        &["--frames", "4", "-o", single.to_str().unwrap()],
    ]
    .concat());
    assert_eq!(
        read(&d.join("single_4.png")),
        read(&whole.join("frame_004.png"))
    );
}

#[test]
fn an_animation_rendered_in_parts_equals_one_run_and_time_picks_the_instant() {
    let d = temp("animation");
    let whole = d.join("whole");
    let split = d.join("split");
    let pattern = |dir: &Path| dir.join("anim_%03d.png").to_str().unwrap().to_owned();
    let base = [
        "render",
        "assets/scenes/animated.toml",
        "--size",
        "48x32",
        "--fps",
        "4",
    ];
    ok(&cat(&base, &["--frames", "0..6", "-o", &pattern(&whole)]));
    ok(&cat(&base, &["--frames", "0..2", "-o", &pattern(&split)]));
    ok(&cat(&base, &["--frames", "2..=5", "-o", &pattern(&split)]));
    let mut names: Vec<String> = std::fs::read_dir(&whole)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let expected: Vec<String> = (0..6).map(|k| format!("anim_{k:03}.png")).collect();
    assert_eq!(names, expected);
    for name in &names {
        assert_eq!(read(&whole.join(name)), read(&split.join(name)), "{name}");
    }
    // The scene moves: consecutive frames differ.
    for k in 0..5 {
        assert_ne!(
            read(&whole.join(&names[k])),
            read(&whole.join(&names[k + 1])),
            "frames {k} and {}",
            k + 1
        );
    }
    // --time picks the instant: frame 3 at 4 fps is t = 0.75 s, and --time shifts frame 0.
    let still = d.join("still.png");
    let s = still.to_str().unwrap();
    ok(&[&base[..4], &["--time", "0.75", "-o", s]].concat());
    assert_eq!(read(&still), read(&whole.join("anim_003.png")));
    let shifted = d.join("shifted_%d.png");
    ok(&cat(
        &base,
        &[
            "--time",
            "0.5",
            "--frames",
            "1",
            "-o",
            shifted.to_str().unwrap(),
        ],
    ));
    assert_eq!(read(&d.join("shifted_1.png")), read(&still));
    // The plan is made per frame: --plan prints one per frame.
    let o = ok(&cat(&base, &["--frames", "0..3", "--plan"]));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.matches("frame plan:").count(), 3, "{text}");
    assert_usage(
        &cat(&base, &["-o", &pattern(&whole)]),
        "--fps 4",
        "--frames",
    );
    assert_eq!(
        phosphor(&cat(
            &base,
            &[
                "--turntable",
                "4",
                "--frames",
                "0..2",
                "-o",
                &pattern(&whole)
            ]
        ))
        .status
        .code(),
        Some(2)
    );
    for bad in ["0", "-1", "nan", "inf"] {
        assert_eq!(
            phosphor(
                &[
                    &base[..4],
                    &["--fps", bad, "--frames", "0..2", "-o", &pattern(&d)]
                ]
                .concat()
            )
            .status
            .code(),
            Some(2),
            "--fps {bad}"
        );
    }
    assert_eq!(
        phosphor(&[&base[..4], &["--time", "nan", "-o", s]].concat())
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn sequence_usage_errors() {
    let d = temp("sequence-errors");
    let numbered = d.join("f_%04d.png");
    let numbered = numbered.to_str().unwrap();
    let plain = d.join("f.png");
    let plain = plain.to_str().unwrap();
    let base = ["render", "--size", "16x16"];
    assert_usage(
        &cat(&base, &["--turntable", "4", "-o", plain]),
        plain,
        "%04d",
    );
    assert_usage(
        &cat(
            &base,
            &["--turntable", "4", "--frames", "2..5", "-o", numbered],
        ),
        "--frames 2..5",
        "out of range",
    );
    assert_usage(
        &cat(
            &base,
            &["--turntable", "4", "--frames", "1..=4", "-o", numbered],
        ),
        "--frames 1..=4",
        "out of range",
    );
    assert_usage(
        &cat(&base, &["--turntable", "4", "-o", "-"]),
        "-o -",
        "one frame",
    );
    assert_usage(&cat(&base, &["--plan", "-o", "-"]), "-o -", "--plan");
    assert_usage(&cat(&base, &["-o", &format!("{plain}%s")]), "-o", "%0Nd");
    // clap's own checks: --frames needs --turntable; ranges must parse; N >= 1.
    for bad in [
        cat(&base, &["--frames", "0..2", "-o", numbered]),
        cat(
            &base,
            &["--turntable", "4", "--frames", "3..1", "-o", numbered],
        ),
        cat(&base, &["--turntable", "0", "-o", numbered]),
    ] {
        assert_eq!(phosphor(&bad).status.code(), Some(2), "{bad:?}");
    }
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "nothing written");
}

#[test]
fn png_on_standard_output_is_the_same_bytes_as_the_file() {
    let d = temp("stdout");
    let file = d.join("frame.png");
    let args = ["render", "assets/scenes/s1.toml", "--size", "40x30", "-o"];
    let to_file = ok(&[&args[..], &[file.to_str().unwrap()]].concat());
    assert!(!to_file.stdout.is_empty(), "the file run reports on stdout");
    let to_stdout = ok(&[&args[..], &["-"]].concat());
    assert_eq!(to_stdout.stdout, read(&file));
    assert!(to_stdout.stdout.starts_with(b"\x89PNG\r\n\x1a\n"));
    // A turntable frame too, chosen by number.
    let numbered = d.join("t_%02d.png");
    let turn = ["--turntable", "8", "--frames", "5"];
    ok(&[&args[..], &[numbered.to_str().unwrap()], &turn[..]].concat());
    let one = ok(&[&args[..], &["-"], &turn[..]].concat());
    assert_eq!(one.stdout, read(&d.join("t_05.png")));
}
