//! Loading the Stanford bunny (75,408 triangles) from OBJ text, binary PLY and binary STL: the
//! whole path a scene takes (parse, weld, triangulate, vertex normals with the default
//! 60-degree crease), from bytes already in memory so the disk does not decide. `build_only`
//! is the part all three share (welded soup to mesh), so the rest is each format's reading.
//!
//! `cargo bench --bench mesh_formats` (set `PHOSPHOR_BENCH_QUICK=1` for a short run).

#![allow(clippy::unwrap_used, reason = "benchmark set-up on known-good data")]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use phosphor::mesh::{MeshFormat, NormalOptions, TriangleSoup, parse_mesh_bytes, parse_obj};

/// The soup as binary little-endian PLY: shared vertices, triangles, no normals (as a scan).
fn ply_binary(soup: &TriangleSoup) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        soup.positions.len(),
        soup.triangles.len()
    )
    .into_bytes();
    for c in soup.positions.iter().flat_map(|p| p.to_array()) {
        out.extend_from_slice(&c.to_le_bytes());
    }
    for t in &soup.triangles {
        out.push(3);
        for i in t {
            out.extend_from_slice(&(*i as i32).to_le_bytes());
        }
    }
    out
}

/// The soup as binary STL: three corners per triangle, facet normals zero.
fn stl_binary(soup: &TriangleSoup) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(soup.triangles.len() as u32).to_le_bytes());
    for t in &soup.triangles {
        out.extend_from_slice(&[0u8; 12]);
        for c in t
            .iter()
            .flat_map(|&i| soup.positions[i as usize].to_array())
        {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

fn load_bunny(c: &mut Criterion) {
    let quick = std::env::var_os("PHOSPHOR_BENCH_QUICK").is_some();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/meshes/bunny.obj");
    let obj = std::fs::read_to_string(path).unwrap();
    let opts = NormalOptions::default();
    let soup = parse_obj(&obj, "bunny.obj", None, &opts).unwrap().to_soup();
    let ply = ply_binary(&soup);
    let stl = stl_binary(&soup);
    let none = |_: &str| Err(std::io::Error::from(std::io::ErrorKind::NotFound));
    let mut g = c.benchmark_group("load_bunny");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(if quick { 2 } else { 8 }));
    g.bench_function("obj", |b| {
        b.iter(|| parse_obj(black_box(&obj), "bunny.obj", None, &opts).unwrap())
    });
    g.bench_function("ply_binary", |b| {
        b.iter(|| {
            parse_mesh_bytes(black_box(&ply), "bunny.ply", MeshFormat::Ply, &none, &opts).unwrap()
        })
    });
    g.bench_function("stl_binary", |b| {
        b.iter(|| {
            parse_mesh_bytes(black_box(&stl), "bunny.stl", MeshFormat::Stl, &none, &opts).unwrap()
        })
    });
    // The part every format shares: welded soup to mesh (normals, surfaces).
    g.bench_function("build_only", |b| b.iter(|| black_box(&soup).build(&opts)));
    g.finish();
}

criterion_group!(benches, load_bunny);
criterion_main!(benches);
