//! What a glTF file may ask of the reader, checked before the reader does it: a GLB's chunks
//! lie within the file (so a truncated file names the chunk, not an anonymous "could not
//! completely read the object"), the triangles its nodes place fit the memory budget (one
//! small mesh placed by thousands of nodes is millions of triangles), and its buffers fit the
//! size cap together, each file or `data:` URI read once however many buffers name it.

use std::collections::HashMap;

use gltf::buffer::Source;
use gltf::mesh::{Mode, Semantic};

use super::super::element_error;
use super::uri::uri_bytes;
use crate::error::MeshError;
use crate::open::{MAX_MESH_FILE_BYTES, limit_text};
use crate::primitives::{Footprint, MEMORY_BUDGET_BYTES};
use crate::sanitize::quote_bytes;

/// GLB: the 12-byte header (`glTF`, version, length), then chunks of an 8-byte header
/// (length, type) and their data.
const HEADER: usize = 12;
const CHUNK_HEADER: usize = 8;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?))
}

/// Checks the layout of a GLB file (`bytes` starting with `glTF`; anything else is JSON and
/// passes): header, version 2, a JSON chunk and an optional BIN chunk, each with its 8-byte
/// header, each within the file. A truncated file is named by the part it ends in (`JSON
/// chunk`, `BIN chunk header`, ...) and where, so that the message says what was lost.
pub(super) fn check_glb(bytes: &[u8], file: &str) -> Result<(), MeshError> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let len = bytes.len();
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(element_error(
            file,
            "header",
            format!("the file ends at byte {len}, inside the {HEADER}-byte header (truncated)"),
        ));
    };
    if version != 2 {
        return Err(element_error(
            file,
            "header",
            format!("GLB version {version} is not supported (2 only)"),
        ));
    }
    let length = length as usize;
    if length < HEADER + CHUNK_HEADER {
        return Err(element_error(
            file,
            "header",
            format!("announces {length} bytes, less than a header and one chunk header"),
        ));
    }
    let announced = if length > len {
        format!("; the header announces {length} bytes")
    } else {
        String::new()
    };
    let ends_inside = |part: &str| {
        element_error(
            file,
            part,
            format!("the file ends at byte {len}, inside it (truncated{announced})"),
        )
    };
    let mut at = HEADER;
    for (k, name, kind) in [(0, "JSON chunk", *b"JSON"), (1, "BIN chunk", *b"BIN\0")] {
        if k == 1 && at >= len {
            if length > len {
                return Err(element_error(
                    file,
                    name,
                    format!("the file ends at byte {len}, before it (truncated{announced})"),
                ));
            }
            return Ok(()); // the BIN chunk is optional
        }
        let (Some(size), Some(found)) = (u32_at(bytes, at), bytes.get(at + 4..at + 8)) else {
            return Err(ends_inside(&format!("{name} header")));
        };
        if found != kind {
            return Err(element_error(
                file,
                format!("{name} header"),
                format!(
                    "chunk {k} is of type '{}', expected '{}'",
                    quote_bytes(found, 12),
                    quote_bytes(&kind, 12)
                ),
            ));
        }
        at += CHUNK_HEADER;
        if size as usize > len - at {
            return Err(ends_inside(name));
        }
        at += size as usize;
    }
    if length > len {
        return Err(element_error(
            file,
            "header",
            format!("announces {length} bytes, the file has {len} (truncated)"),
        ));
    }
    Ok(())
}

/// Refuses, before any buffer is read, the meshes that the placed nodes (each node with a
/// mesh is one copy of it) would make when their triangles and vertices are over the memory
/// budget every built mesh is checked against ([`MEMORY_BUDGET_BYTES`], [`Footprint`]).
pub(super) fn check_placed(
    placed: &[(gltf::Node<'_>, glam::Mat4)],
    file: &str,
) -> Result<(), MeshError> {
    let (mut vertices, mut triangles, mut copies) = (0u64, 0u64, 0u64);
    for (node, _) in placed {
        let Some(mesh) = node.mesh() else { continue };
        copies += 1;
        for primitive in mesh.primitives() {
            let count = primitive
                .get(&Semantic::Positions)
                .map_or(0, |a| a.count() as u64);
            let corners = primitive.indices().map_or(count, |a| a.count() as u64);
            let made = match primitive.mode() {
                Mode::Triangles => corners / 3,
                Mode::TriangleStrip | Mode::TriangleFan => corners.saturating_sub(2),
                _ => continue,
            };
            vertices = vertices.saturating_add(count);
            triangles = triangles.saturating_add(made);
        }
    }
    let footprint = Footprint {
        vertices,
        triangles,
        field: "nodes",
    };
    footprint.check(MEMORY_BUDGET_BYTES).map_err(|e| {
        element_error(
            file,
            "nodes",
            format!("{copies} nodes place meshes: {}", e.what()),
        )
    })
}

/// The bytes of every distinct URI the buffers name (a `data:` URI decoded, a file read
/// through `read_relative`), keyed by the URI, each cut to the longest length a buffer
/// declares for it. The declared lengths of the distinct URIs must fit
/// [`MAX_MESH_FILE_BYTES`] together, checked before anything is read.
pub(super) fn read_uris(
    gltf: &gltf::Gltf,
    file: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
) -> Result<HashMap<String, Vec<u8>>, MeshError> {
    // Each URI once, in the order the buffers name them, with the longest declared length.
    let mut wanted: Vec<(usize, &str, usize)> = Vec::new();
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for buffer in gltf.buffers() {
        if let Source::Uri(uri) = buffer.source() {
            match seen.get(uri) {
                Some(&k) => wanted[k].2 = wanted[k].2.max(buffer.length()),
                None => {
                    seen.insert(uri, wanted.len());
                    wanted.push((buffer.index(), uri, buffer.length()));
                }
            }
        }
    }
    let total: u64 = wanted.iter().map(|&(_, _, n)| n as u64).sum();
    if total > MAX_MESH_FILE_BYTES {
        return Err(element_error(
            file,
            "buffers",
            format!(
                "{} files and data: URIs declare {total} bytes together, over the {} limit",
                wanted.len(),
                limit_text(MAX_MESH_FILE_BYTES)
            ),
        ));
    }
    let mut out = HashMap::new();
    for (index, uri, declared) in wanted {
        let mut data = uri_bytes(uri, read_relative)
            .map_err(|why| element_error(file, format!("buffers[{index}]"), why))?;
        if data.len() > declared {
            // Only the declared bytes are used: the rest is not kept.
            data.truncate(declared);
            data.shrink_to_fit();
        }
        out.insert(uri.to_owned(), data);
    }
    Ok(out)
}
