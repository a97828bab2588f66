//! Summary numbers of a mesh, for `phosphor info`.

use std::collections::HashSet;
use std::fmt;

use glam::Vec3;

use crate::build::weld_key;
use crate::mesh::Mesh;

/// What `phosphor info` prints about a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshStats {
    /// Distinct positions (welded by exact equality, `-0.0 == 0.0`): the points faces share,
    /// whatever the file stored (an STL stores three per triangle).
    pub positions: usize,
    /// Vertices (after splitting where surfaces meet).
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Distinct surface ids.
    pub surfaces: usize,
    /// Distinct non-zero smoothing groups.
    pub smoothing_groups: usize,
    /// Materials from the MTL file.
    pub materials: usize,
    /// Zero-area triangles.
    pub degenerate: usize,
    /// Whether the vertices carry colours ([`Mesh::colors`]).
    pub colors: bool,
    /// Axis-aligned bounds `(min, max)`.
    pub bounds: (Vec3, Vec3),
}

impl Mesh {
    /// Counts and bounds of this mesh.
    #[must_use]
    pub fn stats(&self) -> MeshStats {
        let surfaces: HashSet<u32> = self.surface_ids.iter().copied().collect();
        let groups: HashSet<u32> = self
            .smoothing_groups
            .iter()
            .copied()
            .filter(|&g| g != 0)
            .collect();
        let positions: HashSet<[u32; 3]> = self.positions.iter().map(|&p| weld_key(p)).collect();
        MeshStats {
            positions: positions.len(),
            vertices: self.positions.len(),
            triangles: self.indices.len(),
            surfaces: surfaces.len(),
            smoothing_groups: groups.len(),
            materials: self.materials.len(),
            degenerate: self.degenerate_count(),
            colors: self.colors.is_some(),
            bounds: self.bounds(),
        }
    }
}

impl fmt::Display for MeshStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (lo, hi) = self.bounds;
        writeln!(f, "positions:        {} (distinct, welded)", self.positions)?;
        writeln!(
            f,
            "vertices:         {} (split where surfaces meet)",
            self.vertices
        )?;
        writeln!(f, "triangles:        {}", self.triangles)?;
        writeln!(f, "surfaces:         {}", self.surfaces)?;
        writeln!(f, "smoothing groups: {}", self.smoothing_groups)?;
        writeln!(f, "materials:        {}", self.materials)?;
        writeln!(f, "degenerate faces: {}", self.degenerate)?;
        writeln!(
            f,
            "vertex colours:   {}",
            if self.colors { "yes" } else { "no" }
        )?;
        write!(
            f,
            "bounds:           ({}, {}, {}) .. ({}, {}, {})",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        )
    }
}
