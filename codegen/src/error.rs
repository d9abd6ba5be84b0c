//! The one error type of a build: a scheme that does not compile, a
//! duplicate name, missing configuration, or file I/O. Its own module so
//! that the output-directory code and the builder both return it without
//! importing each other.

use crate::front::scheme::SchemeError;
use std::path::PathBuf;

/// Why a build failed.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error("{origin}: {error}")]
    Scheme { origin: String, error: SchemeError },
    #[error("{origin}: scheme `{name}` is already declared by {first}")]
    DuplicateScheme {
        name: String,
        origin: String,
        first: String,
    },
    #[error("no scheme given")]
    NoScheme,
    #[error("no output directory given")]
    NoOutDir,
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}
