//! The geometric reference of `phosphor accuracy`: where a pixel shows a sphere, a cylinder's
//! side or a torus made by a scene `primitive`, the exact surface that the mesh approximates,
//! in `f64`: the pixel's ray meets the mesh triangle the pixel shows, Newton's method carries
//! that point along the ray onto the implicit surface (`|p| = r`, `sqrt(x^2 + z^2) = r`,
//! `(sqrt(x^2 + z^2) - R)^2 + y^2 = r^2`), and the model is evaluated there with the surface's
//! exact normal (its gradient) by `shade_reference`. Against it, `reference` (the mesh's own
//! interpolated points and normals) shows what tessellation and normal averaging cost, and
//! every mode its total error; the difference is the shading's.
//!
//! A `normalize`d primitive is mapped back to the primitive's own coordinates by the uniform
//! scale and shift that take the normalized mesh's bounds onto the primitive's. Cubes and
//! planes are exact as meshes; a cylinder's caps are flat; textured, vertex-coloured or
//! bump-mapped objects, and pixels whose Newton iteration does not settle within a
//! triangle's size of the mesh, keep the mesh reference's value and are not counted.

use phosphor_lighting::shade_reference;
use phosphor_math::glam::{DMat4, DVec3, DVec4, Vec3};
use phosphor_mesh::{Mesh, primitives};
use phosphor_scene::components::{MeshSource, Primitive};
use phosphor_scene::{FrameOptions, Scene, plan_frame};

use crate::mach::{NO_ID, TriangleIds};

/// The exact image: the mesh reference's colours with the primitives' pixels replaced.
pub struct Geometric {
    /// Row-major linear colours, clamped to `[0, 1]`.
    pub image: Vec<Vec3>,
    /// Which pixels were shaded on an exact surface.
    pub exact: Vec<bool>,
}

impl Geometric {
    /// Pixels shaded on an exact surface.
    pub fn count(&self) -> usize {
        self.exact.iter().filter(|e| **e).count()
    }
}

/// An implicit surface in object space: its value and gradient at `p`.
#[derive(Clone, Copy, Debug)]
enum Surface {
    Sphere { r: f64 },
    CylinderSide { r: f64 },
    Torus { big: f64, small: f64 },
}

impl Surface {
    fn of(p: &Primitive) -> Option<Surface> {
        match *p {
            Primitive::Sphere { radius, .. } => Some(Surface::Sphere {
                r: f64::from(radius),
            }),
            Primitive::Cylinder { radius, .. } => Some(Surface::CylinderSide {
                r: f64::from(radius),
            }),
            Primitive::Torus { major, minor, .. } => Some(Surface::Torus {
                big: f64::from(major),
                small: f64::from(minor),
            }),
            Primitive::Cube { .. } | Primitive::Plane { .. } => None,
        }
    }

    fn value_gradient(self, p: DVec3) -> (f64, DVec3) {
        match self {
            Surface::Sphere { r } => {
                let l = p.length();
                (l - r, p / l)
            }
            Surface::CylinderSide { r } => {
                let l = (p.x * p.x + p.z * p.z).sqrt();
                (l - r, DVec3::new(p.x / l, 0.0, p.z / l))
            }
            Surface::Torus { big, small } => {
                let l = (p.x * p.x + p.z * p.z).sqrt();
                let q = l - big;
                let value = (q * q + p.y * p.y).sqrt() - small;
                let radial = DVec3::new(p.x / l, 0.0, p.z / l);
                (value, (radial * q + DVec3::Y * p.y).normalize())
            }
        }
    }
}

/// The map from a mesh's object space to its primitive's own coordinates: the identity, or for
/// a normalized mesh the uniform scale and shift that take its bounds onto the bounds of the
/// primitive as built. `None` if the bounds are degenerate.
fn to_primitive(p: &Primitive, mesh: &Mesh, normalized: bool) -> Option<DMat4> {
    if !normalized {
        return Some(DMat4::IDENTITY);
    }
    let original = match *p {
        Primitive::Sphere {
            radius,
            segments,
            rings,
        } => primitives::uv_sphere(radius, segments, rings),
        Primitive::Cylinder {
            radius,
            height,
            segments,
        } => primitives::cylinder(radius, height, segments),
        Primitive::Torus {
            major,
            minor,
            segments,
            sides,
        } => primitives::torus(major, minor, segments, sides),
        Primitive::Cube { .. } | Primitive::Plane { .. } => return None,
    };
    let (lo_o, hi_o) = original.bounds();
    let (lo_n, hi_n) = mesh.bounds();
    let (extent_o, extent_n) = ((hi_o - lo_o).as_dvec3(), (hi_n - lo_n).as_dvec3());
    let k = extent_o.max_element() / extent_n.max_element();
    if k.is_nan() || k <= 0.0 || k.is_infinite() {
        return None;
    }
    // x_primitive = lo_o + (x - lo_n) k
    Some(
        DMat4::from_translation(lo_o.as_dvec3())
            * DMat4::from_scale(DVec3::splat(k))
            * DMat4::from_translation(-lo_n.as_dvec3()),
    )
}

/// One object's exact surface and where it lies.
#[derive(Clone, Copy)]
struct Placed {
    surface: Surface,
    /// Object space to the primitive's coordinates.
    local_map: DMat4,
    /// World to the primitive's coordinates.
    inverse: DMat4,
    /// The primitive's coordinates to world.
    world_from_local: DMat4,
}

/// Where the ray `o + t d` meets the triangle `a b c` (any side), `None` if parallel.
fn ray_triangle(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = o - a;
    let q = s.cross(e1);
    Some(e2.dot(q) / det)
}

/// The geometric reference of `scene` drawn as `opts` asks, for the pixels `ids` assigns to a
/// triangle (from [`crate::mach::triangle_ids`] with the same options); elsewhere
/// `mesh_reference`'s colours.
pub fn geometric_reference(
    scene: &Scene,
    opts: &FrameOptions,
    ids: &TriangleIds,
    mesh_reference: &[Vec3],
) -> Geometric {
    let (width, height) = (ids.width, ids.height);
    let camera = scene.camera();
    let plan = plan_frame(scene, &camera, (width, height), opts);
    let mut image = mesh_reference.to_vec();
    let mut exact = vec![false; image.len()];
    // First triangle id of each object, in draw order (as triangle_ids numbers them).
    let mut first = Vec::with_capacity(plan.objects.len());
    let mut next = 0u64;
    for o in &plan.objects {
        first.push(next);
        next += o.mesh.mesh.indices.len() as u64;
    }
    let aspect = width.max(1) as f32 / height.max(1) as f32;
    let inverse_vp = camera.view_proj(aspect).as_dmat4().inverse();
    let eye = camera.eye.as_dvec3();
    let unproject = |x: f64, y: f64, z: f64| {
        let ndc = DVec4::new(
            x / f64::from(width) * 2.0 - 1.0,
            1.0 - y / f64::from(height) * 2.0,
            z,
            1.0,
        );
        let p = inverse_vp * ndc;
        p.truncate() / p.w
    };
    // Per object, once: its surface, the map from world to the primitive's coordinates and
    // back (None: no geometric reference for it).
    let setups: Vec<Option<Placed>> = plan
        .objects
        .iter()
        .map(|o| {
            let MeshSource::Primitive(p) = &o.mesh.source else {
                return None;
            };
            let surface = Surface::of(p)?;
            if o.texture.is_some() || o.bump.is_some() || o.mesh.mesh.colors.is_some() {
                return None;
            }
            let local_map = to_primitive(p, &o.mesh.mesh, o.mesh.normalized)?;
            let inverse = local_map * o.model.as_dmat4().inverse();
            Some(Placed {
                surface,
                local_map,
                inverse,
                world_from_local: inverse.inverse(),
            })
        })
        .collect();
    for (i, &id) in ids.ids.iter().enumerate() {
        if id == NO_ID || i >= image.len() {
            continue;
        }
        let object = first
            .partition_point(|&f| f <= u64::from(id))
            .saturating_sub(1);
        let (Some(o), Some(Some(placed))) = (plan.objects.get(object), setups.get(object)) else {
            continue;
        };
        let Placed {
            surface,
            local_map,
            inverse,
            world_from_local,
        } = *placed;
        let mesh = &o.mesh.mesh;
        let local = (u64::from(id) - first[object]) as usize;
        let Some(tri) = mesh.indices.get(local) else {
            continue;
        };
        let corner = |k: u32| mesh.positions.get(k as usize).map(|v| v.as_dvec3());
        let (Some(a), Some(b), Some(c)) = (corner(tri[0]), corner(tri[1]), corner(tri[2])) else {
            continue;
        };
        // A cylinder's caps are flat: the mesh is exact there.
        if matches!(surface, Surface::CylinderSide { .. })
            && tri.iter().all(|&k| {
                mesh.normals
                    .get(k as usize)
                    .is_some_and(|n| n.y.abs() > 0.999)
            })
        {
            continue;
        }
        // The corners in the primitive's coordinates.
        let (a, b, c) = (
            local_map.transform_point3(a),
            local_map.transform_point3(b),
            local_map.transform_point3(c),
        );
        let (x, y) = (
            (i as u32 % width) as f64 + 0.5,
            (i as u32 / width) as f64 + 0.5,
        );
        let (near, far) = (unproject(x, y, 0.0), unproject(x, y, 0.5));
        let origin = inverse.transform_point3(near);
        let dir = inverse.transform_vector3(far - near);
        let Some(mut t) = ray_triangle(origin, dir, [a, b, c]) else {
            continue;
        };
        let size = (b - a).length().max((c - a).length()).max((c - b).length());
        let t0 = t;
        let mut settled = false;
        for _ in 0..30 {
            let (f, g) = surface.value_gradient(origin + dir * t);
            let slope = g.dot(dir);
            if !(f.is_finite() && slope.is_finite()) || slope == 0.0 {
                break;
            }
            t -= f / slope;
            if f.abs() < 1e-13 * (1.0 + size) {
                settled = true;
                break;
            }
        }
        if !settled || !t.is_finite() || ((t - t0) * dir.length()).abs() > size {
            continue;
        }
        let point = origin + dir * t;
        let (_, gradient) = surface.value_gradient(point);
        let world_point = world_from_local.transform_point3(point);
        let normal = (inverse.transpose().transform_vector3(gradient)).normalize_or_zero();
        if normal == DVec3::ZERO {
            continue;
        }
        let set = &plan.light_sets[o.light_set];
        let v = shade_reference(set, &o.material, world_point, normal, eye);
        image[i] = v.as_vec3().clamp(Vec3::ZERO, Vec3::ONE);
        exact[i] = true;
    }
    Geometric { image, exact }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surfaces_vanish_on_themselves_with_unit_outward_gradients() {
        let cases = [
            (
                Surface::Sphere { r: 2.0 },
                DVec3::new(0.0, 2.0, 0.0),
                DVec3::Y,
            ),
            (
                Surface::CylinderSide { r: 0.5 },
                DVec3::new(0.0, 0.3, -0.5),
                -DVec3::Z,
            ),
            (
                Surface::Torus {
                    big: 0.7,
                    small: 0.25,
                },
                DVec3::new(0.95, 0.0, 0.0),
                DVec3::X,
            ),
            (
                Surface::Torus {
                    big: 0.7,
                    small: 0.25,
                },
                DVec3::new(0.0, 0.25, 0.7),
                DVec3::Y,
            ),
        ];
        for (s, p, n) in cases {
            let (f, g) = s.value_gradient(p);
            assert!(f.abs() < 1e-12, "{s:?} at {p}: {f}");
            assert!((g - n).length() < 1e-12, "{s:?} at {p}: {g}");
        }
    }

    #[test]
    fn the_ray_meets_the_triangle_where_it_crosses_its_plane() {
        let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let t = ray_triangle(DVec3::new(0.2, 0.2, 3.0), DVec3::new(0.0, 0.0, -2.0), tri);
        assert!((t.expect("not parallel") - 1.5).abs() < 1e-12);
        assert!(ray_triangle(DVec3::Z, DVec3::X, tri).is_none());
    }
}
