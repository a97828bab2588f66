//! Arbitrary bytes into the OBJ loader: it must return a consistent mesh or an error naming
//! the file, and never panic, hang or overflow.

#![no_main]

use libfuzzer_sys::fuzz_target;
use phosphor_mesh::{NormalOptions, parse_obj};

fuzz_target!(|data: &[u8]| {
    // parse_obj takes text; invalid UTF-8 is load_obj's (line-numbered) error, tested apart.
    let text = String::from_utf8_lossy(data);
    for opts in [NormalOptions::default(), NormalOptions::s1()] {
        match parse_obj(&text, "fuzz.obj", None, &opts) {
            Ok(mesh) => assert!(mesh.is_consistent() && !mesh.indices.is_empty()),
            Err(e) => assert!(e.to_string().starts_with("fuzz.obj:")),
        }
    }
});
