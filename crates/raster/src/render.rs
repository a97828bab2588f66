//! One frame, draw by draw in submission order ([`Frame`]): each draw's shader runs through
//! the three stages, [`crate::vertex`], [`crate::bin`] and [`crate::bands`]; with
//! anti-aliasing, into a sample image resolved when the frame finishes. [`render`] draws the
//! built-in modes, each specialized for its draw's effects.

use glam::{Mat4, Vec3};
use phosphor_lighting::Effects;

use crate::antialias::{Antialias, resolve};
use crate::bands::Outputs;
use crate::framebuffer::{Framebuffer, RasterError, WindowBuffer};
use crate::pipeline::{positions_only, run};
use crate::shader::Shader;
use crate::shaders::fill::Fill;
use crate::{Camera, DrawItem, MeshView, RenderOptions, RenderStats, ShadingMode};

/// One frame being drawn into a framebuffer: draws of any [`Shader`], in submission order,
/// then [`Frame::finish`]. The framebuffer is cleared to the options' background first (when
/// the first draw runs, band by band). With anti-aliasing on, the draws go into a sample
/// image `k` times larger on each side (kept in the framebuffer for the next frame) that
/// `finish` box-filters into it; an image whose sample image would exceed the largest side is
/// drawn with one sample per pixel, and [`RenderStats::antialias`] says which was used.
pub struct Frame<'f> {
    fb: &'f mut Framebuffer,
    samples: Option<Box<Framebuffer>>,
    factor: u32,
    block: u32,
    eye: Vec3,
    vp: Mat4,
    opts: RenderOptions,
    stats: RenderStats,
    done: bool,
    /// [`Frame::resolve_as_drawn`] was called.
    resolve_as_drawn: bool,
    /// The last draw resolved the samples into the image.
    resolved: bool,
    /// The window's buffer the finished image is read out into ([`Frame::show_in`]).
    window: Option<WindowBuffer<'f>>,
    /// The last draw read the finished image out into the window's buffer.
    read_out: bool,
}

impl<'f> Frame<'f> {
    /// Starts a frame of `fb` seen by `camera`.
    pub fn new(fb: &'f mut Framebuffer, camera: &Camera, opts: &RenderOptions) -> Frame<'f> {
        let aa = opts.antialias;
        let mut samples = None;
        let (mut factor, mut block) = (1, 1);
        if aa != Antialias::Off && aa.fits(fb.width(), fb.height()) {
            let k = aa.factor();
            let (width, height) = (fb.width() * k, fb.height() * k);
            let reusable = fb
                .samples
                .take()
                .filter(|s| s.width() == width && s.height() == height);
            // `fits` checked the sides, so only the allocation itself can fail: draw one
            // sample per pixel then, and say so in the stats.
            samples = reusable.or_else(|| Framebuffer::new(width, height).ok().map(Box::new));
            // The samples keep what the framebuffer keeps, so that the resolve averages it.
            if let Some(s) = &mut samples {
                s.set_hdr(fb.hdr());
            }
            if samples.is_some() {
                factor = k;
                block = if aa.multisample() { k } else { 1 };
            }
        }
        if samples.is_none() {
            fb.samples = None;
        }
        let mut frame = Frame {
            fb,
            samples,
            factor,
            block,
            eye: camera.eye,
            vp: Mat4::IDENTITY,
            opts: *opts,
            stats: RenderStats {
                simd: opts.simd.resolve(),
                ..RenderStats::default()
            },
            done: false,
            resolve_as_drawn: false,
            resolved: false,
            window: None,
            read_out: false,
        };
        if factor > 1 {
            frame.stats.antialias = aa;
        }
        let target = frame.target();
        target.defer_clear(opts.background);
        let aspect = target.width() as f32 / target.height() as f32;
        frame.vp = camera.view_proj(aspect);
        frame
    }

    /// The image the draws go into: the sample image, or the framebuffer itself.
    fn target(&mut self) -> &mut Framebuffer {
        match &mut self.samples {
            Some(s) => s,
            None => self.fb,
        }
    }

    /// The camera's eye, for shaders that need the viewer.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// The frame's options.
    #[must_use]
    pub fn options(&self) -> &RenderOptions {
        &self.opts
    }

    /// Whether the framebuffer keeps intensities above 1 ([`Framebuffer::set_hdr`]): then
    /// nothing is clamped at 1, [`RenderOptions::gouraud_vertex_clamp`] included.
    #[must_use]
    pub fn hdr(&self) -> bool {
        self.fb.hdr()
    }

    /// Draws `mesh` placed by `model` (object to world) with `shader`; `cull_backfaces` skips
    /// its triangles facing away (clockwise on screen), as [`RenderOptions::cull_backfaces`]
    /// does for every draw. Bad input (indices out of range, non-finite positions, zero-area
    /// triangles) is skipped, never a panic.
    pub fn draw<S: Shader>(
        &mut self,
        mesh: &MeshView,
        model: Mat4,
        shader: &S,
        cull_backfaces: bool,
    ) {
        let (vp, block, opts) = (self.vp, self.block, self.opts);
        let cull = opts.cull_backfaces || cull_backfaces;
        let mut stats = self.stats;
        // The bands resolve as they go once the frame's last draws are announced; a draw
        // without that leaves the resolve to the frame's end.
        // And read the finished image out into the window's buffer, when it has the image's
        // size; otherwise the frame's end reads it out.
        let pixels = self.fb.width() as usize * self.fb.height() as usize;
        let words = match (&mut self.window, self.resolve_as_drawn) {
            (Some(w), true) if w.words.len() == pixels => {
                Some((&mut *w.words, (*w.shown).as_ref()))
            }
            _ => None,
        };
        self.read_out = words.is_some();
        let (target, resolve) = match (&mut self.samples, self.resolve_as_drawn) {
            (Some(s), true) => (&mut **s, Some(&mut *self.fb)),
            (Some(s), false) => (&mut **s, None),
            (None, _) => (&mut *self.fb, None),
        };
        self.resolved = resolve.is_some();
        run(
            target,
            (vp, mesh, model),
            shader,
            &opts,
            &mut stats,
            (block, false, cull, false),
            Outputs { resolve, words },
        );
        self.stats = stats;
    }

    /// Draws one of the built-in modes' items ([`render`]).
    pub fn draw_item(&mut self, d: &DrawItem) {
        let n = d.mesh.positions.len();
        let has_frame = d.mesh.uvs.is_some_and(|u| u.len() == n)
            && d.mesh.tangents.is_some_and(|t| t.len() == n);
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
            self.stats.bump_ignored += 1;
        }
        let item = DrawItem { bump, ..*d };
        use crate::shaders::{fast_phong, flat, gouraud, phong, reference};
        match d.mode {
            ShadingMode::Flat => flat::draw(self, &item),
            ShadingMode::Gouraud => gouraud::draw(self, &item),
            ShadingMode::Phong => phong::draw(self, &item),
            ShadingMode::FastPhong => fast_phong::draw(self, &item),
            ShadingMode::Reference => reference::draw(self, &item),
        }
    }

    /// Draws `d` with shadows: `shadowed` are its lights that have a map, `rest` its other
    /// lights and the ambient, and `d.lights` all of them ([`crate::shadow::shade`] says how
    /// each mode and tint is drawn). With no map it is [`Frame::draw_item`].
    pub fn draw_shadowed(
        &mut self,
        d: &DrawItem,
        rest: &phosphor_lighting::LightSet,
        shadowed: &[crate::shadow::ShadowLight],
    ) {
        crate::shadow::shade::draw(self, d, rest, shadowed);
    }

    /// Says that the frame's last draw comes next: from here on each draw resolves the
    /// anti-aliased image band by band, right after drawing a band, while its samples are
    /// still in cache, and [`Frame::finish`] reads nothing back. Each such draw resolves all
    /// that the frame drew so far in its bands, so calling this earlier gives the same image
    /// for more work, and not calling it leaves the resolve to [`Frame::finish`]: the image
    /// is the same either way. Nothing changes without anti-aliasing.
    pub fn resolve_as_drawn(&mut self) {
        self.resolve_as_drawn = true;
    }

    /// Fills `window`'s buffer with the finished image as [`Framebuffer::write_0rgb_over`]
    /// would after [`Frame::finish`], and sets its `shown` to what the buffer then holds.
    /// After [`Frame::resolve_as_drawn`] each draw reads its bands' finished rows out right
    /// after drawing (and resolving) them, while they are still in cache; otherwise, or when
    /// the buffer's length is not the image's, the frame's end reads the whole image out. The
    /// words are the same either way. Whatever draws on the framebuffer after the frame (an
    /// overlay) is not in them.
    pub fn show_in(&mut self, window: WindowBuffer<'f>) {
        self.window = Some(window);
    }

    /// Ends the frame (the clear no draw took, the anti-aliasing resolve, the window's
    /// readout) and returns what it did.
    pub fn finish(mut self) -> RenderStats {
        self.end();
        self.stats
    }

    fn end(&mut self) {
        if self.done {
            return;
        }
        self.done = true;
        self.target().finish_clear();
        if let Some(samples) = self.samples.take() {
            if !self.resolved {
                resolve(&samples, self.fb, self.factor, self.opts.threads);
            }
            self.fb.samples = Some(samples);
        }
        if let Some(w) = self.window.take() {
            let n = w.words.len().min(self.fb.color.len());
            // The last draw's bands read every row out, and nothing drew after them.
            let shown = if self.read_out {
                self.fb.shown(n)
            } else {
                self.fb
                    .write_0rgb_over(w.words, self.opts.threads, (*w.shown).as_ref())
            };
            *w.shown = Some(shown);
        }
    }
}

impl Drop for Frame<'_> {
    /// A frame dropped without [`Frame::finish`] is finished all the same: the framebuffer
    /// never keeps a deferred clear.
    fn drop(&mut self) {
        self.end();
    }
}

/// Renders `draws` seen by `camera` into `fb` (cleared to `opts.background` first), each
/// draw with its own mode, specialized for its effect set ([`Frame`] has the details).
pub fn render(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    render_into(fb, camera, draws, opts, None)
}

/// [`render`], and with `window` the finished image read out into a window's buffer as
/// [`Framebuffer::write_0rgb_over`] reads it, by the last draw's bands while their rows are
/// in cache ([`Frame::show_in`]).
pub fn render_into(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
    window: Option<WindowBuffer<'_>>,
) -> RenderStats {
    let mut frame = Frame::new(fb, camera, opts);
    if let Some(w) = window {
        frame.show_in(w);
    }
    for (i, d) in draws.iter().enumerate() {
        if i + 1 == draws.len() {
            frame.resolve_as_drawn();
        }
        frame.draw_item(d);
    }
    frame.finish()
}

/// Coverage and depth only, every draw in one constant colour (white): the fill-only speed
/// bound. Modes, lights, effects and anti-aliasing are ignored.
pub fn render_fill_only(
    fb: &mut Framebuffer,
    camera: &Camera,
    draws: &[DrawItem],
    opts: &RenderOptions,
) -> RenderStats {
    let opts = RenderOptions {
        antialias: Antialias::Off,
        ..*opts
    };
    let mut frame = Frame::new(fb, camera, &opts);
    let fill = Fill { color: Vec3::ONE };
    for d in draws {
        frame.draw(&positions_only(&d.mesh), d.model, &fill, d.cull_backfaces);
    }
    frame.finish()
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
    let fill = Fill { color: Vec3::ONE };
    let mut stats = RenderStats::default();
    for d in draws {
        let cull = opts.cull_backfaces || d.cull_backfaces;
        run(
            &mut fb,
            (vp, &d.mesh, d.model),
            &fill,
            opts,
            &mut stats,
            (1, true, cull, false),
            Outputs::default(),
        );
    }
    Ok(fb.color.iter().map(|c| c.x as u32).collect())
}
