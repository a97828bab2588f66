//! A band in two passes, for shaders whose pixel stage costs more than a depth test: a depth
//! pass ([`depth_pass`]) that leaves the nearest triangle's id per pixel, then the
//! interpolated triangles shaded from the ids ([`by_pixel_pass`]) and the stepped ones (and,
//! with the incremental scan line, every one) traversed again over the pixels they own
//! ([`visible_pass`]). [`crate::bands`] picks this or its one pass per shader.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::batch::{AttrLanes, shade4};
use crate::bin::{Binned, TriRec};
use crate::bypixel::ByPixel;
use crate::clip::Attrs;
use crate::coverage::{BandTarget, Pass, depth_only, lanes};
use crate::framebuffer::layer::LayerRows;
use crate::group::{Basis, Group, Kind, LANES, Marks, Portable, RowLanes};
use crate::multisample::mark_blocks;
use crate::records::{AHEAD, BandInput};
use crate::setup::RasterTri;
use crate::shader::{Face, Shader, interpolated};
use crate::traverse::{Planes, SpanShade};

/// A thread's buffers for two-pass bands, reused from band to band.
struct Scratch {
    /// The nearest triangle's id per band pixel.
    ids: Vec<u64>,
    /// Per record of the band: whether it is the nearest anywhere after the depth pass (only
    /// such records are visible).
    owns: Vec<bool>,
    /// Per row of the band: the columns the depth pass wrote.
    extents: Vec<(u32, u32)>,
    /// Per record: its index in `planes` (by-pixel shading).
    slot: Vec<u32>,
    /// Attribute planes of the records that were nearest somewhere.
    planes: Vec<Planes>,
    /// Per group of [`LANES`] records of each chunk, the basis the depth pass set its small
    /// ones up with, when the by-pixel pass takes their planes from it ([`keeps_basis`]).
    /// Reused from band to band: only the first `kept` are this band's.
    bases: Vec<Basis>,
    /// How many of `bases` the depth pass set for this band.
    kept: usize,
    /// For a band of `2 x 2` blocks, the id each block's samples share
    /// ([`crate::multisample::mark_blocks`]); reused from band to band.
    whole: Vec<u64>,
    /// Whether `whole` is this band's.
    blocks: bool,
}

/// Ids of the depth pass: a fresh epoch per band job in the high bits, so ids left in a
/// thread's scratch by earlier jobs never match.
static EPOCH: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// Per-thread scratch of two-pass bands.
    static SCRATCH: RefCell<Scratch> = const {
        RefCell::new(Scratch {
            ids: Vec::new(),
            owns: Vec::new(),
            extents: Vec::new(),
            slot: Vec::new(),
            planes: Vec::new(),
            bases: Vec::new(),
            kept: 0,
            whole: Vec::new(),
            blocks: false,
        })
    };
}

/// Band `b` in two passes: the depth pass, then the by-pixel pass and/or the visible pass
/// over the triangles that own a pixel, with this thread's scratch. Widens the target's dirty
/// columns by what the depth pass wrote (its spans are not marked one by one). Returns the
/// pixels shaded.
pub(crate) fn draw_two_pass<S: Shader>(
    input: &BandInput<S>,
    b: usize,
    target: BandTarget,
    block: u32,
    layer: Option<LayerRows>,
) -> u64 {
    SCRATCH.with(|scratch| {
        let scratch = &mut *scratch.borrow_mut();
        two_pass(input, b, target, scratch, (block, layer))
    })
}

/// [`draw_two_pass`] with `scratch`.
fn two_pass<'s, S: Shader>(
    input: &BandInput<S>,
    b: usize,
    mut target: BandTarget<'s>,
    scratch: &'s mut Scratch,
    (block, mut layer): (u32, Option<LayerRows>),
) -> u64 {
    // The depth pass records the columns it writes; the shading passes write only there.
    let dirty = std::mem::take(&mut target.dirty);
    let width = target.width as usize;
    if scratch.ids.len() < target.color.len() {
        scratch.ids.resize(target.color.len(), 0);
    }
    scratch.extents.clear();
    let rows = target.color.len() / width.max(1);
    scratch.extents.resize(rows, (u32::MAX, 0));
    let epoch = EPOCH.fetch_add(1, Ordering::Relaxed) << 32;
    let (ids, extents) = (&mut scratch.ids, &mut scratch.extents);
    let bases = &mut scratch.bases;
    let (records, groups) = depth_pass(input, b, &mut target, (ids, extents, bases), epoch);
    scratch.kept = groups;
    let (rows, avx2) = ((&extents[..], width), input.wide.avx2);
    // A band of 2 x 2 blocks also notes which blocks one triangle covers, for its walk.
    scratch.blocks = block == 2 && extents.len() % 2 == 0;
    if scratch.blocks {
        let owns = &mut scratch.owns;
        owns.clear();
        owns.resize(records, false);
        mark_blocks(ids, rows, epoch, owns, (&mut scratch.whole, avx2));
    } else {
        mark_owners(ids, rows, epoch, records, &mut scratch.owns, avx2);
    }
    // Only the depth pass writes outside the pixels it recorded (the shading passes write
    // where it did).
    for (d, e) in dirty.iter_mut().zip(scratch.extents.iter()) {
        *d = (d.0.min(e.0), d.1.max(e.1));
    }
    let (mut shaded, mut traced) = (0, true);
    if !input.incremental || S::FACE == Face::Stepped {
        let out = (&mut target, layer.as_mut());
        (shaded, traced) = by_pixel_pass(input, b, out, scratch, epoch, block);
    }
    if traced {
        // The visible pass writes samples one by one.
        if let Some(layer) = &mut layer {
            layer.split_all(target.color);
        }
        let scratch: &'s Scratch = scratch;
        target.ids = &scratch.ids;
        shaded += visible_pass(input, b, &mut target, &scratch.owns, epoch);
    }
    shaded
}

/// Whether the depth pass keeps its groups' bases ([`Basis`]) for the by-pixel pass: when
/// the planes have at most eight attributes, so that [`Basis::planes`] gives them for the
/// cost of the attributes' arithmetic, as [`Planes::set`] would. Decided per shader, not per
/// draw, so that the depth pass is one loop.
const fn keeps_basis<S: Shader>() -> bool {
    S::VARYINGS <= 8
}

/// Whether record `r` is shaded from the id buffer (interpolated, and not walked by the
/// incremental scan line).
#[inline(always)]
fn by_pixel<S: Shader>(input: &BandInput<S>, c: &Binned<S::Stepped>, r: &TriRec) -> bool {
    let walked = input.incremental && S::FACE == Face::Interpolated;
    !(walked || BandInput::<S>::is_stepped(c, r))
}

/// The by-pixel pass of band `b`, after the depth pass left its ids in `scratch`: the planes
/// of the visible records ([`visible_planes`]), then every pixel whose id names one of them
/// gets [`Shader::pixel`] of its varyings, eight pixels per call with AVX2 (else four), with
/// no second traversal. Returns the pixels (or pixel and triangle pairs) shaded, and whether
/// some visible record is left for [`visible_pass`].
fn by_pixel_pass<S: Shader>(
    input: &BandInput<S>,
    b: usize,
    (target, layer): (&mut BandTarget, Option<&mut LayerRows>),
    scratch: &mut Scratch,
    epoch: u64,
    block: u32,
) -> (u64, bool) {
    let Scratch {
        ids,
        owns,
        extents,
        slot,
        planes,
        bases,
        kept,
        whole,
        blocks,
    } = scratch;
    let bases = bases.get(..*kept).unwrap_or(&[]);
    #[cfg(target_arch = "x86_64")]
    let traced = match input.wide.avx2 {
        Some(avx2) => avx2.run(PlanesRun {
            input,
            b,
            owns: (owns, bases),
            slot,
            planes,
        }),
        None => visible_planes(input, b, (owns, bases), slot, planes),
    };
    #[cfg(not(target_arch = "x86_64"))]
    let traced = visible_planes(input, b, (owns, bases), slot, planes);
    let pass = ByPixel {
        slot,
        planes,
        ids,
        epoch,
        extents,
        width: target.width,
        y0: target.y0,
        n: interpolated::<S>(),
        perspective: input.perspective && S::VARYINGS > 0,
        block: block as usize,
        ceiling: input.ceiling,
        whole: if *blocks { whole } else { &[] },
    };
    let shader = input.shader;
    // More than eight attributes: a loop compiled for this shader (`ByPixel::shade_wide`).
    let wide_attrs = lanes(interpolated::<S>()) > 8;
    let shaded = if let Some(avx2) = input.wide.avx2 {
        let wide = input.wide;
        let rows = |a: &[Attrs; 8], count, ceiling| wide.shade8(shader, a, count, ceiling);
        let lanes = |a: &AttrLanes, count, ceiling| wide.shade8(shader, a, count, ceiling);
        if wide_attrs {
            #[cfg(target_arch = "x86_64")]
            {
                pass.shade_wide_avx2(avx2, shader, target.color, layer)
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                let _ = avx2;
                pass.shade_wide::<8, _, _>(target.color, layer, (&rows, &lanes))
            }
        } else {
            #[cfg(target_arch = "x86_64")]
            {
                pass.shade_avx2(avx2, target.color, layer, (&rows, &lanes))
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                pass.shade::<8>(target.color, layer, (&rows, &lanes))
            }
        }
    } else {
        let rows = |a: &[Attrs; 4], count, ceiling| shade4(shader, a, count, ceiling);
        let lanes = |a: &AttrLanes, count, ceiling| shade4(shader, a, count, ceiling);
        if wide_attrs {
            pass.shade_wide::<4, _, _>(target.color, layer, (&rows, &lanes))
        } else {
            pass.shade::<4>(target.color, layer, (&rows, &lanes))
        }
    };
    (shaded, traced)
}

/// The depth pass of band `b`: every triangle set up without attributes (the same edges and
/// depth plane), depth-tested and written, and `ids[pixel]` set to `epoch + k` where record
/// `k` of the band is now the nearest; `extents[row]` is widened to the columns written.
/// When the shader [`keeps_basis`], group `i`'s [`Basis`] is set in `bases[i]`. Returns the
/// band's record count and the bases set.
fn depth_pass<S: Shader>(
    input: &BandInput<S>,
    b: usize,
    target: &mut BandTarget,
    (ids, extents, bases): (&mut [u64], &mut [(u32, u32)], &mut Vec<Basis>),
    epoch: u64,
) -> (usize, usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = input.wide.avx2 {
        return avx2.run(DepthRun {
            input,
            b,
            target,
            ids,
            extents,
            bases,
            epoch,
        });
    }
    depth_loop(input, b, target, (ids, extents, bases), epoch, Portable)
}

/// [`depth_pass`] as one AVX2 function.
#[cfg(target_arch = "x86_64")]
struct DepthRun<'p, 'a, 't, S: Shader> {
    input: &'p BandInput<'a, S>,
    b: usize,
    target: &'p mut BandTarget<'t>,
    ids: &'p mut [u64],
    extents: &'p mut [(u32, u32)],
    bases: &'p mut Vec<Basis>,
    epoch: u64,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for DepthRun<'_, '_, '_, S> {
    type Output = (usize, usize);
    #[inline(always)]
    fn run(self, avx2: phosphor_lighting::Avx2) -> (usize, usize) {
        let Self {
            input,
            b,
            target,
            ids,
            extents,
            bases,
            epoch,
        } = self;
        depth_loop(
            input,
            b,
            target,
            (ids, extents, bases),
            epoch,
            crate::group::Avx2Rows::new(avx2.v3()),
        )
    }
}

/// [`depth_pass`]'s loop over the records.
#[inline(always)]
fn depth_loop<S: Shader, R: RowLanes>(
    input: &BandInput<S>,
    b: usize,
    target: &mut BandTarget,
    (ids, extents, bases): (&mut [u64], &mut [(u32, u32)], &mut Vec<Basis>),
    epoch: u64,
    lanes: R,
) -> (usize, usize) {
    let mut t = RasterTri::empty();
    let (mut seq, mut groups) = (epoch, 0);
    let mut basis = Basis::new();
    let (width, y0) = (target.width as usize, target.y0);
    for (c, recs) in input.records(b) {
        // Eight records set up at a time; the small ones drawn from their lanes, the others
        // one by one, in order.
        for group in recs.chunks(LANES) {
            let band = (y0, target.y1);
            // Set on the stack, as the one pass sets it, and kept once the group is drawn.
            let g = if keeps_basis::<S>() {
                Group::set_planes(group, input.pos, target.width, band, &mut basis)
            } else {
                Group::set(group, input.pos, target.width, band)
            };
            let mut marks = Marks::NONE;
            for (k, r) in group.iter().enumerate() {
                match g.kind[k] {
                    Kind::Small => {
                        let band = (&mut *target.depth, width, y0);
                        let passed = g.draw(lanes, k, band, Some((&mut *ids, seq)), |_, _, _| {});
                        if passed > 0 {
                            marks.add(g.bounds(k));
                        }
                    }
                    Kind::Empty => {}
                    Kind::Other => {
                        if input.setup_apart(&mut t, c, r, 0) {
                            depth_only(&t, target, ids, extents, seq);
                        }
                    }
                }
                seq += 1;
            }
            marks.apply(extents, y0);
            if keeps_basis::<S>() {
                basis.keep(&g);
                match bases.get_mut(groups) {
                    Some(kept) => *kept = basis,
                    None => bases.push(basis),
                }
                groups += 1;
            }
        }
    }
    ((seq - epoch) as usize, groups)
}

/// `owns[k]`: whether record `k` of `records` owns a pixel after the depth pass, from the ids
/// it left inside `extents` (rows `width` pixels wide). Only those records are visible: a
/// triangle nearest somewhere when drawn is often covered later by a nearer one (about half
/// of them in S1).
///
/// A triangle's pixels lie side by side along a row, so only an id that differs from the one
/// before it in memory is marked. That one may lie outside every extent (the end of the row
/// above, or a column the band did not write): then it was left by an earlier band, below
/// the epoch, and differs from every id of this band. So each owner is marked at its first
/// pixel at least, and four ids are compared at a time where the CPU has AVX2.
fn mark_owners(
    ids: &[u64],
    (extents, width): (&[(u32, u32)], usize),
    epoch: u64,
    records: usize,
    owns: &mut Vec<bool>,
    avx2: Option<crate::simd::Avx2>,
) {
    owns.clear();
    owns.resize(records, false);
    // A slice, not the vector: its pointer and length stay in registers across the stores.
    let owns = owns.as_mut_slice();
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = avx2 {
        return avx2.run(MarkRun {
            ids,
            extents,
            width,
            epoch,
            owns,
        });
    }
    let _ = avx2;
    mark_rows((ids, extents, width), owns, |ids, i, owns| {
        for i in i {
            if ids.get(i) != i.checked_sub(1).and_then(|j| ids.get(j)) {
                mark(owns, ids[i], epoch);
            }
        }
    });
}

/// Runs `span` over the band pixels `[lo, hi)` of each row of `extents`.
#[inline(always)]
fn mark_rows<F>(
    (ids, extents, width): (&[u64], &[(u32, u32)], usize),
    owns: &mut [bool],
    mut span: F,
) where
    F: FnMut(&[u64], std::ops::Range<usize>, &mut [bool]),
{
    for (row, &(lo, hi)) in extents.iter().enumerate() {
        let (lo, hi) = (
            row * width + lo as usize,
            row * width + (hi as usize).min(width),
        );
        if lo < hi && hi <= ids.len() {
            span(&ids[..hi], lo..hi, owns);
        }
    }
}

/// Marks the record whose id is `id`, if it is one of this band's (ids below the epoch were
/// left by earlier bands).
#[inline(always)]
pub(crate) fn mark(owns: &mut [bool], id: u64, epoch: u64) {
    if let Some(o) = id.checked_sub(epoch).and_then(|k| owns.get_mut(k as usize)) {
        *o = true;
    }
}

/// [`mark_owners`]' loop as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct MarkRun<'a> {
    ids: &'a [u64],
    extents: &'a [(u32, u32)],
    width: usize,
    epoch: u64,
    owns: &'a mut [bool],
}

#[cfg(target_arch = "x86_64")]
impl phosphor_lighting::Avx2Task for MarkRun<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self, avx2: phosphor_lighting::Avx2) {
        let (v, epoch) = (avx2.v3(), self.epoch);
        let rows = (self.ids, self.extents, self.width);
        mark_rows(rows, self.owns, |ids, span, owns| {
            let mut i = span.start;
            if i == 0 {
                mark(owns, ids[0], epoch);
                i = 1;
            }
            // Ids `i - 1 .. i + 4`: four compared with the four before them.
            while let Some(w) = ids.get(i - 1..i + 4) {
                let prev: [u64; 4] = std::array::from_fn(|j| w[j]);
                let cur: [u64; 4] = std::array::from_fn(|j| w[j + 1]);
                let same = v.avx2._mm256_cmpeq_epi64(pulp::cast(cur), pulp::cast(prev));
                let mut changed = !(v.avx._mm256_movemask_pd(pulp::cast(same)) as u32) & 0xf;
                while changed != 0 {
                    mark(owns, cur[changed.trailing_zeros() as usize], epoch);
                    changed &= changed - 1;
                }
                i += 4;
            }
            for i in i..span.end {
                if ids[i] != ids[i - 1] {
                    mark(owns, ids[i], epoch);
                }
            }
        });
    }
}

/// The attribute planes of band `b`'s records that own a pixel and are shaded by pixel:
/// `slot[k]` is record `k`'s index in `planes`, or `u32::MAX`. A small record whose group's
/// basis the depth pass kept in `bases` gets its planes from it ([`Basis::planes`]), the
/// others from [`Planes::set`]: the same bits. Returns whether some owner is not shaded by
/// pixel (and needs [`visible_pass`]).
#[inline(always)]
fn visible_planes<S: Shader>(
    input: &BandInput<S>,
    b: usize,
    (owns, bases): (&[bool], &[Basis]),
    slot: &mut Vec<u32>,
    planes: &mut Vec<Planes>,
) -> bool {
    let n = S::VARYINGS;
    slot.clear();
    planes.clear();
    let (mut k, mut traced, mut sink, mut groups) = (0, false, 0, 0);
    for (c, recs) in input.records(b) {
        let at = groups;
        groups += recs.len().div_ceil(LANES);
        for (i, r) in recs.iter().enumerate() {
            if owns.get(k + AHEAD) == Some(&true) {
                sink ^= input.touch(recs.get(i + AHEAD), n);
            }
            let owner = owns.get(k) == Some(&true);
            let by_pixel = owner && by_pixel(input, c, r);
            traced |= owner && !by_pixel;
            // Its pixels are known: the planes alone, from the kept basis when it is small.
            let set = if by_pixel {
                let lane = i % LANES;
                match bases.get(at + i / LANES).filter(|b| b.small(lane)) {
                    Some(basis) => Some(kept_planes(input, (basis, lane), r)),
                    None => input
                        .vertices_of(r, c, n)
                        .and_then(|(p, a)| Planes::set(p, a, n, input.perspective)),
                }
            } else {
                None
            };
            slot.push(if set.is_some() {
                planes.len() as u32
            } else {
                u32::MAX
            });
            if let Some(mut p) = set {
                if let Some(k) = S::GRADIENTS {
                    p.add_gradients(n, input.perspective, k);
                }
                planes.push(p);
            }
            k += 1;
        }
    }
    std::hint::black_box(sink);
    traced
}

/// The planes of small record `r`, lane `k` of a group whose basis the depth pass kept, over
/// the lanes [`Planes::set`] computes for the shader's varyings (none, four or eight), so that
/// every lane has its bits.
#[inline(always)]
fn kept_planes<S: Shader>(input: &BandInput<S>, kept: (&Basis, usize), r: &TriRec) -> Planes {
    let (basis, k) = kept;
    match S::VARYINGS {
        0 => {
            let (inv_w, a) = input.plane_values::<0>(r);
            basis.planes(k, inv_w, a)
        }
        1..=4 => {
            let (inv_w, a) = input.plane_values::<4>(r);
            basis.planes(k, inv_w, a)
        }
        _ => {
            let (inv_w, a) = input.plane_values::<8>(r);
            basis.planes(k, inv_w, a)
        }
    }
}

/// [`visible_planes`] as one AVX2 task: the planes' f64 arithmetic four lanes wide.
#[cfg(target_arch = "x86_64")]
struct PlanesRun<'p, 'a, S: Shader> {
    input: &'p BandInput<'a, S>,
    b: usize,
    owns: (&'p [bool], &'p [Basis]),
    slot: &'p mut Vec<u32>,
    planes: &'p mut Vec<Planes>,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for PlanesRun<'_, '_, S> {
    type Output = bool;
    #[inline(always)]
    fn run(self, _: phosphor_lighting::Avx2) -> bool {
        visible_planes(self.input, self.b, self.owns, self.slot, self.planes)
    }
}

/// The visible pass of band `b`: the records that own a pixel and were not shaded by pixel
/// traversed again, each pixel shaded where its id (in `target.ids`) names them. Returns the
/// pixels shaded.
fn visible_pass<S: Shader>(
    input: &BandInput<S>,
    b: usize,
    target: &mut BandTarget,
    owns: &[bool],
    epoch: u64,
) -> u64 {
    let n = S::VARYINGS;
    let mut t = RasterTri::empty();
    let mut batched = input.batched();
    let (mut shaded, mut seq) = (0, epoch);
    for (c, recs) in input.records(b) {
        for r in recs {
            let owner = owns.get((seq - epoch) as usize) == Some(&true);
            if owner && !by_pixel(input, c, r) && input.setup(&mut t, c, r, n) {
                target.pass = Pass::Visible(seq);
                shaded += input.draw::<false>(&t, (c, r), target, &mut batched);
            }
            seq += 1;
        }
    }
    batched.flush(target.color);
    shaded
}
