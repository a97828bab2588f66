//! Where a glTF's bytes come from: the GLB binary chunk, base64 `data:` URIs, or files
//! relative to the glTF (a URI with a scheme or an absolute path is refused, never fetched).
//! Buffers and images share one reading of a URI ([`resolve_uri`]); the relative file it
//! names is then confined to the glTF's folder by [`crate::assets::asset_path`], for a buffer
//! through the reader's `read_relative` ([`crate::assets::read_asset`] when loading from disk),
//! for an image directly (see `material`).

use std::borrow::Cow;
use std::collections::HashMap;

use gltf::buffer::Source;

use super::super::element_error;
use crate::error::MeshError;
use crate::sanitize::quote;

/// The bytes of every buffer, each at least as long as the file declares; `uri_data` holds
/// the bytes of the URIs they name (`guard::read_uris`, each URI read once).
pub(super) fn load_buffers<'a>(
    gltf: &'a gltf::Gltf,
    file: &str,
    uri_data: &'a HashMap<String, Vec<u8>>,
) -> Result<Vec<Cow<'a, [u8]>>, MeshError> {
    let mut out = Vec::new();
    for buffer in gltf.buffers() {
        let element = format!("buffers[{}]", buffer.index());
        let data: &'a [u8] = match buffer.source() {
            Source::Bin => gltf.blob.as_deref().ok_or_else(|| {
                element_error(
                    file,
                    &element,
                    "refers to a GLB binary chunk the file lacks",
                )
            })?,
            Source::Uri(uri) => uri_data
                .get(uri)
                .ok_or_else(|| element_error(file, &element, "its uri was not read"))?,
        };
        if data.len() < buffer.length() {
            return Err(element_error(
                file,
                &element,
                format!(
                    "truncated: {} bytes, the file declares {}",
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        out.push(Cow::Borrowed(data));
    }
    Ok(out)
}

/// What a glTF URI (a buffer's or an image's) refers to.
#[derive(Debug, PartialEq)]
pub(super) enum UriTarget {
    /// A base64 `data:` URI, decoded, with its media type when it names one.
    Data {
        /// `image/png` in `data:image/png;base64,...`.
        mime: Option<String>,
        /// The decoded bytes.
        bytes: Vec<u8>,
    },
    /// A file relative to the glTF, `%XX` escapes decoded.
    Relative(String),
}

/// Resolves a URI without reading anything: a base64 `data:` URI is decoded, a relative
/// reference becomes a path; a scheme (`http:`, `file:`) or an absolute path is refused
/// (never fetched). The error is the reason, for a message.
pub(super) fn resolve_uri(uri: &str) -> Result<UriTarget, String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let (meta, payload) = data
            .split_once(',')
            .ok_or_else(|| "data URI without a comma".to_owned())?;
        let Some(mime) = meta.strip_suffix(";base64") else {
            return Err("data URI is not base64".to_owned());
        };
        let bytes =
            base64_decode(payload).ok_or_else(|| "data URI: malformed base64".to_owned())?;
        let mime = (!mime.is_empty()).then(|| mime.to_owned());
        return Ok(UriTarget::Data { mime, bytes });
    }
    // A scheme (`http:`, `file:`) or an absolute path is not a relative reference: refused
    // rather than fetched.
    let scheme = uri.split_once(':').is_some_and(|(s, _)| {
        !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
    });
    if scheme || uri.starts_with('/') || uri.starts_with('\\') {
        return Err(format!(
            "uri '{}' is not a relative file; only relative files, data: URIs and the \
             GLB binary chunk are read",
            quote(uri, 80)
        ));
    }
    let path = percent_decode(uri)
        .ok_or_else(|| format!("uri '{}': malformed %-escape", quote(uri, 80)))?;
    Ok(UriTarget::Relative(path))
}

/// The bytes a glTF buffer's URI names: a base64 `data:` URI decoded, or a file relative to
/// the glTF (its `%XX` escapes decoded) read through `read_relative`, which confines it. A URI
/// with a scheme (`http:`, `file:`) or an absolute path is refused, never fetched. The error
/// is the reason, for a message that names the element.
///
/// ```
/// let never = |_: &str| -> std::io::Result<Vec<u8>> { unreachable!() };
/// let bytes = phosphor_mesh::gltf_uri_bytes("data:application/octet-stream;base64,AAECAw==", &never);
/// assert_eq!(bytes.unwrap(), [0, 1, 2, 3]);
/// assert!(phosphor_mesh::gltf_uri_bytes("http://example.invalid/a.bin", &never).is_err());
/// ```
pub fn uri_bytes(
    uri: &str,
    read_relative: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
) -> Result<Vec<u8>, String> {
    match resolve_uri(uri)? {
        UriTarget::Data { bytes, .. } => Ok(bytes),
        UriTarget::Relative(path) => {
            read_relative(&path).map_err(|e| format!("cannot read '{}': {e}", quote(&path, 80)))
        }
    }
}

/// Standard base64 (RFC 4648), padding optional; `None` on any other character.
fn base64_decode(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    for chunk in digits.chunks(4) {
        if chunk.len() == 1 {
            return None;
        }
        let mut bits = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            bits |= value(c)? << (18 - 6 * k);
        }
        let bytes = bits.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Some(out)
}

/// `%XX` escapes of a URI path decoded (glTF writers escape spaces in file names).
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_with_and_without_padding() {
        assert_eq!(
            base64_decode("aGVsbG8=").as_deref(),
            Some(b"hello".as_slice())
        );
        assert_eq!(
            base64_decode("aGVsbG8").as_deref(),
            Some(b"hello".as_slice())
        );
        assert_eq!(
            base64_decode("AAECAw==").as_deref(),
            Some([0u8, 1, 2, 3].as_slice())
        );
        assert_eq!(base64_decode("").as_deref(), Some([].as_slice()));
        assert!(base64_decode("a").is_none());
        assert!(base64_decode("a$==").is_none());
    }

    #[test]
    fn network_and_absolute_uris_are_refused() {
        let never = |_: &str| -> std::io::Result<Vec<u8>> { panic!("must not read") };
        for uri in [
            "http://example.invalid/a.bin",
            "file:///etc/passwd",
            "/abs/a.bin",
            "C:\\a.bin",
        ] {
            let e = uri_bytes(uri, &never).expect_err(uri);
            assert!(e.contains("not a relative file"), "{e}");
        }
        let read = |p: &str| Ok(p.as_bytes().to_vec());
        assert_eq!(
            uri_bytes("my%20mesh.bin", &read).as_deref(),
            Ok(b"my mesh.bin".as_slice())
        );
        assert_eq!(
            resolve_uri("data:image/png;base64,AAEC"),
            Ok(UriTarget::Data {
                mime: Some("image/png".to_owned()),
                bytes: vec![0, 1, 2]
            })
        );
        assert_eq!(
            resolve_uri("data:;base64,"),
            Ok(UriTarget::Data {
                mime: None,
                bytes: Vec::new()
            })
        );
    }
}
