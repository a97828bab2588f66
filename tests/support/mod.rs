//! Shared helpers of the hard-case suite: owned meshes, renders checked in every mode and at
//! 1 and 2 threads, and exact coverage maps.
//!
//! Every render goes through [`render_checked`], which asserts the three properties each hard
//! case owes (finite pixels, each channel in `[0, 1]`, the same bytes for 1 and 2 threads), so
//! a case only adds what is special about it.

#![allow(
    dead_code,
    reason = "each test binary uses its own subset of the helpers"
)]

use phosphor::lighting::{Effects, LightSet, Material};
use phosphor::math::glam::{DVec4, Mat4, Vec3};
use phosphor::raster::{
    Camera, DrawItem, Framebuffer, MeshView, RenderOptions, RenderStats, ShadingMode,
    coverage_counts, render,
};

/// An owned triangle mesh (positions, normals, indices) that lends a [`MeshView`].
#[derive(Debug, Clone, Default)]
pub struct TriMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
}

impl TriMesh {
    /// A square of side 2 in the plane z = 0 facing the S1 camera, split in two, normals +Z.
    pub fn square() -> TriMesh {
        TriMesh {
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            indices: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    /// A mesh of separate triangles, each corner with its own vertex, normals `+Z`.
    pub fn soup(tris: &[[Vec3; 3]]) -> TriMesh {
        let mut m = TriMesh::default();
        for t in tris {
            m.push_triangle(*t, [Vec3::Z; 3]);
        }
        m
    }

    /// Appends one triangle with its own three vertices.
    pub fn push_triangle(&mut self, p: [Vec3; 3], n: [Vec3; 3]) {
        let base = self.positions.len() as u32;
        self.positions.extend(p);
        self.normals.extend(n);
        self.indices.push([base, base + 1, base + 2]);
    }

    /// The borrowed view the rasterizer takes.
    pub fn view(&self) -> MeshView<'_> {
        MeshView {
            positions: &self.positions,
            normals: &self.normals,
            uvs: None,
            tangents: None,
            colors: None,
            indices: &self.indices,
        }
    }
}

impl From<phosphor::mesh::Mesh> for TriMesh {
    fn from(m: phosphor::mesh::Mesh) -> TriMesh {
        TriMesh {
            positions: m.positions,
            normals: m.normals,
            indices: m.indices,
        }
    }
}

/// Lights, material and camera of one hard case.
#[derive(Debug, Clone)]
pub struct Setup {
    pub lights: LightSet,
    pub material: Material,
    pub camera: Camera,
    pub model: Mat4,
}

impl Default for Setup {
    /// Standard scene S1: its lights (`1/(1 + d)`), material and camera.
    fn default() -> Setup {
        Setup {
            lights: LightSet::s1(),
            material: Material::s1(),
            camera: Camera::s1(),
            model: Mat4::IDENTITY,
        }
    }
}

/// The draw of `mesh` in `mode` under `setup`, every effect on.
pub fn draw<'a>(mesh: &'a TriMesh, setup: &'a Setup, mode: ShadingMode) -> DrawItem<'a> {
    DrawItem {
        mesh: mesh.view(),
        model: setup.model,
        material: &setup.material,
        lights: &setup.lights,
        effects: Effects::ALL,
        mode,
        bump: None,
        texture: None,
        cull_backfaces: false,
    }
}

fn threads(n: usize) -> RenderOptions {
    RenderOptions {
        threads: n,
        ..RenderOptions::default()
    }
}

/// Asserts every channel of every pixel is finite and in `[0, 1]`.
pub fn assert_finite_in_unit_range(fb: &Framebuffer, label: &str) {
    for (i, c) in fb.color().iter().enumerate() {
        assert!(
            c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0,
            "{label}: pixel {i} is {c}"
        );
    }
    for (i, z) in fb.depth().iter().enumerate() {
        assert!(
            z.is_finite() && (0.0..=1.0).contains(z),
            "{label}: depth {i} is {z}"
        );
    }
}

/// The colour and depth bytes of a framebuffer (bit patterns, so NaN would compare too).
pub fn bits(fb: &Framebuffer) -> Vec<u32> {
    fb.color()
        .iter()
        .flat_map(|c| c.to_array())
        .chain(fb.depth().iter().copied())
        .map(f32::to_bits)
        .collect()
}

/// Renders `draws` at `w` x `h` with 1 and with 2 threads; asserts both framebuffers are
/// finite, in `[0, 1]` and byte-identical. Returns the 1-thread image and its statistics.
pub fn render_checked(
    w: u32,
    h: u32,
    camera: &Camera,
    draws: &[DrawItem],
    label: &str,
) -> (Framebuffer, RenderStats) {
    let mut one = Framebuffer::new(w, h).expect("framebuffer size");
    let stats = render(&mut one, camera, draws, &threads(1));
    let mut two = Framebuffer::new(w, h).expect("framebuffer size");
    let stats_two = render(&mut two, camera, draws, &threads(2));
    assert_finite_in_unit_range(&one, label);
    assert!(bits(&one) == bits(&two), "{label}: 1 and 2 threads differ");
    assert_eq!(stats, stats_two, "{label}: statistics differ with threads");
    (one, stats)
}

/// [`render_checked`] of `mesh` under `setup` in every shading mode; returns each mode's image.
pub fn render_all_modes(
    w: u32,
    h: u32,
    mesh: &TriMesh,
    setup: &Setup,
    label: &str,
) -> Vec<(ShadingMode, Framebuffer, RenderStats)> {
    ShadingMode::ALL
        .into_iter()
        .map(|mode| {
            let (fb, stats) = render_checked(
                w,
                h,
                &setup.camera,
                &[draw(mesh, setup, mode)],
                &format!("{label} [{mode}]"),
            );
            (mode, fb, stats)
        })
        .collect()
}

/// Per-pixel cover counts (no depth test) of `mesh`, asserted equal for 1 and 2 threads.
pub fn coverage(w: u32, h: u32, camera: &Camera, mesh: &TriMesh, model: Mat4) -> Vec<u32> {
    let setup = Setup {
        camera: *camera,
        model,
        ..Setup::default()
    };
    let d = [draw(mesh, &setup, ShadingMode::Flat)];
    let one = coverage_counts(w, h, camera, &d, &threads(1)).expect("coverage size");
    let two = coverage_counts(w, h, camera, &d, &threads(2)).expect("coverage size");
    assert_eq!(one, two, "coverage differs between 1 and 2 threads");
    one
}

/// Asserts `hits` is exactly `expected(x, y)` at every pixel, naming the first pixel that is
/// a crack (0 where 1 was expected) or a double hit.
pub fn assert_coverage(hits: &[u32], w: u32, expected: impl Fn(u32, u32) -> u32, label: &str) {
    for (i, &h) in hits.iter().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let e = expected(x, y);
        let what = if h > e { "double hit" } else { "crack" };
        assert_eq!(h, e, "{label}: {what} at pixel ({x}, {y})");
    }
}

/// World point that projects to screen `(x, y)` in pixels (row 0 at the top) at NDC depth
/// `z`, for a `w` x `h` image seen by `camera`: places vertices on exact sub-pixel positions.
pub fn unproject(camera: &Camera, w: u32, h: u32, x: f64, y: f64, z: f64) -> Vec3 {
    let vp = camera.view_proj(w as f32 / h as f32).as_dmat4();
    let ndc = DVec4::new(
        x / f64::from(w) * 2.0 - 1.0,
        1.0 - y / f64::from(h) * 2.0,
        z,
        1.0,
    );
    let p = vp.inverse() * ndc;
    (p.truncate() / p.w).as_vec3()
}

/// A mesh of triangles given in screen pixels, placed at NDC depth 0.5 in front of `camera`.
pub fn screen_mesh(camera: &Camera, w: u32, h: u32, tris: &[[(f64, f64); 3]]) -> TriMesh {
    let at = |(x, y): (f64, f64)| unproject(camera, w, h, x, y, 0.5);
    TriMesh::soup(&tris.iter().map(|t| t.map(at)).collect::<Vec<_>>())
}

/// 1 where the pixel centre lies in `[x0, x1) x [y0, y1)` (the top-left fill rule of an
/// axis-aligned rectangle), else 0.
pub fn in_rect(x: u32, y: u32, (x0, y0, x1, y1): (f64, f64, f64, f64)) -> u32 {
    let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
    u32::from(cx >= x0 && cx < x1 && cy >= y0 && cy < y1)
}

/// Number of pixels covered (depth written) in `fb`.
pub fn covered_pixels(fb: &Framebuffer) -> usize {
    fb.depth().iter().filter(|z| **z < 1.0).count()
}
