//! Unit tests of `setup.rs`: row rounding, edge functions and planes.
use super::*;
use crate::traverse::Planes;

#[test]
fn first_row_follows_ceil_y_minus_half() {
    // y = 0.5 exactly on the centre of row 0: included (top edge).
    assert_eq!(first_row_at_or_below(128), 0);
    assert_eq!(first_row_at_or_below(129), 1);
    assert_eq!(first_row_at_or_below(0), 0);
    assert_eq!(first_row_at_or_below(-300), -1);
    // The shift equals the exact ceiling everywhere, negative values and the extremes
    // of the fixed-point range included.
    let limit = 1i64 << 28;
    for fy in (-2000..2000).chain([-limit, -limit + 1, limit - 1, limit]) {
        assert_eq!(
            first_row_at_or_below(fy),
            ceil_div(fy - HALF, SUBPIXEL_ONE),
            "{fy}"
        );
    }
    assert_eq!(ceil_div(-5, 2), -2);
    assert_eq!(ceil_div(5, 2), 3);
}

#[test]
fn planes_only_set_up_matches_the_full_one_bit_for_bit() {
    let pos = |x: f64, y: f64, depth: f64, inv_w: f64| ScreenPos {
        fx: (x * 256.0) as i32,
        fy: (y * 256.0) as i32,
        depth,
        inv_w,
    };
    let p = [
        pos(3.3, 1.7, 0.25, 0.9),
        pos(40.1, 9.2, 0.5, 0.4),
        pos(12.6, 30.9, 0.75, 0.7),
    ];
    let a: [[f32; 4]; 3] = [
        [1.0, -2.0, 0.3, 7.0],
        [0.5, 4.0, -0.1, 2.0],
        [3.0, 0.0, 0.9, -5.0],
    ];
    // Both windings (the set-up reorders the vertices of one of them).
    for order in [[0, 1, 2], [0, 2, 1]] {
        let (p, a) = (order.map(|i| p[i]), order.map(|i| &a[i][..]));
        let mut full = RasterTri::empty();
        assert!(full.set(p, a, 4, true));
        let planes = Planes::set(p, a, 4, true).expect("a triangle with area");
        let bits = |t: &Planes| {
            let mut v: Vec<u64> = vec![t.origin.0.to_bits(), t.origin.1.to_bits()];
            v.extend(t.inv_w.iter().map(|x| x.to_bits()));
            let attrs = t.attr0.iter().chain(&t.attr_dx).chain(&t.attr_dy);
            v.extend(attrs.map(|x| u64::from(x.to_bits())));
            v
        };
        assert_eq!(bits(&Planes::of(&full)), bits(&planes), "{order:?}");
        assert!(full.attr_dx[0] != 0.0 && full.inv_w[1] != 0.0);
        // The gradient slots alike.
        let (mut with, mut planes) = (full, planes);
        with.add_gradients(1);
        planes.add_gradients(4, true, 1);
        assert_eq!(bits(&Planes::of(&with)), bits(&planes), "{order:?}");
        assert!(with.n > 4 && planes.attr0[4] == full.attr_dx[1]);
    }
    let line = [p[0], p[0], p[1]];
    assert!(Planes::set(line, [&[]; 3], 0, true).is_none());
}
