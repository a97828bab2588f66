//! The pipeline of one frame: vertex stage (model, view, projection), clipping, set-up, then
//! the banded traversal, draw by draw in submission order.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use phosphor_lighting::Effects;

use crate::antialias::{Antialias, resolve};
use crate::bands::{
    BAND_ROWS, Binned, EXTRA_VERTEX, TriRec, band_range, draw_bands, for_each_chunk_pair,
    map_chunks, map_indices,
};
use crate::clip::{ClipVertex, clip_triangle, guard_band, inside_clip_volume};
use crate::framebuffer::{Framebuffer, RasterError};
use crate::setup::{ScreenPos, ScreenVertex, row_range, screen_area2, to_screen};
use crate::shade::fast_phong::FastPhong;
use crate::shade::flat::{FillOnly, Flat};
use crate::shade::gouraud::Gouraud;
use crate::shade::incremental::Incremental;
use crate::shade::phong::Phong;
use crate::shade::reference::Reference;
use crate::shade::{Lit, Mode, VertexIn, effective_material};
use crate::{Camera, DrawItem, Interpolation, RenderOptions, RenderStats, ShadingMode};

/// Renders `draws` seen by `camera` into `fb` (cleared to `opts.background` first).
///
/// With [`RenderOptions::antialias`] on, the frame is drawn into a sample image `k` times
/// larger on each side (kept in `fb` for the next frame) and box-filtered into `fb`; an image
/// whose sample image would exceed the largest side is drawn with one sample per pixel, and
/// [`RenderStats::antialias`] says which was used.
///
/// Every draw is shaded with its own mode and effect set; bad input (indices out of range,
/// non-finite positions, zero-area triangles) is skipped, never a panic.
pub fn render(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    let aa = opts.antialias;
    if aa != Antialias::Off && aa.fits(fb.width(), fb.height()) {
        let k = aa.factor();
        let (width, height) = (fb.width() * k, fb.height() * k);
        let reusable = fb
            .samples
            .take()
            .filter(|s| s.width() == width && s.height() == height);
        // `fits` checked the sides, so only the allocation itself can fail: draw one sample
        // per pixel then, and say so in the stats.
        if let Some(mut samples) =
            reusable.or_else(|| Framebuffer::new(width, height).ok().map(Box::new))
        {
            let block = if aa.multisample() { k } else { 1 };
            let mut stats = render_samples(&mut samples, camera, draws, opts, block);
            resolve(&samples, fb, k, opts.threads);
            fb.samples = Some(samples);
            stats.antialias = aa;
            return stats;
        }
    }
    fb.samples = None;
    render_samples(fb, camera, draws, opts, 1)
}

/// Draws `draws` into `fb` as it is, a sample per pixel (`opts.antialias` is not looked at):
/// with `block > 1`, `fb` is a multisampled sample image whose per-pixel modes shade once per
/// `block x block` samples and triangle.
fn render_samples(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
    block: u32,
) -> RenderStats {
    fb.defer_clear(opts.background);
    let mut stats = RenderStats::default();
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let out = Output::Shade { block };
    for d in draws {
        shade_draw(fb, vp, camera.eye, d, opts, out, &mut stats);
    }
    fb.finish_clear();
    stats
}

/// What [`run`] writes.
#[derive(Debug, Clone, Copy)]
enum Output {
    /// Colours and depths; `block` as in [`draw_bands`] (1: every pixel shaded).
    Shade { block: u32 },
    /// The coverage-count test hook (no depth test): each pixel's red channel counts.
    Count,
}

/// Coverage and depth only, every draw in one constant colour (white): the fill-only speed
/// bound. Modes, lights and effects are ignored.
pub fn render_fill_only(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    fb.defer_clear(opts.background);
    let mut stats = RenderStats::default();
    let vp = camera.view_proj(fb.width() as f32 / fb.height() as f32);
    let mode = FillOnly { color: Vec3::ONE };
    for d in draws {
        run(
            fb,
            vp,
            d,
            &mode,
            opts,
            &mut stats,
            Output::Shade { block: 1 },
        );
    }
    fb.finish_clear();
    stats
}

/// Test hook: how many times each pixel of a `width` x `height` image is covered by `draws`,
/// with no depth test (row-major). With a correct fill rule a closed, non-overlapping
/// triangulation covers every pixel inside its silhouette exactly once per layer.
pub fn coverage_counts(
    width: u32,
    height: u32,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> Result<Vec<u32>, RasterError> {
    let mut fb = Framebuffer::new(width, height)?;
    let vp = camera.view_proj(width as f32 / height as f32);
    let mode = FillOnly { color: Vec3::ONE };
    let mut stats = RenderStats::default();
    for d in draws {
        run(&mut fb, vp, d, &mode, opts, &mut stats, Output::Count);
    }
    Ok(fb.color.iter().map(|c| c.x as u32).collect())
}

fn shade_draw(
    fb: &mut Framebuffer,
    vp: Mat4,
    eye: Vec3,
    d: &DrawItem,
    opts: &RenderOptions,
    out: Output,
    stats: &mut RenderStats,
) {
    let n = d.mesh.positions.len();
    let has_frame =
        d.mesh.uvs.is_some_and(|u| u.len() == n) && d.mesh.tangents.is_some_and(|t| t.len() == n);
    let wants_bump = d.bump.is_some() && d.effects.contains(Effects::BUMP);
    let per_pixel = matches!(
        d.mode,
        ShadingMode::Phong | ShadingMode::FastPhong | ShadingMode::Reference
    );
    let bump = if wants_bump && has_frame && per_pixel {
        d.bump
    } else {
        None
    };
    if wants_bump && bump.is_none() {
        stats.bump_ignored += 1;
    }
    let incremental = opts.interpolation == Interpolation::Incremental;
    let lit = Lit {
        set: d.lights,
        mat: effective_material(d.material, d.effects),
        eye,
    };
    match (d.mode, bump) {
        (ShadingMode::Flat, _) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Flat::<FX> { lit }, opts, stats, out))
        }
        (ShadingMode::Gouraud, _) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Gouraud::<FX> { lit, vertex_clamp: opts.gouraud_vertex_clamp } }, opts, stats, out))
        }
        (ShadingMode::Gouraud, _) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Gouraud::<FX> { lit, vertex_clamp: opts.gouraud_vertex_clamp }, opts, stats, out))
        }
        (ShadingMode::Phong, Some(map)) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Phong::<FX, true> { lit, bump: Some(map) } }, opts, stats, out))
        }
        (ShadingMode::Phong | ShadingMode::FastPhong, Some(map)) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Phong::<FX, true> { lit, bump: Some(map) }, opts, stats, out))
        }
        (ShadingMode::Phong, None) if incremental => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Incremental { inner: Phong::<FX, false> { lit, bump: None } }, opts, stats, out))
        }
        (ShadingMode::Phong, None) => {
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &Phong::<FX, false> { lit, bump: None }, opts, stats, out))
        }
        (ShadingMode::FastPhong, None) => {
            let method = opts.fast_phong;
            crate::with_fx!(d.effects, FX => run(fb, vp, d, &FastPhong::<FX> { lit, method }, opts, stats, out))
        }
        (ShadingMode::Reference, _) => {
            let mut mat = lit.mat;
            if !d.effects.contains(Effects::SPECULAR) {
                mat.ks = Vec3::ZERO;
            }
            if !d.effects.contains(Effects::FRESNEL) {
                mat.fresnel = phosphor_lighting::Fresnel::None;
            }
            let mode = Reference {
                set: d.lights,
                mat,
                eye: eye.as_dvec3(),
                bump,
            };
            run(fb, vp, d, &mode, opts, stats, out);
        }
    }
}

/// The vertex stage: world position, normal (inverse-transpose), uv and tangent per vertex.
fn vertex_stage(d: &DrawItem, vp: Mat4, threads: usize) -> Vec<(Vec4, VertexIn)> {
    let m3 = Mat3::from_mat4(d.model);
    let normal_matrix = {
        let nm = m3.inverse().transpose();
        if nm.is_finite() { nm } else { m3 }
    };
    let flip = if m3.determinant() < 0.0 { -1.0 } else { 1.0 };
    let mesh = &d.mesh;
    map_indices(threads, mesh.positions.len(), 4096, |i| {
        let world = d.model.transform_point3(mesh.positions[i]);
        let normal = mesh
            .normals
            .get(i)
            .map_or(Vec3::ZERO, |n| (normal_matrix * *n).normalize_or_zero());
        let uv = mesh
            .uvs
            .and_then(|u| u.get(i).copied())
            .unwrap_or(Vec2::ZERO);
        let tangent = mesh
            .tangents
            .and_then(|t| t.get(i).copied())
            .map_or(Vec4::ZERO, |t| {
                (m3 * t.truncate()).normalize_or_zero().extend(t.w * flip)
            });
        (
            vp * world.extend(1.0),
            VertexIn {
                world,
                normal,
                uv,
                tangent,
            },
        )
    })
}

/// Set-up results of one chunk of triangles.
struct ChunkSetup<T> {
    binned: Binned<T>,
    drawn: u64,
    fallbacks: u64,
}

/// The world and screen vertices of one accepted triangle, by reference.
type TriRefs<'v> = ([&'v VertexIn; 3], [&'v ScreenVertex; 3]);

/// Accepted triangles waiting for their mode data, computed four at a time
/// ([`Mode::triangle4`]). They wait as references to their vertices, not copies.
struct Group<'m, 'v, M> {
    mode: &'m M,
    perspective: bool,
    queued: [Option<TriRefs<'v>>; 4],
    len: usize,
}

impl<'v, M: Mode> Group<'_, 'v, M> {
    /// Queues a triangle (or computes its data at once when the mode does not batch); returns
    /// the index its data will have in `tris`.
    fn add(&mut self, v: TriRefs<'v>, tris: &mut Vec<M::Tri>) -> u32 {
        let at = (tris.len() + self.len) as u32;
        if !M::BATCH_TRIANGLES {
            tris.push(self.mode.triangle(v.0, v.1, self.perspective));
            return at;
        }
        self.queued[self.len] = Some(v);
        self.len += 1;
        if self.len == 4 {
            self.flush(tris);
        }
        at
    }

    /// Adds data already computed ([`Mode::triangle_from_positions`]), after the queued
    /// triangles; returns its index in `tris`.
    fn add_ready(&mut self, tri: M::Tri, tris: &mut Vec<M::Tri>) -> u32 {
        self.flush(tris);
        tris.push(tri);
        (tris.len() - 1) as u32
    }

    /// Computes the data of a triangle whose vertices do not outlive the call (a clipped
    /// one), after the queued ones; returns its index in `tris`.
    fn add_now(
        &mut self,
        src: [&VertexIn; 3],
        screen: [&ScreenVertex; 3],
        tris: &mut Vec<M::Tri>,
    ) -> u32 {
        self.flush(tris);
        tris.push(self.mode.triangle(src, screen, self.perspective));
        (tris.len() - 1) as u32
    }

    /// Computes the queued triangles' data into `tris`.
    fn flush(&mut self, tris: &mut Vec<M::Tri>) {
        let len = std::mem::take(&mut self.len);
        let Some(first) = self.queued[0] else {
            return;
        };
        // Lanes past `len` repeat the first triangle; their results are dropped.
        let lane = |k: usize| self.queued[k].filter(|_| k < len).unwrap_or(first);
        let out = self.mode.triangle4(
            std::array::from_fn(|k| lane(k).0),
            std::array::from_fn(|k| lane(k).1),
            self.perspective,
        );
        tris.extend(out.into_iter().take(len));
        self.queued = [None; 4];
    }
}

/// What modes that do not read a triangle's vertices ([`Mode::READS_VERTICES`]) are handed.
const NO_VERTEX: VertexIn = VertexIn {
    world: Vec3::ZERO,
    normal: Vec3::ZERO,
    uv: Vec2::ZERO,
    tangent: Vec4::ZERO,
};

/// See [`NO_VERTEX`].
const NO_SCREEN_VERTEX: ScreenVertex = ScreenVertex {
    fx: 0,
    fy: 0,
    x: 0.0,
    y: 0.0,
    depth: 0.0,
    inv_w: 1.0,
    rhw: 1.0,
    attrs: [0.0; crate::clip::MAX_ATTRS],
};

/// Accepts a screen triangle: not degenerate, not culled, covering at least one row of pixel
/// centres. Returns its rows (not clipped to the image).
#[inline]
fn accept(v: [ScreenPos; 3], cull_backfaces: bool) -> Option<(i64, i64)> {
    let area = screen_area2(&v);
    if area == 0 || (cull_backfaces && area > 0) {
        return None;
    }
    let rows = row_range(v.map(|v| i64::from(v.fy)));
    (rows.0 < rows.1).then_some(rows)
}

/// Runs mode `M` over one draw: vertex stage, clip, accept and bin (in parallel, in order),
/// then set-up and traversal per band.
fn run<M: Mode>(
    fb: &mut Framebuffer,
    vp: Mat4,
    d: &DrawItem,
    mode: &M,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    out: Output,
) {
    let (w, h) = (fb.width(), fb.height());
    let verts = vertex_stage(d, vp, opts.threads);
    let guard = guard_band(w, h);
    let persp = opts.perspective_correct;
    let cull = opts.cull_backfaces || d.cull_backfaces;
    // Per vertex, once (a mesh vertex is shared by about six triangles), in one pass: the
    // mode's attributes and, for a vertex inside every clip plane, its snapped screen position
    // and attributes (divided by w), written compactly: accepting and band set-up fetch
    // vertices all over the mesh, and a compact vertex spans fewer cache lines. A triangle
    // whose three vertices are inside is not changed by clipping, so it takes these as they
    // are; a clipped one recomputes its corners' attributes (`clip_vertex`, the same bits).
    let screen_vertex = |cv: &ClipVertex| {
        (cv.pos.is_finite() && inside_clip_volume(cv.pos, guard))
            .then(|| to_screen(cv, w, h, M::ATTRS, persp))
            .flatten()
    };
    let clip_vertex = |i: usize| ClipVertex {
        pos: verts[i].0,
        attrs: mode.vertex(&verts[i].1),
    };
    let mut pos = vec![ScreenPos::NONE; verts.len()];
    let mut attrs = vec![0.0; verts.len() * M::ATTRS];
    let per = (4096, M::ATTRS);
    for_each_chunk_pair(
        opts.threads,
        &mut pos,
        &mut attrs,
        per,
        |first, pos, attrs| {
            let src = &verts[first..first + pos.len()];
            for (g, group) in src.chunks(4).enumerate() {
                let a4 = mode.vertex4(std::array::from_fn(|k| &group[k.min(group.len() - 1)].1));
                for (j, (v, a)) in group.iter().zip(a4).enumerate() {
                    let i = 4 * g + j;
                    if let Some(sv) = screen_vertex(&ClipVertex { pos: v.0, attrs: a }) {
                        pos[i] = sv.pos();
                        let out = attrs.get_mut(i * M::ATTRS..(i + 1) * M::ATTRS);
                        out.unwrap_or(&mut [])
                            .copy_from_slice(&sv.attrs[..M::ATTRS]);
                    }
                }
            }
        },
    );
    // Whole screen vertices only for modes that read them (see `Mode::READS_SCREEN`).
    let screen: Vec<Option<ScreenVertex>> = if M::READS_SCREEN && !M::SCREEN_PER_TRIANGLE {
        map_indices(opts.threads, verts.len(), 4096, |i| {
            screen_vertex(&clip_vertex(i))
        })
    } else {
        Vec::new()
    };
    let bands = h.div_ceil(BAND_ROWS) as usize;
    let on_screen = |v: [ScreenPos; 3], rows: (i64, i64)| {
        let (x0, x1) = row_range(v.map(|v| i64::from(v.fx)));
        let cols = x0.max(0) < x1.min(w as i64);
        band_range(rows.0, rows.1, h).filter(|_| cols)
    };
    let chunks = map_chunks(opts.threads, d.mesh.indices, 1024, |indices| {
        let mut staged: Vec<(TriRec, u32, u32)> = Vec::with_capacity(indices.len());
        let mut tris = Vec::with_capacity(indices.len());
        let mut extra = Vec::new();
        let mut group = Group {
            mode,
            perspective: persp,
            queued: [None; 4],
            len: 0,
        };
        let mut drawn = 0;
        for idx in indices {
            if idx.iter().any(|&i| i as usize >= verts.len()) {
                continue;
            }
            let [i0, i1, i2] = idx.map(|i| i as usize);
            let p = [pos[i0], pos[i1], pos[i2]];
            if !p.iter().any(ScreenPos::is_none) {
                // The common case: no clipping, screen vertices from the per-vertex pass.
                let Some(rows) = accept(p, cull) else {
                    continue;
                };
                drawn += 1;
                if let Some((b0, b1)) = on_screen(p, rows) {
                    let tri = if let Some(tri) = mode.triangle_from_positions(&p) {
                        group.add_ready(tri, &mut tris)
                    } else if M::READS_SCREEN && M::SCREEN_PER_TRIANGLE {
                        let s = [i0, i1, i2].map(|i| screen_vertex(&clip_vertex(i)));
                        let [Some(a), Some(b), Some(c)] = &s else {
                            continue;
                        };
                        let v = if M::READS_VERTICES {
                            [i0, i1, i2].map(|i| &verts[i].1)
                        } else {
                            [&NO_VERTEX; 3]
                        };
                        group.add_now(v, [a, b, c], &mut tris)
                    } else if M::READS_VERTICES || M::READS_SCREEN {
                        let s = if M::READS_SCREEN {
                            let (Some(a), Some(b), Some(c)) =
                                (&screen[i0], &screen[i1], &screen[i2])
                            else {
                                continue;
                            };
                            [a, b, c]
                        } else {
                            [&NO_SCREEN_VERTEX; 3]
                        };
                        let v = if M::READS_VERTICES {
                            [i0, i1, i2].map(|i| &verts[i].1)
                        } else {
                            [&NO_VERTEX; 3]
                        };
                        group.add((v, s), &mut tris)
                    } else {
                        group.add(([&NO_VERTEX; 3], [&NO_SCREEN_VERTEX; 3]), &mut tris)
                    };
                    staged.push((
                        TriRec {
                            v: idx.map(|i| i),
                            tri,
                        },
                        b0,
                        b1,
                    ));
                }
                continue;
            }
            let tri = [clip_vertex(i0), clip_vertex(i1), clip_vertex(i2)];
            if !tri.iter().all(|v| v.pos.is_finite()) {
                continue;
            }
            let src = [verts[i0].1, verts[i1].1, verts[i2].1];
            let poly = clip_triangle(&tri, M::ATTRS, guard);
            let pv = poly.vertices();
            let mut sv = [None; crate::clip::MAX_POLY];
            for (s, v) in sv.iter_mut().zip(pv) {
                *s = to_screen(v, w, h, M::ATTRS, persp);
            }
            let mut any = false;
            // The clipped polygon is convex: a fan keeps the winding.
            for k in 1..pv.len().saturating_sub(1) {
                let (Some(a), Some(b), Some(c)) = (&sv[0], &sv[k], &sv[k + 1]) else {
                    continue;
                };
                let p = [a.pos(), b.pos(), c.pos()];
                let Some(rows) = accept(p, cull) else {
                    continue;
                };
                any = true;
                if let Some((b0, b1)) = on_screen(p, rows) {
                    let base = extra.len() as u32;
                    extra.extend([*a, *b, *c]);
                    let rec = TriRec {
                        v: [base, base + 1, base + 2].map(|i| i | EXTRA_VERTEX),
                        tri: group.add_now(src.each_ref(), [a, b, c], &mut tris),
                    };
                    staged.push((rec, b0, b1));
                }
            }
            drawn += u64::from(any);
        }
        group.flush(&mut tris);
        let fallbacks = tris.iter().map(|t| u64::from(M::is_fallback(t))).sum();
        ChunkSetup {
            binned: Binned::new(&staged, bands, tris, extra),
            drawn,
            fallbacks,
        }
    });
    stats.triangles_in += d.mesh.indices.len() as u64;
    let mut binned = Vec::with_capacity(chunks.len());
    for c in chunks {
        stats.triangles_drawn += c.drawn;
        stats.fallbacks += c.fallbacks;
        binned.push(c.binned);
    }
    let (count, block) = match out {
        Output::Shade { block } => (false, block),
        Output::Count => (true, 1),
    };
    stats.pixels_shaded += draw_bands(
        fb,
        mode,
        &pos,
        &attrs,
        &binned,
        persp,
        opts.threads,
        count,
        block,
    );
}
