//! Tells the viewer's window test whether Xvfb can run it: with `xvfb-run` on the PATH at build
//! time the test runs; without it the test is reported as ignored with the reason, so that
//! `cargo test --workspace` passes on a machine that has only the Rust toolchain.

use std::path::Path;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(has_xvfb)");
    println!("cargo::rerun-if-env-changed=PATH");
    let found = std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| Path::new(&dir).join("xvfb-run").is_file())
    });
    if found {
        println!("cargo::rustc-cfg=has_xvfb");
    }
}
