//! The by-pixel pass: a band shaded from its id buffer alone, after the depth pass, for the
//! triangles whose pixels depend on nothing but their interpolated varyings. Every pixel whose
//! id names a visible triangle gets that triangle's attribute planes evaluated, with no second
//! traversal of the triangles. A row is cut into runs of pixels of one triangle: a long run
//! is evaluated four pixels at a time straight into lanes, the layout the pixel stage reads,
//! and the rest one pixel at a time, stepped by `dA/dx` along the run. Multisampled bands are
//! shaded per block ([`crate::multisample`]).

use glam::Vec3;

use crate::batch::{AttrLanes, LaneShader, Pending, RowShader};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::lanes;
use crate::framebuffer::layer::LayerRows;
use crate::shader::Shader;
use crate::traverse::Planes;

/// The shading pass of a band from its id buffer alone, for kernels that read nothing but the
/// interpolated attributes: every pixel whose id (from [`crate::coverage::depth_only`], `epoch + k`) names
/// record `k` of the band gets the colour of that triangle's `planes[slot[k]]`, four or eight
/// pixels per call, with no second traversal of the triangles. Along a row, the planes of a
/// run of pixels of one triangle are evaluated once per run, and its pixels in lanes or one
/// by one. Only columns `extents[row]` are read.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ByPixel<'a> {
    /// Per record of the band: its index in `planes`, or `u32::MAX` when it has none.
    pub slot: &'a [u32],
    /// Attribute planes of the records that can be visible.
    pub planes: &'a [Planes],
    /// The nearest record's id per band pixel.
    pub ids: &'a [u64],
    /// The id of the band's record 0.
    pub epoch: u64,
    /// Per row of the band: the columns `[lo, hi)` the depth pass wrote.
    pub extents: &'a [(u32, u32)],
    /// Image width.
    pub width: u32,
    /// First row of the band.
    pub y0: i64,
    /// Attributes in use.
    pub n: usize,
    /// Whether attributes are divided by `w`.
    pub perspective: bool,
    /// Multisampling: the band holds samples, `block x block` of them per output pixel
    /// (aligned to the band's first row), and each triangle is shaded once per block at the
    /// centroid of the samples it owns there, and the colour written to each of them. 2 or
    /// 4; any other value shades every sample.
    pub block: usize,
    /// The framebuffer's largest intensity, that every colour is clamped to.
    pub ceiling: f32,
    /// For a band of `2 x 2` blocks, per block the id its four samples share
    /// ([`crate::multisample::mark_blocks`]); empty otherwise, and the walk reads the
    /// samples' ids.
    pub whole: &'a [u64],
}

impl ByPixel<'_> {
    /// Shades the band's pixels into `color`, `N` pixels per call: with `lanes` (the colours of
    /// the first `count` of `N` pixels in lanes), or `rows` (of `N` attribute rows) where a
    /// multisampled band's blocks are queued one by one; returns the pixels shaded.
    pub fn shade<const N: usize>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        (rows, lanes): (&RowShader<'_, N>, &LaneShader<'_, N>),
    ) -> u64 {
        self.shade_impl(color, layer, rows, lanes)
    }

    /// [`ByPixel::shade`] of eight pixels per call in an AVX2 frame, with the loop itself
    /// compiled as AVX2 code: its attributes step as whole vectors.
    #[cfg(target_arch = "x86_64")]
    pub fn shade_avx2(
        &self,
        avx2: crate::simd::Avx2,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        (rows, lanes): (&RowShader<'_, 8>, &LaneShader<'_, 8>),
    ) -> u64 {
        avx2.run(RowRun {
            pass: self,
            rows,
            lanes,
            color,
            layer,
        })
    }

    /// [`ByPixel::shade`], inlined.
    #[inline(always)]
    fn shade_impl<const N: usize>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        rows: &RowShader<'_, N>,
        shade: &LaneShader<'_, N>,
    ) -> u64 {
        match self.block {
            2 => return self.shade_blocks::<N, 2, 4>(color, layer, rows),
            4 => return self.shade_blocks::<N, 4, 16>(color, layer, rows),
            _ => {}
        }
        // The lane count as a constant: the stepping and the divide compile to whole vectors.
        match (self.perspective, lanes(self.n)) {
            (true, 0) => self.run::<N, true, 0, _, _>(color, rows, shade),
            (true, 4) => self.run::<N, true, 4, _, _>(color, rows, shade),
            (true, 8) => self.run::<N, true, 8, _, _>(color, rows, shade),
            (true, _) => self.run::<N, true, MAX_ATTRS, _, _>(color, rows, shade),
            (false, 0) => self.run::<N, false, 0, _, _>(color, rows, shade),
            (false, 4) => self.run::<N, false, 4, _, _>(color, rows, shade),
            (false, 8) => self.run::<N, false, 8, _, _>(color, rows, shade),
            (false, _) => self.run::<N, false, MAX_ATTRS, _, _>(color, rows, shade),
        }
    }

    /// [`ByPixel::shade`] for a shader that interpolates more than eight attributes (a
    /// texture's gradients, a shadow's or a bump map's frame), with its pixel stage `shade`
    /// compiled into the loop. The sixteen-lane loop costs about 10% more instructions when it
    /// calls the stage through [`RowShader`] (measured on a textured sphere), while the loops of
    /// eight lanes or fewer cost less that way; so only these shaders get a loop of their own.
    #[inline(always)]
    pub fn shade_wide<const N: usize, F, G>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        (rows, shade): (&F, &G),
    ) -> u64
    where
        F: Fn(&[Attrs; N], usize, f32) -> [Vec3; N],
        G: Fn(&AttrLanes, usize, f32) -> [Vec3; N],
    {
        match self.block {
            2 => return self.shade_blocks::<N, 2, 4>(color, layer, rows),
            4 => return self.shade_blocks::<N, 4, 16>(color, layer, rows),
            _ => {}
        }
        if self.perspective {
            self.run::<N, true, MAX_ATTRS, F, G>(color, rows, shade)
        } else {
            self.run::<N, false, MAX_ATTRS, F, G>(color, rows, shade)
        }
    }

    /// [`ByPixel::shade_wide`] of eight pixels per call in an AVX2 frame, with the loop itself
    /// compiled as AVX2 code, so that the sixteen attributes step as two vectors. The pixel
    /// stage stays the shader's one eight-lane function, called per eight pixels: inlined
    /// here as well, it made the binaries 5 MB larger and the loop slower.
    #[cfg(target_arch = "x86_64")]
    pub fn shade_wide_avx2<S: Shader>(
        &self,
        avx2: crate::simd::Avx2,
        shader: &S,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
    ) -> u64 {
        avx2.run(WideRun {
            pass: self,
            shader,
            color,
            layer,
        })
    }

    /// [`ByPixel::shade`] evaluating `L` attribute lanes ([`lanes`] of `self.n`). Each row is
    /// cut into runs of pixels of one triangle, and a run's planes are evaluated at its row
    /// once. The pixels of a run of [`QUAD_RUN`] or more go four at a time into lanes whole
    /// ([`Quads`], shaded by `lanes`). The rest (the last `run % 4` of such a run, or a
    /// shorter run) are evaluated at the first of them, stepped by `dA/dx`, and queued one by
    /// one (shaded by `rows`). Both levels cut runs alike, so the four- and eight-lane passes
    /// give each pixel the same bits.
    #[inline(always)]
    fn run<const N: usize, const PERSPECTIVE: bool, const L: usize, F, G>(
        &self,
        color: &mut [Vec3],
        rows: &F,
        lanes: &G,
    ) -> u64
    where
        F: Fn(&[Attrs; N], usize, f32) -> [Vec3; N] + ?Sized,
        G: Fn(&AttrLanes, usize, f32) -> [Vec3; N] + ?Sized,
    {
        let width = self.width as usize;
        let mut shaded = 0;
        let mut pending = Pending::<usize, N>::new(self.ceiling);
        let mut quads = Quads::<N>::new(self.ceiling);
        for (row, &(lo, hi)) in self.extents.iter().enumerate() {
            let base = row * width;
            let (lo, hi) = (lo as usize, (hi as usize).min(width));
            let Some(row_ids) = self.ids.get(base + lo..base + hi) else {
                continue;
            };
            let yc = (self.y0 + row as i64) as f64 + 0.5;
            let mut i = 0;
            while let Some(&id) = row_ids.get(i) {
                let Some(p) = self.planes_of(id) else {
                    i += 1;
                    continue;
                };
                let at = RowPlanes::<L>::of(p, yc);
                // A run of `QUAD_RUN` or more: its whole groups of four into lanes. Short
                // runs (most of a fine mesh's) stay one pixel at a time: cutting them into
                // lanes cost more in branches than the lanes saved.
                let long = row_ids.get(i..i + QUAD_RUN);
                if long.is_some_and(|w| w.iter().all(|&r| r == id)) {
                    let more = row_ids[i + QUAD_RUN..].iter().take_while(|&&r| r == id);
                    let whole = (QUAD_RUN + more.count()) & !3;
                    for q in (0..whole).step_by(4) {
                        quads.push::<PERSPECTIVE, L, G>(&at, lo + i + q, base, lanes, color);
                    }
                    i += whole;
                    shaded += whole as u64;
                }
                // The rest of the run pixel by pixel: evaluated at the first, stepped by
                // `dA/dx`. The run's end is found on the way, with no scan ahead.
                if row_ids.get(i) != Some(&id) {
                    continue;
                }
                let start = i;
                let (mut inv_w, mut attrs) = at.at(lo + i);
                while row_ids.get(i) == Some(&id) {
                    let w = if PERSPECTIVE {
                        (1.0 / inv_w) as f32
                    } else {
                        1.0
                    };
                    if pending.queue(base + lo + i, (&attrs, w, L)) {
                        // Once per `N` pixels: what the loop keeps in registers is saved
                        // around the shading call here, not on every pixel.
                        seldom();
                        pending.flush_side_by_side(rows, color);
                    }
                    if PERSPECTIVE {
                        inv_w += at.inv_w.1;
                    }
                    // Whole vectors, as in `Pending::push`.
                    for k in 0..L {
                        attrs[k] += at.dx[k];
                    }
                    i += 1;
                }
                shaded += (i - start) as u64;
            }
        }
        pending.flush_side_by_side(rows, color);
        quads.flush(lanes, color);
        shaded
    }
}

/// Marks the branch that calls it as rarely taken, so that LLVM places the spills of the loop
/// around it there (`std::hint::cold_path` is newer than the crate's minimum Rust).
#[cold]
#[inline(never)]
fn seldom() {}

/// The shortest run whose pixels go into lanes four at a time ([`Quads`]).
const QUAD_RUN: usize = 8;

/// A triangle's planes along one row: `1/w` and the attributes at the row's `y` (and `x` at
/// the plane's origin), with their steps per pixel along `x`.
///
/// The value at pixel centre `(x, y)` is `row + ox * d/dx`, with `ox = (x + 0.5) - origin.x`
/// in f64 (rounded to f32 for the attributes) and `row = A0 + oy * dA/dy`: the same
/// operations for a pixel whichever lane takes it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowPlanes<const L: usize> {
    /// The plane origin's `x`.
    pub origin_x: f64,
    /// `1/w` at the row and its step per pixel.
    pub inv_w: (f64, f64),
    /// The attributes at the row, then zeros.
    pub attrs: Attrs,
    /// Their steps per pixel, then zeros.
    pub dx: Attrs,
}

impl<const L: usize> RowPlanes<L> {
    /// The planes `p` along the row of pixel centres at `yc`.
    #[inline(always)]
    pub fn of(p: &Planes, yc: f64) -> RowPlanes<L> {
        let oy = yc - p.origin.1;
        let fy = oy as f32;
        let (mut attrs, mut dx) = ([0.0; MAX_ATTRS], [0.0; MAX_ATTRS]);
        for k in 0..L {
            attrs[k] = p.attr0[k] + fy * p.attr_dy[k];
            dx[k] = p.attr_dx[k];
        }
        RowPlanes {
            origin_x: p.origin.0,
            inv_w: (p.inv_w[0] + oy * p.inv_w[2], p.inv_w[1]),
            attrs,
            dx,
        }
    }

    /// `1/w` and the attributes (not divided) at column `x`.
    #[inline(always)]
    pub fn at(&self, x: usize) -> (f64, Attrs) {
        // Columns are below `MAX_SIDE`: through u32, the conversion is one instruction.
        let ox = (f64::from(x as u32) + 0.5) - self.origin_x;
        let fx = ox as f32;
        let mut attrs = [0.0; MAX_ATTRS];
        for k in 0..L {
            attrs[k] = self.attrs[k] + fx * self.dx[k];
        }
        (self.inv_w.0 + ox * self.inv_w.1, attrs)
    }
}

/// Runs' pixels waiting for the pixel stage in groups of four, their attributes already in
/// lanes (`N / 4` groups fill a call), each group with the band pixel of its first.
pub(crate) struct Quads<const N: usize> {
    attrs: AttrLanes,
    first: [usize; 2],
    groups: usize,
    ceiling: f32,
}

impl<const N: usize> Quads<N> {
    /// No pixel waiting; colours will be clamped to `[0, ceiling]`.
    pub fn new(ceiling: f32) -> Quads<N> {
        Quads {
            attrs: [[0.0; 8]; MAX_ATTRS],
            first: [0; 2],
            groups: 0,
            ceiling,
        }
    }

    /// Queues the four pixels from column `x` (band pixels `base + x` on) on the planes
    /// `at`, perspective-divided when `PERSPECTIVE`, shading with `shade` once `N` are
    /// waiting.
    #[inline(always)]
    pub fn push<const PERSPECTIVE: bool, const L: usize, G>(
        &mut self,
        at: &RowPlanes<L>,
        x: usize,
        base: usize,
        shade: &G,
        color: &mut [Vec3],
    ) where
        G: Fn(&AttrLanes, usize, f32) -> [Vec3; N] + ?Sized,
    {
        let g = self.groups & 1;
        let first = f64::from(x as u32);
        // Lane `i` is column `x + i`, as `RowPlanes::at` computes it.
        let ox: [f64; 4] = std::array::from_fn(|i| (first + i as f64 + 0.5) - at.origin_x);
        let fx: [f32; 4] = ox.map(|o| o as f32);
        let w: [f32; 4] = if PERSPECTIVE {
            ox.map(|o| (1.0 / (at.inv_w.0 + o * at.inv_w.1)) as f32)
        } else {
            [1.0; 4]
        };
        for k in 0..L {
            let (a, d) = (at.attrs[k], at.dx[k]);
            let v: [f32; 4] = std::array::from_fn(|i| (a + fx[i] * d) * w[i]);
            self.attrs[k][g * 4..g * 4 + 4].copy_from_slice(&v);
        }
        self.first[g] = base + x;
        self.groups = g + 1;
        if self.groups * 4 >= N {
            self.shade_into(shade, color);
        }
    }

    /// Shades the waiting pixels with `shade` and writes their colours.
    #[inline(always)]
    pub fn flush<G>(&mut self, shade: &G, color: &mut [Vec3])
    where
        G: Fn(&AttrLanes, usize, f32) -> [Vec3; N] + ?Sized,
    {
        if self.groups == 0 {
            return;
        }
        // A half-empty call: its last lanes repeat the first group (finite attributes).
        for lane in &mut self.attrs {
            for i in self.groups * 4..8 {
                lane[i] = lane[i - 4];
            }
        }
        self.shade_into(shade, color);
    }

    #[inline(always)]
    fn shade_into<G>(&mut self, shade: &G, color: &mut [Vec3])
    where
        G: Fn(&AttrLanes, usize, f32) -> [Vec3; N] + ?Sized,
    {
        let n = (self.groups * 4).min(N);
        let c = shade(&self.attrs, n, self.ceiling);
        for g in 0..n / 4 {
            let at = self.first[g];
            color[at..at + 4].copy_from_slice(&c[g * 4..g * 4 + 4]);
        }
        self.groups = 0;
    }
}

impl ByPixel<'_> {
    /// The planes of the triangle with id `id`, if it is shaded here (ids below the epoch
    /// were left by earlier bands).
    #[inline(always)]
    pub(crate) fn planes_of(&self, id: u64) -> Option<&Planes> {
        (id >= self.epoch)
            .then(|| self.slot.get((id - self.epoch) as usize))
            .flatten()
            .and_then(|&s| self.planes.get(s as usize))
    }
}

/// [`ByPixel::shade_wide_avx2`]'s loop as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct WideRun<'p, 'a, 'l, S> {
    pass: &'p ByPixel<'a>,
    shader: &'p S,
    color: &'p mut [Vec3],
    layer: Option<&'p mut LayerRows<'l>>,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for WideRun<'_, '_, '_, S> {
    type Output = u64;
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> u64 {
        let (shader, wide) = (self.shader, crate::batch::Wide { avx2: Some(s) });
        let rows = |a: &[Attrs; 8], count, ceiling| wide.shade8(shader, a, count, ceiling);
        let lanes = |a: &AttrLanes, count, ceiling| wide.shade8(shader, a, count, ceiling);
        self.pass
            .shade_wide::<8, _, _>(self.color, self.layer, (&rows, &lanes))
    }
}

/// [`ByPixel::shade_avx2`]'s loop as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct RowRun<'p, 'a, 's, 'l> {
    pass: &'p ByPixel<'a>,
    rows: &'p RowShader<'s, 8>,
    lanes: &'p LaneShader<'s, 8>,
    color: &'p mut [Vec3],
    layer: Option<&'p mut LayerRows<'l>>,
}

#[cfg(target_arch = "x86_64")]
impl phosphor_lighting::Avx2Task for RowRun<'_, '_, '_, '_> {
    type Output = u64;
    #[inline(always)]
    fn run(self, _: phosphor_lighting::Avx2) -> u64 {
        self.pass
            .shade_impl(self.color, self.layer, self.rows, self.lanes)
    }
}
