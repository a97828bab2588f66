//! Phosphor against a CPU peer, euc 0.5, on the standard scene S1 with the bunny at 1920x1080:
//! the same mesh, camera, lights and equations (S1, docs/conventions.md:
//! `I = ka Ia + sum f(d) Il (kd max(N.L, 0) + ks max(R.V, 0)^ns)`, `f(d) = 1/(1 + d)`),
//! evaluated per pixel (`phong`) and per vertex (`gouraud`) in euc's shaders, plus a
//! constant-colour fill. euc 0.5 draws on one thread; Phosphor is measured on one thread and
//! on all cores. Before the criterion group runs, one line per mode prints the medians and
//! the ratio `euc / phosphor`.
//!
//! Run: `cargo bench --bench peers` (or `-- --quick`).

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use euc::buffer::Buffer2d;
use euc::{Interpolate, Pipeline, Target, rasterizer};
use phosphor::lighting::{LightSet, Material, effects_for};
use phosphor::math::glam::{Mat4, Vec3};
use phosphor::mesh::{Mesh, NormalOptions, load_obj};
use phosphor::raster::{
    Camera, DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode, render, render_fill_only,
};

const WIDTH: u32 = 1920;
const HEIGHT: u32 = 1080;

/// S1 as plain data, shared by both renderers.
struct Scene {
    mesh: Mesh,
    material: Material,
    lights: LightSet,
    camera: Camera,
    view_proj: Mat4,
    /// `[position, Il]` of S1's point lights (diffuse and specular `Il` are equal in S1).
    points: Vec<[Vec3; 2]>,
}

fn s1() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/meshes/bunny.obj");
    let mut mesh = load_obj(&path, &NormalOptions::s1()).expect("the bunny loads");
    mesh.normalize_unit();
    // Render order, as Phosphor's scene loader stores it; both renderers get this mesh.
    mesh.sort_spatially();
    let lights = LightSet::s1();
    let points = lights.points().iter().map(|p| [p.position, p.il]).collect();
    let camera = Camera::s1();
    Scene {
        mesh,
        material: Material::s1(),
        lights,
        view_proj: camera.view_proj(WIDTH as f32 / HEIGHT as f32),
        camera,
        points,
    }
}

/// S1's model in plain f32 as a peer would write it.
fn s1_model(s: &Scene, p: Vec3, n: Vec3) -> Vec3 {
    let m = &s.material;
    let n = n.normalize_or_zero();
    let v = (s.camera.eye - p).normalize_or_zero();
    let mut i = m.ka * s.lights.ambient();
    for &[position, il] in &s.points {
        let delta = position - p;
        let d = delta.length();
        let l = delta / d;
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        let r = 2.0 * n_dot_l * n - l;
        let spec = r.dot(v).max(0.0).powf(m.shininess);
        i += il / (1.0 + d) * (m.kd * n_dot_l + m.ks * spec);
    }
    i.min(Vec3::ONE)
}

/// What euc interpolates for Phong: world position and normal.
#[derive(Clone, Copy)]
struct Surface(Vec3, Vec3);

impl Interpolate for Surface {
    fn lerp2(a: Self, b: Self, x: f32, y: f32) -> Self {
        Surface(a.0 * x + b.0 * y, a.1 * x + b.1 * y)
    }
    fn lerp3(a: Self, b: Self, c: Self, x: f32, y: f32, z: f32) -> Self {
        Surface(a.0 * x + b.0 * y + c.0 * z, a.1 * x + b.1 * y + c.1 * z)
    }
}

/// An interpolated colour.
#[derive(Clone, Copy)]
struct Rgb(Vec3);

impl Interpolate for Rgb {
    fn lerp2(a: Self, b: Self, x: f32, y: f32) -> Self {
        Rgb(a.0 * x + b.0 * y)
    }
    fn lerp3(a: Self, b: Self, c: Self, x: f32, y: f32, z: f32) -> Self {
        Rgb(a.0 * x + b.0 * y + c.0 * z)
    }
}

struct EucPhong<'a>(&'a Scene);

impl Pipeline for EucPhong<'_> {
    type Vertex = u32;
    type VsOut = Surface;
    type Pixel = [f32; 3];
    fn vert(&self, &i: &u32) -> ([f32; 4], Surface) {
        let (p, n) = (
            self.0.mesh.positions[i as usize],
            self.0.mesh.normals[i as usize],
        );
        ((self.0.view_proj * p.extend(1.0)).to_array(), Surface(p, n))
    }
    fn frag(&self, s: &Surface) -> [f32; 3] {
        s1_model(self.0, s.0, s.1).to_array()
    }
}

struct EucGouraud<'a>(&'a Scene, &'a [Vec3]);

impl Pipeline for EucGouraud<'_> {
    type Vertex = u32;
    type VsOut = Rgb;
    type Pixel = [f32; 3];
    fn vert(&self, &i: &u32) -> ([f32; 4], Rgb) {
        let p = self.0.mesh.positions[i as usize];
        let clip = self.0.view_proj * p.extend(1.0);
        (clip.to_array(), Rgb(self.1[i as usize]))
    }
    fn frag(&self, c: &Rgb) -> [f32; 3] {
        c.0.to_array()
    }
}

struct EucFill<'a>(&'a Scene);

impl Pipeline for EucFill<'_> {
    type Vertex = u32;
    type VsOut = ();
    type Pixel = [f32; 3];
    fn vert(&self, &i: &u32) -> ([f32; 4], ()) {
        let p = self.0.mesh.positions[i as usize];
        ((self.0.view_proj * p.extend(1.0)).to_array(), ())
    }
    fn frag(&self, _: &()) -> [f32; 3] {
        [1.0; 3]
    }
}

/// The euc side: buffers and the flattened index list.
struct Euc {
    color: Buffer2d<[f32; 3]>,
    depth: Buffer2d<f32>,
    indices: Vec<u32>,
}

impl Euc {
    fn new(s: &Scene) -> Euc {
        let size = [WIDTH as usize, HEIGHT as usize];
        Euc {
            color: Buffer2d::new(size, [0.0; 3]),
            depth: Buffer2d::new(size, 1.0),
            indices: s.mesh.indices.iter().flatten().copied().collect(),
        }
    }

    fn frame(&mut self, s: &Scene, mode: &str) {
        self.color.clear([0.0; 3]);
        self.depth.clear(1.0);
        let (color, depth) = (&mut self.color, Some(&mut self.depth));
        match mode {
            "phong" => EucPhong(s).draw::<rasterizer::Triangles<_>, _>(&self.indices, color, depth),
            "gouraud" => {
                // Per vertex once a frame, as Phosphor's gouraud does.
                let lit: Vec<Vec3> = (s.mesh.positions.iter().zip(&s.mesh.normals))
                    .map(|(&p, &n)| s1_model(s, p, n))
                    .collect();
                EucGouraud(s, &lit).draw::<rasterizer::Triangles<_>, _>(&self.indices, color, depth)
            }
            _ => EucFill(s).draw::<rasterizer::Triangles<_>, _>(&self.indices, color, depth),
        }
    }
}

fn phosphor_frame(s: &Scene, fb: &mut Framebuffer, mode: &str, threads: usize) {
    let item = DrawItem {
        mesh: MeshView {
            positions: &s.mesh.positions,
            normals: &s.mesh.normals,
            uvs: None,
            tangents: None,
            colors: None,
            indices: &s.mesh.indices,
        },
        model: Mat4::IDENTITY,
        material: &s.material,
        lights: &s.lights,
        effects: effects_for(&s.lights, &s.material),
        mode: if mode == "gouraud" {
            ShadingMode::Gouraud
        } else {
            ShadingMode::Phong
        },
        bump: None,
        texture: None,
        cull_backfaces: false,
    };
    let opts = RenderOptions {
        threads,
        ..RenderOptions::default()
    };
    if mode == "fill" {
        render_fill_only(fb, &s.camera, &[item], &opts);
    } else {
        render(fb, &s.camera, &[item], &opts);
    }
}

fn median_ms(frames: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut ms: Vec<f64> = (0..frames)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    ms.sort_by(f64::total_cmp);
    ms[ms.len() / 2]
}

const MODES: [&str; 3] = ["phong", "gouraud", "fill"];

fn peers(c: &mut Criterion) {
    let s = s1();
    let mut fb = Framebuffer::new(WIDTH, HEIGHT).expect("1080p framebuffer");
    let mut euc = Euc::new(&s);
    for mode in MODES {
        let e = median_ms(9, || euc.frame(&s, mode));
        let p1 = median_ms(9, || phosphor_frame(&s, &mut fb, mode, 1));
        let pn = median_ms(9, || phosphor_frame(&s, &mut fb, mode, 0));
        // Both must have drawn the bunny: lit pixels of each image.
        let euc_px = euc
            .color
            .as_ref()
            .iter()
            .filter(|c| **c != [0.0; 3])
            .count();
        let phosphor_px = (0..HEIGHT)
            .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
            .filter(|&(x, y)| fb.pixel(x, y) != Vec3::ZERO)
            .count();
        println!(
            "peers {mode:<8} euc_ms={e:.2} phosphor_1t_ms={p1:.2} phosphor_all_ms={pn:.2} \
             ratio_1t={:.2} ratio_all={:.2} euc_px={euc_px} phosphor_px={phosphor_px}",
            e / p1,
            e / pn
        );
    }
    let mut g = c.benchmark_group("peers");
    g.sample_size(10);
    for mode in MODES {
        g.bench_function(BenchmarkId::new("euc", mode), |b| {
            b.iter(|| euc.frame(black_box(&s), mode))
        });
        for threads in [1, 0] {
            let id = BenchmarkId::new(format!("phosphor-{threads}t"), mode);
            g.bench_function(id, |b| {
                b.iter(|| phosphor_frame(black_box(&s), &mut fb, mode, threads))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, peers);
criterion_main!(benches);
