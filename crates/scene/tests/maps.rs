//! Texture and normal maps named by mesh files, end to end: an OBJ whose MTL names a PNG
//! colour map and a normal map, and a glTF whose material names a JPEG base-colour texture
//! with a colour factor, all written by the test, loaded through a scene file and drawn in
//! every shading mode.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use phosphor_raster::{BumpMap, Framebuffer, ShadingMode};
use phosphor_scene::{Bump, FrameOptions, Scene, ShadingChoice, load_scene, render_frame};

fn temp_dir(test: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("phosphor-scene-maps-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A `side x side` image of 2x2 squares, red and blue.
fn checker_image(side: u32) -> image::RgbImage {
    image::RgbImage::from_fn(side, side, |x, y| {
        if (x < side / 2) == (y < side / 2) {
            image::Rgb([255, 0, 0])
        } else {
            image::Rgb([0, 0, 255])
        }
    })
}

/// A scene file framing the unit quad `mesh` face-on, lit from the front and from the left.
fn scene_file(dir: &Path, mesh: &str) -> PathBuf {
    let text = format!(
        "[camera]\neye = [0, 0, 2.5]\ntarget = [0, 0, 0]\nfov_y_deg = 45\n\
         [ambient]\nintensity = 0.1\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0.6, 0, -0.8]\nintensity = 1\n\
         [materials.m]\nka = 1\nkd = 0.8\nks = 0\n\
         [[objects]]\nname = \"quad\"\nmesh = \"{mesh}\"\nmaterial = \"m\"\nnormalize = false\n"
    );
    let path = dir.join(format!("{mesh}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn draw(scene: &Scene, mode: ShadingMode, maps: bool) -> Framebuffer {
    let mut fb = Framebuffer::new(64, 48).unwrap();
    let opts = FrameOptions {
        shading: Some(ShadingChoice::Mode(mode)),
        textures: maps,
        bump: maps,
        ..FrameOptions::default()
    };
    render_frame(scene, &mut fb, &opts);
    fb
}

/// Pixels clearly red and clearly blue: the map shows.
fn red_and_blue(fb: &Framebuffer) -> (usize, usize) {
    let red = fb.color().iter().filter(|c| c.x > 4.0 * c.z + 0.05).count();
    let blue = fb.color().iter().filter(|c| c.z > 4.0 * c.x + 0.05).count();
    (red, blue)
}

const MODES: [ShadingMode; 5] = [
    ShadingMode::Flat,
    ShadingMode::Gouraud,
    ShadingMode::FastPhong,
    ShadingMode::Phong,
    ShadingMode::Reference,
];

/// Writes `quad.obj` (the unit quad facing +z, with texture coordinates) and `quad.mtl`,
/// whose material names the colour map `c.png` (a checker) and the normal map `n.png` (every
/// texel `normal`), the `norm` line with `options` before the file name.
fn textured_quad(dir: &Path, normal: [u8; 3], options: &str) {
    checker_image(16).save(dir.join("c.png")).unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb(normal))
        .save(dir.join("n.png"))
        .unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        format!("newmtl m\nKd 1 1 1\nmap_Kd c.png\nnorm {options}n.png\n"),
    )
    .unwrap();
    std::fs::write(
        dir.join("quad.obj"),
        "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
    )
    .unwrap();
}

#[test]
fn an_obj_with_a_png_colour_map_and_a_normal_map_shows_both() {
    let dir = temp_dir("obj");
    // Every normal leans 45 degrees towards +T (+u, here +x): m = (0.71, 0, 0.71).
    textured_quad(&dir, [218, 128, 218], "-bm 0.5 ");
    let scene = load_scene(&scene_file(&dir, "quad.obj")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let bump = scene
        .world
        .query::<&Bump>()
        .iter()
        .map(|b| b.0.clone())
        .next()
        .expect("the mesh's normal map");
    let BumpMap::Normals { scale, width, .. } = &*bump else {
        panic!("a normal map, got {bump:?}");
    };
    assert_eq!((scale, width), (&0.5, &4));
    for mode in MODES {
        let (red, blue) = red_and_blue(&draw(&scene, mode, true));
        assert!(red > 300 && blue > 300, "{mode:?}: {red} red, {blue} blue");
        let (red, blue) = red_and_blue(&draw(&scene, mode, false));
        assert_eq!((red, blue), (0, 0), "{mode:?} without maps");
    }
    // The light comes from -x: normals leaning to +x (scaled by 0.5 in x and y) turn away
    // from it, so the modes that draw normal maps are darker with the map than without.
    let brightness = |fb: &Framebuffer| {
        let covered = fb.color().iter().zip(fb.depth()).filter(|(_, z)| **z < 1.0);
        covered.map(|(c, _)| c.x + c.z).sum::<f32>()
    };
    for mode in [ShadingMode::Phong, ShadingMode::Reference] {
        let plain = draw(&scene, mode, false);
        let mapped = {
            let mut fb = Framebuffer::new(64, 48).unwrap();
            let opts = FrameOptions {
                shading: Some(ShadingChoice::Mode(mode)),
                textures: false,
                bump: true,
                ..FrameOptions::default()
            };
            render_frame(&scene, &mut fb, &opts);
            fb
        };
        let (a, b) = (brightness(&plain), brightness(&mapped));
        // Closed form at every pixel: N' = normalize(0.5 * 0.71, 0, 0.71) and L = (-0.6,
        // 0, 0.8): cos = (-0.21 + 0.57) / 0.79 = 0.45 against 0.8 unperturbed.
        let lit = |n: Vec3| 0.1 + 0.8 * n.normalize().dot(Vec3::new(-0.6, 0.0, 0.8)).max(0.0);
        let want = lit(Vec3::new(0.5 * 0.7098, 0.0, 0.7098)) / lit(Vec3::Z);
        assert!(
            ((b / a) - want).abs() < 0.02,
            "{mode:?}: ratio {} vs {want}",
            b / a
        );
    }
}

#[test]
fn a_gltf_with_a_jpeg_texture_shows_it_times_its_colour_factor() {
    let dir = temp_dir("gltf");
    let mut jpeg = Vec::new();
    image::DynamicImage::ImageRgb8(checker_image(32))
        .write_to(
            &mut std::io::Cursor::new(&mut jpeg),
            image::ImageFormat::Jpeg,
        )
        .unwrap();
    std::fs::write(dir.join("c.jpg"), jpeg).unwrap();
    let mut bin = Vec::new();
    for p in [[-1f32, -1., 0.], [1., -1., 0.], [1., 1., 0.], [-1., 1., 0.]] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
    }
    for t in [[0f32, 1.], [1., 1.], [1., 0.], [0., 0.]] {
        bin.extend(t.iter().flat_map(|c| c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend(i.to_le_bytes());
    }
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let gltf = |factor: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1}},"indices":2,"material":0}}]}}],
            "materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"baseColorFactor":{factor}}}}}],
            "textures":[{{"source":0}}],"images":[{{"uri":"c.jpg"}}],
            "accessors":[
              {{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]}},
              {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
              {{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}],
            "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":32}},
              {{"buffer":0,"byteOffset":80,"byteLength":12}}],
            "buffers":[{{"byteLength":92,"uri":"quad.bin"}}]}}"#
        )
    };
    std::fs::write(dir.join("quad.gltf"), gltf("[1, 1, 1, 1]")).unwrap();
    std::fs::write(dir.join("half.gltf"), gltf("[1, 1, 0.5, 1]")).unwrap();
    let scene = load_scene(&scene_file(&dir, "quad.gltf")).unwrap();
    let half = load_scene(&scene_file(&dir, "half.gltf")).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    for mode in MODES {
        let fb = draw(&scene, mode, true);
        let (red, blue) = red_and_blue(&fb);
        assert!(red > 300 && blue > 300, "{mode:?}: {red} red, {blue} blue");
        // The factor halves blue and leaves red: compare the blue squares' blue channel.
        let h = draw(&half, mode, true);
        let (mut sum, mut sum_half, mut n) = (0.0, 0.0, 0);
        for (c, d) in fb.color().iter().zip(h.color()) {
            if c.z > 4.0 * c.x + 0.05 {
                (sum, sum_half, n) = (sum + c.z, sum_half + d.z, n + 1);
            }
            if c.x > 4.0 * c.z + 0.05 {
                assert!((c.x - d.x).abs() < 1e-6, "{mode:?}: red moved {c} {d}");
            }
        }
        assert!(
            n > 300 && (sum_half / sum - 0.5).abs() < 0.01,
            "{mode:?}: {}",
            sum_half / sum
        );
    }
}

#[test]
fn a_scene_notes_every_file_it_was_made_from_for_live_reload() {
    let dir = temp_dir("noting");
    textured_quad(&dir, [128, 128, 255], "");
    let path = scene_file(&dir, "quad.obj");
    let (scene, files) = phosphor_scene::load_scene_noting(&path);
    let scene = scene.unwrap();
    let want: std::collections::BTreeSet<PathBuf> =
        ["quad.obj.toml", "quad.obj", "quad.mtl", "c.png", "n.png"]
            .iter()
            .map(|f| dir.join(f))
            .collect();
    assert_eq!(files, want);
    assert_eq!(
        phosphor_scene::image_files(&scene),
        want.iter()
            .filter(|f| f.extension().is_some_and(|e| e == "png"))
            .cloned()
            .collect()
    );
    // A scene that fails still names what it read up to the error: here the mesh it could
    // not find, so that creating it reloads the scene.
    std::fs::remove_file(dir.join("quad.obj")).unwrap();
    let (scene, files) = phosphor_scene::load_scene_noting(&path);
    assert!(scene.is_err());
    assert!(
        files.contains(&path) && files.contains(&dir.join("quad.obj")),
        "{files:?}"
    );
    // And a scene file that does not parse names itself.
    std::fs::write(&path, "[[objects]\n").unwrap();
    let (scene, files) = phosphor_scene::load_scene_noting(&path);
    assert!(scene.is_err());
    assert_eq!(files, std::collections::BTreeSet::from([path.clone()]));
    let _ = std::fs::remove_dir_all(&dir);
}
