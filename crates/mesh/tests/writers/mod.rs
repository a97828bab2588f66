//! Writers of small mesh files for the format tests: OBJ, PLY (ASCII and both binary byte
//! orders), STL (ASCII and binary), glTF (JSON with a data URI or an external buffer, GLB).
#![allow(dead_code)] // each test file uses a different subset

use glam::Vec3;

mod gltf_writer;

pub use gltf_writer::*;

/// Positions and polygons (any number of corners), counter-clockwise seen from outside.
pub struct Shape {
    pub positions: Vec<Vec3>,
    pub faces: Vec<Vec<u32>>,
}

/// The unit cube of the crate docs: 8 corners, 6 quads.
pub fn cube() -> Shape {
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    Shape {
        positions: vec![
            p(0., 0., 0.),
            p(1., 0., 0.),
            p(1., 1., 0.),
            p(0., 1., 0.),
            p(0., 0., 1.),
            p(1., 0., 1.),
            p(1., 1., 1.),
            p(0., 1., 1.),
        ],
        faces: vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
    }
}

impl Shape {
    /// The shape's triangles (polygons fanned; the test shapes are convex).
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.faces
            .iter()
            .flat_map(|f| (1..f.len() - 1).map(move |i| [f[0], f[i], f[i + 1]]))
            .collect()
    }

    /// The same shape with polygons split into triangles.
    pub fn triangulated(&self) -> Shape {
        Shape {
            positions: self.positions.clone(),
            faces: self.triangles().iter().map(|t| t.to_vec()).collect(),
        }
    }

    pub fn obj(&self) -> String {
        let mut s = String::new();
        for p in &self.positions {
            s += &format!("v {} {} {}\n", p.x, p.y, p.z);
        }
        for f in &self.faces {
            let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
            s += &format!("f {}\n", corners.join(" "));
        }
        s
    }
}

/// A PLY encoding.
#[derive(Clone, Copy, Debug)]
pub enum Ply {
    Ascii,
    Little,
    Big,
}

/// How a PLY file stores vertex colours.
#[derive(Clone, Copy, Debug)]
pub enum PlyColor {
    /// `uchar red green blue alpha`, 0 to 255 (alpha 255).
    UChar,
    /// `float red green blue`, 0 to 1.
    Float,
}

/// A PLY file of `shape`, with `normals` per vertex when given. The vertex element carries an
/// extra `confidence` float and the file an `edge` element, both to be read past.
pub fn ply(shape: &Shape, normals: Option<&[Vec3]>, encoding: Ply) -> Vec<u8> {
    ply_with(shape, normals, None, encoding)
}

/// [`ply`] with vertex colours when given.
pub fn ply_with(
    shape: &Shape,
    normals: Option<&[Vec3]>,
    colors: Option<(&[Vec3], PlyColor)>,
    encoding: Ply,
) -> Vec<u8> {
    let format = match encoding {
        Ply::Ascii => "ascii",
        Ply::Little => "binary_little_endian",
        Ply::Big => "binary_big_endian",
    };
    let mut header = format!(
        "ply\nformat {format} 1.0\ncomment written by the phosphor tests\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n",
        shape.positions.len()
    );
    if normals.is_some() {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    match colors {
        Some((_, PlyColor::UChar)) => {
            header += "property uchar red\nproperty uchar green\nproperty uchar blue\n\
                       property uchar alpha\n";
        }
        Some((_, PlyColor::Float)) => {
            header += "property float red\nproperty float green\nproperty float blue\n";
        }
        None => {}
    }
    header += &format!(
        "property float confidence\nelement face {}\nproperty list uchar int vertex_indices\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n",
        shape.faces.len()
    );
    let mut out = header.into_bytes();
    let f32s = |out: &mut Vec<u8>, values: &[f32]| {
        for v in values {
            match encoding {
                Ply::Ascii => out.extend_from_slice(format!("{v} ").as_bytes()),
                Ply::Little => out.extend_from_slice(&v.to_le_bytes()),
                Ply::Big => out.extend_from_slice(&v.to_be_bytes()),
            }
        }
    };
    let i32s = |out: &mut Vec<u8>, values: &[i32]| {
        for v in values {
            match encoding {
                Ply::Ascii => out.extend_from_slice(format!("{v} ").as_bytes()),
                Ply::Little => out.extend_from_slice(&v.to_le_bytes()),
                Ply::Big => out.extend_from_slice(&v.to_be_bytes()),
            }
        }
    };
    let end_line = |out: &mut Vec<u8>| {
        if let Ply::Ascii = encoding {
            out.push(b'\n');
        }
    };
    for (i, p) in shape.positions.iter().enumerate() {
        f32s(&mut out, &p.to_array());
        if let Some(n) = normals {
            f32s(&mut out, &n[i].to_array());
        }
        match colors {
            Some((c, PlyColor::UChar)) => {
                let bytes = (c[i] * 255.0).round().to_array().map(|x| x as u8);
                for b in bytes.into_iter().chain([255]) {
                    match encoding {
                        Ply::Ascii => out.extend_from_slice(format!("{b} ").as_bytes()),
                        _ => out.push(b),
                    }
                }
            }
            Some((c, PlyColor::Float)) => f32s(&mut out, &c[i].to_array()),
            None => {}
        }
        f32s(&mut out, &[0.5]);
        end_line(&mut out);
    }
    for f in &shape.faces {
        match encoding {
            Ply::Ascii => out.extend_from_slice(format!("{} ", f.len()).as_bytes()),
            _ => out.push(f.len() as u8),
        }
        let ix: Vec<i32> = f.iter().map(|&i| i as i32).collect();
        i32s(&mut out, &ix);
        end_line(&mut out);
    }
    i32s(&mut out, &[0, 1]);
    end_line(&mut out);
    out
}

/// An ASCII STL of `shape`'s triangles (facet normals left zero, as many writers do).
pub fn stl_ascii(shape: &Shape) -> Vec<u8> {
    let mut s = String::from("solid test\n");
    for t in shape.triangles() {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for i in t {
            let p = shape.positions[i as usize];
            s += &format!("      vertex {} {} {}\n", p.x, p.y, p.z);
        }
        s += "    endloop\n  endfacet\n";
    }
    s += "endsolid test\n";
    s.into_bytes()
}

/// A binary STL of `shape`'s triangles; the header starts with `solid` on purpose (as some
/// CAD exporters write it), which must not make the file read as ASCII.
pub fn stl_binary(shape: &Shape) -> Vec<u8> {
    let tris = shape.triangles();
    let mut out = b"solid binary, written by the phosphor tests".to_vec();
    out.resize(80, b' ');
    out.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        for _ in 0..3 {
            out.extend_from_slice(&0f32.to_le_bytes());
        }
        for i in t {
            for c in shape.positions[i as usize].to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// A fresh directory under the system's temporary directory for one test.
pub fn temp_dir(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "phosphor-mesh-formats-{test}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}
