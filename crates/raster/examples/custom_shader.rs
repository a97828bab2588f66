//! A shader of one's own, written against the public contract alone: cel (toon) shading of
//! the Stanford bunny, lit by one directional light, with its diffuse term cut into three
//! flat bands, a hard-edged highlight, and a dark rim where the surface turns away.
//!
//! `cargo run --release -p phosphor-raster --example custom_shader -- OUT.png [WxH]`

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use phosphor_lighting::{Lanes, Vec3s};
use phosphor_mesh::{NormalOptions, load_obj};
use phosphor_output::image::{Transfer, write_png};
use phosphor_raster::encode::{Encoder, Encoding};
use phosphor_raster::shader::{MAX_VARYINGS, Shader, Varyings, VertexLanes, put_vec3, vec3_at};
use phosphor_raster::{Camera, Frame, Framebuffer, MeshView, RenderOptions};

/// Cel shading: `N.L` quantized to three levels, the Blinn highlight to one, and a rim where
/// `N.V` is small. Varyings: world position 0..3, normal 3..6.
struct Cel {
    /// Unit direction towards the light.
    to_light: Vec3,
    /// The eye, for the highlight and the rim.
    eye: Vec3,
    /// The surface colour.
    base: Vec3,
}

impl Shader for Cel {
    const VARYINGS: usize = 6;
    type Stepped = ();

    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
        put_vec3(&mut out, 0, v.position);
        put_vec3(&mut out, 3, v.normal);
        out
    }

    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        let (p, n) = (vec3_at(v, 0), vec3_at(v, 3));
        let like = p.x;
        let c = |x: f32| like.splat(x);
        let zero = Vec3s::broadcast(like, Vec3::ZERO);
        let n = n.safe_normalize(zero);
        let to_eye = (Vec3s::broadcast(like, self.eye) - p).safe_normalize(n);
        let l = Vec3s::broadcast(like, self.to_light);
        // Three bands of diffuse light: 0.25, 0.6 and 1.0 of the base colour.
        let n_dot_l = n.dot(l);
        let band = n_dot_l
            .cmp_ge(c(0.55))
            .blend(c(1.0), n_dot_l.cmp_ge(c(0.1)).blend(c(0.6), c(0.25)));
        // A hard highlight where Blinn's N.H passes 0.97.
        let h = (l + to_eye).safe_normalize(n);
        let highlight = n.dot(h).cmp_ge(c(0.97)).blend(c(0.6), c(0.0));
        // A dark outline where the surface turns away from the eye.
        let rim = n.dot(to_eye).cmp_le(c(0.2)).blend(c(0.15), c(1.0));
        let base = Vec3s::broadcast(like, self.base);
        let lit = base * band + Vec3s::new(highlight, highlight, highlight);
        lit * rim
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = PathBuf::from(args.first().ok_or("usage: custom_shader OUT.png [WxH]")?);
    let (width, height) = match args.get(1) {
        Some(s) => {
            let (w, h) = s.split_once('x').ok_or("size is WxH")?;
            (w.parse()?, h.parse()?)
        }
        None => (960, 540),
    };
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/meshes/bunny.obj");
    let mut mesh = load_obj(&assets, &NormalOptions::s1())?;
    mesh.normalize_unit();
    let camera = Camera::s1();
    let shader = Cel {
        to_light: Vec3::new(1.0, 1.0, 1.2).normalize(),
        eye: camera.eye,
        base: Vec3::new(0.85, 0.45, 0.2),
    };
    let view = MeshView::new(&mesh.positions, &mesh.normals, &mesh.indices);
    let mut fb = Framebuffer::new(width, height)?;
    let opts = RenderOptions {
        background: Vec3::new(0.92, 0.9, 0.85),
        ..RenderOptions::default()
    };
    let mut frame = Frame::new(&mut fb, &camera, &opts);
    frame.draw(&view, Mat4::IDENTITY, &shader, false);
    let stats = frame.finish();
    let encoder = Encoder::new(Encoding::Srgb);
    let colour = fb.color();
    let mut row = |y: u32, bytes: &mut [u8]| {
        let start = (y * width) as usize;
        for (px, c) in bytes
            .chunks_exact_mut(3)
            .zip(&colour[start..start + width as usize])
        {
            px.copy_from_slice(&c.to_array().map(|v| encoder.encode(v)));
        }
    };
    write_png(
        &out,
        false,
        (width, height),
        Transfer::Srgb,
        &mut row,
        &mut |_| {},
    )?;
    println!(
        "wrote {}: {width}x{height}, {} triangles drawn, {} pixels shaded",
        out.display(),
        stats.triangles_drawn,
        stats.pixels_shaded
    );
    Ok(())
}
