//! `auto` keeps its promise: over a generated corpus of scenes (primitives and meshes, every
//! material term, every light kind, the attenuation models, spot cones, random cameras and
//! small frame sizes, both encodings), no pixel of the `auto` picture is more than one
//! displayed 8-bit code from `reference`, and no plan reason prints `inf` or `NaN`.
//!
//! A displayed code is measured on the continuous encoding (the scene's sRGB curve or linear
//! times 255) before rounding, which is what the plan's bounds promise; rounding to 8 bits
//! then moves two values at most one code apart by at most one code.

#![allow(clippy::unwrap_used)]

use phosphor::raster::encode::srgb_encode;
use phosphor::raster::{Framebuffer, ShadingMode};
use phosphor::scene::components::ShadingChoice;
use phosphor::scene::{FrameOptions, Scene, render_frame};
use proptest::prelude::*;

#[derive(Debug, Clone)]
struct Case {
    object: String,
    transform: String,
    material: String,
    lights: Vec<String>,
    camera: String,
    ambient: f32,
    size: (u32, u32),
    srgb: bool,
}

fn v3(r: f32) -> impl Strategy<Value = [f32; 3]> {
    [-r..r, -r..r, -r..r]
}

fn fmt(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

fn object() -> impl Strategy<Value = String> {
    prop_oneof![
        (3u32..48, 2u32..24).prop_map(|(s, r)| format!(
            "primitive = {{ shape = \"sphere\", segments = {s}, rings = {r} }}"
        )),
        Just("primitive = { shape = \"cube\" }".to_owned()),
        (3u32..40).prop_map(|s| format!("primitive = {{ shape = \"cylinder\", segments = {s} }}")),
        (3u32..32, 3u32..16).prop_map(|(s, t)| format!(
            "primitive = {{ shape = \"torus\", segments = {s}, sides = {t} }}"
        )),
        (1u32..6).prop_map(|s| format!("primitive = {{ shape = \"plane\", subdivisions = {s} }}")),
        Just("mesh = \"assets/meshes/teapot.obj\"\nnormalize = true".to_owned()),
        Just("mesh = \"assets/meshes/cube.obj\"\nnormalize = true".to_owned()),
        Just("mesh = \"assets/meshes/bunny_small.obj\"\nnormalize = true".to_owned()),
    ]
}

fn transform() -> impl Strategy<Value = String> {
    (
        v3(180.0),
        prop_oneof![
            3 => (0.5f32..1.5).prop_map(|s| format!("{s}")),
            1 => [0.5f32..1.5, 0.5f32..1.5, 0.5f32..1.5].prop_map(fmt),
        ],
    )
        .prop_map(|(r, s)| format!("transform = {{ rotate_deg = {}, scale = {s} }}", fmt(r)))
}

fn material() -> impl Strategy<Value = String> {
    (
        [0.0f32..0.4, 0.0f32..0.4, 0.0f32..0.4],
        [0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0],
        prop_oneof![Just(0.0f32), 0.0f32..1.0],
        1.0f32..200.0,
        any::<bool>(),
        prop_oneof![
            3 => Just(String::new()),
            1 => (0.02f32..0.9).prop_map(|f| format!("fresnel = {{ model = \"schlick\", f0 = {f} }}\n")),
        ],
        prop_oneof![3 => Just(String::new()), 1 => (0.0f32..0.3).prop_map(|e| format!("emission = {e}\n"))],
    )
        .prop_map(|(ka, kd, ks, n, blinn, fresnel, emission)| {
            format!(
                "[materials.m]\nka = {}\nkd = {}\nks = {ks}\nshininess = {n}\nspecular = \"{}\"\n{fresnel}{emission}",
                fmt(ka),
                fmt(kd),
                if blinn { "blinn" } else { "phong" }
            )
        })
}

fn attenuation() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("attenuation = { model = \"inverse-square\" }\n".to_owned()),
        (0.0f32..2.0).prop_map(|k| format!("attenuation = {{ model = \"offset\", k = {k} }}\n")),
        (0.0f32..1.0, 0.0f32..0.5, 0.0f32..0.5).prop_map(|(c, l, q)| format!(
            "attenuation = {{ model = \"quadratic\", c = {c}, l = {l}, q = {q} }}\n"
        )),
    ]
}

fn light() -> impl Strategy<Value = String> {
    let il = [0.1f32..2.0, 0.1f32..2.0, 0.1f32..2.0].prop_map(fmt);
    let kind = prop_oneof![
        v3(1.0).prop_map(|d| format!(
            "type = \"directional\"\ndirection = {}\n",
            fmt([d[0], d[1] - 0.2, d[2] - 0.2])
        )),
        v3(4.0).prop_map(|p| format!("type = \"point\"\nposition = {}\n", fmt(p))),
        (v3(4.0), v3(1.0), 0.0f32..40.0, 0.0f32..30.0).prop_map(|(p, d, inner, width)| format!(
            "type = \"spot\"\nposition = {}\ndirection = {}\ninner_deg = {inner}\nouter_deg = {}\n",
            fmt(p),
            fmt([-p[0] + d[0], -p[1] + d[1], -p[2] + d[2]]),
            inner + width
        )),
        (v3(4.0), v3(1.0)).prop_map(|(a, d)| format!(
            "type = \"tube\"\nstart = {}\nend = {}\nsamples = 3\n",
            fmt(a),
            fmt([a[0] + d[0], a[1] + d[1], a[2] + d[2]])
        )),
        (v3(4.0), v3(1.0), v3(1.0)).prop_map(|(c, u, v)| format!(
            "type = \"rect\"\ncorner = {}\nedge_u = {}\nedge_v = {}\nsamples = 2\n",
            fmt(c),
            fmt([u[0] + 0.3, u[1], u[2]]),
            fmt([v[0], v[1] + 0.3, v[2]])
        )),
    ];
    (kind, il, attenuation()).prop_map(|(k, il, att)| {
        // A directional light is at infinity: no attenuation.
        let att = if k.contains("directional") {
            String::new()
        } else {
            att
        };
        format!("[[lights]]\n{k}intensity = {il}\n{att}")
    })
}

fn camera() -> impl Strategy<Value = String> {
    (v3(1.0), 2.5f32..7.0, v3(0.3), 30.0f32..70.0).prop_map(|(d, r, t, fov)| {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
        let eye = if len < 0.05 {
            [0.0, 0.0, r]
        } else {
            [d[0] / len * r, d[1] / len * r, d[2] / len * r]
        };
        format!(
            "[camera]\neye = {}\ntarget = {}\nfov_y_deg = {fov}\n",
            fmt(eye),
            fmt(t)
        )
    })
}

fn case() -> impl Strategy<Value = Case> {
    (
        object(),
        transform(),
        material(),
        prop::collection::vec(light(), 1..4),
        camera(),
        0.0f32..0.6,
        (16u32..72, 12u32..56),
        any::<bool>(),
    )
        .prop_map(
            |(object, transform, material, lights, camera, ambient, size, srgb)| Case {
                object,
                transform,
                material,
                lights,
                camera,
                ambient,
                size,
                srgb,
            },
        )
}

impl Case {
    fn toml(&self) -> String {
        format!(
            "[render]\nencoding = \"{}\"\n{}\n[ambient]\nintensity = {}\n{}{}\n[[objects]]\nname = \"o\"\n{}\nmaterial = \"m\"\n{}\n",
            if self.srgb { "srgb" } else { "linear" },
            self.camera,
            self.ambient,
            self.lights.concat(),
            self.material,
            self.object,
            self.transform
        )
    }
}

fn render(
    scene: &Scene,
    (w, h): (u32, u32),
    shading: Option<ShadingChoice>,
) -> (Framebuffer, String) {
    let mut fb = Framebuffer::new(w, h).unwrap();
    let opts = FrameOptions {
        shading,
        threads: 1,
        ..FrameOptions::default()
    };
    let report = render_frame(scene, &mut fb, &opts);
    (fb, report.plan.to_string())
}

/// The largest per-channel difference of two pictures in displayed codes.
fn worst_codes(a: &Framebuffer, b: &Framebuffer, srgb: bool) -> f32 {
    let code = |v: f32| {
        if srgb {
            srgb_encode(v) * 255.0
        } else {
            v.clamp(0.0, 1.0) * 255.0
        }
    };
    a.color()
        .iter()
        .zip(b.color())
        .flat_map(|(x, y)| (0..3).map(move |c| (code(x[c]) - code(y[c])).abs()))
        .fold(0.0, f32::max)
}

#[test]
fn where_auto_picks_flat_or_gouraud_it_keeps_the_promise() {
    // Scenes where the bound accepts the cheap modes, so that the promise is tested on them
    // and not only on phong: a subdivided floor under a far point light (gouraud), a tilted
    // plane and a cube under the sun (flat, exact).
    let cases = [
        (
            "[[lights]]\ntype = \"point\"\nposition = [3, 40, 2]\nintensity = 1.5\n[materials.m]\nks = 0\n[[objects]]\nname = \"floor\"\nprimitive = { shape = \"plane\", half_size = 2, subdivisions = 8 }\nmaterial = \"m\"\n",
            ShadingMode::Gouraud,
        ),
        (
            "[[lights]]\ntype = \"directional\"\ndirection = [-1, -2, -1]\nintensity = 1\n[materials.m]\nks = 0\n[[objects]]\nname = \"cube\"\nprimitive = { shape = \"cube\" }\nmaterial = \"m\"\ntransform = { rotate_deg = [20, 30, 0] }\n",
            ShadingMode::Flat,
        ),
    ];
    for (body, mode) in cases {
        for srgb in [false, true] {
            let text = format!(
                "[render]\nencoding = \"{}\"\n[camera]\neye = [0.5, 2.5, 3.5]\ntarget = [0, 0, 0]\n[ambient]\nintensity = 0.3\n{body}",
                if srgb { "srgb" } else { "linear" }
            );
            let scene = Scene::parse(&text, "cheap.toml").unwrap();
            let (auto, plan) = render(&scene, (96, 72), None);
            assert!(plan.contains(&format!(": {} (", mode.name())), "{plan}");
            let (reference, _) = render(
                &scene,
                (96, 72),
                Some(ShadingChoice::Mode(ShadingMode::Reference)),
            );
            let worst = worst_codes(&auto, &reference, srgb);
            assert!(worst <= 1.0, "{worst} codes\n{plan}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, max_shrink_iters: 64, ..ProptestConfig::default() })]

    #[test]
    fn auto_is_within_one_displayed_code_of_reference(c in case()) {
        let text = c.toml();
        let scene = Scene::parse(&text, "corpus.toml").unwrap();
        let (auto, plan) = render(&scene, c.size, None);
        let (reference, _) = render(&scene, c.size, Some(ShadingChoice::Mode(ShadingMode::Reference)));
        prop_assert!(!plan.contains("inf") && !plan.contains("NaN"), "{plan}");
        let code = |v: f32| {
            if c.srgb { srgb_encode(v) * 255.0 } else { v.clamp(0.0, 1.0) * 255.0 }
        };
        let mut worst = (0.0f32, 0usize);
        for (i, (a, r)) in auto.color().iter().zip(reference.color()).enumerate() {
            for ch in 0..3 {
                let d = (code(a[ch]) - code(r[ch])).abs();
                if d > worst.0 {
                    worst = (d, i);
                }
            }
        }
        prop_assert!(
            worst.0 <= 1.0,
            "{:.3} codes at pixel {} (x {}, y {})\n{plan}\n{text}",
            worst.0,
            worst.1,
            worst.1 % c.size.0 as usize,
            worst.1 / c.size.0 as usize
        );
    }
}
