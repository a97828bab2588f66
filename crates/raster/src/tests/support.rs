//! Meshes and scenes built in the tests (no dependency on phosphor-mesh).

use glam::{Mat4, Vec2, Vec3, Vec4};
use phosphor_lighting::{Attenuation, Effects, Light, LightSet, Material};

use crate::{
    Camera, DrawItem, Framebuffer, MeshView, RenderOptions, RenderStats, ShadingMode, render,
};

/// An owned mesh.
#[derive(Default, Clone)]
pub struct TestMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub tangents: Vec<Vec4>,
    pub indices: Vec<[u32; 3]>,
}

impl TestMesh {
    pub fn view(&self) -> MeshView<'_> {
        MeshView {
            positions: &self.positions,
            normals: &self.normals,
            uvs: (self.uvs.len() == self.positions.len()).then_some(&self.uvs[..]),
            tangents: (self.tangents.len() == self.positions.len()).then_some(&self.tangents[..]),
            colors: None,
            indices: &self.indices,
        }
    }
}

/// UV sphere with exact normals, uvs and tangents; counter-clockwise seen from outside.
pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> TestMesh {
    let mut m = TestMesh::default();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            );
            m.positions.push(n * radius);
            m.normals.push(n);
            m.uvs.push(Vec2::new(
                s as f32 / segments as f32,
                r as f32 / rings as f32,
            ));
            m.tangents
                .push(Vec4::new(-phi.sin(), 0.0, -phi.cos(), -1.0));
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b) = (r * row + s, r * row + s + 1);
            let (c, d) = (a + row, b + row);
            if r != 0 {
                m.indices.push([a, c, b]);
            }
            if r != rings - 1 {
                m.indices.push([b, c, d]);
            }
        }
    }
    m
}

/// Regular icosahedron of circumradius 1, flat normals per face (vertices split).
pub fn icosahedron() -> TestMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let v = [
        Vec3::new(-1.0, t, 0.0),
        Vec3::new(1.0, t, 0.0),
        Vec3::new(-1.0, -t, 0.0),
        Vec3::new(1.0, -t, 0.0),
        Vec3::new(0.0, -1.0, t),
        Vec3::new(0.0, 1.0, t),
        Vec3::new(0.0, -1.0, -t),
        Vec3::new(0.0, 1.0, -t),
        Vec3::new(t, 0.0, -1.0),
        Vec3::new(t, 0.0, 1.0),
        Vec3::new(-t, 0.0, -1.0),
        Vec3::new(-t, 0.0, 1.0),
    ]
    .map(|p| p.normalize());
    let f: [[usize; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut m = TestMesh::default();
    for tri in f {
        let base = m.positions.len() as u32;
        let n = (v[tri[1]] - v[tri[0]])
            .cross(v[tri[2]] - v[tri[0]])
            .normalize();
        for i in tri {
            m.positions.push(v[i]);
            m.normals.push(n);
        }
        m.indices.push([base, base + 1, base + 2]);
    }
    m
}

/// S1's lights (`docs/conventions.md`) with `f(d) = 1/(1 + d)`.
pub fn s1_lights() -> LightSet {
    let att = Attenuation::Offset { k: 1.0 };
    let l = |p: Vec3, i: Vec3| Light::point(p, i).unwrap().with_attenuation(att).unwrap();
    LightSet::new(
        Vec3::ONE,
        &[
            l(Vec3::new(2.0, 2.0, 2.0), Vec3::splat(3.0)),
            l(Vec3::new(-2.0, 1.0, 1.0), Vec3::new(2.0, 2.0, 2.4)),
            l(Vec3::new(0.0, -2.0, 2.0), Vec3::splat(1.2)),
        ],
    )
}

/// One draw of `mesh`.
pub fn item<'a>(
    mesh: &'a TestMesh,
    material: &'a Material,
    lights: &'a LightSet,
    mode: ShadingMode,
) -> DrawItem<'a> {
    DrawItem {
        mesh: mesh.view(),
        model: Mat4::IDENTITY,
        material,
        lights,
        effects: Effects::ALL,
        mode,
        bump: None,
        texture: None,
        cull_backfaces: false,
    }
}

/// Renders `draws` at `w` x `h` with `opts`.
pub fn draw_image(
    w: u32,
    h: u32,
    cam: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> (Framebuffer, RenderStats) {
    let mut fb = Framebuffer::new(w, h).unwrap();
    let stats = render(&mut fb, cam, draws, opts);
    (fb, stats)
}

/// World point that projects to screen `(x, y)` (pixels) at NDC depth `z`.
pub fn unproject(cam: &Camera, w: u32, h: u32, x: f64, y: f64, z: f32) -> Vec3 {
    let vp = cam.view_proj(w as f32 / h as f32).as_dmat4();
    let ndc = glam::DVec4::new(
        x / w as f64 * 2.0 - 1.0,
        1.0 - y / h as f64 * 2.0,
        z as f64,
        1.0,
    );
    let p = vp.inverse() * ndc;
    (p.truncate() / p.w).as_vec3()
}

/// Per-channel absolute differences of two images.
pub fn diffs(a: &Framebuffer, b: &Framebuffer) -> Vec<f32> {
    a.color()
        .iter()
        .zip(b.color())
        .map(|(x, y)| (*x - *y).abs().max_element())
        .collect()
}

/// Writes `fb` to docs/NAME when PHOSPHOR_WRITE_DOCS is set (the PNGs committed in docs/).
pub fn maybe_write_doc(fb: &Framebuffer, name: &str) {
    if std::env::var_os("PHOSPHOR_WRITE_DOCS").is_some() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs");
        std::fs::create_dir_all(&dir).unwrap();
        // S1 is linear-encoded; the PNG says so, as `phosphor render --encoding linear` does.
        let rgb = fb.to_rgb8(crate::Encoding::Linear);
        let stride = fb.width() as usize * 3;
        let mut row = |y: u32, out: &mut [u8]| {
            out.copy_from_slice(&rgb[y as usize * stride..][..stride]);
        };
        phosphor_output::image::write_png(
            &dir.join(name),
            false,
            (fb.width(), fb.height()),
            phosphor_output::image::Transfer::Linear,
            &mut row,
            &mut |_| {},
        )
        .unwrap();
    }
}
