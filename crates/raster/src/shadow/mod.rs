//! Shadow maps (Williams 1978, "Casting curved shadows on curved surfaces"): the depth of the
//! nearest caster seen from a light, rendered once per frame into a square map, then looked up
//! per pixel of every receiver: a point farther from the light than the map's depth at its
//! place is in shadow.
//!
//! * **Views** ([`LightView`], [`fit()`]): an orthographic box along a directional light, a
//!   perspective cone from a spot or point light. Each is fitted by bounding spheres to the
//!   casters and receivers that matter, so the map's texels cover only the region where a
//!   shadow can fall on something visible. A point light gets one perspective map when its
//!   casters fit in a cone of at most [`MAX_POINT_HALF_ANGLE_DEG`], and otherwise a cube map
//!   ([`cube`]): up to six faces, only those through which a caster can shadow a receiver.
//! * **Rendering** ([`ShadowMap::render`]): the casters go through the frame's own stages
//!   (clipping, the top-left coverage rule, the exact depth of every pixel, bands in parallel)
//!   writing depth alone, so the map is the same for any thread count; its depths are then
//!   turned into distances along the light's axis, and each texel's footprint range taken.
//! * **Lookup** ([`ShadowMap::visibility`]): percentage-closer filtering (Reeves, Salesin and
//!   Cook 1987) over a 4 x 4-texel footprint with tent weights, which is a 3 x 3 box of
//!   bilinear 2 x 2 taps: the comparisons are filtered, not the depths, so the result is the
//!   fraction of the footprint that is lit, in `[0, 1]`, smooth across texels.
//! * **Bias**: a receiver is compared at its distance less
//!   `texel * (BIAS_CONSTANT + BIAS_SLOPE * tan(theta))` (theta between the normal and the
//!   light, `tan` capped at [`MAX_BIAS_SLOPE`]), `texel` the world size of one texel there. Too
//!   little bias and a lit surface shadows itself in stripes (acne: the map holds the surface's
//!   own depth, sampled at texel centres, and the footprint reaches up to three texels away where a
//!   sloped surface is nearer the light); too much and shadows detach from their casters
//!   (peter-panning). The slope term grows the bias only where the surface is steep to the
//!   light, and the footprint's reach (under three texels) sets its size.
//!
//! The lookup is written once over lanes (`lookup.rs`): every step is the `f32` step lane by
//! lane, so the picture is the same at every SIMD width.

use glam::{Mat4, Vec3};

use crate::framebuffer::{FAR_DEPTH, Framebuffer, RasterError};
use crate::parallel::for_each_chunk_pair;
use crate::{MeshView, RenderOptions, RenderStats};

pub mod cube;
pub mod fit;
mod lookup;
pub mod rays;
pub mod shade;

pub use cube::{CubeFace, CubeShadow, Extent, FaceFit, fit_cube};
pub use fit::{LightShape, NoMap, Sphere, can_shadow, fit};
pub use rays::{Occluders, RayTarget};
pub use shade::{LightMaps, ShadowLight};

/// Largest map side accepted.
pub const MAX_SHADOW_SIZE: u32 = 4096;
/// Smallest map side.
pub const MIN_SHADOW_SIZE: u32 = 16;
/// Constant bias, in texels.
pub const BIAS_CONSTANT: f32 = 1.0;
/// Slope-scaled bias, in texels per unit of `tan(theta)`: the PCF footprint's reach (its
/// farthest texel centre is under `2 sqrt 2` texels away).
pub const BIAS_SLOPE: f32 = 3.0;
/// Largest `tan(theta)` the bias follows (about 80 degrees from the light).
pub const MAX_BIAS_SLOPE: f32 = 6.0;
/// Widest cone a point light's single map may cover, half-angle in degrees.
pub const MAX_POINT_HALF_ANGLE_DEG: f32 = 60.0;

/// How a light sees its casters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Parallel rays (a directional light): the box `[-half_width, half_width]` across.
    Orthographic {
        /// Half the box's side, world units.
        half_width: f32,
    },
    /// A cone from the light's position (spot and point lights).
    Perspective {
        /// `tan` of the half-angle.
        tan_half: f32,
    },
}

/// A light's view of the casters: where it looks from, along which axis, how wide and over
/// which distances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// World to light view (right-handed, looking down -z).
    pub view: Mat4,
    /// Orthographic or perspective.
    pub projection: Projection,
    /// Nearest distance along the axis (> 0 for perspective).
    pub near: f32,
    /// Farthest distance along the axis (> near).
    pub far: f32,
    /// Where the light is: its position (perspective), or the unit direction towards it
    /// (orthographic).
    pub toward: Vec3,
}

impl LightView {
    /// The OpenGL projection of the view.
    #[must_use]
    pub fn projection_matrix(&self) -> Mat4 {
        match self.projection {
            Projection::Orthographic { half_width: h } => {
                glam::camera::rh::proj::opengl::orthographic(-h, h, -h, h, self.near, self.far)
            }
            Projection::Perspective { tan_half } => glam::camera::rh::proj::opengl::perspective(
                2.0 * tan_half.atan(),
                1.0,
                self.near,
                self.far,
            ),
        }
    }

    /// Whether every value is finite and the ranges are not empty.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        let shape = match self.projection {
            Projection::Orthographic { half_width } => half_width.is_finite() && half_width > 0.0,
            Projection::Perspective { tan_half } => {
                tan_half.is_finite() && tan_half > 0.0 && self.near > 0.0
            }
        };
        shape
            && self.view.is_finite()
            && self.near.is_finite()
            && self.far.is_finite()
            && self.far > self.near
            && self.toward.is_finite()
    }

    /// The unit direction from `p` towards the light (zero at the light itself).
    #[must_use]
    pub fn to_light(&self, p: Vec3) -> Vec3 {
        match self.projection {
            Projection::Orthographic { .. } => self.toward,
            Projection::Perspective { .. } => (self.toward - p).normalize_or_zero(),
        }
    }
}

/// One caster: a mesh placed in the world.
#[derive(Debug, Clone, Copy)]
pub struct Caster<'a> {
    /// The mesh.
    pub mesh: MeshView<'a>,
    /// Object to world.
    pub model: Mat4,
}

/// Rows of a map converted per parallel task.
const ROWS_PER_TASK: usize = 32;

/// Largest map side whose buffers are kept for the next map (see [`SPARE`]).
const MAX_SPARE_SIZE: u32 = 2048;
/// Distance and range arrays kept per thread, of each (a frame's maps are alive together: one
/// per light).
const MAX_SPARE_DISTANCES: usize = 4;

/// Buffers of the maps last rendered on this thread, for the next ones: a map is rendered
/// every frame, and a fresh buffer of its size costs the system's page faults and zeroing
/// (megabytes per map) each time. The frame is given back as soon as the map is read out,
/// the distances when the map is dropped; maps over [`MAX_SPARE_SIZE`] keep nothing.
#[derive(Default)]
struct Spare {
    frame: Option<Framebuffer>,
    distances: Vec<Vec<f32>>,
    ranges: Vec<Vec<[f32; 2]>>,
}

thread_local! {
    static SPARE: std::cell::RefCell<Spare> = std::cell::RefCell::default();
}

/// A kept buffer of `len` items from `list`, if there is one.
fn take_spare<T>(list: &mut Vec<Vec<T>>, len: usize) -> Option<Vec<T>> {
    let at = list.iter().position(|b| b.len() == len)?;
    Some(list.swap_remove(at))
}

/// Keeps `buffer` in `list` for the next map, unless the list is full.
fn keep_spare<T>(list: &mut Vec<Vec<T>>, buffer: Vec<T>) {
    if list.len() < MAX_SPARE_DISTANCES {
        list.push(buffer);
    }
}

/// A light's depth map: per texel, the distance along the light's axis of the nearest caster
/// (`f32::MAX` where none).
#[derive(Debug, Clone)]
pub struct ShadowMap {
    light: LightView,
    size: u32,
    /// Row after row, `stride` texels each: [`lookup::PAD`] texels of `f32::MAX` on every
    /// side of the `size` x `size` distances.
    distance: Vec<f32>,
    /// Per texel of `distance`, the least and greatest distance of the 4 x 4 texels from it
    /// rightwards and downwards (fewer at the array's last rows and columns): the lookup's
    /// footprint, so that a point wholly lit or wholly in shadow skips the 16 comparisons.
    ranges: Vec<[f32; 2]>,
    stride: usize,
    /// World size of a texel: at unit distance for perspective, everywhere for orthographic.
    texel: f32,
}

impl Drop for ShadowMap {
    fn drop(&mut self) {
        if self.size <= MAX_SPARE_SIZE {
            let distance = std::mem::take(&mut self.distance);
            let ranges = std::mem::take(&mut self.ranges);
            // `try_with`: a map dropped while its thread ends keeps nothing.
            let _ = SPARE.try_with(|s| {
                let spare = &mut *s.borrow_mut();
                keep_spare(&mut spare.distances, distance);
                keep_spare(&mut spare.ranges, ranges);
            });
        }
    }
}

impl ShadowMap {
    /// Bytes rendering a map of side `size` takes at its peak (the frame's colour and depth,
    /// then the padded distances and their footprints' ranges).
    #[must_use]
    pub fn bytes_for(size: u32) -> u64 {
        let padded = u64::from(size) + 2 * lookup::PAD as u64;
        u64::from(size) * u64::from(size) * 16 + padded * padded * 12
    }

    /// Renders the casters as `light` sees them into a `size` x `size` map, with `opts`'
    /// threads and SIMD level (the map does not depend on either).
    ///
    /// # Errors
    /// A side outside [`MIN_SHADOW_SIZE`]..=[`MAX_SHADOW_SIZE`], or a view that is not valid.
    pub fn render(
        light: &LightView,
        size: u32,
        casters: &[Caster],
        opts: &RenderOptions,
    ) -> Result<ShadowMap, RasterError> {
        if !(MIN_SHADOW_SIZE..=MAX_SHADOW_SIZE).contains(&size) {
            return Err(RasterError::BadSize {
                width: size,
                height: size,
                what: "shadow map side outside 16..=4096",
            });
        }
        if !light.is_valid() {
            return Err(RasterError::BadSize {
                width: size,
                height: size,
                what: "shadow view not finite",
            });
        }
        let spare = SPARE.with(|s| s.borrow_mut().frame.take());
        let mut fb = match spare {
            // The last map's frame: only the pixels it wrote are cleared again.
            Some(mut fb) if fb.width() == size => {
                fb.clear(glam::Vec3::ZERO);
                fb
            }
            _ => Framebuffer::new(size, size)?,
        };
        let vp = light.projection_matrix() * light.view;
        let opts = RenderOptions {
            perspective_correct: true,
            cull_backfaces: false,
            antialias: crate::Antialias::Off,
            ..*opts
        };
        let mut stats = RenderStats::default();
        for c in casters {
            crate::pipeline::run_depth(&mut fb, vp, &c.mesh, c.model, &opts, &mut stats);
        }
        let (n, f) = (light.near, light.far);
        let perspective = matches!(light.projection, Projection::Perspective { .. });
        // Depth to distance along the axis; no caster (or a value that overflows) is
        // `f32::MAX`. Written without branches per texel so that it runs in vectors.
        let to_distance = |d: f32| {
            let z = 2.0 * d - 1.0;
            let dist = if perspective {
                // Inverse of the OpenGL perspective depth.
                2.0 * n * f / ((f + n) - z * (f - n))
            } else {
                n + d * (f - n)
            };
            if d < FAR_DEPTH && dist.is_finite() {
                dist
            } else {
                f32::MAX
            }
        };
        let side = size as usize;
        let stride = side + 2 * lookup::PAD;
        // A spare of the same size has its padding already (only the inside is written).
        let mut distance = SPARE
            .with(|s| take_spare(&mut s.borrow_mut().distances, stride * stride))
            .unwrap_or_else(|| vec![f32::MAX; stride * stride]);
        // Rows in parallel, like the map's bands (each row is its own; the same bits for any
        // thread count).
        let depth = &fb.depth;
        let inside = &mut distance[lookup::PAD * stride..(lookup::PAD + side) * stride];
        let task = ROWS_PER_TASK * stride;
        for_each_chunk_pair(
            opts.threads,
            inside,
            &mut [0u8; 0],
            (task, 0),
            |first, out, _| {
                for (i, row) in out.chunks_exact_mut(stride).enumerate() {
                    let y = first / stride + i;
                    let Some(src) = depth.get(y * side..(y + 1) * side) else {
                        continue;
                    };
                    for (out, &d) in row[lookup::PAD..lookup::PAD + side].iter_mut().zip(src) {
                        *out = to_distance(d);
                    }
                }
            },
        );
        if fb.width() <= MAX_SPARE_SIZE {
            SPARE.with(|s| s.borrow_mut().frame = Some(fb));
        }
        let mut ranges = SPARE
            .with(|s| take_spare(&mut s.borrow_mut().ranges, stride * stride))
            .unwrap_or_else(|| vec![[0.0; 2]; stride * stride]);
        let (all, task) = (&distance[..], ROWS_PER_TASK * stride);
        for_each_chunk_pair(
            opts.threads,
            &mut ranges,
            &mut [0u8; 0],
            (task, 0),
            |first, out, _| {
                lookup::footprint_ranges(all, stride, first / stride, out);
            },
        );
        let texel = match light.projection {
            Projection::Orthographic { half_width } => 2.0 * half_width / size as f32,
            Projection::Perspective { tan_half } => 2.0 * tan_half / size as f32,
        };
        Ok(ShadowMap {
            light: *light,
            size,
            distance,
            ranges,
            stride,
            texel,
        })
    }

    /// The map's side in texels.
    #[must_use]
    pub fn size(&self) -> u32 {
        self.size
    }

    /// The view it was rendered with.
    #[must_use]
    pub fn light(&self) -> &LightView {
        &self.light
    }

    /// The stored distance at texel `(x, y)` (row 0 at the top), `f32::MAX` where no caster is.
    #[must_use]
    pub fn distance_at(&self, x: u32, y: u32) -> f32 {
        let (x, y) = (x as usize + lookup::PAD, y as usize + lookup::PAD);
        self.distance[y * self.stride + x]
    }
}
