//! Tests of [`super`]: tiling, winding, and the work large and self-intersecting polygons take.

use super::*;

fn area(points: &[Vec3], tris: &[[usize; 3]]) -> f32 {
    tris.iter()
        .map(|t| {
            let (a, b, c) = (points[t[0]], points[t[1]], points[t[2]]);
            (b - a).cross(c - a).z * 0.5
        })
        .sum()
}

#[test]
fn concave_polygon_is_ear_clipped_not_fanned() {
    // An arrow / chevron: fanning from corner 0 would cover area outside the polygon.
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ];
    // A fan from corner 0 would use the diagonal 0-2, which lies outside the polygon.
    let tris = triangulate(&pts);
    assert_eq!(tris.len(), 2);
    // Every triangle is counter-clockwise (same winding as the polygon) and the total area
    // equals the polygon's (1.0): no triangle outside it.
    for t in &tris {
        assert!(area(&pts, &[*t]) > 0.0);
    }
    assert!((area(&pts, &tris) - 1.0).abs() < 1e-6);
}

#[test]
fn clockwise_polygon_keeps_its_winding() {
    let pts = [Vec3::ZERO, Vec3::Y, Vec3::new(1.0, 1.0, 0.0), Vec3::X];
    let tris = triangulate(&pts);
    assert!((area(&pts, &tris) + 1.0).abs() < 1e-6);
}

#[test]
fn degenerate_and_huge_polygons_are_fanned_with_n_minus_2_triangles() {
    assert_eq!(triangulate(&[Vec3::ZERO; 5]).len(), 3);
    let big: Vec<Vec3> = (0..MAX_EAR_CLIPPED + 1)
        .map(|i| {
            let a = i as f32 / (MAX_EAR_CLIPPED + 1) as f32 * std::f32::consts::TAU;
            Vec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    assert_eq!(triangulate(&big).len(), MAX_EAR_CLIPPED - 1);
}

/// Checks that `tris` tile the simple counter-clockwise polygon `pts`: `n - 2` triangles,
/// each counter-clockwise (none folded outside), adding up to the polygon's area.
fn assert_tiles(pts: &[Vec3], tris: &[[usize; 3]]) {
    assert_eq!(tris.len(), pts.len() - 2);
    let shoelace: f64 = (0..pts.len())
        .map(|i| {
            let (a, b) = (pts[i].as_dvec3(), pts[(i + 1) % pts.len()].as_dvec3());
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5;
    let mut sum = 0.0;
    for t in tris {
        let [a, b, c] = t.map(|i| pts[i].as_dvec3());
        let twice = (b - a).cross(c - a).z;
        assert!(twice > 0.0, "triangle {t:?} is folded or flat");
        sum += twice * 0.5;
    }
    assert!(
        (sum - shoelace).abs() < 1e-9 * shoelace.abs().max(1.0),
        "{sum} vs {shoelace}"
    );
}

#[test]
fn huge_convex_polygon_is_clipped_without_a_fan() {
    let n = 10_000;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            Vec3::new(a.cos() as f32, a.sin() as f32, 0.0)
        })
        .collect();
    let tris = triangulate(&pts);
    assert_tiles(&pts, &tris);
    // Every other corner per lap: no corner is shared by more than a few triangles per
    // halving of the polygon (a fan would give one corner n - 2 of them).
    let mut valence = vec![0usize; n];
    for t in &tris {
        for &i in t {
            valence[i] += 1;
        }
    }
    let most = valence.iter().copied().max().unwrap_or(0);
    assert!(most <= 2 * 14 + 2, "a corner is shared by {most} triangles");
}

#[test]
fn huge_comb_is_ear_clipped_correctly() {
    // A comb: 2000 tapered teeth of height 10 on a bar, 6003 corners, deeply concave;
    // a fan from any corner would cover the gaps between the teeth.
    let teeth = 2000;
    let right = 2.0 * teeth as f32;
    let mut pts = vec![
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(right, -1.0, 0.0),
        Vec3::new(right, 0.0, 0.0),
    ];
    for k in (0..teeth).rev() {
        let x = 2.0 * k as f32;
        pts.push(Vec3::new(x + 1.5, 10.0, 0.0));
        pts.push(Vec3::new(x + 0.5, 10.0, 0.0));
        pts.push(Vec3::new(x, 0.0, 0.0));
    }
    let tris = triangulate(&pts);
    assert_tiles(&pts, &tris);
}

#[test]
fn huge_star_is_ear_clipped_correctly() {
    let spikes = 5000;
    let pts: Vec<Vec3> = (0..2 * spikes)
        .map(|i| {
            let a = i as f64 / (2 * spikes) as f64 * std::f64::consts::TAU;
            let r = if i % 2 == 0 { 2.0 } else { 1.0 };
            Vec3::new((r * a.cos()) as f32, (r * a.sin()) as f32, 0.0)
        })
        .collect();
    let tris = triangulate(&pts);
    assert_tiles(&pts, &tris);
}

proptest::proptest! {
    #[test]
    fn star_shaped_polygons_of_any_size_are_tiled(
        radii in proptest::collection::vec(0.2f64..2.0, 4..300),
    ) {
        // Corners at increasing angles around the origin: simple and star-shaped, concave
        // wherever a radius dips; above 32 corners the indexed pass runs.
        let n = radii.len();
        let pts: Vec<Vec3> = radii
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                Vec3::new((r * a.cos()) as f32, (r * a.sin()) as f32, 0.0)
            })
            .collect();
        let tris = triangulate(&pts);
        assert_tiles(&pts, &tris);
    }

    #[test]
    fn any_polygon_gives_n_minus_2_triangles_of_its_own_corners(
        pts in proptest::collection::vec((-3i8..3, -3i8..3, -1i8..1), 3..120),
    ) {
        // Repeated, collinear and crossing corners: never a panic, always n - 2 triangles.
        let pts: Vec<Vec3> = pts
            .iter()
            .map(|&(x, y, z)| Vec3::new(f32::from(x), f32::from(y), f32::from(z)))
            .collect();
        let tris = triangulate(&pts);
        proptest::prop_assert_eq!(tris.len(), pts.len() - 2);
        proptest::prop_assert!(tris.iter().flatten().all(|&i| i < pts.len()));
    }
}

/// `n` corners scattered at random in the unit square: a polygon that crosses itself
/// thousands of times.
fn random_polygon(n: usize) -> Vec<Vec3> {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n).map(|_| Vec3::new(next(), next(), 0.0)).collect()
}

#[test]
fn self_intersecting_polygon_takes_near_linear_work() {
    // Before ears were pruned by their edges, 20,000 random corners took 120 units of work
    // per corner and 640,000 took 53 s: each long thin ear visited most of the tree.
    let n = 20_000;
    let pts = random_polygon(n);
    let q = project(&pts).expect("a normal");
    let (tris, work) = indexed_counted(&q, u64::MAX);
    assert_eq!(tris.len(), n - 2);
    assert!(tris.iter().flatten().all(|&i| i < n));
    assert!(
        work <= 32 * n as u64,
        "{} units per corner",
        work / n as u64
    );
}

#[test]
fn huge_comb_takes_near_linear_work() {
    // 10,000 teeth: 710 units of work per corner before ears were pruned by their edges.
    let teeth = 10_000;
    let mut pts = vec![
        Vec3::new(0.0, -1.0, 0.0),
        Vec3::new(2.0 * teeth as f32, -1.0, 0.0),
        Vec3::new(2.0 * teeth as f32, 0.0, 0.0),
    ];
    for k in (0..teeth).rev() {
        let x = 2.0 * k as f32;
        pts.extend([
            Vec3::new(x + 1.5, 10.0, 0.0),
            Vec3::new(x + 0.5, 10.0, 0.0),
            Vec3::new(x, 0.0, 0.0),
        ]);
    }
    let q = project(&pts).expect("a normal");
    let (tris, work) = indexed_counted(&q, u64::MAX);
    assert_tiles(&pts, &tris);
    let n = pts.len() as u64;
    assert!(work <= 64 * n, "{} units per corner", work / n);
}

#[test]
fn past_the_work_budget_the_rest_is_fanned() {
    let pts = random_polygon(5_000);
    let q = project(&pts).expect("a normal");
    let (tris, work) = indexed_counted(&q, 100);
    assert_eq!(tris.len(), pts.len() - 2);
    // One query may run past the budget; none starts after it.
    assert!(work < 100 + pts.len() as u64, "{work}");
}

#[test]
fn huge_spiral_is_ear_clipped_correctly() {
    // An arm of width 1 winding 10 times (3 units apart): ears only near its two ends.
    let per_side = 3000;
    let turns = 10.0 * std::f64::consts::TAU;
    let point = |t: f64, r0: f64| {
        let theta = t * turns;
        let r = r0 + 3.0 * theta / std::f64::consts::TAU;
        Vec3::new((r * theta.cos()) as f32, (r * theta.sin()) as f32, 0.0)
    };
    let mut pts: Vec<Vec3> = (0..per_side)
        .map(|i| point(i as f64 / per_side as f64, 2.0))
        .collect();
    pts.extend(
        (0..per_side)
            .rev()
            .map(|i| point(i as f64 / per_side as f64, 1.0)),
    );
    let tris = triangulate(&pts);
    assert_tiles(&pts, &tris);
}

#[test]
fn clockwise_huge_polygon_keeps_its_winding() {
    let n = 1000;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let a = -(i as f64) / n as f64 * std::f64::consts::TAU;
            Vec3::new(a.cos() as f32, a.sin() as f32, 0.0)
        })
        .collect();
    let tris = triangulate(&pts);
    assert_eq!(tris.len(), n - 2);
    assert!(area(&pts, &tris) < 0.0);
}
