//! Stage 3, BANDS: the image is split into horizontal bands of [`crate::bin::BAND_ROWS`]
//! pixel rows (of samples, when multisampled), drawn in parallel. Each band clears its rows,
//! then sets up and draws the triangles the bin stage recorded for it, chunk after chunk in
//! submission order, so the picture is bit-identical for any thread count (bands depend on the
//! image, not on the threads). Bands are sized by work: a 1080-row image has 68 of them, many
//! more than cores.
//!
//! The rasterizer picks the passes from what the shader declares ([`Shader::FACE`],
//! [`Shader::SHADE_ONCE`]): one pass ([`draw_single`]) for constant colours and for pixel
//! stages cheaper than a depth pass; otherwise the two passes of [`crate::two_pass`]: a depth
//! pass that leaves the nearest triangle's id per pixel, then the interpolated triangles
//! shaded from the ids and the stepped ones (and, with the incremental scan line, every one)
//! traversed again over the pixels they own.

use glam::Vec3;
use rayon::prelude::*;

use crate::antialias::{ResolveRule, SampleRows};
use crate::coverage::BandTarget;
use crate::coverage::lanes;
use crate::encode::{Encoder, Encoding};
use crate::framebuffer::layer::LayerRows;
use crate::framebuffer::readout::{background_word, word_row, written_row};
use crate::framebuffer::{Framebuffer, Shown, clear_rows, same_color};
use crate::group::{Basis, Group, Kind, LANES, Marks, Portable, RowLanes};
use crate::parallel::{effective_threads, pool};
use crate::records::{AHEAD, BandInput};
use crate::setup::RasterTri;
use crate::shader::{Face, Shader, interpolated};
use crate::traverse::{OnePixel, Solid};
use crate::two_pass::draw_two_pass;
use crate::viewport::{BAND_ROWS, band_rows};

/// Draws `input` into `fb` over bands on `threads`. With `block > 1` the image holds samples,
/// `block x block` per pixel, and the by-pixel pass shades each triangle once per pixel
/// ([`crate::bypixel::ByPixel::block`]); `count` is the coverage-count test hook (no depth test, every band
/// one pass). Returns the pixels (or, multisampled, the pixel and triangle pairs) shaded.
///
/// With `outputs.resolve`, the image `fb`'s samples resolve into (`fb` `k` times as wide
/// and as tall), each band resolves its rows into it right after drawing them, while they
/// are in cache: the columns the frame drew in them so far ([`ResolveRule`]), as
/// [`crate::antialias`]'s resolve would at the frame's end. With `outputs.words`, each band
/// then reads its finished rows out into the window's words, as
/// [`Framebuffer::write_0rgb_over`] would after the draw. Neither for the coverage hook or a
/// depth-only draw.
pub(crate) fn draw_bands<S: Shader>(
    fb: &mut Framebuffer,
    input: &BandInput<S>,
    (threads, count, block): (usize, bool, u32),
    outputs: Outputs<'_>,
) -> u64 {
    let band_rows = band_rows(block);
    let width = fb.width();
    let chunk = (band_rows * width) as usize;
    let clear = fb.pending_clear.take();
    // Outside its dirty columns a row already holds the last clear's colour and depth.
    let only_dirty = clear.is_some_and(|bg| same_color(fb.clean, bg));
    if clear.is_some() {
        fb.clean = clear;
    }
    // A multisampled image keeps whole pixels' colours in its pixel layer.
    let layered = block > 1 && !count && !input.depth_only && !layerless();
    fb.set_layer(if layered { block } else { 1 });
    let one_pass = one_pass::<S>();
    let drawn_image = !count && !input.depth_only;
    let mut out = outputs.resolve.filter(|_| drawn_image);
    let k = out.as_ref().map_or(1, |o| fb.width() / o.width().max(1));
    let rule = out.as_ref().map(|o| ResolveRule::new(fb, o, k));
    // The finished image's size and rows per band: the output's, or `fb`'s own.
    let (image_width, image_height) = out
        .as_ref()
        .map_or((width, fb.height()), |o| (o.width(), o.height()));
    let image_rows = band_rows as usize / k as usize;
    let readout = outputs
        .words
        .filter(|(w, _)| drawn_image && w.len() == image_width as usize * image_height as usize);
    // The clear colour is final once this draw's clear is taken: the readout's background.
    let background = background_word(fb.clean);
    let before = readout.as_ref().and_then(|(w, held)| {
        let size = (image_width, image_height);
        Shown::new(size, w.len(), background).kept(*held)
    });
    let mut words = readout.map(|(w, _)| w.chunks_mut(image_rows * image_width as usize));
    let mut outs = out.as_deref_mut().map(|o| {
        let rows = band_rows as usize / k as usize * o.width() as usize;
        o.color
            .chunks_mut(rows)
            .zip(o.depth.chunks_mut(rows))
            .zip(o.dirty.chunks_mut(band_rows as usize / k as usize))
    });
    let (color, depth, dirty) = (&mut fb.color, &mut fb.depth, &mut fb.dirty);
    let mut layers = fb.layer.as_mut().map(|l| l.bands(BAND_ROWS as usize));
    let bands: Vec<Rows> = color
        .chunks_mut(chunk)
        .zip(depth.chunks_mut(chunk))
        .zip(dirty.chunks_mut(band_rows as usize))
        .map(|((color, depth), dirty)| Rows {
            color,
            depth,
            dirty,
            layer: layers.as_mut().and_then(Iterator::next),
            out: outs.as_mut().and_then(Iterator::next),
            words: words.as_mut().and_then(Iterator::next),
        })
        .collect();
    let run = |(b, rows): (usize, Rows)| -> u64 {
        let Rows {
            color,
            depth,
            dirty,
            mut layer,
            out,
            words,
        } = rows;
        if let Some(bg) = clear {
            // The frame's clear, deferred to here: each band clears its rows in parallel,
            // just before drawing them (they stay in cache). A depth-only draw never wrote
            // the colour, so it keeps its last clear; a layered image's samples hold no
            // colour until their pixel is split.
            let shown: &mut [Vec3] = if input.depth_only || layer.is_some() {
                &mut []
            } else {
                &mut *color
            };
            if let Some(layer) = &mut layer {
                layer.clear(bg, only_dirty.then_some(&*dirty));
            }
            clear_rows((shown, &mut *depth, &mut *dirty), width, bg, only_dirty);
        }
        let y0 = b as i64 * band_rows as i64;
        let in_band: usize = input.records(b).map(|(_, r)| r.len()).sum();
        let mut shaded = 0;
        if in_band > 0 {
            // A band of one record is not worth a depth pass, except multisampled: one pass
            // would shade each of its samples, not each pixel once, and split every pixel.
            let single = one_pass || count || (in_band < 2 && block == 1);
            if single {
                if let Some(layer) = &mut layer {
                    layer.split_all(color);
                }
            }
            let mut target =
                BandTarget::new(&mut *color, &mut *depth, width, y0, count).with_dirty(&mut *dirty);
            shaded = if single {
                draw_single(input, b, &mut target)
            } else {
                let rows = layer.as_mut().map(LayerRows::reborrow);
                draw_two_pass(input, b, target, block, rows)
            };
        }
        // The band's finished rows: resolved into the output, or its own.
        let finished: (&[Vec3], &[(u32, u32)]) = match (&rule, out) {
            (Some(rule), Some(((out_color, out_depth), out_dirty))) => {
                let rows = ((&mut *out_color, &mut *out_depth), &mut *out_dirty);
                resolve_band(rule, (&*color, &*depth, &*dirty), layer.as_ref(), rows);
                (&*out_color, &*out_dirty)
            }
            _ => (&*color, &*dirty),
        };
        if let Some(words) = words {
            let first = b * image_rows;
            let before = before.and_then(|r| r.get(first..));
            read_out_band(words, finished, image_width, background, before);
        }
        shaded
    };
    let threads = effective_threads(threads);
    let shaded = match (threads > 1).then(|| pool(threads)).flatten() {
        Some(p) => p.install(|| bands.into_par_iter().enumerate().map(run).sum()),
        None => bands.into_iter().enumerate().map(run).sum(),
    };
    if let (Some(rule), Some(out)) = (rule, out) {
        rule.finish(out);
    }
    shaded
}

#[cfg(test)]
thread_local! {
    /// Test hook: multisampled draws on this thread write every sample, with no pixel layer
    /// (the reference the layer is tested against).
    pub(crate) static LAYERLESS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the `LAYERLESS` test hook is set on this thread (never outside tests).
fn layerless() -> bool {
    #[cfg(test)]
    return LAYERLESS.get();
    #[cfg(not(test))]
    false
}

/// One band's rows: sample (or pixel) colours and depths, the dirty columns per row, and the
/// pixel layer's rows of a multisampled image.
struct Rows<'a> {
    color: &'a mut [Vec3],
    depth: &'a mut [f32],
    dirty: &'a mut [(u32, u32)],
    layer: Option<LayerRows<'a>>,
    /// The rows of the image the band resolves into, with their dirty columns.
    out: Option<OutRows<'a>>,
    /// The window's words of the band's rows of the finished image.
    words: Option<&'a mut [u32]>,
}

/// What a draw's bands write besides their own rows once the frame's last draws are
/// announced ([`crate::Frame::resolve_as_drawn`]).
#[derive(Default)]
pub(crate) struct Outputs<'a> {
    /// The output image the draw's samples resolve into.
    pub resolve: Option<&'a mut Framebuffer>,
    /// A window's words for the finished image (`resolve`, or the drawn image itself
    /// without samples), a word per pixel, with what the buffer holds ([`Shown`]).
    pub words: Option<(&'a mut [u32], Option<&'a Shown>)>,
}

/// Reads a band's finished rows (`color`, `width` long, with their dirty columns) out into
/// its rows of a window's `words` through [`word_row`], as
/// [`Framebuffer::write_0rgb_over`] reads those rows: `background` is the clear colour's
/// word, and `before` the band's rows of the columns the buffer holds outside it.
fn read_out_band(
    words: &mut [u32],
    (color, dirty): (&[Vec3], &[(u32, u32)]),
    width: u32,
    background: Option<u32>,
    before: Option<&[(u32, u32)]>,
) {
    let enc = Encoder::new(Encoding::Srgb);
    let rows = words
        .chunks_mut(width as usize)
        .zip(color.chunks(width as usize));
    for (y, (dst, src)) in rows.enumerate() {
        let written = written_row(background, dirty.get(y).copied(), width);
        let before = before.and_then(|b| b.get(y)).copied();
        word_row(enc, (src, dst), (written, background), before);
    }
}

/// A band's rows of the output image: colours, depths, and dirty columns per row.
type OutRows<'a> = ((&'a mut [Vec3], &'a mut [f32]), &'a mut [(u32, u32)]);

/// Resolves a band's sample rows (`color`, `depth`, with their dirty columns and pixel
/// layer) into its output rows `out` by `rule`, and records each output row's drawn columns.
fn resolve_band(
    rule: &ResolveRule,
    (color, depth, dirty): (&[Vec3], &[f32], &[(u32, u32)]),
    layer: Option<&LayerRows>,
    ((out_color, out_depth), out_dirty): OutRows,
) {
    let (k, width) = (rule.k, rule.width);
    let layer = layer
        .filter(|l| l.k == k)
        .map(|l| (&l.color[..], &l.split[..]));
    let samples = SampleRows::band(k, width, (color, depth), layer);
    let rows = out_color
        .chunks_mut(width)
        .zip(out_depth.chunks_mut(width))
        .zip(out_dirty.iter_mut());
    for (y, ((c, d), out_dirty)) in rows.enumerate() {
        let drawn = rule.drawn(dirty.get(y * k..(y + 1) * k).unwrap_or(&[]));
        let stale = rule.stale(*out_dirty);
        rule.row((drawn, stale), samples.row(y), (c, d));
        *out_dirty = drawn;
    }
}

/// Whether `S` draws every band in one pass: a constant colour, or a pixel stage cheap
/// enough to run for every pixel drawn.
const fn one_pass<S: Shader>() -> bool {
    match S::FACE {
        Face::Constant => true,
        Face::Interpolated => !S::SHADE_ONCE,
        Face::Stepped => false,
    }
}

/// Band `b` in one pass: each triangle depth-tested, shaded and written in turn. Widens the
/// target's dirty columns by every span drawn. Returns the pixels shaded.
fn draw_single<S: Shader>(input: &BandInput<S>, b: usize, target: &mut BandTarget) -> u64 {
    // Two-pass shaders come here only for bands of one record without multisampling: not
    // worth a second copy.
    #[cfg(target_arch = "x86_64")]
    if let (true, Some(avx2)) = (one_pass::<S>(), input.wide.avx2) {
        return avx2.run(SingleRun { input, b, target });
    }
    single_loop::<S, false, _>(input, b, target, Portable)
}

/// [`draw_single`]'s loop over the records; `INLINE`: with the traversal inlined
/// ([`BandInput::draw`]).
#[inline(always)]
fn single_loop<S: Shader, const INLINE: bool, R: RowLanes>(
    input: &BandInput<S>,
    b: usize,
    target: &mut BandTarget,
    lanes: R,
) -> u64 {
    if grouped(input, target) {
        return group_loop::<S, INLINE, R>(input, b, target, lanes);
    }
    let n = if S::FACE == Face::Constant {
        0
    } else {
        S::VARYINGS
    };
    let mut t = RasterTri::empty();
    let mut batched = input.batched();
    let (mut shaded, mut sink) = (0, 0);
    for (c, recs) in input.records(b) {
        for (i, r) in recs.iter().enumerate() {
            sink ^= input.touch(recs.get(i + AHEAD), n);
            if input.setup(&mut t, c, r, n) {
                shaded += input.draw::<INLINE>(&t, (c, r), target, &mut batched);
            }
        }
    }
    std::hint::black_box(sink);
    shaded
}

/// Whether [`single_loop`] draws `input`'s records through [`group_loop`] (not the
/// coverage-count hook): a constant colour (or depth alone), or a pixel stage run per pixel
/// as it passes (`gouraud`'s) on up to four attributes, whose planes the lanes' basis gives
/// for the cost of their arithmetic ([`Group::planes`]). Not the incremental scan line,
/// which steps its own edges, nor a shader that reads gradients.
#[inline(always)]
fn grouped<S: Shader>(input: &BandInput<S>, target: &BandTarget) -> bool {
    !target.count
        && match S::FACE {
            Face::Constant => true,
            Face::Interpolated => {
                !S::SHADE_ONCE
                    && !input.incremental
                    && S::GRADIENTS.is_none()
                    && lanes(interpolated::<S>()) <= 4
            }
            Face::Stepped => false,
        }
}

/// [`single_loop`] for the shaders [`grouped`] names: eight records set up at a time, the
/// small ones drawn from their lanes ([`Group`]), the others one by one, in order.
#[inline(always)]
fn group_loop<S: Shader, const INLINE: bool, R: RowLanes>(
    input: &BandInput<S>,
    b: usize,
    target: &mut BandTarget,
    lanes: R,
) -> u64 {
    let n = if S::FACE == Face::Constant {
        0
    } else {
        S::VARYINGS
    };
    let mut t = RasterTri::empty();
    let mut batched = input.batched();
    let mut shaded = 0;
    let (width, y0) = (target.width as usize, target.y0);
    let mut basis = Basis::new();
    for (c, recs) in input.records(b) {
        for group in recs.chunks(LANES) {
            let band = (y0, target.y1);
            let g = if S::FACE == Face::Constant {
                Group::set(group, input.pos, target.width, band)
            } else {
                Group::set_planes(group, input.pos, target.width, band, &mut basis)
            };
            let mut marks = Marks::NONE;
            for (k, r) in group.iter().enumerate() {
                match g.kind[k] {
                    Kind::Small => {
                        let (color, depth) = (&mut *target.color, &mut *target.depth);
                        let band = (depth, width, y0);
                        if S::FACE == Face::Constant {
                            let fill = (!input.depth_only).then(|| {
                                let rgb = c.colors.get(r.tri as usize).copied();
                                let Solid(rgb) =
                                    Solid::of(rgb.unwrap_or(Vec3::ZERO), input.ceiling);
                                (color, rgb)
                            });
                            shaded += u64::from(g.draw(lanes, k, band, fill, |_, _, _| {}));
                        } else {
                            let (inv_w, a) = input.plane_values::<4>(r);
                            let planes = g.planes((&basis, k), inv_w, a);
                            let mut shade = OnePixel(input.shader, input.ceiling);
                            let drawn = g.draw_shaded(lanes, k, band, (&planes, &mut shade), color);
                            shaded += u64::from(drawn);
                        }
                        // Its spans are marked whether or not they passed the depth test.
                        marks.add(g.bounds(k));
                    }
                    Kind::Empty => {}
                    Kind::Other => {
                        if input.setup(&mut t, c, r, n) {
                            shaded += input.draw::<INLINE>(&t, (c, r), target, &mut batched);
                        }
                    }
                }
            }
            marks.apply(target.dirty, y0);
        }
    }
    shaded
}

/// [`draw_single`] as one AVX2 function (flat faces, fill-only, shadow casters, Gouraud):
/// set-up, coverage, depth and the pixel stage compiled with the wider instruction set.
#[cfg(target_arch = "x86_64")]
struct SingleRun<'p, 'a, 't, S: Shader> {
    input: &'p BandInput<'a, S>,
    b: usize,
    target: &'p mut BandTarget<'t>,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for SingleRun<'_, '_, '_, S> {
    type Output = u64;
    #[inline(always)]
    fn run(self, avx2: phosphor_lighting::Avx2) -> u64 {
        single_loop::<S, true, _>(
            self.input,
            self.b,
            self.target,
            crate::group::Avx2Rows::new(avx2.v3()),
        )
    }
}
