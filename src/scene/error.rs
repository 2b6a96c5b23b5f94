//! Scene errors: each names the file and the line and column, or the field.

/// Why a scene could not be loaded.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{path}: cannot read the scene file: {source}")]
    Io {
        /// The scene file.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Not valid RON, an unknown field, a missing field or a wrong type.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        /// The scene file.
        path: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A value is out of range, a name does not resolve, a mesh is unusable.
    #[error("{path}: `{field}`: {message}")]
    Invalid {
        /// The scene file.
        path: String,
        /// The field, as a path (`bodies[1].scale`).
        field: String,
        /// What is wrong and what was expected.
        message: String,
    },
}
