//! Writers of small mesh files for the format tests: OBJ, PLY (ASCII and both binary byte
//! orders), STL (ASCII and binary), glTF (JSON with a data URI or an external buffer, GLB).
#![allow(dead_code)] // each test file uses a different subset

use glam::Vec3;

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
