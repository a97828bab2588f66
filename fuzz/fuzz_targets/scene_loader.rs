//! Arbitrary bytes into the scene loader: it must return a scene or an error naming the file,
//! never panic; and a scene that loads must render to finite pixels in [0, 1].

#![no_main]

use libfuzzer_sys::fuzz_target;
use phosphor_raster::Framebuffer;
use phosphor_scene::{FrameOptions, Scene, render_frame};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match Scene::parse(&text, "fuzz.toml") {
        Err(e) => assert!(e.to_string().starts_with("fuzz.toml")),
        Ok(scene) => {
            // Small frames: the target is the loader and the plan, not fill rate.
            let Ok(mut fb) = Framebuffer::new(16, 12) else {
                return;
            };
            let opts = FrameOptions {
                threads: 1,
                ..FrameOptions::default()
            };
            render_frame(&scene, &mut fb, &opts);
            assert!(fb.color().iter().all(|c| c.is_finite()
                && c.min_element() >= 0.0
                && c.max_element() <= 1.0));
        }
    }
});
