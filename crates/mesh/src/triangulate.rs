//! Polygon triangulation by ear clipping, so concave OBJ polygons are not fanned.
//!
//! The polygon is projected onto the plane of its Newell normal (dropping the dominant axis),
//! oriented counter-clockwise, and ears are clipped: a convex corner whose triangle holds no
//! other remaining corner. Output triangles keep the polygon's winding. Limits (documented and
//! tested): polygons with more than [`MAX_EAR_CLIPPED`] corners, polygons whose Newell normal is
//! zero (degenerate or figure-eight), and the remainder of a self-intersecting polygon where no
//! ear exists are fanned from their first corner instead; every path yields `n - 2` triangles.

use glam::{DVec2, DVec3, Vec3};

/// Largest polygon that is ear-clipped (the algorithm is quadratic); larger ones are fanned.
pub const MAX_EAR_CLIPPED: usize = 4096;

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
    let fan = |from: &[usize]| -> Vec<[usize; 3]> {
        (1..from.len() - 1)
            .map(|i| [from[0], from[i], from[i + 1]])
            .collect()
    };
    let all: Vec<usize> = (0..n).collect();
    if n > MAX_EAR_CLIPPED {
        return fan(&all);
    }
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
        return fan(&all);
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
    let q: Vec<DVec2> = p
        .iter()
        .map(|v| match axis {
            0 => DVec2::new(v.y, v.z * sign),
            1 => DVec2::new(v.z, v.x * sign),
            _ => DVec2::new(v.x, v.y * sign),
        })
        .collect();
    let cross = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let mut remaining = all;
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
            && remaining.iter().all(|&j| {
                if j == ia || j == ib || j == ic {
                    return true;
                }
                let x = q[j];
                // Corners on the boundary count as inside, so no clipped ear touches another corner.
                !(cross(a, b, x) >= 0.0 && cross(b, c, x) >= 0.0 && cross(c, a, x) >= 0.0)
            });
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
}
