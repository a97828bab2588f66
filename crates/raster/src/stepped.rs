//! Stepped triangles ([`Face::Stepped`](crate::shader::Face::Stepped)) shaded in lanes. The
//! traversal steps a triangle's quadratics along each span by forward differences in `f64`, as
//! before; each covered pixel is then queued with its varyings, its quadratics' values and its
//! centre, and the queue goes through [`Shader::stepped_pixel`] eight pixels at a time with
//! AVX2 (else four), and at the end of the triangle, whose data every lane shares. Each lane
//! gets the bits of the one-lane call, so the picture is the one a pixel at a time gives.

use glam::Vec3;
use phosphor_lighting::Lanes;

use crate::batch::{Wide, clamped_colors, varyings_of_rows};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::lanes;
use crate::shader::{MAX_QUADRATICS, Pixels, Shader, Stepped, interpolated};
use crate::span::SpanShade;

/// Up to eight pixels of one stepped triangle waiting for its pixel stage; a band keeps one
/// and reuses it from triangle to triangle.
#[derive(Debug, Clone)]
pub(crate) struct StepQueue {
    /// Where each colour goes: a pixel index of the band.
    idx: [usize; 8],
    /// Each pixel's varyings (attributes times `w`).
    attrs: [Attrs; 8],
    /// Each pixel's quadratics' values.
    q: [[f32; MAX_QUADRATICS]; 8],
    /// Each pixel's centre.
    x: [f32; 8],
    y: [f32; 8],
    len: usize,
}

impl StepQueue {
    /// An empty queue.
    pub fn new() -> StepQueue {
        StepQueue {
            idx: [0; 8],
            attrs: [[0.0; MAX_ATTRS]; 8],
            q: [[0.0; MAX_QUADRATICS]; 8],
            x: [0.0; 8],
            y: [0.0; 8],
            len: 0,
        }
    }
}

/// A stepped triangle's pixels, queued in `queue` and shaded in lanes of the frame's width.
pub(crate) struct SteppedSpan<'s, S: Shader> {
    pub shader: &'s S,
    pub tri: &'s Stepped<S::Stepped>,
    /// The framebuffer's largest intensity.
    pub ceiling: f32,
    pub wide: Wide,
    pub queue: &'s mut StepQueue,
}

impl<S: Shader> SpanShade for SteppedSpan<'_, S> {
    const ATTRS: usize = interpolated::<S>();
    type Span = [[f64; 3]; MAX_QUADRATICS];
    #[inline(always)]
    fn span(&self, x: f64, y: f64) -> Self::Span {
        let t = self.tri;
        let (u, v) = (x - t.origin.0, y - t.origin.1);
        let mut d = [[0.0; 3]; MAX_QUADRATICS];
        for (d, q) in d.iter_mut().zip(&t.quadratics).take(t.count) {
            *d = q.differences(u, v);
        }
        d
    }
    #[inline(always)]
    fn pixel(
        &mut self,
        d: &Self::Span,
        idx: usize,
        (a, w): (&Attrs, f32),
        (x, y): (i64, i64),
        c: &mut [Vec3],
    ) {
        let q = &mut *self.queue;
        // `len < 8` always; masked so that no bounds check is compiled.
        let k = q.len & 7;
        q.idx[k] = idx;
        let row = &mut q.attrs[k];
        for j in 0..lanes(Self::ATTRS) {
            row[j] = a[j] * w;
        }
        q.q[k] = d.map(|d| d[0] as f32);
        (q.x[k], q.y[k]) = (x as f32 + 0.5, y as f32 + 0.5);
        q.len += 1;
        if q.len == 8 {
            self.flush(c);
        }
    }
    #[inline(always)]
    fn step(d: &mut Self::Span) {
        for d in d.iter_mut() {
            d[0] += d[1];
            d[1] += d[2];
        }
    }
    #[inline(always)]
    fn flush(&mut self, c: &mut [Vec3]) {
        let q = &mut *self.queue;
        let count = q.len;
        if count == 0 {
            return;
        }
        q.len = 0;
        let (shader, data, ceiling) = (self.shader, &self.tri.data, self.ceiling);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.wide.avx2 {
            let colors = avx2.run(Stepped8 {
                shader,
                data,
                queue: q,
                count,
                ceiling,
            });
            for k in 0..count {
                c[q.idx[k]] = colors[k];
            }
            return;
        }
        for half in [0, 4] {
            if half >= count {
                break;
            }
            let n = (count - half).min(4);
            let colors = stepped4(shader, data, q, half, n, ceiling);
            for k in 0..n {
                c[q.idx[half + k]] = colors[k];
            }
        }
    }
}

/// [`Shader::stepped_pixel`] for the `count` pixels of `q` from `from` on, as `N` lanes of
/// the kind of `like` (the lanes past `count` repeat the first), clamped.
#[inline(always)]
fn shade_queue<S: Shader, L: Lanes, const N: usize>(
    (shader, data): (&S, &S::Stepped),
    like: L,
    q: &StepQueue,
    (from, count): (usize, usize),
    ceiling: f32,
) -> [Vec3; N] {
    let pick = |k: usize| from + if k < count { k } else { 0 };
    let rows: [Attrs; N] = std::array::from_fn(|k| q.attrs[pick(k)]);
    let quads: [[f32; 8]; 8] = std::array::from_fn(|k| q.q[pick(k.min(N - 1))]);
    let (mut x, mut y) = ([0.0; 8], [0.0; 8]);
    for k in 0..N {
        (x[k], y[k]) = (q.x[pick(k)], q.y[pick(k)]);
    }
    let v = varyings_of_rows::<S, L, N>(like, &rows);
    let at = Pixels {
        x: like.with_lanes(x),
        y: like.with_lanes(y),
    };
    let c = shader.stepped_pixel(data, &like.columns(&quads), &v, &at);
    clamped_colors(c, count, ceiling)
}

/// [`shade_queue`] in four lanes: not inlined, so that a shader's four-lane stepped pixel
/// stage is compiled once.
#[inline(never)]
fn stepped4<S: Shader>(
    shader: &S,
    data: &S::Stepped,
    q: &StepQueue,
    from: usize,
    count: usize,
    ceiling: f32,
) -> [Vec3; 4] {
    shade_queue(
        (shader, data),
        phosphor_lighting::f32x4::ZERO,
        q,
        (from, count),
        ceiling,
    )
}

/// The queue's pixels as one AVX2 task of eight lanes.
#[cfg(target_arch = "x86_64")]
struct Stepped8<'a, S: Shader> {
    shader: &'a S,
    data: &'a S::Stepped,
    queue: &'a StepQueue,
    count: usize,
    ceiling: f32,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for Stepped8<'_, S> {
    type Output = [Vec3; 8];
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> [Vec3; 8] {
        shade_queue(
            (self.shader, self.data),
            s.splat(0.0),
            self.queue,
            (0, self.count),
            self.ceiling,
        )
    }
}
