//! Polygon triangulation by ear clipping, so concave OBJ polygons are not fanned.
//!
//! The polygon is projected onto the plane of its Newell normal (dropping the dominant axis),
//! oriented counter-clockwise, and ears are clipped: a convex corner whose triangle holds no
//! other remaining corner (corners on its boundary count as inside). Output triangles keep the
//! polygon's winding and every path yields `n - 2` triangles.
//!
//! Two passes, by size. Up to [`MAX_EAR_CLIPPED`] corners, each candidate ear is tested against
//! every remaining corner and the walk stays on the corner after a clipped ear. Larger polygons
//! test a candidate only against the corners that are not strictly convex (in a simple polygon,
//! an ear that holds any corner holds one of those), found through a k-d tree, and take
//! candidates from a work queue: a corner that fails is tested again only when a neighbour is
//! clipped (its ear changed) or when the corner found inside its ear is clipped, and the
//! neighbours of a clipped ear go to the back of the queue, so a lap clips every other corner.
//! On convex, star-shaped, comb and spiral polygons the work is near-linear and no corner
//! collects a fan of thousands of triangles. Limits: a polygon whose Newell normal is zero
//! (degenerate or figure-eight), and the remainder of a self-intersecting polygon where no ear
//! exists, are fanned from a corner instead.

use std::collections::VecDeque;

use glam::{DVec2, DVec3, Vec3};

/// Largest polygon clipped by the exhaustive pass (every candidate ear tested against every
/// remaining corner, cubic in the worst case); larger ones take the indexed pass.
pub const MAX_EAR_CLIPPED: usize = 32;

/// Triangulates the polygon `points` (in order, any winding); returns corner indices into
/// `points`, `points.len() - 2` triangles, none for fewer than 3 points.
#[must_use]
pub fn triangulate(points: &[Vec3]) -> Vec<[usize; 3]> {
    let n = points.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    let all: Vec<usize> = (0..n).collect();
    let Some(q) = project(points) else {
        return fan(&all);
    };
    if n <= MAX_EAR_CLIPPED {
        exhaustive(&q)
    } else {
        indexed(&q)
    }
}

/// Triangles fanned from the first corner of `from`.
fn fan(from: &[usize]) -> Vec<[usize; 3]> {
    (1..from.len().saturating_sub(1))
        .map(|i| [from[0], from[i], from[i + 1]])
        .collect()
}

/// Twice the signed area of `abc` (positive: counter-clockwise).
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Whether `x` lies inside triangle `abc` or on its boundary (`abc` counter-clockwise).
fn inside_or_on(a: DVec2, b: DVec2, c: DVec2, x: DVec2) -> bool {
    cross(a, b, x) >= 0.0 && cross(b, c, x) >= 0.0 && cross(c, a, x) >= 0.0
}

/// The polygon projected onto the plane of its Newell normal, counter-clockwise; `None` when
/// that normal is zero or not finite.
fn project(points: &[Vec3]) -> Option<Vec<DVec2>> {
    let n = points.len();
    // Newell's normal: robust for non-planar and concave polygons.
    let p: Vec<DVec3> = points.iter().map(|v| v.as_dvec3()).collect();
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    if !normal.is_finite() || normal == DVec3::ZERO {
        return None;
    }
    // Project dropping the dominant axis; flip one axis when needed so the polygon is CCW.
    let abs = normal.abs();
    let (axis, sign) = if abs.x >= abs.y && abs.x >= abs.z {
        (0, normal.x.signum())
    } else if abs.y >= abs.z {
        (1, normal.y.signum())
    } else {
        (2, normal.z.signum())
    };
    Some(
        p.iter()
            .map(|v| match axis {
                0 => DVec2::new(v.y, v.z * sign),
                1 => DVec2::new(v.z, v.x * sign),
                _ => DVec2::new(v.x, v.y * sign),
            })
            .collect(),
    )
}

/// Ear clipping testing every remaining corner; stays on the corner after each clipped ear.
fn exhaustive(q: &[DVec2]) -> Vec<[usize; 3]> {
    let n = q.len();
    let mut remaining: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n - 2);
    let mut i = 0;
    let mut since_last_ear = 0;
    while remaining.len() > 3 {
        let m = remaining.len();
        let (ia, ib, ic) = (
            remaining[(i + m - 1) % m],
            remaining[i % m],
            remaining[(i + 1) % m],
        );
        let (a, b, c) = (q[ia], q[ib], q[ic]);
        let convex = cross(a, b, c) > 0.0;
        let is_ear = convex
            && remaining
                .iter()
                .all(|&j| j == ia || j == ib || j == ic || !inside_or_on(a, b, c, q[j]));
        if is_ear {
            out.push([ia, ib, ic]);
            remaining.remove(i % m);
            since_last_ear = 0;
            if i >= remaining.len() {
                i = 0;
            }
        } else {
            i = (i + 1) % m;
            since_last_ear += 1;
            if since_last_ear > m {
                // No ear: self-intersecting or numerically degenerate remainder.
                out.extend(fan(&remaining));
                return out;
            }
        }
    }
    out.push([remaining[0], remaining[1], remaining[2]]);
    out
}

/// A k-d tree over every corner, counting per node the *active* corners: those that may block
/// an ear (not strictly convex when indexed, not yet clipped). Nodes without active corners
/// are skipped, so a query costs about the tree's depth plus the active corners near the ear,
/// whether the corners fill an area or lie along a curve.
struct Blockers {
    /// Corner ids, permuted so that each node covers a contiguous range.
    order: Vec<u32>,
    nodes: Vec<Node>,
    /// The leaf holding each corner.
    leaf_of: Vec<u32>,
    active: Vec<bool>,
}

/// A node of [`Blockers`]: the bounds of its corners and its active count.
struct Node {
    lo: DVec2,
    hi: DVec2,
    start: u32,
    end: u32,
    /// Children, `NONE` for a leaf.
    children: [u32; 2],
    parent: u32,
    active: u32,
}

const NONE: u32 = u32::MAX;

/// Corners per leaf.
const LEAF: usize = 8;

impl Blockers {
    fn new(q: &[DVec2]) -> Blockers {
        let mut tree = Blockers {
            order: (0..q.len() as u32).collect(),
            nodes: Vec::with_capacity(q.len() / 2 + 1),
            leaf_of: vec![NONE; q.len()],
            active: vec![false; q.len()],
        };
        // Explicit stack: (start, end, parent, slot in the parent's children).
        let mut stack = vec![(0usize, q.len(), NONE, 0usize)];
        while let Some((start, end, parent, slot)) = stack.pop() {
            let range = &mut tree.order[start..end];
            let (lo, hi) = range.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), &j| (lo.min(q[j as usize]), hi.max(q[j as usize])),
            );
            let id = tree.nodes.len() as u32;
            if parent != NONE {
                tree.nodes[parent as usize].children[slot] = id;
            }
            let mut node = Node {
                lo,
                hi,
                start: start as u32,
                end: end as u32,
                children: [NONE; 2],
                parent,
                active: 0,
            };
            if end - start <= LEAF {
                for &j in range.iter() {
                    tree.leaf_of[j as usize] = id;
                }
            } else {
                // Split at the median of the longer side.
                let axis = usize::from(hi.y - lo.y > hi.x - lo.x);
                let mid = (end - start) / 2;
                range.select_nth_unstable_by(mid, |&a, &b| {
                    q[a as usize][axis].total_cmp(&q[b as usize][axis])
                });
                stack.push((start + mid, end, id, 1));
                stack.push((start, start + mid, id, 0));
                node.children = [0, 0];
            }
            tree.nodes.push(node);
        }
        tree
    }

    /// Adds `j` to or removes it from the active corners.
    fn set_active(&mut self, j: usize, on: bool) {
        if self.active[j] == on {
            return;
        }
        self.active[j] = on;
        let mut n = self.leaf_of[j];
        while n != NONE {
            let node = &mut self.nodes[n as usize];
            node.active = if on { node.active + 1 } else { node.active - 1 };
            n = node.parent;
        }
    }

    /// An active corner other than the ear's own inside or on the ear `[a, b, c]`, if any;
    /// `stack` is scratch space.
    fn blocker(&self, q: &[DVec2], ear: [usize; 3], stack: &mut Vec<u32>) -> Option<usize> {
        let [a, b, c] = ear.map(|i| q[i]);
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if node.active == 0
                || node.lo.x > hi.x
                || node.lo.y > hi.y
                || node.hi.x < lo.x
                || node.hi.y < lo.y
            {
                continue;
            }
            if node.children[0] == NONE {
                let range = &self.order[node.start as usize..node.end as usize];
                for &j in range {
                    let j = j as usize;
                    if self.active[j] && !ear.contains(&j) && inside_or_on(a, b, c, q[j]) {
                        return Some(j);
                    }
                }
            } else {
                stack.extend(node.children);
            }
        }
        None
    }
}

/// Ear clipping for large polygons: candidates tested against the corners that were not
/// strictly convex, found through a k-d tree, in a work queue (see the module docs).
fn indexed(q: &[DVec2]) -> Vec<[usize; 3]> {
    let n = q.len();
    let mut next: Vec<usize> = (1..=n).map(|i| i % n).collect();
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut removed = vec![false; n];
    let turn = |prev: &[usize], next: &[usize], j: usize| cross(q[prev[j]], q[j], q[next[j]]);
    let mut blockers = Blockers::new(q);
    for j in 0..n {
        if turn(&prev, &next, j) <= 0.0 {
            blockers.set_active(j, true);
        }
    }
    // Candidates in file order; an entry is stale once its corner is queued again.
    let mut stamp = vec![0u32; n];
    let mut queue: VecDeque<(usize, u32)> = (0..n).map(|i| (i, 0)).collect();
    // Candidates that failed because of a corner inside their ear, listed under that corner.
    let mut waiting: Vec<Vec<u32>> = vec![Vec::new(); n];
    fn requeue(queue: &mut VecDeque<(usize, u32)>, stamp: &mut [u32], j: usize) {
        stamp[j] = stamp[j].wrapping_add(1);
        queue.push_back((j, stamp[j]));
    }
    let mut scratch = Vec::new();
    let mut out = Vec::with_capacity(n - 2);
    let mut left = n;
    let mut alive = 0usize;
    while left > 3 {
        let Some((ear, st)) = queue.pop_front() else {
            // Every candidate failed since it last changed: a self-intersecting or
            // numerically degenerate remainder with no ear.
            let mut rest = Vec::with_capacity(left);
            let mut j = alive;
            for _ in 0..left {
                rest.push(j);
                j = next[j];
            }
            out.extend(fan(&rest));
            return out;
        };
        if removed[ear] || st != stamp[ear] {
            continue;
        }
        let (ia, ic) = (prev[ear], next[ear]);
        if cross(q[ia], q[ear], q[ic]) <= 0.0 {
            // Tested again when a neighbour is clipped, the only change that can make it convex.
            continue;
        }
        if let Some(j) = blockers.blocker(q, [ia, ear, ic], &mut scratch) {
            waiting[j].push(ear as u32);
            continue;
        }
        out.push([ia, ear, ic]);
        removed[ear] = true;
        blockers.set_active(ear, false);
        next[ia] = ic;
        prev[ic] = ia;
        left -= 1;
        alive = ia;
        for j in [ia, ic] {
            // A neighbour whose turn is no longer strictly convex may now block an ear.
            if turn(&prev, &next, j) <= 0.0 {
                blockers.set_active(j, true);
            }
            // Queued at the back, so a lap clips every other corner rather than a fan.
            requeue(&mut queue, &mut stamp, j);
        }
        for w in std::mem::take(&mut waiting[ear]) {
            if !removed[w as usize] {
                requeue(&mut queue, &mut stamp, w as usize);
            }
        }
    }
    out.push([prev[alive], alive, next[alive]]);
    out
}

#[cfg(test)]
mod tests {
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
}
