//! The one way grove opens a file it reads.
//!
//! Every input file, whatever command names it, goes through [`open`], [`read`] or
//! [`read_text`] (a test fails when `File::open`, `fs::read` or `fs::read_to_string` appear
//! anywhere else in `src/` or `systems/src`). They:
//!
//! - accept only a regular file: a symbolic link is resolved first and its target must be a
//!   regular file; a folder, a named pipe, a socket or a device is refused from its metadata,
//!   and the file is opened non-blocking and checked again through the open handle, so that a
//!   pipe swapped in meanwhile is refused without ever blocking;
//! - check the size against the limit for that [`Kind`] of file before reading anything, and
//!   read at most one byte past it in case the file grows meanwhile;
//! - with [`within`], check that a path a file names (a glTF buffer, a texture, a scene named by
//!   a recording) lies inside a folder by canonical path, so that `..`, absolute paths and
//!   symbolic links cannot lead out of it.
//!
//! Errors are one line ([`FileError`]'s `Display`): the path, then what is wrong.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// What a file is, for its size limit and for the error messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A scene (`.ron`), given on the command line or named by a recording.
    Scene,
    /// A recording (`.jsonl`), read line by line; each line has its own limit.
    Recording,
    /// An L-system grammar.
    Grammar,
    /// A `crowns.csv` or another table of numbers.
    Table,
    /// A small settings or index file (a catalogue, a task, a pyramid's index).
    Index,
    /// A scenario file (`docs/scenarios.md`).
    Scenario,
    /// A glTF file (`.gltf` or `.glb`).
    Gltf,
    /// A buffer or an image a glTF file names, or a file of a model bank.
    ModelFile,
    /// An image (PNG, TIFF) decoded whole; its decoder also bounds it by the dimensions in its
    /// header.
    Image,
    /// An image streamed row by row (`grove aerial tile`): of any length, bounded by the
    /// dimensions its header states, which the reader checks before decoding.
    ImageRows,
    /// A cache file grove wrote itself (impostor atlases).
    Cache,
    /// A small status file of the operating system (`/proc/self/status`).
    Status,
    /// A file a session server sends as it is (a page, the wasm module, a scene, a model).
    Served,
}

impl Kind {
    /// The largest file of this kind, bytes.
    pub fn limit(self) -> u64 {
        use crate::limits as l;
        match self {
            Kind::Scene => l::MAX_SCENE_BYTES,
            Kind::Recording => l::MAX_RECORDING_BYTES,
            Kind::Grammar => l::MAX_GRAMMAR_BYTES,
            Kind::Table => l::MAX_TABLE_BYTES,
            Kind::Index => l::MAX_INDEX_BYTES,
            Kind::Scenario => l::MAX_SCENARIO_BYTES,
            Kind::Gltf | Kind::ModelFile => l::MAX_MODEL_FILE_BYTES,
            Kind::Image => l::MAX_IMAGE_FILE_BYTES,
            Kind::ImageRows => u64::MAX,
            Kind::Cache => l::MAX_CACHE_BYTES,
            Kind::Status => 1 << 20,
            Kind::Served => l::MAX_MODEL_FILE_BYTES,
        }
    }

    /// The kind of file in words, for messages.
    pub fn what(self) -> &'static str {
        match self {
            Kind::Scene => "a scene",
            Kind::Recording => "a recording",
            Kind::Grammar => "a grammar",
            Kind::Table => "a table",
            Kind::Index => "an index file",
            Kind::Scenario => "a scenario file",
            Kind::Gltf => "a glTF file",
            Kind::ModelFile => "a model's file",
            Kind::Image | Kind::ImageRows => "an image",
            Kind::Cache => "a cache file",
            Kind::Status => "a status file",
            Kind::Served => "a served file",
        }
    }
}

/// Why a file was not read. `Display` is one line that starts with the path.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FileError {
    /// Nothing at that path (a dangling symbolic link included).
    #[error("{path}: no such file")]
    NotFound {
        /// The path as given.
        path: String,
    },
    /// A folder where a file was expected.
    #[error("{path}: is a directory, not {what}")]
    Directory {
        /// The path as given.
        path: String,
        /// The kind of file expected.
        what: &'static str,
    },
    /// A pipe, socket or device.
    #[error("{path}: is not a regular file (a device, pipe or socket); {what} must be a regular file")]
    NotRegular {
        /// The path as given.
        path: String,
        /// The kind of file expected.
        what: &'static str,
    },
    /// Over the size limit of its kind.
    #[error("{path}: is larger than the limit of {limit} bytes for {what} ({raise})", raise = crate::limits::RAISE)]
    TooLarge {
        /// The path as given.
        path: String,
        /// The limit, bytes.
        limit: u64,
        /// The kind of file.
        what: &'static str,
    },
    /// A path that leads out of the folder it must stay in.
    #[error("{path}: lies outside {folder} (through '..', an absolute path or a symbolic link); only files inside it are read")]
    Outside {
        /// The path as given.
        path: String,
        /// The folder it must stay in.
        folder: String,
    },
    /// Text that is not UTF-8.
    #[error("{path}: not valid UTF-8 text")]
    NotUtf8 {
        /// The path as given.
        path: String,
    },
    /// Any other I/O error, on one line.
    #[error("{path}: {message}")]
    Io {
        /// The path as given.
        path: String,
        /// The error, on one line.
        message: String,
    },
}

impl FileError {
    /// The same error without the leading path (for messages that name the file their own way).
    pub fn reason(&self) -> String {
        let full = self.to_string();
        let path = match self {
            FileError::NotFound { path }
            | FileError::Directory { path, .. }
            | FileError::NotRegular { path, .. }
            | FileError::TooLarge { path, .. }
            | FileError::Outside { path, .. }
            | FileError::NotUtf8 { path }
            | FileError::Io { path, .. } => path,
        };
        full.strip_prefix(path.as_str()).and_then(|s| s.strip_prefix(": ")).map(str::to_string).unwrap_or(full)
    }
}

impl FileError {
    /// The reason without any path of this machine (not the file's, not its folder's), for a
    /// client of a server that must not learn where its files lie.
    pub fn public_reason(&self) -> String {
        match self {
            FileError::Outside { .. } => "lies outside its folder (through '..', an absolute path or a symbolic link); only files inside it are read".into(),
            other => other.reason(),
        }
    }
}

fn io_error(path: &Path, e: &std::io::Error) -> FileError {
    let path = path.display().to_string();
    match e.kind() {
        std::io::ErrorKind::NotFound => FileError::NotFound { path },
        std::io::ErrorKind::PermissionDenied => FileError::Io { path, message: "permission denied".into() },
        _ => FileError::Io { path, message: e.to_string().replace('\n', " ") },
    }
}

/// Checks what is at `path` (following symbolic links) without opening it: a regular file of
/// at most the kind's limit. Returns its length.
pub fn check(path: &Path, kind: Kind) -> Result<u64, FileError> {
    let meta = std::fs::metadata(path).map_err(|e| io_error(path, &e))?;
    check_meta(path, &meta, kind)
}

fn check_meta(path: &Path, meta: &std::fs::Metadata, kind: Kind) -> Result<u64, FileError> {
    let shown = || path.display().to_string();
    if meta.is_dir() {
        return Err(FileError::Directory { path: shown(), what: kind.what() });
    }
    if !meta.is_file() {
        return Err(FileError::NotRegular { path: shown(), what: kind.what() });
    }
    if meta.len() > kind.limit() {
        return Err(FileError::TooLarge { path: shown(), limit: kind.limit(), what: kind.what() });
    }
    Ok(meta.len())
}

/// Opens a regular file of at most the kind's limit for reading, without blocking on a pipe or
/// a device. Returns the file and its length; read it with [`read_bounded`] or through
/// `Read::take(kind.limit() + 1)`.
pub fn open(path: &Path, kind: Kind) -> Result<(File, u64), FileError> {
    check(path, kind)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // O_NONBLOCK: a pipe swapped in after the check opens at once instead of waiting for a
        // writer; the check on the handle below then refuses it. Regular files ignore the flag.
        const O_NONBLOCK: i32 = if cfg!(any(target_os = "macos", target_os = "ios", target_os = "freebsd")) { 0x4 } else { 0o4000 };
        options.custom_flags(O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| io_error(path, &e))?;
    let meta = file.metadata().map_err(|e| io_error(path, &e))?;
    let len = check_meta(path, &meta, kind)?;
    Ok((file, len))
}

/// Reads at most `kind.limit()` bytes from an opened file; more is [`FileError::TooLarge`].
pub fn read_bounded(path: &Path, file: File, len_hint: u64, kind: Kind) -> Result<Vec<u8>, FileError> {
    let limit = kind.limit();
    let mut bytes = Vec::with_capacity(len_hint.min(limit) as usize);
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| io_error(path, &e))?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge { path: path.display().to_string(), limit, what: kind.what() });
    }
    Ok(bytes)
}

/// Reads a whole regular file of at most the kind's limit.
pub fn read(path: &Path, kind: Kind) -> Result<Vec<u8>, FileError> {
    let (file, len) = open(path, kind)?;
    read_bounded(path, file, len, kind)
}

/// Reads a whole regular file of at most the kind's limit as UTF-8 text.
pub fn read_text(path: &Path, kind: Kind) -> Result<String, FileError> {
    let bytes = read(path, kind)?;
    String::from_utf8(bytes).map_err(|_| FileError::NotUtf8 { path: path.display().to_string() })
}

/// Resolves `path` (symbolic links and `..` included) and checks that it lies inside `folder`
/// (itself resolved). Returns the resolved path. A path that does not exist is
/// [`FileError::NotFound`]; one that resolves outside is [`FileError::Outside`].
pub fn within(path: &Path, folder: &Path) -> Result<PathBuf, FileError> {
    let real = std::fs::canonicalize(path).map_err(|e| io_error(path, &e))?;
    let base = std::fs::canonicalize(folder).map_err(|e| io_error(folder, &e))?;
    if !real.starts_with(&base) {
        return Err(FileError::Outside { path: path.display().to_string(), folder: folder.display().to_string() });
    }
    Ok(real)
}

/// Whether a path is a symbolic link (not followed).
pub fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).map(|m| m.file_type().is_symlink()).unwrap_or(false)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An empty folder under the system's temporary folder, removed with all it holds when
    /// the test ends, passed or failed.
    fn temp(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new().prefix(&format!("grove-files-{name}-")).tempdir().unwrap()
    }

    #[test]
    fn a_named_pipe_is_refused_without_blocking() {
        let d = temp("fifo");
        let fifo = d.path().join("pipe");
        let status = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !matches!(status, Ok(s) if s.success()) {
            panic!("mkfifo is needed for this test");
        }
        let start = std::time::Instant::now();
        let e = read_text(&fifo, Kind::Grammar).unwrap_err();
        assert!(matches!(e, FileError::NotRegular { .. }), "{e}");
        assert!(start.elapsed() < std::time::Duration::from_secs(1));
        assert!(e.to_string().starts_with(&fifo.display().to_string()));
    }

    #[test]
    fn devices_and_folders_are_refused_and_sizes_bounded() {
        let e = read(Path::new("/dev/zero"), Kind::Grammar).unwrap_err();
        assert!(matches!(e, FileError::NotRegular { .. }), "{e}");
        let d = temp("size");
        assert!(matches!(read(d.path(), Kind::Scene).unwrap_err(), FileError::Directory { .. }));
        let big = d.path().join("big.txt");
        std::fs::write(&big, vec![b'x'; (Kind::Grammar.limit() + 1) as usize]).unwrap();
        let e = read_text(&big, Kind::Grammar).unwrap_err();
        assert!(matches!(e, FileError::TooLarge { .. }), "{e}");
        assert!(!e.to_string().contains('\n'));
        let small = d.path().join("small.txt");
        std::fs::write(&small, "F=FF").unwrap();
        assert_eq!(read_text(&small, Kind::Grammar).unwrap(), "F=FF");
    }

    #[test]
    fn a_link_out_of_the_folder_is_outside() {
        let d = temp("within");
        let inside = d.path().join("model");
        std::fs::create_dir_all(&inside).unwrap();
        std::fs::write(inside.join("a.bin"), b"abc").unwrap();
        std::fs::write(d.path().join("secret.bin"), b"secret").unwrap();
        std::os::unix::fs::symlink(d.path().join("secret.bin"), inside.join("extra.bin")).unwrap();
        std::os::unix::fs::symlink(inside.join("a.bin"), inside.join("alias.bin")).unwrap();
        assert!(within(&inside.join("a.bin"), &inside).is_ok());
        assert!(within(&inside.join("alias.bin"), &inside).is_ok(), "a link that stays inside is fine");
        let e = within(&inside.join("extra.bin"), &inside).unwrap_err();
        assert!(matches!(e, FileError::Outside { .. }), "{e}");
        let e = within(&inside.join("../secret.bin"), &inside).unwrap_err();
        assert!(matches!(e, FileError::Outside { .. }), "{e}");
        assert!(is_link(&inside.join("extra.bin")));
        assert_eq!(FileError::NotFound { path: "x".into() }.reason(), "no such file");
    }
}
