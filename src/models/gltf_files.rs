//! The buffers and images a glTF file names beside itself, read through
//! `grove_systems::files`: a URI's place is checked before anything is read, so that `..`, an
//! absolute path (`/dev/zero`, `/etc/passwd`), a URL or a symbolic link out of the model's
//! folder is refused by name and never opened; what is inside is read as a regular file of at
//! most the model-file limit ([`Kind::ModelFile`]).

use std::path::{Path, PathBuf};

use grove_systems::files::{self, Kind};

use super::error::GltfProblem;

/// The path a URI names relative to the glTF file's folder (percent-decoded, `./` parts
/// dropped), or `None` for a `data:` URI. A URL (`http:`, `file:`, …) is refused: grove reads
/// only files beside the model.
pub fn relative_path(uri: &str) -> Result<Option<String>, GltfProblem> {
    if uri.starts_with("data:") {
        return Ok(None);
    }
    let scheme = uri
        .split_once(':')
        .is_some_and(|(s, _)| s.len() > 1 && s.chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)));
    if scheme {
        return Err(GltfProblem::Url);
    }
    let decoded = percent_decode(uri)?;
    if decoded.starts_with('/') {
        return Ok(Some(decoded));
    }
    let parts: Vec<&str> = decoded.split('/').filter(|p| !p.is_empty() && *p != ".").collect();
    Ok(Some(parts.join("/")))
}

/// Decodes `%XX` escapes (UTF-8).
fn percent_decode(uri: &str) -> Result<String, GltfProblem> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            let v = hex.ok_or(GltfProblem::BrokenEscape)?;
            out.push(v);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| GltfProblem::NotUtf8)
}

/// Resolves a URI the file in `base` names to the real path of a file inside `base`, refusing,
/// before anything is opened, one that leads out (`..`, an absolute path, a symbolic link to a
/// file or through a folder outside). `Ok(None)` for a `data:` URI.
pub fn resolve(base: &Path, uri: &str) -> Result<Option<PathBuf>, GltfProblem> {
    let Some(rel) = relative_path(uri)? else { return Ok(None) };
    if !grove_systems::bank::is_inside(&rel) {
        return Err(GltfProblem::Outside);
    }
    let real = files::within(&base.join(&rel), base).map_err(|e| match e {
        files::FileError::Outside { .. } => GltfProblem::SymlinkOut,
        other => GltfProblem::Unreadable(other),
    })?;
    Ok(Some(real))
}

/// Reads the file a URI names (see [`resolve`]); `Ok(None)` for a `data:` URI.
pub fn read_uri(base: &Path, uri: &str) -> Result<Option<Vec<u8>>, GltfProblem> {
    match resolve(base, uri)? {
        Some(p) => files::read(&p, Kind::ModelFile).map(Some).map_err(GltfProblem::Unreadable),
        None => Ok(None),
    }
}

/// The bytes of a `data:` URI (base64 only).
pub fn data_uri(uri: &str) -> Result<Vec<u8>, GltfProblem> {
    let rest = uri.strip_prefix("data:").ok_or(GltfProblem::NotDataUri)?;
    let (_, b64) = rest.split_once(";base64,").ok_or(GltfProblem::NotBase64Uri)?;
    base64_decode(b64)
}

/// The file's buffers: the GLB binary chunk, `data:` URIs and files beside it, each at least
/// as long as its `byteLength`. Errors name the buffer by its URI or index.
pub fn load_buffers(
    doc: &gltf::Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<gltf::buffer::Data>, GltfProblem> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let (name, bytes) = match b.source() {
            gltf::buffer::Source::Bin => {
                (format!("buffer {}", b.index()), blob.take().ok_or(GltfProblem::NoBinChunk(b.index()))?)
            }
            gltf::buffer::Source::Uri(uri) => {
                let name =
                    if uri.starts_with("data:") { format!("buffer {}", b.index()) } else { format!("buffer '{uri}'") };
                let bytes = if uri.starts_with("data:") {
                    data_uri(uri)
                } else {
                    read_uri(base, uri).map(Option::unwrap_or_default)
                };
                (name.clone(), bytes.map_err(|m| GltfProblem::Part { name, problem: Box::new(m) })?)
            }
        };
        if bytes.len() < b.length() {
            return Err(GltfProblem::ShortBuffer { name, len: bytes.len(), byte_length: b.length() });
        }
        out.push(gltf::buffer::Data(bytes));
    }
    Ok(out)
}

/// A small standard base64 decoder for `data:` URIs.
pub fn base64_decode(s: &str) -> Result<Vec<u8>, GltfProblem> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        })
    };
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in s.bytes() {
        if c == b'=' || c.is_ascii_whitespace() {
            continue;
        }
        let v = val(c).ok_or(GltfProblem::InvalidBase64)?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_a_known_string() {
        assert_eq!(base64_decode("aGVsbG8gd29ybGQ=").unwrap(), b"hello world");
    }

    #[test]
    fn uris_outside_the_folder_are_refused_before_reading() {
        let d = std::env::temp_dir().join(format!("grove-gltf-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("m/tex")).unwrap();
        std::fs::write(d.join("m/a b.bin"), b"abcd").unwrap();
        std::fs::write(d.join("secret.bin"), b"secret").unwrap();
        std::os::unix::fs::symlink(d.join("secret.bin"), d.join("m/extra.bin")).unwrap();
        std::os::unix::fs::symlink(&d, d.join("m/up")).unwrap();
        let base = d.join("m");
        assert_eq!(read_uri(&base, "a%20b.bin").unwrap().unwrap(), b"abcd");
        assert_eq!(read_uri(&base, "./a%20b.bin").unwrap().unwrap(), b"abcd");
        assert_eq!(relative_path("./tex/./a.png").unwrap().as_deref(), Some("tex/a.png"));
        assert_eq!(read_uri(&base, "data:x;base64,aGk=").unwrap(), None);
        for bad in [
            "/dev/zero",
            "/etc/passwd",
            "../secret.bin",
            "extra.bin",
            "up/secret.bin",
            "http://example.com/a.bin",
            "file:///etc/passwd",
        ] {
            let e = read_uri(&base, bad).unwrap_err().to_string();
            assert!(e.contains("outside") || e.contains("out of") || e.contains("URL"), "{bad}: {e}");
            assert!(!e.contains('\n'));
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}
