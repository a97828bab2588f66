//! Scan-line interpolation (Gouraud 1971): the traversal's incremental values equal the closed
//! forms `I4 = (y4 - y2)/(y1 - y2) I1 + (y1 - y4)/(y1 - y2) I2`, `I5` likewise on the other edge,
//! and `Ip = (x5 - xp)/(x5 - x4) I4 + (xp - x4)/(x5 - x4) I5`.

use glam::Vec3;

use crate::batch::AttrLanes;
use crate::bypixel::ByPixel;
use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::{BandTarget, depth_only};
use crate::framebuffer::clamp_color;
use crate::setup::{RasterTri, ScreenVertex};
use crate::traverse::{Planes, SpanShade, traverse};

struct Record;

impl SpanShade for Record {
    const ATTRS: usize = 1;
    type Span = ();
    fn span(&self, _: f64, _: f64) {}
    fn pixel(&mut self, _: &(), idx: usize, (a, w): (&Attrs, f32), _: (i64, i64), c: &mut [Vec3]) {
        c[idx] = clamp_color(Vec3::splat(a[0] * w));
    }
    fn step(_: &mut ()) {}
}

fn vertex(x: f64, y: f64, i: f32) -> ScreenVertex {
    vertex_at_depth(x, y, i, 0.5)
}

fn vertex_at_depth(x: f64, y: f64, i: f32, depth: f64) -> ScreenVertex {
    let mut attrs = [0.0; MAX_ATTRS];
    attrs[0] = i;
    let (fx, fy) = ((x * 256.0).round() as i64, (y * 256.0).round() as i64);
    ScreenVertex {
        fx,
        fy,
        x: fx as f64 / 256.0,
        y: fy as f64 / 256.0,
        depth,
        inv_w: 1.0,
        rhw: 1.0,
        attrs,
    }
}

/// Gouraud's closed form at pixel centre (xp, yp), from the two edges the scan line crosses.
fn closed_form(v: &[(f64, f64, f64); 3], xp: f64, yp: f64) -> f64 {
    let mut hits = Vec::new();
    for (a, b) in [(0, 1), (1, 2), (0, 2)] {
        let ((x1, y1, i1), (x2, y2, i2)) = (v[a], v[b]);
        if y1 == y2 || yp < y1.min(y2) || yp > y1.max(y2) {
            continue;
        }
        // Gouraud 1971: I4 = (y4 - y2)/(y1 - y2) I1 + (y1 - y4)/(y1 - y2) I2 (same for x).
        let i = (yp - y2) / (y1 - y2) * i1 + (y1 - yp) / (y1 - y2) * i2;
        let x = (yp - y2) / (y1 - y2) * x1 + (y1 - yp) / (y1 - y2) * x2;
        hits.push((x, i));
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let ((x4, i4), (x5, i5)) = (hits[0], hits[hits.len() - 1]);
    if x5 == x4 {
        return i4;
    }
    (x5 - xp) / (x5 - x4) * i4 + (xp - x4) / (x5 - x4) * i5
}

#[test]
fn scanline_increments_reproduce_gouraud_closed_form_i4_i5_ip() {
    let (w, h) = (40u32, 30u32);
    for tri in [
        [(5.0, 2.0, 0.2), (35.0, 12.25, 0.9), (12.0, 27.5, 0.5)],
        [(30.5, 1.5, 1.0), (2.25, 20.0, 0.0), (33.0, 28.75, 0.4)],
        [(3.0, 3.0, 0.7), (37.0, 3.0, 0.1), (20.0, 26.0, 0.95)],
    ] {
        let verts = tri.map(|(x, y, i)| vertex(x, y, i as f32));
        let snapped = verts.map(|v| (v.x, v.y, v.attrs[0] as f64));
        let tri = RasterTri::new([&verts[0], &verts[1], &verts[2]], 1, false).unwrap();
        let mut color = vec![Vec3::splat(-1.0); (w * h) as usize];
        let mut depth = vec![1.0; (w * h) as usize];
        let mut target = BandTarget::new(&mut color, &mut depth, w, 0, false);
        let n = traverse(&tri, &mut Record, &mut target);
        assert!(n > 100);
        let mut checked = 0;
        for y in 0..h {
            for x in 0..w {
                let c = color[(y * w + x) as usize].x;
                if c < 0.0 {
                    continue;
                }
                let expected = closed_form(&snapped, x as f64 + 0.5, y as f64 + 0.5);
                assert!(
                    (c as f64 - expected).abs() < 1e-5,
                    "({x}, {y}): {c} vs {expected}"
                );
                checked += 1;
            }
        }
        assert_eq!(checked, n);
    }
}

#[test]
fn by_pixel_shading_reproduces_the_closed_form_of_the_nearest_triangle() {
    // Two crossing triangles at different tilts in depth: each pixel of the depth pass's id
    // buffer is shaded from the planes of the triangle it names, runs restarting where the
    // nearest triangle changes along a row. Every shaded pixel must carry the closed form of
    // its own triangle, and the count must be the pixels the depth pass left to each.
    let (w, h) = (48u32, 32u32);
    let tris = [
        [
            (2.0, 1.0, 0.2, 0.2),
            (45.0, 9.25, 0.9, 0.8),
            (10.0, 30.5, 0.5, 0.5),
        ],
        [
            (40.5, 2.5, 1.0, 0.9),
            (4.25, 18.0, 0.0, 0.1),
            (38.0, 29.75, 0.4, 0.3),
        ],
    ];
    let verts = tris.map(|t| t.map(|(x, y, i, d)| vertex_at_depth(x, y, i as f32, d)));
    let snapped = verts.map(|v| v.map(|v| (v.x, v.y, v.attrs[0] as f64)));
    let raster = verts.map(|v| RasterTri::new([&v[0], &v[1], &v[2]], 1, false).unwrap());
    let mut color = vec![Vec3::splat(-1.0); (w * h) as usize];
    let mut depth = vec![1.0; (w * h) as usize];
    let mut ids = vec![0u64; (w * h) as usize];
    let mut extents = vec![(u32::MAX, 0u32); h as usize];
    let epoch = 1u64 << 32;
    let mut target = BandTarget::new(&mut color, &mut depth, w, 0, false);
    for (k, t) in raster.iter().enumerate() {
        assert!(depth_only(t, &mut target, &mut ids, &mut extents, epoch + k as u64) > 0);
    }
    let planes = raster.map(|t| Planes::of(&t));
    let pass = ByPixel {
        slot: &[0, 1],
        planes: &planes,
        ids: &ids,
        epoch,
        extents: &extents,
        width: w,
        y0: 0,
        n: 1,
        perspective: false,
        block: 1,
        ceiling: 1.0,
        whole: &[],
    };
    let rows = |a: &[Attrs; 4], _, _| a.map(|a| Vec3::splat(a[0]));
    let lanes = |a: &AttrLanes, _, _| std::array::from_fn(|i| Vec3::splat(a[0][i]));
    let n = pass.shade::<4>(&mut color, None, (&rows, &lanes));
    let owned: Vec<usize> = (0..2)
        .map(|k| ids.iter().filter(|&&id| id == epoch + k as u64).count())
        .collect();
    assert!(owned[0] > 50 && owned[1] > 50, "both visible: {owned:?}");
    assert_eq!(n as usize, owned[0] + owned[1]);
    for y in 0..h {
        for x in 0..w {
            let idx = (y * w + x) as usize;
            let c = color[idx].x;
            let Some(k) = ids[idx].checked_sub(epoch) else {
                assert_eq!(c, -1.0, "({x}, {y}) shaded without a triangle");
                continue;
            };
            let expected = closed_form(&snapped[k as usize], x as f64 + 0.5, y as f64 + 0.5);
            assert!(
                (c as f64 - expected).abs() < 1e-5,
                "({x}, {y}) of triangle {k}: {c} vs {expected}"
            );
        }
    }
}

#[test]
fn attributes_a_triangle_was_not_set_up_with_read_as_zero() {
    // The traversal steps a kernel's attribute lanes whole, whatever the planes hold past the
    // set-up's count; a triangle set up with fewer attributes than the kernel reads must still
    // hand it zeros there, not what an earlier set-up left in the planes.
    let (w, h) = (24u32, 16u32);
    let verts = [
        vertex(2.0, 1.0, 0.75),
        vertex(21.0, 4.5, 0.25),
        vertex(6.0, 14.0, 0.5),
    ];
    let mut tri = RasterTri::new([&verts[0], &verts[1], &verts[2]], 1, false).unwrap();
    assert!(tri.attr0[0] != 0.0 && tri.attr_dx[0] != 0.0);
    // Set up again in place with no attributes: the old plane stays in the arrays.
    let p = verts.map(|v| v.pos());
    assert!(tri.set(p, [&[]; 3], 0, false));
    assert_eq!(tri.n, 0);
    let mut color = vec![Vec3::splat(-1.0); (w * h) as usize];
    let mut depth = vec![1.0; (w * h) as usize];
    let mut target = BandTarget::new(&mut color, &mut depth, w, 0, false);
    let n = traverse(&tri, &mut Record, &mut target);
    assert!(n > 50);
    let drawn: Vec<f32> = color.iter().map(|c| c.x).filter(|&c| c >= 0.0).collect();
    assert_eq!(drawn.len() as u64, n);
    assert!(drawn.iter().all(|&c| c == 0.0), "{drawn:?}");
}
