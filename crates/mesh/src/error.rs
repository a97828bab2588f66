//! Errors of mesh loading: every message names the file, and the line where one is known.

use thiserror::Error;

/// A mesh file (OBJ and its MTL, PLY, STL, glTF) that could not be turned into a [`crate::Mesh`].
///
/// `Display` is `FILE:LINE: what` when the offending line is known, `FILE: ELEMENT: what` for
/// an element of a binary file, `FILE: what` otherwise.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The file could not be read (missing, unreadable).
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file as given by the caller.
        file: String,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// A line that is not valid OBJ: malformed number, zero or out-of-range index, NaN or
    /// infinite coordinate, bad smoothing group, invalid UTF-8, ...
    #[error("{file}:{line}: {what}")]
    Parse {
        /// The file as given by the caller.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong with the line.
        what: String,
    },
    /// The file parsed but holds no polygon with three or more corners.
    #[error("{file}: no faces (a mesh needs at least one polygon with 3 or more vertices)")]
    NoFaces {
        /// The file as given by the caller.
        file: String,
    },
    /// An element of a binary file (or one with no line to give) that is wrong: truncated data,
    /// an index out of range, a NaN coordinate, an unsupported encoding.
    #[error("{file}: {element}: {what}")]
    Element {
        /// The file as given by the caller.
        file: String,
        /// The element: `facet 12`, `face 7 of 40`, `meshes[0].primitives[1]`.
        element: String,
        /// What is wrong with it.
        what: String,
    },
    /// An error without a line: reported by tobj after our own line scan accepted the file,
    /// or a mesh with no drawable face (every triangle of zero area).
    #[error("{file}: {what}")]
    Invalid {
        /// The file as given by the caller.
        file: String,
        /// What is wrong.
        what: String,
    },
}

impl MeshError {
    /// The 1-based line number the error names, if any.
    #[must_use]
    pub fn line(&self) -> Option<usize> {
        match self {
            MeshError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }
}
