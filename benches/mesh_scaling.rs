//! How OBJ loading grows with the inputs that once made it quadratic: one triangle repeated
//! (every copy on the same three edges), a cone (every face around one apex), one huge convex
//! polygon and one huge star (one face of many corners), beside an ordinary grid mesh for
//! reference. Each shape is timed at n and 10 n; near-linear processing shows about 10x between
//! the two (as the grid does), not 100x.
//!
//! `cargo bench --bench mesh_scaling` (under a minute).

#![allow(clippy::unwrap_used, reason = "benchmark set-up on known-good data")]

use std::fmt::Write;
use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use phosphor::mesh::{NormalOptions, parse_obj};

/// One triangle written `n` times.
fn repeated(n: usize) -> String {
    format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{}", "f 1 2 3\n".repeat(n))
}

/// A cone of `n` triangles sharing the apex.
fn cone(n: usize) -> String {
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

/// One polygon of `n` corners on a circle whose radius alternates by `ratio` (1: convex;
/// below 1: a star, concave at every other corner).
fn polygon(n: usize, ratio: f64) -> String {
    let mut s = String::new();
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        let r = if i % 2 == 0 { 1.0 } else { ratio };
        writeln!(s, "v {} {} 0", r * a.cos(), r * a.sin()).unwrap();
    }
    s.push('f');
    for i in 1..=n {
        write!(s, " {i}").unwrap();
    }
    s.push('\n');
    s
}

/// An ordinary mesh for reference: a wavy square grid of about `n` triangles.
fn grid(n: usize) -> String {
    let m = ((n / 2) as f64).sqrt().round() as usize;
    let mut s = String::new();
    for j in 0..=m {
        for i in 0..=m {
            let (u, v) = (i as f64 / m as f64, j as f64 / m as f64);
            writeln!(s, "v {u} {v} {}", 0.1 * (7.0 * u).sin() * (5.0 * v).cos()).unwrap();
        }
    }
    for j in 0..m {
        for i in 0..m {
            let a = j * (m + 1) + i + 1;
            writeln!(
                s,
                "f {a} {} {}\nf {a} {} {}",
                a + 1,
                a + m + 2,
                a + m + 2,
                a + m + 1
            )
            .unwrap();
        }
    }
    s
}

/// OBJ text of a shape of the given size.
type Shape = fn(usize) -> String;

fn scaling(c: &mut Criterion) {
    let shapes: [(&str, Shape, usize); 5] = [
        ("repeated_triangle", repeated, 4_000),
        ("cone_apex", cone, 5_000),
        ("convex_polygon", |n| polygon(n, 1.0), 5_000),
        ("star_polygon", |n| polygon(n, 0.5), 5_000),
        ("ordinary_grid", grid, 5_000),
    ];
    let opts = NormalOptions::default();
    for (name, make, n) in shapes {
        let mut g = c.benchmark_group(format!("mesh_scaling/{name}"));
        g.sample_size(10)
            .warm_up_time(Duration::from_millis(300))
            .measurement_time(Duration::from_secs(2));
        for size in [n, 10 * n] {
            let text = make(size);
            // Every input must load (a failure would time an error path).
            assert!(parse_obj(&text, "bench.obj", None, &opts).is_ok());
            g.bench_with_input(BenchmarkId::from_parameter(size), &text, |b, text| {
                b.iter(|| parse_obj(black_box(text), "bench.obj", None, &opts).unwrap());
            });
        }
        g.finish();
    }
}

criterion_group!(benches, scaling);
criterion_main!(benches);
