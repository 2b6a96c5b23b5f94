//! Reading input files (scenes, OBJ meshes, CCD query files) safely: only
//! regular files (a FIFO would block forever, `/dev/zero` never ends),
//! never more than a stated number of bytes, and text that is not UTF-8
//! named by line and column. A UTF-8 byte-order mark is accepted.

use std::io::Read;
use std::path::Path;

/// The most bytes a scene file may have: 64 MiB.
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// The most bytes an OBJ mesh or a CCD query file may have: 2 GiB.
pub const MAX_DATA_BYTES: u64 = 2 << 30;

/// Why a file could not be read as text.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The operating system's error (missing file, permissions, ...).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A folder, FIFO, socket or device.
    #[error("not a regular file (a folder, FIFO or device): give the path of a file")]
    NotRegular,
    /// Larger than the limit.
    #[error("larger than {limit} bytes, the most a {what} may have")]
    TooLarge {
        /// The limit in bytes.
        limit: u64,
        /// What the file was read as.
        what: &'static str,
    },
    /// Not UTF-8 text; the position of the first bad byte (1-based line,
    /// 1-based column in characters).
    #[error("line {line}, column {column}: not valid UTF-8 text")]
    NotUtf8 {
        /// The line.
        line: usize,
        /// The column.
        column: usize,
    },
}

impl ReadError {
    /// The error as an I/O error (for error types that carry one).
    pub fn into_io(self) -> std::io::Error {
        match self {
            ReadError::Io(error) => error,
            other => std::io::Error::new(std::io::ErrorKind::InvalidData, other.to_string()),
        }
    }
}

/// Reads `path` whole, at most `limit` bytes (`what` names the kind of
/// file in the error); a folder, FIFO or device is refused before opening.
pub fn read_bytes(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>, ReadError> {
    // Checked before opening: opening a FIFO blocks until a writer comes.
    if !std::fs::metadata(path)?.is_file() {
        return Err(ReadError::NotRegular);
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge { limit, what });
    }
    Ok(bytes)
}

/// Reads `path` as UTF-8 text of at most `limit` bytes (`what` names the
/// kind of file in the error), without a leading byte-order mark.
pub fn read_text(path: &Path, limit: u64, what: &'static str) -> Result<String, ReadError> {
    text_of(read_bytes(path, limit, what)?)
}

/// `bytes` as UTF-8 text without a leading byte-order mark; the first bad
/// byte is named by its line and column.
pub fn text_of(bytes: Vec<u8>) -> Result<String, ReadError> {
    let text = String::from_utf8(bytes).map_err(|error| {
        let valid = &error.as_bytes()[..error.utf8_error().valid_up_to()];
        // Valid up to here, so this slice is text.
        let before = String::from_utf8_lossy(valid);
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        ReadError::NotUtf8 { line, column }
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let path = std::env::temp_dir().join(format!("nearmiss-input-{}-{name}", std::process::id()));
        std::fs::write(&path, bytes).unwrap();
        path
    }

    #[test]
    fn bad_utf8_is_named_by_line_and_column_and_a_bom_is_accepted() {
        let path = temp("utf8", b"ab\ncd\xffe\n");
        assert!(matches!(read_text(&path, 100, "scene"), Err(ReadError::NotUtf8 { line: 2, column: 3 })));
        let path = temp("bom", "\u{feff}Scene()".as_bytes());
        assert_eq!(read_text(&path, 100, "scene").unwrap(), "Scene()");
        let path = temp("big", &[b'x'; 101]);
        assert!(matches!(read_text(&path, 100, "scene"), Err(ReadError::TooLarge { limit: 100, .. })));
        assert!(matches!(read_text(&std::env::temp_dir(), 100, "scene"), Err(ReadError::NotRegular)));
    }

    #[cfg(unix)]
    #[test]
    fn devices_are_refused_without_reading() {
        let path = Path::new("/dev/zero");
        if path.exists() {
            assert!(matches!(read_text(path, 100, "mesh"), Err(ReadError::NotRegular)));
        }
    }
}
