//! A scene file, and the files it names, read as regular files only: a FIFO standing for the
//! scene or for one of its meshes is refused on one line instead of blocking the load, and a
//! glTF's buffer stays inside the glTF's folder.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use phosphor_scene::{Scene, load_scene};

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "phosphor-scene-hostile-{test}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Loads the scene at `path` on another thread; `None` when it has not finished within 30 s
/// (a load blocked on a FIFO never would).
fn load_or_hang(path: &Path) -> Option<Result<Scene, String>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let path = path.to_owned();
    std::thread::spawn(move || {
        let _ = tx.send(load_scene(&path).map_err(|e| e.to_string()));
    });
    rx.recv_timeout(std::time::Duration::from_secs(30)).ok()
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let made = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .unwrap();
    assert!(made.success(), "mkfifo failed");
}

#[cfg(unix)]
#[test]
fn fifo_as_scene_file_is_refused_without_blocking() {
    let dir = temp_dir("fifo-scene");
    let fifo = dir.join("scene.toml");
    mkfifo(&fifo);
    let Err(e) = load_or_hang(&fifo).expect("a FIFO scene file must not block the load") else {
        panic!("a FIFO scene file must be refused");
    };
    assert!(e.contains("a FIFO, not a regular file"), "{e}");
    assert!(e.starts_with(&fifo.display().to_string()), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn fifo_as_scene_mesh_is_refused_without_blocking() {
    let dir = temp_dir("fifo-mesh");
    for name in ["pipe.obj", "pipe.stl"] {
        mkfifo(&dir.join(name));
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, format!("[[objects]]\nmesh = \"{name}\"\n")).unwrap();
        let Err(e) = load_or_hang(&scene).expect("a FIFO mesh must not block the load") else {
            panic!("a FIFO mesh must be refused");
        };
        assert!(e.contains("objects[0].mesh"), "{e}");
        assert!(e.contains("a FIFO, not a regular file"), "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn scene_gltf_buffer_outside_the_gltf_folder_is_not_read() {
    let dir = temp_dir("escape");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let bin: Vec<u8> = [[0.0f32, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    std::fs::write(dir.join("tri.bin"), bin).unwrap();
    let gltf = "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\
                \"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],\
                \"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\
                \"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[2,2,0]}],\
                \"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\
                \"buffers\":[{\"byteLength\":36,\"uri\":\"../tri.bin\"}]}";
    std::fs::write(dir.join("meshes/tri.gltf"), gltf).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "[[objects]]\nmesh = \"meshes/tri.gltf\"\n").unwrap();
    let Err(e) = load_scene(&scene) else {
        panic!("a buffer outside the glTF's folder must be refused");
    };
    let e = e.to_string();
    assert!(e.contains("buffers[0]: cannot read '../tri.bin'"), "{e}");
    assert!(e.contains("leads outside the glTF file's folder"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
