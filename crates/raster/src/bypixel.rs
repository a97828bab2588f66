//! The by-pixel pass: a band shaded from its id buffer alone, after the depth pass, for the
//! triangles whose pixels depend on nothing but their interpolated varyings. Every pixel whose
//! id names a visible triangle gets that triangle's attribute planes evaluated, and a run of
//! pixels of one triangle along a row is stepped by `dA/dx` from its first pixel, with no
//! second traversal of the triangles. Multisampled bands are shaded per block
//! ([`crate::multisample`]).

use glam::Vec3;

use crate::batch::{Pending, RowShader};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::lanes;
use crate::framebuffer::layer::LayerRows;
use crate::shader::Shader;
use crate::traverse::{Planes, planes_at};

/// The shading pass of a band from its id buffer alone, for kernels that read nothing but the
/// interpolated attributes: every pixel whose id (from [`crate::coverage::depth_only`], `epoch + k`) names
/// record `k` of the band gets the colour of that triangle's `planes[slot[k]]`, four pixels per
/// call, with no second traversal of the triangles. Along a row, a run of pixels of one
/// triangle is evaluated once at its first pixel and then stepped by `dA/dx` (the incremental
/// form along a span, as in the traversal's spans). Only columns `extents[row]` are read.
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
}

impl ByPixel<'_> {
    /// Shades the band's pixels into `color` with `shade` (the colours of the first `count` of
    /// `N` attribute sets), `N` pixels per call; returns the pixels shaded.
    pub fn shade<const N: usize>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        shade: &RowShader<'_, N>,
    ) -> u64 {
        self.shade_impl(color, layer, shade)
    }

    /// [`ByPixel::shade`] of eight pixels per call in an AVX2 frame, with the loop itself
    /// compiled as AVX2 code: its attributes step as whole vectors.
    #[cfg(target_arch = "x86_64")]
    pub fn shade_avx2(
        &self,
        avx2: crate::simd::Avx2,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        shade: &RowShader<'_, 8>,
    ) -> u64 {
        avx2.run(RowRun {
            pass: self,
            shade,
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
        shade: &RowShader<'_, N>,
    ) -> u64 {
        match self.block {
            2 => return self.shade_blocks::<N, 2, 4>(color, layer, shade),
            4 => return self.shade_blocks::<N, 4, 16>(color, layer, shade),
            _ => {}
        }
        // The lane count as a constant: the stepping and the divide compile to whole vectors.
        match (self.perspective, lanes(self.n)) {
            (true, 0) => self.run::<N, true, 0, _>(color, shade),
            (true, 4) => self.run::<N, true, 4, _>(color, shade),
            (true, 8) => self.run::<N, true, 8, _>(color, shade),
            (true, _) => self.run::<N, true, MAX_ATTRS, _>(color, shade),
            (false, 0) => self.run::<N, false, 0, _>(color, shade),
            (false, 4) => self.run::<N, false, 4, _>(color, shade),
            (false, 8) => self.run::<N, false, 8, _>(color, shade),
            (false, _) => self.run::<N, false, MAX_ATTRS, _>(color, shade),
        }
    }

    /// [`ByPixel::shade`] for a shader that interpolates more than eight attributes (a
    /// texture's gradients, a shadow's or a bump map's frame), with its pixel stage `shade`
    /// compiled into the loop. The sixteen-lane loop costs about 10% more instructions when it
    /// calls the stage through [`RowShader`] (measured on a textured sphere), while the loops of
    /// eight lanes or fewer cost less that way; so only these shaders get a loop of their own.
    #[inline(always)]
    pub fn shade_wide<const N: usize, F>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        shade: &F,
    ) -> u64
    where
        F: Fn(&[Attrs; N], usize, f32) -> [Vec3; N],
    {
        match self.block {
            2 => return self.shade_blocks::<N, 2, 4>(color, layer, shade),
            4 => return self.shade_blocks::<N, 4, 16>(color, layer, shade),
            _ => {}
        }
        if self.perspective {
            self.run::<N, true, MAX_ATTRS, F>(color, shade)
        } else {
            self.run::<N, false, MAX_ATTRS, F>(color, shade)
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

    /// [`ByPixel::shade`] stepping `L` attribute lanes ([`lanes`] of `self.n`).
    #[inline(always)]
    fn run<const N: usize, const PERSPECTIVE: bool, const L: usize, F>(
        &self,
        color: &mut [Vec3],
        shade4: &F,
    ) -> u64
    where
        F: Fn(&[Attrs; N], usize, f32) -> [Vec3; N] + ?Sized,
    {
        let width = self.width as usize;
        let mut shaded = 0;
        let mut pending = Pending::<usize, N>::new(self.ceiling);
        for (row, &(lo, hi)) in self.extents.iter().enumerate() {
            let base = row * width;
            let (lo, hi) = (lo as usize, (hi as usize).min(width));
            let Some(row_ids) = self.ids.get(base + lo..base + hi) else {
                continue;
            };
            let yc = (self.y0 + row as i64) as f64 + 0.5;
            // The run being stepped: its id, the next column it would continue at, and its
            // steps per pixel (kept, so that a pixel continuing it looks nothing up).
            let (mut run, mut next) = (u64::MAX, usize::MAX);
            let (mut inv_w, mut attrs) = (1.0f64, [0.0f32; MAX_ATTRS]);
            let (mut step_w, mut step) = (0.0f64, [0.0f32; MAX_ATTRS]);
            for (i, &id) in row_ids.iter().enumerate() {
                let x = lo + i;
                if id == run && x == next {
                    if PERSPECTIVE {
                        inv_w += step_w;
                    }
                    // Whole vectors, as in `Pending::push`.
                    for k in 0..L {
                        attrs[k] += step[k];
                    }
                } else {
                    let Some(p) = self.planes_of(id) else {
                        continue;
                    };
                    let o = (x as f64 + 0.5 - p.origin.0, yc - p.origin.1);
                    (inv_w, attrs) = planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], o, L);
                    (step_w, step) = (p.inv_w[1], p.attr_dx);
                    run = id;
                }
                next = x + 1;
                let w = if PERSPECTIVE {
                    (1.0 / inv_w) as f32
                } else {
                    1.0
                };
                pending.push(base + x, (&attrs, w, L), shade4, color);
                shaded += 1;
            }
        }
        pending.flush_with(shade4, color);
        shaded
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
        let kernel = |a: &[Attrs; 8], count, ceiling| wide.shade8(shader, a, count, ceiling);
        self.pass
            .shade_wide::<8, _>(self.color, self.layer, &kernel)
    }
}

/// [`ByPixel::shade_avx2`]'s loop as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct RowRun<'p, 'a, 's, 'l> {
    pass: &'p ByPixel<'a>,
    shade: &'p RowShader<'s, 8>,
    color: &'p mut [Vec3],
    layer: Option<&'p mut LayerRows<'l>>,
}

#[cfg(target_arch = "x86_64")]
impl phosphor_lighting::Avx2Task for RowRun<'_, '_, '_, '_> {
    type Output = u64;
    #[inline(always)]
    fn run(self, _: phosphor_lighting::Avx2) -> u64 {
        self.pass.shade_impl(self.color, self.layer, self.shade)
    }
}
