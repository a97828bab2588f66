//! Texture references in materials: MTL `map_Kd`, `map_Ks`, `norm` with their options, the
//! statements Phosphor does not use, glTF base colour and normal textures with sampler wraps
//! from files, data URIs and buffer views; bad references are warnings, never panics.

mod writers;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec3, Vec4};
use phosphor_mesh::{
    Mesh, MeshFormat, MtlMaterial, NormalOptions, TextureRef, TextureSource, Wrap,
    load_obj_with_warnings, parse_mesh_bytes, parse_obj_with_warnings,
};
use writers::{GltfAttribute, GltfBuffer, GltfDoc, GltfImage, GltfMesh, Shape};

const OBJ: &str = "mtllib mats/m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
usemtl clamped\nf 1 2 3\nusemtl scaled\nf 2 4 3\nusemtl other\nf 1 3 4\n";

const MTL: &str = "# three materials\nnewmtl clamped\nKd 1 1 1\nmap_Kd -clamp on tex.png\n\
newmtl scaled\nKs 0.5 0.5 0.5\nmap_Kd -s 1 1 1 -o 0 0 0 tex dir/checker.png\n\
map_Ks spec.png\nnorm -bm 0.5 n.png\nillum 2\nd 1\n\
newmtl other\nKd 0.5 0.25 0.125\nd 0.5\nTr 0.5\nmap_Ka a.png\nrefl -type sphere r.png\n\
disp d.png\nmap_Ns ns.png\nbump b.png\nmap_Bump -bm 2 b2.png\nmap_d -clamp on alpha.png\n\
d 0.25\n";

fn file_map(dir: &Path, name: &str) -> TextureSource {
    TextureSource::File(dir.join(name))
}

#[test]
fn mtl_maps_resolve_against_the_mtl_folder_with_their_options() {
    let dir = writers::temp_dir("mtl-maps");
    std::fs::create_dir_all(dir.join("mats")).expect("dir");
    std::fs::write(dir.join("m.obj"), OBJ).expect("obj");
    std::fs::write(dir.join("mats/m.mtl"), MTL).expect("mtl");
    let (m, warnings) =
        load_obj_with_warnings(&dir.join("m.obj"), &NormalOptions::default()).expect("loads");
    assert!(warnings.is_empty(), "{warnings:?}");
    let mats = dir.join("mats");
    let [clamped, scaled, other] = &m.materials[..] else {
        panic!("three materials: {:?}", m.materials);
    };
    let kd = clamped.kd_map.as_ref().expect("map_Kd");
    assert_eq!(kd.source, file_map(&mats, "tex.png"));
    assert_eq!(
        (kd.wrap_u, kd.wrap_v),
        (Wrap::ClampToEdge, Wrap::ClampToEdge)
    );
    assert_eq!(kd.written, "tex.png");
    let kd = scaled.kd_map.as_ref().expect("map_Kd");
    assert_eq!(
        kd.written, "tex dir/checker.png",
        "options read past, spaces kept"
    );
    assert_eq!(kd.source, file_map(&mats, "tex dir/checker.png"));
    assert_eq!((kd.wrap_u, kd.wrap_v), (Wrap::Repeat, Wrap::Repeat));
    assert_eq!(
        scaled.ks_map.as_ref().map(|t| &t.source),
        Some(&file_map(&mats, "spec.png"))
    );
    let (normal, scale) = scaled.normal_map.as_ref().expect("norm");
    assert_eq!((normal.written.as_str(), *scale), ("n.png", 0.5));
    assert_eq!(scaled.ks, Vec3::splat(0.5), "colours still come from tobj");
    assert!(scaled.unused.is_empty(), "illum 2 and d 1 change nothing");
    assert_eq!(
        other.unused,
        [
            "d", "Tr", "map_Ka", "refl", "disp", "map_Ns", "bump", "map_Bump", "map_d"
        ]
    );
    assert_eq!(other.kd, Vec3::new(0.5, 0.25, 0.125));
    assert!(other.kd_map.is_none() && other.normal_map.is_none());
}

#[test]
fn mtl_text_maps_resolve_against_the_obj_name_and_mtllib() {
    let (m, warnings) =
        parse_obj_with_warnings(OBJ, "assets/m.obj", Some(MTL), &NormalOptions::default())
            .expect("parses");
    assert!(warnings.is_empty(), "{warnings:?}");
    let kd = m.materials[0].kd_map.as_ref().expect("map_Kd");
    assert_eq!(
        kd.source,
        TextureSource::File(PathBuf::from("assets/mats/tex.png"))
    );
}

#[test]
fn bad_mtl_map_lines_are_warnings_and_the_colours_survive() {
    let mtl = "newmtl a\nKd 0.25 0.5 1\nmap_Kd -clamp sometimes t.png\nmap_Ks\nnorm -bm x n.png\n\
               map_Kd   \n";
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let (m, warnings) = parse_obj_with_warnings(obj, "m.obj", Some(mtl), &NormalOptions::default())
        .expect("parses");
    let a: &MtlMaterial = &m.materials[0];
    assert_eq!(
        a.kd,
        Vec3::new(0.25, 0.5, 1.0),
        "one bad map line loses no colour"
    );
    let kd = a.kd_map.as_ref().expect("used without the bad option");
    assert_eq!((kd.written.as_str(), kd.wrap_u), ("t.png", Wrap::Repeat));
    assert!(a.ks_map.is_none());
    assert_eq!(
        a.normal_map.as_ref().map(|(t, s)| (t.written.as_str(), *s)),
        Some(("n.png", 1.0))
    );
    assert_eq!(warnings.len(), 4, "{warnings:?}");
    assert!(warnings[0].starts_with("m.mtl:3: map_Kd: -clamp expects on or off"));
    assert!(warnings[1].starts_with("m.mtl:4: map_Ks: no file name"));
    assert!(warnings[2].starts_with("m.mtl:5: norm: -bm expects a number"));
    assert!(warnings[3].starts_with("m.mtl:6: map_Kd: no file name"));
}

/// A unit quad in z = 0 facing +Z, with uvs, normals and tangents.
fn quad() -> Shape {
    Shape {
        positions: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        faces: vec![vec![0, 1, 2, 3]],
    }
}

fn quad_attributes(tangent: Vec4) -> [GltfAttribute; 2] {
    [
        GltfAttribute::f32("TEXCOORD_0", 2, &[0., 1., 1., 1., 1., 0., 0., 0.]),
        GltfAttribute::f32("TANGENT", 4, &tangent.to_array().repeat(4)),
    ]
}

const NORMALS: [Vec3; 4] = [Vec3::Z; 4];

fn load(
    bytes: &[u8],
    name: &str,
    read: &dyn Fn(&str) -> std::io::Result<Vec<u8>>,
) -> (Mesh, Vec<String>) {
    let format = MeshFormat::from_path(Path::new(name));
    let (m, w) = parse_mesh_bytes(bytes, name, format, read, &NormalOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(m.is_consistent(), "{name}");
    (m, w)
}

fn no_files(_: &str) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::from(std::io::ErrorKind::NotFound))
}

/// A quad whose one material uses `materials`, `textures`, `samplers` and `images`.
fn textured_quad(
    buffer: GltfBuffer,
    materials: &[String],
    textures: &[String],
    samplers: &[String],
    images: &[GltfImage],
    extensions_used: &[&str],
) -> Vec<u8> {
    let shape = quad();
    let extras = quad_attributes(Vec4::new(1.0, 0.0, 0.0, 1.0));
    let mesh = GltfMesh {
        shape: &shape,
        normals: Some(&NORMALS),
        extras: &extras,
        material: Some(0),
    };
    writers::gltf_doc(&GltfDoc {
        meshes: &[mesh],
        node_extras: &[],
        base_colours: &[],
        buffer,
        materials,
        textures,
        samplers,
        images,
        extensions_used,
    })
    .0
}

fn strings(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| (*s).to_owned()).collect()
}

const MATERIAL: &str = "{\"name\":\"tex\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.25,1,1],\
\"baseColorTexture\":{\"index\":0}},\"normalTexture\":{\"index\":1,\"scale\":0.75}}";

#[test]
fn gltf_textures_from_files_and_data_uris_with_sampler_wraps() {
    let bytes = textured_quad(
        GltfBuffer::DataUri,
        &strings(&[MATERIAL]),
        &strings(&["{\"sampler\":0,\"source\":0}", "{\"source\":1}"]),
        &strings(&["{\"wrapS\":33071,\"wrapT\":33648}"]),
        &[
            GltfImage::Uri("tex%20a.png".to_owned()),
            GltfImage::Uri("data:image/png;base64,AAEC".to_owned()),
        ],
        &[],
    );
    let (m, warnings) = load(&bytes, "models/a.gltf", &no_files);
    assert!(warnings.is_empty(), "{warnings:?}");
    let mat = &m.materials[0];
    assert_eq!(mat.kd, Vec3::new(0.5, 0.25, 1.0), "the factor stays kd");
    let kd = mat.kd_map.as_ref().expect("base colour texture");
    assert_eq!(
        kd.source,
        TextureSource::File(PathBuf::from("models/tex a.png"))
    );
    assert_eq!(
        (kd.wrap_u, kd.wrap_v),
        (Wrap::ClampToEdge, Wrap::MirroredRepeat)
    );
    let (normal, scale): &(TextureRef, f32) = mat.normal_map.as_ref().expect("normal texture");
    assert_eq!(*scale, 0.75);
    assert_eq!((normal.wrap_u, normal.wrap_v), (Wrap::Repeat, Wrap::Repeat));
    assert_eq!(
        normal.source,
        TextureSource::Embedded {
            name: "images[1]".to_owned(),
            mime: Some("image/png".to_owned()),
            bytes: Arc::from(&[0u8, 1, 2][..]),
        }
    );
}

#[test]
fn glb_textures_from_buffer_views_are_copied_and_shared() {
    let png = vec![0x89, b'P', b'N', b'G', 7, 8, 9];
    let shared = "{\"name\":\"t\",\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}},\
                  \"normalTexture\":{\"index\":0}}";
    let bytes = textured_quad(
        GltfBuffer::Glb,
        &strings(&[shared]),
        &strings(&["{\"source\":0,\"sampler\":0}"]),
        &strings(&["{\"wrapS\":10497,\"wrapT\":33071}"]),
        &[GltfImage::View {
            mime: "image/png".to_owned(),
            bytes: png.clone(),
        }],
        &[],
    );
    let (m, warnings) = load(&bytes, "a.glb", &no_files);
    assert!(warnings.is_empty(), "{warnings:?}");
    let kd = m.materials[0].kd_map.as_ref().expect("base colour");
    let TextureSource::Embedded { mime, bytes, .. } = &kd.source else {
        panic!("embedded: {kd:?}");
    };
    assert_eq!((mime.as_deref(), &bytes[..]), (Some("image/png"), &png[..]));
    assert_eq!((kd.wrap_u, kd.wrap_v), (Wrap::Repeat, Wrap::ClampToEdge));
    let (normal, scale) = m.materials[0].normal_map.as_ref().expect("normal");
    assert_eq!(*scale, 1.0, "scale defaults to 1");
    let TextureSource::Embedded { bytes: again, .. } = &normal.source else {
        panic!("embedded");
    };
    assert!(Arc::ptr_eq(bytes, again), "one copy of an image used twice");
}

#[test]
fn bad_gltf_texture_references_are_warnings_and_the_mesh_loads() {
    let materials = strings(&[
        // texCoord 1, a texture out of range, and an unused occlusion texture.
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,\"texCoord\":1}},\
         \"normalTexture\":{\"index\":9},\"occlusionTexture\":{\"index\":0}}",
        // A texture whose image does not exist.
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":1}}}",
    ]);
    let bytes = textured_quad(
        GltfBuffer::DataUri,
        &materials,
        &strings(&["{\"source\":0,\"sampler\":4}", "{\"source\":5}"]),
        &[],
        &[GltfImage::Uri("http://example.invalid/t.png".to_owned())],
        &["KHR_texture_transform"],
    );
    let (m, warnings) = load(&bytes, "bad.gltf", &no_files);
    let has = |needle: &str| warnings.iter().any(|w| w.contains(needle));
    assert!(has("textures[0]: sampler does not exist"), "{warnings:?}");
    assert!(has("textures[1]: image 5 does not exist"), "{warnings:?}");
    assert!(
        has("materials[0].normalTexture: texture 9 does not exist"),
        "{warnings:?}"
    );
    assert!(has("texCoord 1 is not supported"), "{warnings:?}");
    assert!(
        has("extension KHR_texture_transform is not supported"),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().all(|w| w.starts_with("bad.gltf: ")),
        "{warnings:?}"
    );
    assert!(
        m.materials
            .iter()
            .all(|x| x.kd_map.is_none() && x.normal_map.is_none())
    );
    assert_eq!(m.materials[0].unused, ["occlusionTexture"]);
    // An image URI with a scheme is refused, never fetched.
    let materials = strings(&["{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}"]);
    let bytes = textured_quad(
        GltfBuffer::DataUri,
        &materials,
        &strings(&["{\"source\":0}"]),
        &[],
        &[GltfImage::Uri("http://example.invalid/t.png".to_owned())],
        &[],
    );
    let (m, warnings) = load(&bytes, "net.gltf", &no_files);
    assert!(m.materials[0].kd_map.is_none());
    assert!(
        warnings[0].contains("is not a relative file"),
        "{warnings:?}"
    );
}

#[test]
fn gltf_authored_tangents_are_kept_and_turned_by_the_node() {
    let shape = quad();
    // MikkTSpace would give +X here; the file says +Y, left-handed.
    let extras = quad_attributes(Vec4::new(0.0, 2.0, 0.0, -1.0));
    for (node, want) in [
        ("", Vec4::new(0.0, 1.0, 0.0, -1.0)),
        // A quarter turn about Z takes +Y to -X.
        (
            "\"rotation\":[0,0,0.70710677,0.70710677]",
            Vec4::new(-1.0, 0.0, 0.0, -1.0),
        ),
        // A mirror in X keeps +Y and flips the handedness.
        ("\"scale\":[-1,1,1]", Vec4::new(0.0, 1.0, 0.0, 1.0)),
    ] {
        let mesh = GltfMesh {
            shape: &shape,
            normals: Some(&NORMALS),
            extras: &extras,
            material: None,
        };
        let (bytes, _) = writers::gltf(&[mesh], &[node], &[], GltfBuffer::DataUri);
        let (m, _) = load(&bytes, "t.gltf", &no_files);
        for t in m.tangents.as_ref().expect("tangents") {
            assert!((*t - want).length() < 1e-5, "{node}: {t} vs {want}");
        }
    }
}
