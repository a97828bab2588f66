//! Overlays drawn over a finished frame: the wireframe's lines where they are seen and hidden,
//! one pixel per step or two sharing it, the grid under the scene, the axes' triad, and that
//! an overlay changes nothing but the colours of its lines (and survives the window's
//! partial clears).

#![allow(clippy::unwrap_used)]

use phosphor_lighting::{Effects, Light, LightSet, Material};
use phosphor_math::glam::{DVec4, Mat4, Vec3};
use phosphor_raster::overlay::{self, AXIS_COLORS, Edges, Grid, LineStyle, Overlays, edge_list};
use phosphor_raster::{Camera, DrawItem, Framebuffer, MeshView, RenderOptions, ShadingMode};

type Quad = (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>);

/// A quad of two triangles (diagonal from `(x0, y1)` to `(x1, y0)`) spanning the given
/// pixel box at NDC depth `z`: positions, normals and triangles.
fn quad(cam: &Camera, (w, h): (u32, u32), (x0, y0, x1, y1): (f64, f64, f64, f64), z: f64) -> Quad {
    let inv = cam.view_proj(w as f32 / h as f32).as_dmat4().inverse();
    let p = |x: f64, y: f64| {
        let ndc = DVec4::new(
            x / f64::from(w) * 2.0 - 1.0,
            1.0 - y / f64::from(h) * 2.0,
            z,
            1.0,
        );
        let p = inv * ndc;
        (p.truncate() / p.w).as_vec3()
    };
    (
        vec![p(x0, y1), p(x1, y1), p(x1, y0), p(x0, y0)],
        vec![Vec3::Z; 4],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

fn item<'a>(m: &'a Quad, material: &'a Material, lights: &'a LightSet) -> DrawItem<'a> {
    DrawItem {
        mesh: MeshView::new(&m.0, &m.1, &m.2),
        model: Mat4::IDENTITY,
        material,
        lights,
        effects: Effects::DIFFUSE,
        mode: ShadingMode::Flat,
        bump: None,
        texture: None,
        cull_backfaces: false,
    }
}

fn lights() -> LightSet {
    LightSet::new(
        Vec3::ZERO,
        &[Light::directional(-Vec3::Z, Vec3::splat(0.5)).unwrap()],
    )
}

const SIZE: (u32, u32) = (64, 48);
const RED: Vec3 = Vec3::new(1.0, 0.0, 0.0);

fn render(draws: &[DrawItem]) -> Framebuffer {
    let mut fb = Framebuffer::new(SIZE.0, SIZE.1).unwrap();
    let opts = RenderOptions {
        threads: 1,
        ..RenderOptions::default()
    };
    phosphor_raster::render(&mut fb, &Camera::s1(), draws, &opts);
    fb
}

#[test]
fn edges_are_drawn_once_per_column_where_seen_and_hidden_behind_nearer_surfaces() {
    let cam = Camera::s1();
    let (lights, material) = (lights(), Material::s1());
    // The back quad spans columns 8.5..56.5; the front one, nearer, covers its right half.
    let back = quad(&cam, SIZE, (8.5, 8.5, 56.5, 40.5), 0.9);
    let front = quad(&cam, SIZE, (36.2, 4.3, 60.7, 44.6), 0.5);
    let draws = [
        item(&back, &material, &lights),
        item(&front, &material, &lights),
    ];
    let shaded = render(&draws);
    let mut wired = shaded.clone();
    let style = LineStyle {
        color: RED,
        smooth: false,
    };
    let written = overlay::wireframe(&mut wired, &cam, &draws, Edges::All, style);
    let is_red = |x: u32, y: u32| wired.pixel(x, y) == RED;
    // The back quad's top edge, row 8 (y = 8.5 lies on the border of rows 8 and 9: the pixel
    // holding it is row 8), from column 8 to where the front quad begins.
    for x in 9..35 {
        assert!(is_red(x, 8), "top edge at column {x}");
        assert!(
            !is_red(x, 7) && !is_red(x, 10),
            "one pixel thick at column {x}"
        );
    }
    // Its diagonal, from (8.5, 40.5) to (56.5, 8.5): one pixel per column (it spans more
    // columns than rows), in the row holding the exact point at the column's centre.
    for x in 9..35 {
        let t = (f64::from(x) + 0.5 - 8.5) / 48.0;
        let y = (40.5 - t * 32.0).floor() as u32;
        assert!(is_red(x, y), "diagonal at ({x}, {y})");
        let in_column = (0..SIZE.1).filter(|&y| is_red(x, y)).count();
        assert_eq!(in_column, 3, "column {x}: top, diagonal and bottom edges");
    }
    // Behind the front quad the back quad's edges are hidden: in columns 38..56 its top and
    // bottom rows and its diagonal show only where the front quad's own diagonal crosses.
    let (mut top, mut bottom, mut diagonal) = (0, 0, 0);
    for x in 38..56 {
        top += usize::from(is_red(x, 8));
        bottom += usize::from(is_red(x, 40));
        let t = (f64::from(x) + 0.5 - 8.5) / 48.0;
        diagonal += usize::from(is_red(x, (40.5 - t * 32.0).floor() as u32));
        assert!(
            is_red(x, 4) && is_red(x, 44),
            "front quad's edges at column {x}"
        );
    }
    assert!(
        top <= 2 && bottom <= 2 && diagonal <= 2,
        "{top} {bottom} {diagonal}"
    );
    // Nothing but line pixels changed (a pixel two edges cross is written twice), and the
    // depths, hence the coverage, are the frame's.
    let mut changed = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if wired.pixel(x, y) != shaded.pixel(x, y) {
                assert!(is_red(x, y), "({x}, {y})");
                changed += 1;
            }
        }
    }
    assert!(
        changed > 100 && changed <= written,
        "{changed} of {written}"
    );
    assert_eq!(wired.depth(), shaded.depth());
    // A mesh with an index out of range, or a vertex at infinity, is skipped, not a panic.
    let mut broken = quad(&cam, SIZE, (8.5, 8.5, 56.5, 40.5), 0.9);
    broken.2.push([0, 1, 99]);
    broken.0[2] = Vec3::INFINITY;
    let mut fb = shaded.clone();
    overlay::wireframe(
        &mut fb,
        &cam,
        &[item(&broken, &material, &lights)],
        Edges::All,
        style,
    );
    assert!(fb.color().iter().all(|c| c.is_finite()));
    // Colours are clamped to the framebuffer's range.
    let mut fb = shaded.clone();
    let wild = LineStyle {
        color: Vec3::new(f32::NAN, 9.0, -1.0),
        smooth: true,
    };
    assert!(overlay::wireframe(&mut fb, &cam, &draws, Edges::All, wild) > 100);
    assert!(
        fb.color()
            .iter()
            .all(|c| c.is_finite() && c.max_element() <= 1.0 && c.min_element() >= 0.0)
    );
}

#[test]
fn smooth_lines_share_each_step_between_the_two_pixels_either_side() {
    let cam = Camera::s1();
    let (lights, material) = (lights(), Material::s1());
    // One quad filling the frame, and a thin one (its edges are the lines) in front of it.
    let wall = quad(&cam, SIZE, (-1.0, -1.0, 65.0, 49.0), 0.9);
    let card = quad(&cam, SIZE, (10.0, 12.3, 50.0, 30.0), 0.5);
    let shaded = render(&[
        item(&wall, &material, &lights),
        item(&card, &material, &lights),
    ]);
    let mut fb = shaded.clone();
    let card_only = [item(&card, &material, &lights)];
    let white = LineStyle {
        color: Vec3::ONE,
        smooth: true,
    };
    overlay::wireframe(&mut fb, &cam, &card_only, Edges::All, white);
    // The top edge at y = 12.3 lies between the centres of rows 11 (11.5) and 12 (12.5):
    // row 11 takes 0.2 of the white, row 12 takes 0.8, nothing else in the column.
    for x in 12..30 {
        let before = |y| shaded.pixel(x, y).x;
        let share = |y| (fb.pixel(x, y).x - before(y)) / (1.0 - before(y));
        assert!((share(11) - 0.2).abs() < 1e-3, "column {x}: {}", share(11));
        assert!((share(12) - 0.8).abs() < 1e-3, "column {x}: {}", share(12));
        assert_eq!(fb.pixel(x, 10), shaded.pixel(x, 10));
        assert_eq!(fb.pixel(x, 13), shaded.pixel(x, 13));
    }
}

#[test]
fn the_grid_lies_under_the_scene_in_round_steps_and_shows_where_nothing_hides_it() {
    let cam = Camera {
        eye: Vec3::new(0.0, 3.0, 4.0),
        target: Vec3::ZERO,
        ..Camera::s1()
    };
    let (lights, material) = (lights(), Material::s1());
    // A box 3 wide (x), 2 deep (z), from y = -0.5 to 0.5, centred at (0.2, 0, 0.1).
    let mut cube = quad(&Camera::s1(), SIZE, (0.0, 0.0, 1.0, 1.0), 0.5);
    cube.0 = [-1.0f32, 1.0]
        .iter()
        .flat_map(|&x| {
            [-1.0f32, 1.0]
                .iter()
                .flat_map(move |&y| [-1.0f32, 1.0].map(|z| Vec3::new(x, y, z)))
        })
        .map(|p| p * Vec3::new(1.5, 0.5, 1.0) + Vec3::new(0.2, 0.0, 0.1))
        .collect();
    cube.1 = vec![Vec3::Y; 8];
    cube.2 = vec![
        [0, 1, 3],
        [0, 3, 2],
        [4, 6, 7],
        [4, 7, 5],
        [0, 4, 5],
        [0, 5, 1],
        [2, 3, 7],
        [2, 7, 6],
        [0, 2, 6],
        [0, 6, 4],
        [1, 5, 7],
        [1, 7, 3],
    ];
    let draws = [item(&cube, &material, &lights)];
    let grid = Grid::under(&draws).unwrap();
    assert_eq!(grid.y, -0.5);
    // Three across over eight cells: 0.375, rounded up to 0.5; centred on a crossing.
    assert!((grid.spacing - 0.5).abs() < 1e-6, "{}", grid.spacing);
    assert_eq!(grid.center.to_array(), [0.0, 0.0]);
    // It reaches past the box (1.7 from the centre in x) by a cell at least.
    assert!(
        grid.half_lines as f32 * grid.spacing >= 1.7 + 0.5,
        "{grid:?}"
    );
    assert!(Grid::under(&[]).is_none());

    let mut fb = Framebuffer::new(SIZE.0, SIZE.1).unwrap();
    let opts = RenderOptions {
        threads: 1,
        ..RenderOptions::default()
    };
    phosphor_raster::render(&mut fb, &cam, &draws, &opts);
    let shaded = fb.clone();
    let written = grid.draw(
        &mut fb,
        &cam,
        LineStyle {
            color: RED,
            smooth: false,
        },
    );
    let mut on_background = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if fb.pixel(x, y) != shaded.pixel(x, y) {
                assert_eq!(fb.pixel(x, y), RED);
                // The box stands on the grid, so no grid line covers the box's upper faces.
                // The box stands on the grid: a line shows on it only along its foot.
                if shaded.depth_at(x, y) < 1.0 {
                    let foot = (1..=2).any(|k| shaded.depth_at(x, y + k) == 1.0);
                    assert!(foot, "({x}, {y})");
                } else {
                    on_background += 1;
                }
            }
        }
    }
    assert!(
        on_background > 100 && written >= on_background,
        "{on_background} {written}"
    );
    // A grid with values that are not finite draws nothing.
    let bad = Grid {
        spacing: f32::NAN,
        ..grid
    };
    assert_eq!(
        bad.draw(
            &mut fb,
            &cam,
            LineStyle {
                color: RED,
                smooth: true
            }
        ),
        0
    );
}

#[test]
fn the_axes_turn_with_the_view_in_the_corner_and_survive_the_next_clear() {
    let mut fb = Framebuffer::new(200, 100).unwrap();
    let front = Camera::s1();
    // Seen from +z: x points right, y up, z at the viewer (a point).
    let written = overlay::axes(&mut fb, &front, false);
    let length = (100.0f32 * 0.06).round() as u32;
    let (ox, oy) = (9u32, 91u32);
    assert!(written >= u64::from(2 * length));
    for k in 0..length {
        assert_eq!(fb.pixel(ox + k, oy), AXIS_COLORS[0], "x at {k}");
        assert_eq!(fb.pixel(ox, oy - 1 - k), AXIS_COLORS[1], "y at {k}");
    }
    // Nothing outside the corner.
    for y in 0..100 {
        for x in 0..200 {
            if x > 20 || y < 80 {
                assert_eq!(fb.pixel(x, y), Vec3::ZERO, "({x}, {y})");
            }
        }
    }
    // The window's conversion fills the columns nothing drew with the background: the triad
    // counts as drawn, so it is on screen, and the next clear removes it.
    let mut out = vec![0u32; 200 * 100];
    fb.write_0rgb(&mut out);
    assert_ne!(out[(oy * 200 + ox + 2) as usize], 0);
    fb.clear(Vec3::ZERO);
    assert!(fb.color().iter().all(|&c| c == Vec3::ZERO));
    // Seen from above (+y), z points down the screen and y at the viewer.
    let top = Camera {
        eye: Vec3::new(0.0, 4.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        ..Camera::s1()
    };
    overlay::axes(&mut fb, &top, false);
    // (The origin's pixel is the last drawn of x and z, both in the view plane.)
    for k in 1..length {
        assert_eq!(fb.pixel(ox + k, oy), AXIS_COLORS[0], "x at {k}");
        assert_eq!(fb.pixel(ox, oy + k), AXIS_COLORS[2], "z at {k}");
    }
    assert!([AXIS_COLORS[0], AXIS_COLORS[2]].contains(&fb.pixel(ox, oy)));
}

#[test]
fn overlays_draw_in_one_call_and_none_changes_nothing() {
    let cam = Camera::s1();
    let (lights, material) = (lights(), Material::s1());
    let back = quad(&cam, SIZE, (8.5, 8.5, 56.5, 40.5), 0.9);
    let draws = [item(&back, &material, &lights)];
    let shaded = render(&draws);
    let mut fb = shaded.clone();
    assert!(Overlays::default().is_empty());
    assert_eq!(Overlays::default().draw(&mut fb, &cam, &draws, true), 0);
    assert_eq!(fb.color(), shaded.color());
    let all = Overlays {
        wireframe: Some((Edges::Creases { angle_deg: 60.0 }, RED)),
        grid: Some(Vec3::splat(0.5)),
        axes: true,
    };
    let written = all.draw(&mut fb, &cam, &draws, false);
    // The flat quad's creases are its four borders, not its diagonal.
    let mut alone = shaded.clone();
    let style = LineStyle {
        color: RED,
        smooth: false,
    };
    let borders = overlay::wireframe(
        &mut alone,
        &cam,
        &draws,
        Edges::Creases { angle_deg: 60.0 },
        style,
    );
    let every = overlay::wireframe(&mut shaded.clone(), &cam, &draws, Edges::All, style);
    assert!(borders > 100 && every > borders + 30, "{borders} {every}");
    assert!(written > borders);
}

/// A unit cube as 24 vertices (4 per face, split for flat normals) and 12 triangles.
fn split_cube() -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let n = Vec3::AXES[axis] * sign;
            let u = Vec3::AXES[(axis + 1) % 3];
            let v = n.cross(u);
            let base = positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                positions.push(n + u * su + v * sv);
                normals.push(n);
            }
            indices.push([base, base + 1, base + 2]);
            indices.push([base, base + 2, base + 3]);
        }
    }
    (positions, normals, indices)
}

#[test]
fn a_cube_has_eighteen_edges_and_twelve_creases_whatever_its_vertex_split() {
    let (p, n, i) = split_cube();
    let mesh = MeshView::new(&p, &n, &i);
    // 12 cube edges and 6 face diagonals, each once although the 24 vertices are split.
    assert_eq!(edge_list(&mesh, Edges::All).len(), 18);
    let creases = edge_list(&mesh, Edges::Creases { angle_deg: 60.0 });
    assert_eq!(creases.len(), 12);
    // Each crease runs along a cube edge: its ends differ in exactly one coordinate.
    for (a, b) in creases {
        let d = p[a as usize] - p[b as usize];
        let moved = d.to_array().iter().filter(|c| c.abs() > 1e-6).count();
        assert_eq!(moved, 1, "{:?} {:?}", p[a as usize], p[b as usize]);
    }
    // Faces at 90 degrees are not creases above 90 degrees.
    assert!(edge_list(&mesh, Edges::Creases { angle_deg: 90.5 }).is_empty());
    assert_eq!(
        edge_list(
            &mesh,
            Edges::Creases {
                angle_deg: f32::NAN
            }
        )
        .len(),
        12
    );
}

#[test]
fn open_borders_stay_and_broken_triangles_are_left_out() {
    // Two coplanar triangles: only the four border edges are creases.
    let p = [
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::Y,
        Vec3::splat(f32::NAN),
        Vec3::new(2.0, 0.0, 0.0),
    ];
    let n = [Vec3::Z; 6];
    // Then: an index out of range, a repeated corner, a NaN corner, and a face of zero area
    // on the edge 0-1.
    let i = [
        [0, 1, 2],
        [0, 2, 3],
        [0, 1, 9],
        [1, 1, 2],
        [0, 4, 1],
        [0, 5, 1],
    ];
    let mesh = MeshView::new(&p, &n, &i);
    let mut creases = edge_list(&mesh, Edges::Creases { angle_deg: 1.0 });
    creases.sort_unstable();
    // Faces without a normal take no part: the edge 0-1 stays the quad's border, and the
    // shared diagonal 0-2 is flat.
    assert_eq!(creases, [(0, 1), (0, 3), (1, 2), (2, 3)]);
    // Every edge: the quad's five, the NaN face's two (the line drawer drops them) and the
    // flat face's two; out-of-range and repeated-corner triangles add nothing.
    let all = edge_list(&mesh, Edges::All);
    assert!(all.iter().all(|&(a, b)| a < 6 && b < 6 && a < b));
    assert_eq!(all.len(), 9);
}

#[test]
fn grid_steps_are_round_and_never_below_an_eighth_of_the_scene() {
    let (lights, material) = (lights(), Material::s1());
    // A flat strip `across` wide in x: the step is the smallest 1, 2 or 5 times a power of
    // ten that is at least across / 8.
    for (across, step) in [
        (2.4f32, 0.5f32),
        (8.0, 1.0),
        (8.08, 2.0),
        (20.0, 5.0),
        (56.0, 10.0),
        (0.0096, 0.002),
    ] {
        let strip: Quad = (
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(across, 0.0, 0.0),
                Vec3::new(across, 0.0, across / 10.0),
            ],
            vec![Vec3::Y; 3],
            vec![[0, 1, 2]],
        );
        let grid = Grid::under(&[item(&strip, &material, &lights)]).unwrap();
        assert!(
            (grid.spacing - step).abs() < step * 1e-5,
            "{across}: {}",
            grid.spacing
        );
        assert!(
            grid.half_lines as f32 * grid.spacing >= across / 2.0,
            "{across}: {grid:?}"
        );
    }
}

#[test]
fn overlay_strokes_are_opaque_in_alpha_until_the_next_frame() {
    let mut fb = Framebuffer::new(200, 100).unwrap();
    let front = Camera::s1();
    let (ox, oy) = (9usize, 91usize);
    let length = (100.0f32 * 0.06).round() as usize;
    // Exact lines: alpha 1 on the x axis' pixels, 0 where nothing was drawn.
    overlay::axes(&mut fb, &front, false);
    let alpha = fb.alpha(0.0);
    for k in 0..length {
        assert_eq!(alpha[oy * 200 + ox + k], 1.0, "x at {k}");
    }
    assert_eq!(alpha[50 * 200 + 100], 0.0);
    // Smooth lines over a black, transparent background, seen at a slant: the pixels hold
    // colours premultiplied by their alpha (no channel above it, every axis colour's channels
    // being at most 1), alpha is 0 exactly where nothing was drawn, and steps shared between
    // two pixels leave alphas strictly between 0 and 1.
    fb.clear(Vec3::ZERO);
    assert!(fb.alpha(0.0).iter().all(|&a| a == 0.0));
    let slant = Camera {
        eye: Vec3::new(3.0, 2.0, 4.0),
        target: Vec3::ZERO,
        ..Camera::s1()
    };
    assert!(overlay::axes(&mut fb, &slant, true) > 0);
    let alpha = fb.alpha(0.0);
    let mut partial = 0;
    for (i, &a) in alpha.iter().enumerate() {
        let c = fb.color()[i];
        assert!((0.0..=1.0).contains(&a), "{i}: {a}");
        assert_eq!(a == 0.0, c == Vec3::ZERO, "{i}: {a} {c}");
        assert!(c.max_element() <= a + 1e-6, "{i}: {a} {c}");
        partial += usize::from(a > 0.0 && a < 1.0);
    }
    assert!(partial > 4, "{partial}");
    // Over an opaque background nothing changes: alpha is 1 everywhere.
    assert!(fb.alpha(1.0).iter().all(|&a| a == 1.0));
    // The next frame's clear (deferred to the render) forgets the strokes.
    phosphor_raster::render(&mut fb, &front, &[], &RenderOptions::default());
    assert!(fb.alpha(0.0).iter().all(|&a| a == 0.0));
}
