//! Scene errors: every message names the file and the field (and, for meshes, the OBJ line).

use thiserror::Error;

/// A scene that could not be loaded, saved or built.
///
/// `Display` is `FILE: FIELD: what` (docs/conventions.md, "Messages"), for example
/// `s1.toml: lights[2].intensity: expected 3 numbers, found 2`. A mesh error keeps the mesh
/// crate's own `OBJ:LINE: what` after the field that named the mesh.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The scene file as given.
        file: String,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not valid TOML.
    #[error("{file}:{line}: {what}")]
    Syntax {
        /// The scene file as given.
        file: String,
        /// 1-based line of the syntax error.
        line: usize,
        /// The parser's message.
        what: String,
    },
    /// A field with a missing, mistyped or out-of-range value.
    #[error("{file}: {field}: {what}")]
    Field {
        /// The scene file as given.
        file: String,
        /// The path of the field, `lights[2].intensity`.
        field: String,
        /// What is wrong with it.
        what: String,
    },
    /// A mesh named by an object could not be loaded.
    #[error("{file}: {field}: {source}")]
    Mesh {
        /// The scene file as given.
        file: String,
        /// The field that named the mesh, `objects[0].mesh`.
        field: String,
        /// The mesh crate's error (names the mesh file and its line or element).
        #[source]
        source: phosphor_mesh::MeshError,
    },
    /// A scene could not be written.
    #[error("{file}: cannot write: {what}")]
    Write {
        /// The output file.
        file: String,
        /// What went wrong.
        what: String,
    },
}

impl SceneError {
    /// A field error.
    pub(crate) fn field(file: &str, field: impl Into<String>, what: impl Into<String>) -> Self {
        SceneError::Field {
            file: file.to_owned(),
            field: field.into(),
            what: what.into(),
        }
    }
}
