//! glTF writers: JSON with a data URI or an external buffer, GLB; extra vertex attributes,
//! materials, textures, samplers and images.

use glam::Vec3;

use super::Shape;

/// Standard base64 with padding.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = u32::from_be_bytes([0, b[0], b[1], b[2]]);
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// One glTF mesh: a shape's triangles, optional per-vertex normals, more vertex attributes,
/// and a material index.
pub struct GltfMesh<'a> {
    pub shape: &'a Shape,
    pub normals: Option<&'a [Vec3]>,
    pub extras: &'a [GltfAttribute],
    pub material: Option<usize>,
}

/// A vertex attribute beyond `POSITION` and `NORMAL`: `COLOR_0`, `TEXCOORD_0`, `TANGENT`.
pub struct GltfAttribute {
    pub semantic: &'static str,
    /// `VEC2`, `VEC3`, `VEC4`.
    pub kind: &'static str,
    pub component_type: u32,
    pub normalized: bool,
    pub count: usize,
    pub bytes: Vec<u8>,
}

impl GltfAttribute {
    /// Float components, `width` per element (2, 3 or 4).
    pub fn f32(semantic: &'static str, width: usize, values: &[f32]) -> GltfAttribute {
        GltfAttribute {
            semantic,
            kind: ["", "", "VEC2", "VEC3", "VEC4"][width],
            component_type: 5126,
            normalized: false,
            count: values.len() / width,
            bytes: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        }
    }

    /// Normalized unsigned bytes, 4 per element (VEC4 keeps every element 4-byte aligned).
    pub fn u8_vec4(semantic: &'static str, values: &[[u8; 4]]) -> GltfAttribute {
        GltfAttribute {
            semantic,
            kind: "VEC4",
            component_type: 5121,
            normalized: true,
            count: values.len(),
            bytes: values.iter().flatten().copied().collect(),
        }
    }
}

/// A glTF image: a file next to the glTF, or bytes in a buffer view.
pub enum GltfImage {
    Uri(String),
    View { mime: String, bytes: Vec<u8> },
}

/// A whole glTF document (see [`gltf`] for the common case). `materials`, `textures` and
/// `samplers` are raw JSON objects; `materials` replaces the ones made from `base_colours`.
pub struct GltfDoc<'a> {
    pub meshes: &'a [GltfMesh<'a>],
    pub node_extras: &'a [&'a str],
    pub base_colours: &'a [[f32; 4]],
    pub buffer: GltfBuffer,
    pub materials: &'a [String],
    pub textures: &'a [String],
    pub samplers: &'a [String],
    pub images: &'a [GltfImage],
    pub extensions_used: &'a [&'a str],
}

/// Where a glTF's buffer lives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GltfBuffer {
    DataUri,
    External,
    Glb,
}

/// A glTF document: one node per mesh with the given node JSON (`"translation": ...` etc.,
/// without `mesh`), materials with the given base colours. Returns the file's bytes and, for
/// `External`, the buffer's bytes (to write next to it as `mesh.bin`).
pub fn gltf(
    meshes: &[GltfMesh<'_>],
    node_extras: &[&str],
    base_colours: &[[f32; 4]],
    buffer: GltfBuffer,
) -> (Vec<u8>, Vec<u8>) {
    gltf_doc(&GltfDoc {
        meshes,
        node_extras,
        base_colours,
        buffer,
        materials: &[],
        textures: &[],
        samplers: &[],
        images: &[],
        extensions_used: &[],
    })
}

/// The file's bytes and, for `External`, the buffer's bytes of `doc`.
pub fn gltf_doc(doc: &GltfDoc<'_>) -> (Vec<u8>, Vec<u8>) {
    let GltfDoc {
        meshes,
        node_extras,
        base_colours,
        buffer,
        ..
    } = *doc;
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut json_meshes = Vec::new();
    let add_view = |bin: &mut Vec<u8>, data: &[u8], views: &mut Vec<String>| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}}}",
            bin.len(),
            data.len()
        ));
        bin.extend_from_slice(data);
        views.len() - 1
    };
    for m in meshes {
        let (lo, hi) = m.shape.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let floats = |v: &[Vec3]| -> Vec<u8> {
            v.iter()
                .flat_map(|p| p.to_array())
                .flat_map(f32::to_le_bytes)
                .collect()
        };
        let view = add_view(&mut bin, &floats(&m.shape.positions), &mut views);
        accessors.push(format!(
            "{{\"bufferView\":{view},\"componentType\":5126,\"count\":{},\"type\":\"VEC3\",\
             \"min\":[{},{},{}],\"max\":[{},{},{}]}}",
            m.shape.positions.len(),
            lo.x,
            lo.y,
            lo.z,
            hi.x,
            hi.y,
            hi.z
        ));
        let mut attributes = format!("\"POSITION\":{}", accessors.len() - 1);
        if let Some(n) = m.normals {
            let view = add_view(&mut bin, &floats(n), &mut views);
            accessors.push(format!(
                "{{\"bufferView\":{view},\"componentType\":5126,\"count\":{},\"type\":\"VEC3\"}}",
                n.len()
            ));
            attributes += &format!(",\"NORMAL\":{}", accessors.len() - 1);
        }
        for a in m.extras {
            let view = add_view(&mut bin, &a.bytes, &mut views);
            accessors.push(format!(
                "{{\"bufferView\":{view},\"componentType\":{},\"normalized\":{},\"count\":{},\
                 \"type\":\"{}\"}}",
                a.component_type, a.normalized, a.count, a.kind
            ));
            attributes += &format!(",\"{}\":{}", a.semantic, accessors.len() - 1);
        }
        let indices: Vec<u8> = m
            .shape
            .triangles()
            .iter()
            .flatten()
            .flat_map(|&i| (i as u16).to_le_bytes())
            .collect();
        let view = add_view(&mut bin, &indices, &mut views);
        accessors.push(format!(
            "{{\"bufferView\":{view},\"componentType\":5123,\"count\":{},\"type\":\"SCALAR\"}}",
            indices.len() / 2
        ));
        let material = m
            .material
            .map_or(String::new(), |i| format!(",\"material\":{i}"));
        json_meshes.push(format!(
            "{{\"name\":\"mesh{}\",\"primitives\":[{{\"attributes\":{{{attributes}}},\
             \"indices\":{}{material}}}]}}",
            json_meshes.len(),
            accessors.len() - 1
        ));
    }
    let images: Vec<String> = doc
        .images
        .iter()
        .map(|image| match image {
            GltfImage::Uri(uri) => format!("{{\"uri\":\"{uri}\"}}"),
            GltfImage::View { mime, bytes } => {
                let view = add_view(&mut bin, bytes, &mut views);
                format!("{{\"bufferView\":{view},\"mimeType\":\"{mime}\"}}")
            }
        })
        .collect();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let nodes: Vec<String> = (0..meshes.len())
        .map(|i| {
            let extra = node_extras.get(i).copied().unwrap_or("");
            let sep = if extra.is_empty() { "" } else { "," };
            format!("{{\"mesh\":{i}{sep}{extra}}}")
        })
        .collect();
    let mut materials: Vec<String> = base_colours
        .iter()
        .enumerate()
        .map(|(i, c)| {
            format!(
                "{{\"name\":\"paint{i}\",\"pbrMetallicRoughness\":{{\"baseColorFactor\":[{},{},{},{}]}}}}",
                c[0], c[1], c[2], c[3]
            )
        })
        .collect();
    if !doc.materials.is_empty() {
        materials = doc.materials.to_vec();
    }
    let mut more = String::new();
    for (key, list) in [
        ("textures", doc.textures.to_vec()),
        ("samplers", doc.samplers.to_vec()),
        ("images", images),
    ] {
        if !list.is_empty() {
            more += &format!(",\"{key}\":[{}]", list.join(","));
        }
    }
    if !doc.extensions_used.is_empty() {
        let names: Vec<String> = doc
            .extensions_used
            .iter()
            .map(|e| format!("\"{e}\""))
            .collect();
        more += &format!(",\"extensionsUsed\":[{}]", names.join(","));
    }
    let uri = match buffer {
        GltfBuffer::DataUri => format!(
            ",\"uri\":\"data:application/octet-stream;base64,{}\"",
            base64(&bin)
        ),
        GltfBuffer::External => ",\"uri\":\"mesh.bin\"".to_owned(),
        GltfBuffer::Glb => String::new(),
    };
    let scene_nodes: Vec<String> = (0..meshes.len()).map(|i| i.to_string()).collect();
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\"}},\"scene\":0,\"scenes\":[{{\"nodes\":[{}]}}],\
         \"nodes\":[{}],\"meshes\":[{}],\"materials\":[{}],\"accessors\":[{}],\
         \"bufferViews\":[{}],\"buffers\":[{{\"byteLength\":{}{uri}}}]{more}}}",
        scene_nodes.join(","),
        nodes.join(","),
        json_meshes.join(","),
        materials.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    )
    .replace(",\"materials\":[]", "");
    match buffer {
        GltfBuffer::Glb => (glb(&json, &bin), Vec::new()),
        GltfBuffer::External => (json.into_bytes(), bin),
        GltfBuffer::DataUri => (json.into_bytes(), Vec::new()),
    }
}

/// A GLB container: header, JSON chunk (space padded), BIN chunk (zero padded).
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}
