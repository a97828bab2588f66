//! Mesh processing grows about linearly with the input, for the shapes that once made it
//! quadratic: one triangle repeated (every face on the same three edges), a fan of faces
//! around one vertex (a cone's apex), and one polygon with many corners. Each shape is loaded
//! at `n` and `10 n` faces or corners; criterion's report shows the time growing about 10x,
//! not 100x.
//!
//! `cargo bench --bench mesh_growth` (set `PHOSPHOR_BENCH_QUICK=1` for a short run).

#![allow(clippy::unwrap_used, reason = "benchmark set-up on known-good data")]

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use phosphor::mesh::{NormalOptions, Weighting, parse_obj};

/// One triangle's corners, then `n` faces all on them.
fn repeated_faces(n: usize) -> String {
    let mut s = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    s.push_str(&"f 1 2 3\n".repeat(n));
    s
}

/// A cone of `n` faces around the apex.
fn fan(n: usize) -> String {
    let mut s = String::from("v 0 1 0\n");
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        writeln!(s, "v {} 0 {}", a.cos(), -a.sin()).unwrap();
    }
    for i in 0..n {
        writeln!(s, "f 1 {} {}", i + 2, (i + 1) % n + 2).unwrap();
    }
    s
}

/// One convex polygon of `n` corners.
fn polygon(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        writeln!(s, "v {} {} 0", a.cos(), a.sin()).unwrap();
    }
    s.push('f');
    for i in 1..=n {
        write!(s, " {i}").unwrap();
    }
    s.push('\n');
    s
}

/// Makes the OBJ text of a shape of `n` faces or corners.
type MakeObj = fn(usize) -> String;

fn growth(c: &mut Criterion) {
    let quick = std::env::var_os("PHOSPHOR_BENCH_QUICK").is_some();
    let shapes: [(&str, MakeObj); 3] = [
        ("repeated_faces", repeated_faces),
        ("fan_around_one_vertex", fan),
        ("one_polygon", polygon),
    ];
    let smooth = NormalOptions::smooth_all(Weighting::Uniform);
    for (name, make) in shapes {
        let mut g = c.benchmark_group(format!("mesh_growth/{name}"));
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(if quick { 1 } else { 4 }));
        for n in [10_000, 100_000] {
            let text = make(n);
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::from_parameter(n), &text, |b, text| {
                b.iter(|| black_box(parse_obj(text, "growth.obj", None, &smooth).unwrap()));
            });
        }
        g.finish();
    }
}

criterion_group!(benches, growth);
criterion_main!(benches);
