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
//! The k-d tree skips every node whose box lies outside one edge of the candidate ear, so a
//! long thin ear does not visit the polygon's whole width. On convex, star-shaped, comb and
//! spiral polygons the work is near-linear and no corner collects a fan of thousands of
//! triangles; on self-intersecting ones (random corners) it is near-linear too, and past
//! [`WORK_PER_CORNER`] units of work per corner, which no polygon measured comes near, the
//! remainder is fanned, so no polygon takes more than linear work. Limits: a polygon whose
//! Newell normal is zero (degenerate or figure-eight), and the remainder of a
//! self-intersecting polygon where no ear exists, are fanned from a corner instead: a
//! self-intersecting polygon has no inside to tile, and the fan keeps its corners and its
//! `n - 2` triangles.

use std::collections::VecDeque;

use glam::{DVec2, DVec3, Vec3};

/// Most work the indexed pass may do per corner (queue entries taken and k-d tree nodes
/// visited) before the rest of the polygon is fanned. Simple polygons measured take 15 to 55
/// (convex, star, comb and spiral polygons of up to 640,000 corners; random self-intersecting
/// ones 15 to 19), so this is reached only by a polygon built to defeat the pruning, and bounds
/// the time of any polygon to linear.
pub const WORK_PER_CORNER: u64 = 256;

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

/// Whether the box `lo..hi` lies wholly outside one edge of the counter-clockwise triangle
/// `t` (every corner strictly right of it): then no point of the box is in the triangle. A
/// long thin ear has a box that covers much of the polygon; its edges rule most of it out.
fn outside_an_edge(t: [DVec2; 3], lo: DVec2, hi: DVec2) -> bool {
    let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
    (0..3).any(|k| {
        let (p, q) = (t[k], t[(k + 1) % 3]);
        corners.iter().all(|&x| cross(p, q, x) < 0.0)
    })
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
    fn blocker(
        &self,
        q: &[DVec2],
        ear: [usize; 3],
        stack: &mut Vec<u32>,
        work: &mut u64,
    ) -> Option<usize> {
        let [a, b, c] = ear.map(|i| q[i]);
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            *work += 1;
            let node = &self.nodes[n as usize];
            if node.active == 0
                || node.lo.x > hi.x
                || node.lo.y > hi.y
                || node.hi.x < lo.x
                || node.hi.y < lo.y
                || outside_an_edge([a, b, c], node.lo, node.hi)
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
    let budget = (q.len() as u64).saturating_mul(WORK_PER_CORNER);
    indexed_counted(q, budget).0
}

/// [`indexed`] within `budget` units of work (queue entries taken and k-d tree nodes
/// visited), past which the remainder is fanned; and the work it took.
fn indexed_counted(q: &[DVec2], budget: u64) -> (Vec<[usize; 3]>, u64) {
    let mut work = 0u64;
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
        let next_entry = if work > budget {
            None // past the budget: fanned below, as a remainder without an ear is
        } else {
            queue.pop_front()
        };
        let Some((ear, st)) = next_entry else {
            // Every candidate failed since it last changed: a self-intersecting or
            // numerically degenerate remainder with no ear.
            let mut rest = Vec::with_capacity(left);
            let mut j = alive;
            for _ in 0..left {
                rest.push(j);
                j = next[j];
            }
            out.extend(fan(&rest));
            return (out, work);
        };
        work += 1;
        if removed[ear] || st != stamp[ear] {
            continue;
        }
        let (ia, ic) = (prev[ear], next[ear]);
        if cross(q[ia], q[ear], q[ic]) <= 0.0 {
            // Tested again when a neighbour is clipped, the only change that can make it convex.
            continue;
        }
        if let Some(j) = blockers.blocker(q, [ia, ear, ic], &mut scratch, &mut work) {
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
    (out, work)
}

#[cfg(test)]
mod tests;
