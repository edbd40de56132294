//! What loading, generating, checking and writing a scene can fail with:
//! files and their contents. Every variant prints as one clear line.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("file not found: {0}")]
    NotFound(PathBuf),
    #[error("cannot read {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("cannot write {path}: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("unknown scene '{0}': expected one of {1} or a path to a .gltf/.glb/.obj file")]
    UnknownScene(String, String),
    #[error("unsupported file type '{0}': expected .gltf, .glb or .obj")]
    UnsupportedFormat(PathBuf),
    #[error("malformed {format} file {path}: {msg}")]
    Malformed { format: &'static str, path: PathBuf, msg: String },
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error("empty scene: {0}")]
    EmptyScene(String),
    #[error("unsafe URI '{uri}' in {path}: buffers and images must lie inside the asset's folder")]
    UnsafeUri { uri: String, path: PathBuf },
    #[error("malformed camera path {path}: {msg}")]
    CameraPath { path: PathBuf, msg: String },
    #[error("cannot write '{0}': expected a .obj or .glb file name")]
    UnknownExport(PathBuf),
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
