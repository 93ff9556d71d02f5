//! Scene errors: one message per problem, naming the file, the key, the value and
//! what is allowed. Messages are lower-case and end without a period.

use thiserror::Error;

/// Everything that can be wrong with a scene.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read.
    #[error("{path}: cannot read the scene file: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax, unknown key, wrong type or missing key, with position.
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        /// File.
        path: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong (and a did-you-mean where one helps).
        message: String,
    },
    /// A value outside its allowed range.
    #[error("{path}: {key} = {value} is out of range: allowed {allowed}")]
    OutOfRange {
        /// File.
        path: String,
        /// Dotted key.
        key: String,
        /// Value as written.
        value: String,
        /// Allowed range, with unit.
        allowed: String,
    },
    /// A value that is valid alone but not with the rest of the scene.
    #[error("{path}: {key}: {message}")]
    Invalid {
        /// File.
        path: String,
        /// Dotted key.
        key: String,
        /// What is wrong and how to fix it.
        message: String,
    },
}
