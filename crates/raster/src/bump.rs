//! Bump mapping (Blinn 1978: the normal is perturbed before the shading model is applied): a
//! height field `h(u, v)` tilts the interpolated normal in the tangent frame,
//! `N' = normalize(N - scale (dh/du T + dh/dv B))`, `B = w (N x T)` with the tangent's
//! handedness `w`. A tangent-space normal map gives the perturbed normal directly:
//! `N' = normalize(s m_x T + s m_y B + m_z N)` for the map's unit vector `m` and scale `s`
//! (the glTF 2.0 convention, shared by MikkTSpace tangents and Blender's bakes: `+y` along
//! `B`, towards `+v`). Used by `phong`, `reference`, and `fast-phong` (which draws bumped items
//! with `phong`); `flat` and `gouraud` ignore it (counted in `RenderStats::bump_ignored`).

use std::f32::consts::TAU;

use glam::{Vec2, Vec3, Vec4};
use phosphor_math::safe_normalize;

use crate::framebuffer::RasterError;

/// Built-in height fields, periodic in uv.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProceduralBump {
    /// An egg-crate grid: `h = sin(2 pi f u) sin(2 pi f v) / (2 pi f)`, f = 8 per uv unit.
    Bumps,
    /// Concentric ripples around uv (0.5, 0.5): `h = sin(2 pi f r) / (2 pi f)`, f = 12.
    Ripples,
}

/// A height field for bump mapping; `scale` multiplies its slopes.
#[derive(Debug, Clone, PartialEq)]
pub enum BumpMap {
    /// A built-in height field.
    Procedural {
        /// Which one.
        kind: ProceduralBump,
        /// Slope multiplier (0 = flat).
        scale: f32,
    },
    /// Heights in `[0, 1]` sampled bilinearly with wrap-around, row 0 at v = 0.
    Image {
        /// Row-major heights, `width * height` of them.
        heights: Vec<f32>,
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Slope multiplier, in height units per uv unit.
        scale: f32,
    },
    /// Tangent-space unit normals `(x, y, z)` along `(T, B, N)`, sampled bilinearly with
    /// wrap-around, row 0 at v = 0.
    Normals {
        /// Row-major normals, `width * height` of them.
        normals: Vec<Vec3>,
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Multiplier of the `x` and `y` components (glTF's `normalTexture.scale`).
        scale: f32,
    },
}

impl BumpMap {
    /// A height field from raw texels: `heights` row-major, `width * height` of them, row 0 at
    /// v = 0 (as [`BumpMap::Image`]). Non-finite heights become 0. Decoding an image file into
    /// heights is the caller's (`phosphor-scene` reads the bump maps a scene names).
    ///
    /// # Errors
    /// A non-finite `scale`, an empty field, or a texel count other than `width * height`.
    pub fn from_heights(
        mut heights: Vec<f32>,
        width: u32,
        height: u32,
        scale: f32,
    ) -> Result<BumpMap, RasterError> {
        check_texels(
            heights.len(),
            (width, height),
            scale,
            ("height field", "heights"),
        )?;
        for h in &mut heights {
            if !h.is_finite() {
                *h = 0.0;
            }
        }
        Ok(BumpMap::Image {
            heights,
            width,
            height,
            scale,
        })
    }

    /// A normal map from raw texels: `normals` row-major, `width * height` of them, row 0 at
    /// v = 0 (as [`BumpMap::Normals`]), each normalized; a non-finite, zero or inward
    /// (`z <= 0`) one becomes `(0, 0, 1)`, the unperturbed normal. Decoding an image's
    /// `2 c - 1` components is the caller's.
    ///
    /// # Errors
    /// A non-finite `scale`, an empty map, or a texel count other than `width * height`.
    pub fn from_normals(
        mut normals: Vec<Vec3>,
        width: u32,
        height: u32,
        scale: f32,
    ) -> Result<BumpMap, RasterError> {
        check_texels(
            normals.len(),
            (width, height),
            scale,
            ("normal map", "normals"),
        )?;
        for n in &mut normals {
            *n = safe_normalize(*n, Vec3::Z);
            if n.z <= 0.0 {
                *n = Vec3::Z;
            }
        }
        Ok(BumpMap::Normals {
            normals,
            width,
            height,
            scale,
        })
    }

    /// The tangent-space normal at `uv` before it is normalized: the map's bilinear sample
    /// with `x` and `y` scaled, or the height field's `(-dh/du, -dh/dv, 1)`.
    #[must_use]
    pub fn tangent_normal(&self, uv: Vec2) -> Vec3 {
        if let BumpMap::Normals {
            normals,
            width,
            height,
            scale,
        } = self
        {
            if !uv.is_finite() || normals.len() != *width as usize * *height as usize {
                return Vec3::Z;
            }
            let m = sample(normals, *width, *height, uv.x, uv.y);
            let m = Vec3::new(m.x * scale, m.y * scale, m.z);
            return if m.is_finite() { m } else { Vec3::Z };
        }
        let g = self.gradient(uv);
        Vec3::new(-g.x, -g.y, 1.0)
    }

    /// `(dh/du, dh/dv)` times the scale at `uv`; zero for non-finite input. For a normal
    /// map, the slopes of the surface its normal stands on, `(-x/z, -y/z)` (zero where the
    /// sample is edge-on).
    #[must_use]
    pub fn gradient(&self, uv: Vec2) -> Vec2 {
        if !uv.is_finite() {
            return Vec2::ZERO;
        }
        let g = match self {
            BumpMap::Procedural { kind, scale } => procedural_gradient(*kind, uv) * *scale,
            BumpMap::Image {
                heights,
                width,
                height,
                scale,
            } => {
                let (w, h) = (*width as f32, *height as f32);
                if heights.len() != *width as usize * *height as usize || heights.is_empty() {
                    return Vec2::ZERO;
                }
                let s = |u: f32, v: f32| sample(heights, *width, *height, u, v);
                // Central differences one texel apart.
                let du = (s(uv.x + 1.0 / w, uv.y) - s(uv.x - 1.0 / w, uv.y)) * (w * 0.5);
                let dv = (s(uv.x, uv.y + 1.0 / h) - s(uv.x, uv.y - 1.0 / h)) * (h * 0.5);
                Vec2::new(du, dv) * *scale
            }
            BumpMap::Normals { .. } => {
                let m = self.tangent_normal(uv);
                if m.z > 1e-6 {
                    Vec2::new(-m.x, -m.y) / m.z
                } else {
                    Vec2::ZERO
                }
            }
        };
        if g.is_finite() { g } else { Vec2::ZERO }
    }

    /// The perturbed unit normal; returns the (normalized) `n` when the frame is degenerate.
    #[must_use]
    pub fn perturb(&self, n: Vec3, tangent: Vec4, uv: Vec2) -> Vec3 {
        let n = safe_normalize(n, Vec3::ZERO);
        if n == Vec3::ZERO {
            return n;
        }
        let t = safe_normalize(
            tangent.truncate() - n * n.dot(tangent.truncate()),
            Vec3::ZERO,
        );
        if t == Vec3::ZERO {
            return n;
        }
        let handed = if tangent.w < 0.0 { -1.0 } else { 1.0 };
        let b = n.cross(t) * handed;
        let m = self.tangent_normal(uv);
        safe_normalize(t * m.x + b * m.y + n * m.z, n)
    }
}

/// The checks both raw maps share: a finite `scale`, a non-empty `width x height`, and `len`
/// texels for it; `what` names the map and its texels in the message.
fn check_texels(
    len: usize,
    (width, height): (u32, u32),
    scale: f32,
    (map, texels): (&str, &str),
) -> Result<(), RasterError> {
    if !scale.is_finite() {
        return Err(RasterError::BadBump(format!("scale {scale} is not finite")));
    }
    if width == 0 || height == 0 {
        return Err(RasterError::BadBump(format!(
            "empty {map} ({width}x{height})"
        )));
    }
    if len as u64 != u64::from(width) * u64::from(height) {
        return Err(RasterError::BadBump(format!(
            "{len} {texels} for {width}x{height} texels"
        )));
    }
    Ok(())
}

fn procedural_gradient(kind: ProceduralBump, uv: Vec2) -> Vec2 {
    match kind {
        ProceduralBump::Bumps => {
            let f = 8.0 * TAU;
            let (su, cu) = (f * uv.x).sin_cos();
            let (sv, cv) = (f * uv.y).sin_cos();
            Vec2::new(cu * sv, su * cv)
        }
        ProceduralBump::Ripples => {
            let d = uv - Vec2::splat(0.5);
            let r = d.length();
            if r < 1e-6 {
                return Vec2::ZERO;
            }
            d * ((12.0 * TAU * r).cos() / r)
        }
    }
}

/// Bilinear sample with wrap-around; texel centres at `(i + 0.5) / width`.
fn sample<T>(heights: &[T], width: u32, height: u32, u: f32, v: f32) -> T
where
    T: Copy + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    let (w, h) = (width as i64, height as i64);
    let x = u * width as f32 - 0.5;
    let y = v * height as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| {
        let (i, j) = (i.rem_euclid(w), j.rem_euclid(h));
        heights[(j * w + i) as usize]
    };
    // Coordinates far outside i64 were rejected by the finiteness check; huge ones wrap.
    let (i0, j0) = (x0 as i64, y0 as i64);
    let top = at(i0, j0) * (1.0 - fx) + at(i0 + 1, j0) * fx;
    let bottom = at(i0, j0 + 1) * (1.0 - fx) + at(i0 + 1, j0 + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_height_field_leaves_the_normal_and_slopes_tilt_it_away_from_uphill() {
        let flat = BumpMap::Image {
            heights: vec![0.5; 16],
            width: 4,
            height: 4,
            scale: 1.0,
        };
        let n = flat.perturb(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, 1.0), Vec2::new(0.3, 0.7));
        assert!((n - Vec3::Z).length() < 1e-6);
        // Height rising along u: the normal leans towards -T.
        let ramp = BumpMap::Image {
            heights: vec![0.0, 0.25, 0.5, 0.75],
            width: 4,
            height: 1,
            scale: 1.0,
        };
        let n = ramp.perturb(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, 1.0), Vec2::new(0.5, 0.5));
        assert!(n.x < -0.1 && (n.length() - 1.0).abs() < 1e-5);
        let p = BumpMap::Procedural {
            kind: ProceduralBump::Bumps,
            scale: 0.5,
        };
        for i in 0..100 {
            let uv = Vec2::new(i as f32 * 0.013, i as f32 * 0.029);
            let m = p.perturb(Vec3::Y, Vec4::new(1.0, 0.0, 0.0, -1.0), uv);
            assert!((m.length() - 1.0).abs() < 1e-5 && m.y > 0.0);
        }
    }

    #[test]
    fn raw_heights_are_checked_and_cleaned() {
        let map = BumpMap::from_heights(vec![0.5, f32::NAN, f32::INFINITY, 1.0], 2, 2, 2.0);
        assert_eq!(
            map.unwrap(),
            BumpMap::Image {
                heights: vec![0.5, 0.0, 0.0, 1.0],
                width: 2,
                height: 2,
                scale: 2.0,
            }
        );
        let err = |r: Result<BumpMap, RasterError>| r.unwrap_err().to_string();
        assert!(err(BumpMap::from_heights(vec![0.0], 1, 1, f32::NAN)).contains("scale NaN"));
        assert!(err(BumpMap::from_heights(vec![], 0, 1, 1.0)).contains("empty"));
        assert!(err(BumpMap::from_heights(vec![0.0; 3], 2, 2, 1.0)).contains("3 heights"));
    }
}
