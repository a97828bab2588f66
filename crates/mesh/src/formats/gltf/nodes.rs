//! The nodes a glTF file shows, each with its world transform.

use glam::Mat4;

use super::super::element_error;
use crate::error::MeshError;

/// Every node of the scene to show, with its world transform (parents first).
pub(super) fn placed_nodes<'a>(
    gltf: &'a gltf::Gltf,
    file: &str,
) -> Result<Vec<(gltf::Node<'a>, Mat4)>, MeshError> {
    let roots: Vec<gltf::Node<'a>> = match gltf.default_scene().or_else(|| gltf.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; gltf.nodes().len()];
            for n in gltf.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            gltf.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut visited = vec![false; gltf.nodes().len()];
    let mut stack: Vec<(gltf::Node<'a>, Mat4)> = roots
        .into_iter()
        .rev()
        .map(|n| (n, Mat4::IDENTITY))
        .collect();
    let mut out = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        let element = format!("nodes[{}]", node.index());
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(element_error(
                file,
                element,
                "reached twice (a glTF node has at most one parent and no cycle)",
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(element_error(
                file,
                element,
                "transform is not finite (NaN or overflow)",
            ));
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
        out.push((node, world));
    }
    Ok(out)
}
