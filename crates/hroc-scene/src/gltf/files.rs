//! The glTF loader's file access: GLB containers split by hand, and
//! buffers read only from `data:` URIs and relative paths inside the
//! asset's folder (percent-decoded, no `..`, no link out of it).

use std::path::{Component, Path, PathBuf};

use super::Msg;
use crate::error::{Error, Result};

/// Splits a GLB container into its JSON chunk and optional BIN chunk.
pub(super) fn split_glb(bytes: &[u8]) -> Msg<(&[u8], Option<Vec<u8>>)> {
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(format!("truncated GLB: {} bytes, the header alone needs 12", bytes.len()));
    };
    if version != 2 {
        return Err(format!("unsupported GLB version {version} (expected 2)"));
    }
    if length < 12 {
        return Err(format!("invalid GLB header: total length {length} is below 12"));
    }
    if length > bytes.len() {
        return Err(format!("truncated GLB: header says {length} bytes, file has {}", bytes.len()));
    }
    let mut rest = &bytes[12..length];
    let (json, ty) = take_chunk(&mut rest)?.ok_or("GLB has no JSON chunk")?;
    if &ty != b"JSON" {
        return Err(format!("GLB: first chunk is {:?}, expected \"JSON\"", String::from_utf8_lossy(&ty)));
    }
    // Chunks of unknown type are to be ignored (GLB spec); BIN is the first after JSON.
    let bin = match take_chunk(&mut rest)? {
        Some((d, ty)) if &ty == b"BIN\0" => Some(d.to_vec()),
        _ => None,
    };
    Ok((json, bin))
}

fn u32_at(b: &[u8], at: usize) -> Option<usize> {
    let s = b.get(at..at + 4)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]) as usize)
}

/// Takes the next chunk (data, type) off `rest`; `None` at the end.
fn take_chunk<'a>(rest: &mut &'a [u8]) -> Msg<Option<(&'a [u8], [u8; 4])>> {
    if rest.is_empty() {
        return Ok(None);
    }
    let (Some(len), Some(ty)) = (u32_at(rest, 0), rest.get(4..8)) else {
        return Err("truncated GLB: incomplete chunk header".into());
    };
    let ty = [ty[0], ty[1], ty[2], ty[3]];
    let Some(data) = rest.get(8..8 + len) else {
        return Err(format!("truncated GLB: chunk of {len} bytes, only {} left", rest.len() - 8));
    };
    *rest = &rest[8 + len..];
    Ok(Some((data, ty)))
}

/// Rejects buffer and image URIs that could reach outside the asset's folder,
/// before any file is opened.
pub(super) fn check_uris(doc: &gltf::Document, base: &Path, path: &Path) -> Result<()> {
    let buffer_uris = doc.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(u) => Some(u),
        gltf::buffer::Source::Bin => None,
    });
    let image_uris = doc.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    for uri in buffer_uris.chain(image_uris) {
        resolve_uri(uri, base, path)?;
    }
    Ok(())
}

/// `None` for a `data:` URI, else the file a relative URI names inside `base`.
fn resolve_uri(uri: &str, base: &Path, path: &Path) -> Result<Option<PathBuf>> {
    if uri.starts_with("data:") {
        return Ok(None);
    }
    let unsafe_uri = || Error::UnsafeUri { uri: uri.to_string(), path: path.to_path_buf() };
    let decoded = percent_decode(uri).ok_or_else(|| Error::Malformed { format: "glTF", path: path.to_path_buf(), msg: format!("URI '{uri}' has invalid percent-encoding") })?;
    // Any ':' is a scheme (http:, file:) or a drive letter; both are refused.
    // Both slash kinds separate components so that `..\` is caught everywhere.
    let normal = !decoded.is_empty()
        && !decoded.contains([':', '\0'])
        && !decoded.starts_with(['/', '\\'])
        && decoded.split(['/', '\\']).all(|c| c != "..")
        && Path::new(&decoded).components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if !normal {
        return Err(unsafe_uri());
    }
    Ok(Some(base.join(decoded)))
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

pub(super) fn read_buffers(doc: &gltf::Document, base: &Path, mut blob: Option<Vec<u8>>, path: &Path) -> Result<Vec<Vec<u8>>> {
    let bad = |msg: String| Error::Malformed { format: "glTF", path: path.to_path_buf(), msg };
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let bi = buffer.index();
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| bad(format!("buffer {bi} has no URI and there is no (unused) GLB BIN chunk")))?,
            gltf::buffer::Source::Uri(uri) => match resolve_uri(uri, base, path)? {
                None => gltf::buffer::Data::from_source(buffer.source(), None).map_err(|e| bad(format!("buffer {bi}: bad data URI: {e}")))?.0,
                Some(file) => read_external(&file, base, uri, path)?,
            },
        };
        if data.len() < buffer.length() {
            return Err(bad(format!("buffer {bi}: {} bytes of data, byteLength says {}", data.len(), buffer.length())));
        }
        out.push(data);
    }
    Ok(out)
}

/// Reads a buffer file, refusing symlinks that lead outside the asset's folder.
fn read_external(file: &Path, base: &Path, uri: &str, path: &Path) -> Result<Vec<u8>> {
    let io = |e: std::io::Error| match e.kind() {
        std::io::ErrorKind::NotFound => Error::NotFound(file.to_path_buf()),
        _ => Error::Io { path: file.to_path_buf(), source: e },
    };
    let (real, real_base) = (file.canonicalize().map_err(io)?, base.canonicalize().map_err(io)?);
    if !real.starts_with(&real_base) {
        return Err(Error::UnsafeUri { uri: uri.to_string(), path: path.to_path_buf() });
    }
    std::fs::read(&real).map_err(io)
}
