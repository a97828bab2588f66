//! Small triangles in lanes against the one-triangle path: the same depths (bit for bit) and
//! the same nearest triangle at every pixel of a band, at every lane width this CPU runs.

use glam::Vec3;

use super::*;
use crate::bin::TriRec;
use crate::clip::Attrs;
use crate::coverage::{BandTarget, depth_at, depth_only};
use crate::setup::RasterTri;
use crate::traverse::SpanShade;

const WIDTH: u32 = 37;
const BAND: (i64, i64) = (32, 48);

/// A small deterministic generator (xorshift).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo) as u64) as i32
    }
}

/// Vertices for `n` triangles: most small (within a few pixels, some exactly on pixel
/// centres or sharing a row), some near the limits of "small", some large, some degenerate,
/// some straddling the band's or the image's edges.
fn triangles(rng: &mut Rng, n: usize) -> Vec<ScreenPos> {
    let one = SUBPIXEL_ONE as i32;
    let mut pos = Vec::new();
    for t in 0..n {
        let cx = rng.range(-4 * one, (WIDTH as i32 + 4) * one);
        let cy = rng.range(26 * one, 54 * one);
        let reach = match t % 8 {
            0 => 4 * one,
            1 => 8 * one,
            2 => 40 * one,
            3 => one / 2,
            4 => 7 * one,
            _ => 2 * one,
        };
        let mut corner = || {
            let (mut x, mut y) = (
                cx + rng.range(-reach, reach + 1),
                cy + rng.range(-reach, reach + 1),
            );
            if t % 11 == 0 {
                // On pixel centres: ties on edges and on the fill rule.
                x = x / one * one + one / 2;
                y = y / one * one + one / 2;
            }
            ScreenPos {
                fx: x,
                fy: y,
                depth: f64::from(rng.range(0, 1 << 20)) / f64::from(1 << 20) * 0.9 + 0.05,
                inv_w: 1.0,
            }
        };
        let mut c = [corner(), corner(), corner()];
        if t % 13 == 0 {
            // Collinear: no area.
            c[2].fx = 2 * c[1].fx - c[0].fx;
            c[2].fy = 2 * c[1].fy - c[0].fy;
        }
        pos.extend(c);
    }
    pos
}

/// The band drawn record by record through the one-triangle path: depths and ids.
fn reference(pos: &[ScreenPos], recs: &[TriRec]) -> (Vec<f32>, Vec<u64>) {
    let len = WIDTH as usize * (BAND.1 - BAND.0) as usize;
    let (mut color, mut depth, mut ids) = (vec![Vec3::ZERO; len], vec![1.0f32; len], vec![0; len]);
    let mut extents = vec![(u32::MAX, 0); (BAND.1 - BAND.0) as usize];
    let mut target = BandTarget::new(&mut color, &mut depth, WIDTH, BAND.0, false);
    let mut t = RasterTri::empty();
    for (id, r) in recs.iter().enumerate() {
        let p = r.v.map(|i| pos[i as usize]);
        if t.set(p, [&[]; 3], 0, true) {
            depth_only(&t, &mut target, &mut ids, &mut extents, id as u64 + 1);
        }
    }
    (depth, ids)
}

/// The band drawn eight records at a time as the depth pass draws it: small ones from the
/// lanes, the others through the one-triangle path. Also returns how many were small, and
/// checks that the marks hold every pixel written.
fn grouped<R: RowLanes>(r: R, pos: &[ScreenPos], recs: &[TriRec]) -> (Vec<f32>, Vec<u64>, usize) {
    let len = WIDTH as usize * (BAND.1 - BAND.0) as usize;
    let (mut color, mut depth, mut ids) = (vec![Vec3::ZERO; len], vec![1.0f32; len], vec![0; len]);
    let mut extents = vec![(u32::MAX, 0); (BAND.1 - BAND.0) as usize];
    let mut target = BandTarget::new(&mut color, &mut depth, WIDTH, BAND.0, false);
    let mut t = RasterTri::empty();
    let mut small = 0;
    for (g_at, group) in recs.chunks(LANES).enumerate() {
        let g = Group::set(group, pos, WIDTH, BAND);
        let mut marks = Marks::NONE;
        for (k, rec) in group.iter().enumerate() {
            let id = (g_at * LANES + k) as u64 + 1;
            match g.kind[k] {
                Kind::Small => {
                    small += 1;
                    let band = (&mut *target.depth, WIDTH as usize, BAND.0);
                    let passed = g.draw(r, k, band, Some((&mut ids[..], id)), |_, _, _| {});
                    if passed > 0 {
                        marks.add(g.bounds(k));
                    }
                }
                Kind::Empty => {
                    // Nothing in the band: the one-triangle path agrees.
                    let p = rec.v.map(|i| pos[i as usize]);
                    let mut probe = RasterTri::empty();
                    if probe.set(p, [&[]; 3], 0, true) {
                        let mut none = true;
                        crate::coverage::for_each_span(&probe, WIDTH, BAND.0, BAND.1, |_, _, _| {
                            none = false;
                        });
                        assert!(none, "an empty record covers pixels: {p:?}");
                    }
                }
                Kind::Other => {
                    let p = rec.v.map(|i| pos[i as usize]);
                    if t.set(p, [&[]; 3], 0, true) {
                        depth_only(&t, &mut target, &mut ids, &mut extents, id);
                    }
                }
            }
        }
        marks.apply(&mut extents, BAND.0);
    }
    // Every pixel written lies inside its row's extent.
    for (i, &id) in ids.iter().enumerate() {
        let (row, x) = (i / WIDTH as usize, (i % WIDTH as usize) as u32);
        if id != 0 {
            let (lo, hi) = extents[row];
            assert!(
                lo <= x && x < hi,
                "pixel {x} of row {row} outside its extent {lo}..{hi}"
            );
        }
    }
    (depth, ids, small)
}

fn check<R: RowLanes>(r: R, seed: u64) {
    let mut rng = Rng(seed);
    let pos = triangles(&mut rng, 600);
    let recs: Vec<TriRec> = (0..pos.len() as u32 / 3)
        .map(|t| TriRec {
            v: [3 * t, 3 * t + 1, 3 * t + 2],
            tri: t,
        })
        .collect();
    let (want_depth, want_ids) = reference(&pos, &recs);
    let (depth, ids, small) = grouped(r, &pos, &recs);
    assert!(
        small > recs.len() / 4,
        "only {small} of {} were small",
        recs.len()
    );
    assert!(
        want_ids.iter().filter(|&&i| i != 0).count() > 200,
        "too little drawn"
    );
    for (i, (a, b)) in want_depth.iter().zip(&depth).enumerate() {
        assert_eq!(a.to_bits(), b.to_bits(), "depth of band pixel {i}");
    }
    assert_eq!(want_ids, ids);
}

#[test]
fn small_triangles_in_lanes_draw_what_one_at_a_time_draws() {
    for seed in [1, 0x9e37_79b9_7f4a_7c15, 42, 7_777_777] {
        check(Portable, seed);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = phosphor_lighting::Avx2::detect() {
            avx2.run(|a: phosphor_lighting::Avx2| check(Avx2Rows::new(a.v3()), seed));
        }
    }
}

#[test]
fn a_record_with_a_clipped_or_missing_vertex_is_left_to_the_one_triangle_path() {
    let one = SUBPIXEL_ONE as i32;
    let p = |x: i32, y: i32| ScreenPos {
        fx: x * one,
        fy: y * one,
        depth: 0.5,
        inv_w: 1.0,
    };
    let pos = [p(3, 33), p(5, 33), p(4, 36), ScreenPos::NONE];
    let recs = [
        TriRec {
            v: [0, 1, 2],
            tri: 0,
        },
        TriRec {
            v: [0, 1, 3],
            tri: 1,
        },
        TriRec {
            v: [0, 1, crate::bin::EXTRA_VERTEX],
            tri: 2,
        },
        TriRec {
            v: [0, 1, 99],
            tri: 3,
        },
    ];
    let g = Group::set(&recs, &pos, WIDTH, BAND);
    assert_eq!(
        g.kind[..4],
        [Kind::Small, Kind::Other, Kind::Other, Kind::Other]
    );
}

#[test]
fn the_depth_formula_is_the_one_the_lanes_compute() {
    // `depth_at` is row part plus column part; the lanes add the same two f64 values.
    let one = SUBPIXEL_ONE as i32;
    let v = |x: i32, y: i32, d: f64| ScreenPos {
        fx: x,
        fy: y,
        depth: d,
        inv_w: 1.0,
    };
    let pos = [
        v(3 * one + 17, 33 * one + 5, 0.1),
        v(9 * one, 35 * one, 0.7),
        v(4 * one, 40 * one, 0.3),
    ];
    let mut t = RasterTri::empty();
    assert!(t.set(pos, [&[]; 3], 0, true));
    let recs = [TriRec {
        v: [0, 1, 2],
        tri: 0,
    }];
    let g = Group::set(&recs, &pos, WIDTH, BAND);
    assert_eq!(g.kind[0], Kind::Small);
    let mut depth = vec![1.0f32; WIDTH as usize * 16];
    let mut rows = Vec::new();
    g.draw(
        Portable,
        0,
        (&mut depth, WIDTH as usize, BAND.0),
        None::<(&mut [u64], u64)>,
        |at, [_, passed], xy| {
            rows.push((at, passed, xy));
        },
    );
    let mut seen = 0;
    for (at, passed, (x0, y)) in rows {
        for_bits(passed, |j| {
            let i = at + j;
            let x = (i % WIDTH as usize) as i64;
            assert_eq!(
                (x, y),
                (x0 + j as i64, (i / WIDTH as usize) as i64 + BAND.0)
            );
            assert_eq!(
                depth[i].to_bits(),
                (depth_at(&t, x, y) as f32).to_bits(),
                "({x}, {y})"
            );
            seen += 1;
        });
    }
    assert!(seen > 10, "{seen} pixels");
}

/// Writes `w` times the first three attributes as the colour: what `gouraud`'s pixel stage
/// does, without a shader.
struct ThreeAttrs;

impl SpanShade for ThreeAttrs {
    const ATTRS: usize = 3;
    type Span = ();
    fn span(&self, _: f64, _: f64) {}
    fn pixel(&mut self, _: &(), idx: usize, (a, w): (&Attrs, f32), _: (i64, i64), c: &mut [Vec3]) {
        c[idx] = Vec3::new(a[0] * w, a[1] * w, a[2] * w);
    }
    fn step(_: &mut ()) {}
}

/// Records in order, depth-tested and shaded as they are drawn, with three perspective-correct
/// attributes: through the one-triangle traversal (`lanes` `None`), or eight at a time with
/// the small ones from the lanes `r` (their planes from [`Group::planes`]). The band's colours
/// and depths.
fn shaded<R: RowLanes>(
    r: Option<R>,
    pos: &[ScreenPos],
    attrs: &[f32],
    recs: &[TriRec],
) -> (Vec<Vec3>, Vec<f32>) {
    let len = WIDTH as usize * (BAND.1 - BAND.0) as usize;
    let (mut color, mut depth) = (vec![Vec3::ZERO; len], vec![1.0f32; len]);
    let mut target = BandTarget::new(&mut color, &mut depth, WIDTH, BAND.0, false);
    let mut t = RasterTri::empty();
    let of = |v: [u32; 3]| v.map(|i| &attrs[3 * i as usize..3 * i as usize + 3]);
    let mut one = |rec: &TriRec, target: &mut BandTarget| {
        if t.set(rec.v.map(|i| pos[i as usize]), of(rec.v), 3, true) {
            crate::traverse::traverse(&t, &mut ThreeAttrs, target);
        }
    };
    for group in recs.chunks(LANES) {
        let Some(r) = r else {
            group.iter().for_each(|rec| one(rec, &mut target));
            continue;
        };
        let mut basis = Basis::new();
        let g = Group::set_planes(group, pos, WIDTH, BAND, &mut basis);
        for (k, rec) in group.iter().enumerate() {
            match g.kind[k] {
                Kind::Small => {
                    let inv_w = rec.v.map(|i| pos[i as usize].inv_w);
                    let a = of(rec.v).map(|a| [a[0], a[1], a[2], 0.0]);
                    let planes = g.planes((&basis, k), (inv_w, true), a);
                    let band = (&mut *target.depth, WIDTH as usize, BAND.0);
                    let shade = (&planes, &mut ThreeAttrs);
                    g.draw_shaded(r, k, band, shade, target.color);
                }
                Kind::Empty => {}
                Kind::Other => one(rec, &mut target),
            }
        }
    }
    (color, depth)
}

fn shaded_alike<R: RowLanes>(r: R, seed: u64) {
    let mut rng = Rng(seed);
    let mut pos = triangles(&mut rng, 600);
    for p in &mut pos {
        // `1/w` from 0.1 to 4: perspective that differs across each triangle.
        p.inv_w = 0.1 + f64::from(rng.range(0, 1 << 16)) / f64::from(1 << 16) * 3.9;
    }
    let attrs: Vec<f32> = (0..3 * pos.len())
        .map(|_| rng.range(-1000, 1000) as f32 / 317.0)
        .collect();
    let recs: Vec<TriRec> = (0..pos.len() as u32 / 3)
        .map(|t| TriRec {
            v: [3 * t, 3 * t + 1, 3 * t + 2],
            tri: t,
        })
        .collect();
    let (want_color, want_depth) = shaded(None::<R>, &pos, &attrs, &recs);
    let (color, depth) = shaded(Some(r), &pos, &attrs, &recs);
    let drawn = want_color.iter().filter(|c| **c != Vec3::ZERO).count();
    assert!(drawn > 200, "too little drawn: {drawn}");
    for (i, (a, b)) in want_depth.iter().zip(&depth).enumerate() {
        assert_eq!(a.to_bits(), b.to_bits(), "depth of band pixel {i}");
    }
    for (i, (a, b)) in want_color.iter().zip(&color).enumerate() {
        let bits = |c: &Vec3| c.to_array().map(f32::to_bits);
        assert_eq!(
            bits(a),
            bits(b),
            "colour of band pixel {i}: {a} against {b}"
        );
    }
}

#[test]
fn interpolated_pixels_from_the_lanes_are_the_traversals_bit_for_bit() {
    for seed in [5, 0x853c_49e6_748f_ea9b, 2024] {
        shaded_alike(Portable, seed);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = phosphor_lighting::Avx2::detect() {
            avx2.run(|a: phosphor_lighting::Avx2| shaded_alike(Avx2Rows::new(a.v3()), seed));
        }
    }
}

/// The planes of small triangles from the lanes' basis over `L` lanes with `n` attributes,
/// against [`Planes::set`]'s, bit for bit in every lane (the padding's zeros, of either sign,
/// included), with and without perspective. Returns the triangles checked.
fn planes_alike<const L: usize>(n: usize) -> usize {
    let mut rng = Rng(99 + n as u64);
    let pos = triangles(&mut rng, 400);
    let mut checked = 0;
    for (t, tri) in pos.chunks_exact(3).enumerate() {
        let mut p = [tri[0], tri[1], tri[2]];
        for (j, v) in p.iter_mut().enumerate() {
            v.inv_w = 0.25 + (t * 3 + j) as f64 * 0.001;
        }
        let a: [[f32; L]; 3] = std::array::from_fn(|j| {
            let v = |q: usize| ((t * 7 + j * 3 + q) % 23) as f32 / 7.0 - 1.5;
            std::array::from_fn(|q| if q < n { v(q) } else { 0.0 })
        });
        let recs = [TriRec {
            v: [0, 1, 2],
            tri: 0,
        }];
        let mut basis = Basis::new();
        let g = Group::set_planes(&recs, &p, WIDTH, BAND, &mut basis);
        basis.keep(&g);
        assert_eq!(basis.small(0), g.kind[0] == Kind::Small);
        if g.kind[0] != Kind::Small {
            continue;
        }
        let inv_w = [p[0].inv_w, p[1].inv_w, p[2].inv_w];
        for perspective in [true, false] {
            let inv_w = (inv_w, perspective && n > 0);
            let want = Planes::set(p, [&a[0][..n], &a[1][..n], &a[2][..n]], n, perspective)
                .expect("a small triangle has area");
            // From the group just set (gouraud's one pass) and from the kept basis (the
            // by-pixel pass's).
            for got in [
                g.planes((&basis, 0), inv_w, a),
                basis.planes::<L>(0, inv_w, a),
            ] {
                assert_eq!(got.origin, want.origin);
                assert_eq!(got.inv_w.map(f64::to_bits), want.inv_w.map(f64::to_bits));
                for (x, y) in [
                    (got.attr0, want.attr0),
                    (got.attr_dx, want.attr_dx),
                    (got.attr_dy, want.attr_dy),
                ] {
                    let bits = |a: &Attrs| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&x), bits(&y), "triangle {t}, {n} attributes");
                }
            }
        }
        checked += 1;
    }
    checked
}

#[test]
fn a_small_triangles_planes_are_the_set_ups_bit_for_bit() {
    // As the set-up pads them: no lanes, four (gouraud's three attributes), eight (phong's
    // six).
    for checked in [
        planes_alike::<0>(0),
        planes_alike::<4>(3),
        planes_alike::<8>(6),
    ] {
        assert!(checked > 100, "{checked} small triangles");
    }
}

/// Rows written by `fill_in` with lanes `r`, a colour and an id per step, against writing
/// each passed pixel one by one: the same pixels at every step, windows at the row's end
/// included.
fn fill_matches_one_by_one<R: RowLanes>(r: R, seed: u64) {
    let mut rng = Rng(seed);
    let len = WIDTH as usize;
    let (mut color, mut ids) = (vec![Vec3::ZERO; len], vec![0u64; len]);
    let (mut want_color, mut want_ids) = (color.clone(), ids.clone());
    for step in 1..=400u64 {
        let at = rng.range(0, WIDTH as i32) as usize;
        let bits = (rng.next() & 0xffff) as u32;
        let rgb = Vec3::new(step as f32, -(step as f32), 0.5 / step as f32);
        let id = step << 40 | rng.next() >> 40;
        fill_in(r, &mut color, at, bits, rgb);
        fill_in(r, &mut ids, at, bits, id);
        for j in (0..16).filter(|j| bits >> j & 1 == 1 && at + j < len) {
            (want_color[at + j], want_ids[at + j]) = (rgb, id);
        }
        assert_eq!(
            want_ids, ids,
            "ids after step {step} (at {at}, bits {bits:#x})"
        );
        let bits_of = |c: &[Vec3]| -> Vec<[u32; 3]> {
            c.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
        };
        assert_eq!(
            bits_of(&want_color),
            bits_of(&color),
            "colours after step {step}"
        );
    }
}

#[test]
fn rows_filled_eight_columns_at_a_time_set_exactly_the_passed_pixels() {
    for seed in [3, 0x2545_f491_4f6c_dd1d] {
        fill_matches_one_by_one(Portable, seed);
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = phosphor_lighting::Avx2::detect() {
            avx2.run(|a: phosphor_lighting::Avx2| {
                fill_matches_one_by_one(Avx2Rows::new(a.v3()), seed)
            });
        }
    }
}
