//! Writing files without leaving partial ones: every file grove writes (recordings excepted,
//! which are append-only by design) is written under a temporary name in the same folder and
//! renamed to its real name only when complete. A failed or interrupted write leaves no file
//! under the real name, and an existing file is replaced in one step.

use std::path::{Path, PathBuf};


/// The temporary name beside `path`: hidden, unique to this process and file, and keeping the
/// extension so that writers which choose the format by extension (PNG, CSV) still do.
pub fn temp_path(path: &Path) -> PathBuf {
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = match path.extension() {
        Some(ext) => format!(".{stem}.tmp-{}-{n}.{}", std::process::id(), ext.to_string_lossy()),
        None => format!(".{stem}.tmp-{}-{n}", std::process::id()),
    };
    path.with_file_name(name)
}

/// A file that could not be put in place: its temporary file could not be written, or renamed.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot write ({source})", path.display())]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// Why.
    #[source]
    pub source: std::io::Error,
}

/// Calls `write` with a temporary path beside `path`, then renames the temporary file to
/// `path`. If `write` fails, or the rename does, the temporary file is removed and `path` is
/// left as it was. Any error type that a [`WriteError`] converts into will do.
pub fn via_temp<T, E: From<WriteError>>(path: &Path, write: impl FnOnce(&Path) -> Result<T, E>) -> Result<T, E> {
    let tmp = temp_path(path);
    let result = write(&tmp).and_then(|value| {
        std::fs::rename(&tmp, path).map_err(|source| WriteError { path: path.to_path_buf(), source })?;
        Ok(value)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// [`via_temp`] for a writer that returns `anyhow::Result`.
pub fn write_via_temp<T>(path: &Path, write: impl FnOnce(&Path) -> anyhow::Result<T>) -> anyhow::Result<T> {
    via_temp(path, write)
}

/// Writes bytes to `path` through a temporary file and a rename.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    via_temp(path, |tmp| std::fs::write(tmp, bytes).map_err(|source| WriteError { path: path.to_path_buf(), source }))
}

/// Writes bytes to `path` through a temporary file and a rename, the file readable and writable
/// by its owner only (a private key, the server's token).
pub fn write_private(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    via_temp(path, |tmp| {
        let mut o = std::fs::OpenOptions::new();
        o.write(true).create_new(true);
        #[cfg(unix)]
        std::os::unix::fs::OpenOptionsExt::mode(&mut o, 0o600);
        let written = o.open(tmp).and_then(|mut f| std::io::Write::write_all(&mut f, bytes));
        written.map_err(|source| WriteError { path: path.to_path_buf(), source })
    })
}

/// [`write_bytes`] for a caller that returns `anyhow::Result`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    Ok(write_bytes(path, bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_neither_the_file_nor_a_temporary_one() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        let r: anyhow::Result<()> = write_via_temp(&path, |tmp| {
            std::fs::write(tmp, b"half")?;
            Err(anyhow::anyhow!("the encoder failed"))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing is left behind");
    }

    #[test]
    fn a_write_replaces_the_old_content_and_keeps_the_extension_while_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        std::fs::write(&path, b"old").unwrap();
        write_via_temp(&path, |tmp| {
            assert_eq!(tmp.extension().unwrap(), "json");
            assert_eq!(tmp.parent(), path.parent());
            assert_eq!(std::fs::read(&path).unwrap(), b"old", "the old file stays until the rename");
            Ok(std::fs::write(tmp, b"new")?)
        })
        .unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_typed_write_into_a_missing_folder_names_the_file_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no-such-folder/summary.json");
        let e = write_bytes(&path, b"{}").unwrap_err();
        assert_eq!(e.path, path);
        assert!(e.to_string().starts_with(&format!("{}: cannot write (", path.display())), "{e}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}
