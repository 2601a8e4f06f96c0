//! The text of an input file: UTF-8, with an optional byte-order mark, and an error that says
//! where an invalid byte sits.
//!
//! Every file ftwire reads as text (wire, sensor, rig and scene TOML files, calibration weights,
//! JSON Lines logs and batches) goes through [`read_text`] (or [`decode`] on bytes read
//! otherwise), or for a stream read line by line through [`strip_bom`] on its first line and
//! [`utf8`] on each, so that all of them accept a
//! leading UTF-8 byte-order mark (which some Windows editors write) and report invalid UTF-8
//! by its line and column.

use std::io::Read;
use std::path::Path;

use crate::CoreError;

/// The UTF-8 byte-order mark, `EF BB BF`: some editors write it at the start of a file. It is
/// not part of the text, so readers drop it.
pub const BOM: &[u8] = b"\xEF\xBB\xBF";

/// `bytes` without a leading UTF-8 byte-order mark ([`BOM`]).
///
/// # Example
/// ```
/// use ftwire_core::text::strip_bom;
/// assert_eq!(strip_bom(b"\xEF\xBB\xBFrate = 5"), b"rate = 5");
/// assert_eq!(strip_bom(b"rate = 5"), b"rate = 5");
/// ```
pub fn strip_bom(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(BOM).unwrap_or(bytes)
}

/// `bytes` as UTF-8 text.
///
/// # Errors
/// [`CoreError::NotUtf8`] with the line and column (from 1, counted within `bytes`) and the
/// byte offset (from 0) of the first invalid byte.
///
/// # Example
/// ```
/// use ftwire_core::{CoreError, text::utf8};
/// assert_eq!(utf8("länge = 1".as_bytes()), Ok("länge = 1"));
/// assert_eq!(
///     utf8(b"a = 1\nb\xC3\xA9 = \xFF\n"), // "é" is two bytes, one column
///     Err(CoreError::NotUtf8 { line: 2, column: 6, offset: 12, byte: 0xFF })
/// );
/// ```
pub fn utf8(bytes: &[u8]) -> Result<&str, CoreError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let offset = e.valid_up_to();
        let (valid, rest) = bytes.split_at(offset);
        // The bytes before the error are valid UTF-8, so they can be counted in characters.
        let before = String::from_utf8_lossy(valid);
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        CoreError::NotUtf8 {
            line: before.matches('\n').count() + 1,
            column: before.get(line_start..).map_or(0, |s| s.chars().count()) + 1,
            offset,
            byte: rest.first().copied().unwrap_or(0),
        }
    })
}

/// The text of a whole file's bytes: a leading byte-order mark dropped, checked to be UTF-8.
///
/// # Errors
/// [`CoreError::NotUtf8`] locating the first invalid byte (its offset counted from the start of
/// `bytes`, byte-order mark included).
///
/// # Example
/// ```
/// use ftwire_core::{CoreError, text::decode};
/// assert_eq!(decode(b"\xEF\xBB\xBF{}"), Ok("{}"));
/// assert!(matches!(decode(b"\xEF\xBB\xBF\xFF"), Err(CoreError::NotUtf8 { offset: 3, .. })));
/// ```
pub fn decode(bytes: &[u8]) -> Result<&str, CoreError> {
    let text = strip_bom(bytes);
    let skipped = bytes.len() - text.len();
    utf8(text).map_err(|e| match e {
        CoreError::NotUtf8 {
            line,
            column,
            offset,
            byte,
        } => CoreError::NotUtf8 {
            line,
            column,
            offset: offset + skipped,
            byte,
        },
        e => e,
    })
}

/// The text of the file at `path`: read whole and [`decode`]d. The one text-file reader of the
/// workspace.
///
/// # Errors
/// [`CoreError::Unreadable`] with the system's message (the caller names the file), or
/// [`CoreError::NotUtf8`] as [`decode`].
///
/// # Example
/// ```
/// let dir = std::env::temp_dir().join(format!("ftwire-text-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let path = dir.join("bom.toml");
/// std::fs::write(&path, b"\xEF\xBB\xBFrate = 5\n")?;
/// assert_eq!(ftwire_core::text::read_text(&path)?, "rate = 5\n");
/// assert!(ftwire_core::text::read_text(&dir.join("missing.toml")).is_err());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_text(path: &Path) -> Result<String, CoreError> {
    let mut bytes = Vec::new();
    open_regular(path)?
        .take(MAX_TEXT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| CoreError::Unreadable {
            message: e.to_string(),
        })?;
    if bytes.len() as u64 > MAX_TEXT_BYTES {
        return Err(CoreError::Unreadable {
            message: format!(
                "it is larger than {} MiB, too large for a settings file",
                MAX_TEXT_BYTES >> 20
            ),
        });
    }
    decode(&bytes).map(str::to_owned)
}

/// `text` with its control characters (ESC, NUL, BEL, tabs, …; newlines kept) written as
/// `\u{1b}` escapes: safe to print where a terminal would act on them.
///
/// # Example
/// ```
/// assert_eq!(ftwire_core::text::printable("a\u{1b}]0;x\u{7}b"), "a\\u{1b}]0;x\\u{7}b");
/// assert_eq!(ftwire_core::text::printable("plain — text"), "plain — text");
/// ```
pub fn printable(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_owned();
    }
    text.chars()
        .map(|c| {
            if c.is_control() && c != '\n' {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// A number as an error message shows it: as Rust prints it, unless it is huge or tiny (`1e308`
/// would be 309 digits, `1e-300` 301 zeros), then in exponent notation.
///
/// # Example
/// ```
/// use ftwire_core::text::Number;
/// assert_eq!(Number(1e308).to_string(), "1e308");
/// assert_eq!(Number(-2.5e-9).to_string(), "-2.5e-9");
/// assert_eq!(Number(0.25).to_string(), "0.25");
/// assert_eq!(Number(1e6).to_string(), "1000000");
/// assert_eq!(Number(f64::NAN).to_string(), "NaN");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Number(pub f64);

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let size = self.0.abs();
        if self.0.is_finite() && size != 0.0 && !(1e-6..1e15).contains(&size) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

/// Largest text file [`read_text`] reads \[bytes\]: settings and calibration files are kB.
pub const MAX_TEXT_BYTES: u64 = 256 << 20;

/// Opens `path` for reading if it is a regular file (or a link to one). A FIFO, a device or a
/// folder is refused before it is opened: reading one could block for ever or never end.
///
/// # Errors
/// [`CoreError::Unreadable`] saying what the path is, or with the system's message.
pub fn open_regular(path: &Path) -> Result<std::fs::File, CoreError> {
    let meta = std::fs::metadata(path).map_err(|e| CoreError::Unreadable {
        message: e.to_string(),
    })?;
    if !meta.is_file() {
        let what = if meta.is_dir() {
            "a folder"
        } else {
            "not a regular file (a FIFO, a socket or a device)"
        };
        return Err(CoreError::Unreadable {
            message: format!("it is {what}; give a regular file"),
        });
    }
    std::fs::File::open(path).map_err(|e| CoreError::Unreadable {
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_invalid_byte_is_found_on_its_line_and_column() {
        assert_eq!(
            utf8(b"\xC3"),
            Err(CoreError::NotUtf8 {
                line: 1,
                column: 1,
                offset: 0,
                byte: 0xC3
            })
        );
        // A truncated two-byte sequence after two characters of the third line.
        assert_eq!(
            utf8(b"x\n\ny\xC3\xA9\xC3"),
            Err(CoreError::NotUtf8 {
                line: 3,
                column: 3,
                offset: 6,
                byte: 0xC3
            })
        );
        assert_eq!(utf8(b""), Ok(""));
    }

    #[test]
    fn only_a_leading_bom_is_dropped() {
        assert_eq!(strip_bom(b"\xEF\xBB\xBF\xEF\xBB\xBFa"), b"\xEF\xBB\xBFa");
        assert_eq!(strip_bom(b"a\xEF\xBB\xBF"), b"a\xEF\xBB\xBF");
        assert_eq!(strip_bom(b"\xEF\xBB"), b"\xEF\xBB");
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_a_device_and_a_folder_are_refused_without_blocking() {
        let dir = std::env::temp_dir().join(format!("ftwire-core-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a folder");
        let fifo = dir.join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let error = read_text(&fifo).expect_err("a FIFO");
            assert!(error.to_string().contains("not a regular file"), "{error}");
        }
        let error = read_text(Path::new("/dev/zero")).expect_err("a device");
        assert!(error.to_string().contains("not a regular file"), "{error}");
        let error = read_text(&dir).expect_err("a folder");
        assert!(error.to_string().contains("a folder"), "{error}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
