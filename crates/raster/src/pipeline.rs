//! One draw through the three stages ([`run`]): [`crate::vertex`], [`crate::bin`] and
//! [`crate::bands`]. [`crate::render`]'s frames and the shadow maps' depth draws both come
//! here, so that neither module needs the other's internals.

use glam::{Mat4, Vec3};

use crate::bands::{Outputs, draw_bands};
use crate::batch::Wide;
use crate::bin::{BinInput, bin_draw};
use crate::framebuffer::Framebuffer;
use crate::records::BandInput;
use crate::shader::{Face, Shader};
use crate::shaders::fill::Fill;
use crate::vertex::{Used, vertex_positions, vertex_varyings};
use crate::viewport::Viewport;
use crate::{Interpolation, MeshView, RenderOptions, RenderStats};

/// Draws `mesh` placed by `model` into `fb` seen through `vp`, every face, for its depth
/// alone: a shadow map's casters.
pub(crate) fn run_depth(
    fb: &mut Framebuffer,
    vp: Mat4,
    mesh: &MeshView,
    model: Mat4,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) {
    let fill = Fill { color: Vec3::ZERO };
    run(
        fb,
        (vp, &positions_only(mesh), model),
        &fill,
        opts,
        stats,
        (1, false, false, true),
        Outputs::default(),
    );
}

/// `mesh` with its positions and triangles alone, for a constant-colour draw that reads
/// nothing else: the vertex stage then transforms no normals.
pub(crate) fn positions_only<'a>(mesh: &MeshView<'a>) -> MeshView<'a> {
    MeshView::new(mesh.positions, &[], mesh.indices)
}

/// Runs `shader` over one draw through the three stages: vertex, bin (both in parallel over
/// the mesh, in order; the varyings only for the vertices the bin stage recorded) and bands. `block`: samples per pixel side of a multisampled image (1:
/// none); `count`: the coverage-count hook; `depth_only`: a constant-colour shader writes
/// depth alone (a shadow map), and the colour is neither written nor cleared. With
/// `out.resolve` (the output image `fb`'s samples resolve into) each band resolves its rows
/// after drawing them, and with `out.words` reads its finished rows out into a window's
/// words ([`draw_bands`]).
pub(crate) fn run<S: Shader>(
    fb: &mut Framebuffer,
    (vp, mesh, model): (Mat4, &MeshView, Mat4),
    shader: &S,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    (block, count, cull, depth_only): (u32, bool, bool, bool),
    out: Outputs<'_>,
) {
    let view = Viewport::new(fb.width(), fb.height(), opts.perspective_correct, block);
    let wide = Wide {
        avx2: opts.simd.token(),
    };
    let threads = opts.threads;
    let mut verts = vertex_positions(mesh, model, vp, &view, (threads, wide, S::VARYINGS > 0));
    let used = Used::new(verts.clip.len(), S::VARYINGS > 0);
    let bin = BinInput {
        shader,
        indices: mesh.indices,
        verts: &verts,
        view: &view,
        cull,
        wide,
        used: &used,
    };
    let binned = bin_draw(&bin, threads);
    vertex_varyings(&mut verts, shader, &used, (threads, wide));
    stats.triangles_in += mesh.indices.len() as u64;
    stats.triangles_drawn += binned.drawn;
    stats.fallbacks += binned.fallbacks;
    let input = BandInput {
        shader,
        pos: &verts.pos,
        attrs: &verts.attrs,
        chunks: &binned.chunks,
        perspective: view.perspective,
        incremental: opts.interpolation == Interpolation::Incremental
            && S::FACE == Face::Interpolated,
        wide,
        ceiling: fb.ceiling,
        depth_only: depth_only && S::FACE == Face::Constant,
    };
    stats.pixels_shaded += draw_bands(fb, &input, (threads, count, block), out);
}
