//! Writes a mesh (any format `load_mesh` reads) as binary PLY or binary STL, by the output's
//! extension: positions welded, triangles as loaded, no normals (readers recompute them).
//!
//! ```text
//! cargo run --release -p phosphor-mesh --example mesh_convert -- assets/meshes/bunny.obj bunny.ply
//! cargo run --release -p phosphor-mesh --example mesh_convert -- assets/meshes/bunny.obj bunny.stl
//! ```

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use phosphor_mesh::{MeshFormat, NormalOptions, load_mesh};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: mesh_convert IN.(obj|ply|stl|gltf|glb) OUT.(ply|stl)");
        return ExitCode::from(2);
    };
    match convert(Path::new(input), Path::new(output)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn convert(input: &Path, output: &Path) -> Result<(), String> {
    let mesh = load_mesh(input, &NormalOptions::default()).map_err(|e| e.to_string())?;
    let soup = mesh.to_soup();
    let mut out = Vec::new();
    match MeshFormat::from_path(output) {
        MeshFormat::Ply => {
            write!(
                out,
                "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
                 property float y\nproperty float z\nelement face {}\n\
                 property list uchar int vertex_indices\nend_header\n",
                soup.positions.len(),
                soup.triangles.len()
            )
            .map_err(|e| e.to_string())?;
            for p in &soup.positions {
                for c in p.to_array() {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            for t in &soup.triangles {
                out.push(3);
                for i in t {
                    out.extend_from_slice(&(*i as i32).to_le_bytes());
                }
            }
        }
        MeshFormat::Stl => {
            let mut header = b"binary STL written by phosphor mesh_convert".to_vec();
            header.resize(80, b' ');
            out.extend_from_slice(&header);
            out.extend_from_slice(&(soup.triangles.len() as u32).to_le_bytes());
            for t in &soup.triangles {
                let [a, b, c] = t.map(|i| soup.positions[i as usize]);
                let n = (b - a).cross(c - a).normalize_or_zero();
                for v in [n, a, b, c] {
                    for x in v.to_array() {
                        out.extend_from_slice(&x.to_le_bytes());
                    }
                }
                out.extend_from_slice(&[0, 0]);
            }
        }
        _ => return Err(format!("{}: output must be .ply or .stl", output.display())),
    }
    std::fs::write(output, out).map_err(|e| format!("{}: cannot write: {e}", output.display()))
}
