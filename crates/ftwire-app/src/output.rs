//! The commands' output conventions, for every front end that prints a result: a result as
//! one JSON object or as human text, JSON Lines flushed per line, and the error object of a bad
//! JSON Lines request with the values it echoes cut short.

use std::fmt::Display;
use std::io::{self, Write};

use serde::Serialize;

use crate::error::LabError;

/// A command's result: serialised for `--json`, written as text otherwise.
pub trait Report: Serialize {
    /// Writes the human-readable text.
    ///
    /// # Errors
    /// The writer's.
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()>;
}

/// Prints `report` on stdout: one JSON object on one line with `json`, the text otherwise.
///
/// # Errors
/// [`LabError::Io`] if stdout cannot be written (e.g. a closed pipe).
pub fn print(report: &impl Report, json: bool) -> Result<(), LabError> {
    let stdout = io::stdout();
    let mut out = stdout.lock();
    write(&mut out, report, json)
}

/// Writes `report` to `out` as [`print()`] does.
///
/// # Errors
/// [`LabError::Io`] if `out` cannot be written.
pub fn write(out: &mut impl Write, report: &impl Report, json: bool) -> Result<(), LabError> {
    let written = if json {
        serde_json::to_writer(&mut *out, report)
            .map_err(io::Error::from)
            .and_then(|()| out.write_all(b"\n"))
    } else {
        // The text may quote what the user gave (a path, a log's name): its control
        // characters are escaped, as the binary's errors are (JSON escapes its own).
        let mut text = Vec::new();
        report.write_text(&mut text).and_then(|()| {
            out.write_all(ftwire_core::text::printable(&String::from_utf8_lossy(&text)).as_bytes())
        })
    };
    written
        .and_then(|()| out.flush())
        .map_err(|e| LabError::io("writing the result", e))
}

/// Prints `value` as [`print()`] does, with its [`Display`] as the text: the lab's answers
/// (`ftwire_logs::identify::EstimateReport`, ...) carry their human text so.
///
/// # Errors
/// As [`print()`].
pub fn print_display(value: &(impl Serialize + Display), json: bool) -> Result<(), LabError> {
    print(&Displayed(value), json)
}

/// A value whose [`Display`] is its report's text.
#[derive(Serialize)]
#[serde(transparent)]
struct Displayed<'a, T>(&'a T);

impl<T: Serialize + Display> Report for Displayed<'_, T> {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        write!(out, "{}", self.0)
    }
}

/// JSON Lines: one object per line, each flushed as soon as it is written, so that a process
/// reading the other end of a pipe gets every answer at once.
#[derive(Debug)]
pub struct JsonLines<W: Write> {
    out: W,
}

impl<W: Write> JsonLines<W> {
    /// Writes to `out` (e.g. `io::stdout().lock()`).
    pub fn new(out: W) -> Self {
        Self { out }
    }

    /// Writes one value on one line and flushes.
    ///
    /// # Errors
    /// [`LabError::Io`] if the writer fails.
    pub fn write(&mut self, value: &impl Serialize) -> Result<(), LabError> {
        serde_json::to_writer(&mut self.out, value)
            .map_err(io::Error::from)
            .and_then(|()| self.out.write_all(b"\n"))
            .and_then(|()| self.out.flush())
            .map_err(|e| LabError::io("writing a JSON line", e))
    }

    /// The writer back.
    pub fn into_inner(self) -> W {
        self.out
    }
}

/// The error object of one bad JSON Lines request: `{"error": ..., "kind": ..., "line": ...}`
/// (`kind` is [`LabError::kind`], `line` counts from 1). Values the message echoes are cut to
/// [`ECHO_CHARS`] characters ([`shorten_echoes`]), so that a huge bad value is not sent back
/// whole.
#[derive(Debug, Serialize)]
pub struct ErrorLine {
    /// What was wrong.
    pub error: String,
    /// `"bad_input"`, `"no_answer"` or `"io"`.
    pub kind: &'static str,
    /// The input line, from 1.
    pub line: usize,
}

impl ErrorLine {
    /// The error object of input line `line` (from 1).
    pub fn new(error: &LabError, line: usize) -> Self {
        Self {
            error: shorten_echoes(&error.to_string()),
            kind: error.kind(),
            line,
        }
    }
}

/// The most characters of an echoed value that an error object keeps.
pub const ECHO_CHARS: usize = 200;

/// `message` with every quoted value longer than [`ECHO_CHARS`] characters (a `"..."` string
/// with its escapes, as parsers echo a bad value, or a `` `...` `` name) cut to its first
/// [`ECHO_CHARS`] characters and `… (N characters)`; a message still longer than
/// `4 ·` [`ECHO_CHARS`] (an unquoted echo) is cut the same way as a whole.
///
/// # Example
/// ```
/// use ftwire_app::output::shorten_echoes;
/// let long = "x".repeat(10_000);
/// let message = format!("invalid type: string \"{long}\", expected f64 at line 1 column 10015");
/// let short = shorten_echoes(&message);
/// assert!(short.starts_with("invalid type: string \"xxx"));
/// assert!(short.contains("… (10000 characters)\", expected f64 at line 1 column 10015"));
/// assert!(short.len() < 300);
/// assert_eq!(shorten_echoes("c must have 3 values"), "c must have 3 values");
/// ```
pub fn shorten_echoes(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(8 * ECHO_CHARS));
    let mut rest = message;
    while let Some(open) = rest.find(['"', '`']) {
        let quote = rest[open..].chars().next().unwrap_or('"');
        out.push_str(&rest[..=open]);
        let inner = &rest[open + 1..];
        let Some(close) = closing_quote(inner, quote) else {
            rest = inner;
            break;
        };
        out.push_str(&cut(&inner[..close]));
        out.push(quote);
        rest = &inner[close + 1..];
    }
    out.push_str(rest);
    if out.chars().count() > 4 * ECHO_CHARS {
        cut(&out)
    } else {
        out
    }
}

/// The byte index of the quote that closes a value opened by `quote` (`"` skips escaped
/// characters), if there is one.
fn closing_quote(inner: &str, quote: char) -> Option<usize> {
    let mut escaped = false;
    for (i, c) in inner.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if quote == '"' => escaped = true,
            c if c == quote => return Some(i),
            _ => {}
        }
    }
    None
}

/// `value` cut to its first [`ECHO_CHARS`] characters and `… (N characters)` if longer.
pub(crate) fn cut(value: &str) -> String {
    let count = value.chars().count();
    if count <= ECHO_CHARS {
        return value.to_owned();
    }
    let head: String = value.chars().take(ECHO_CHARS).collect();
    format!("{head}… ({count} characters)")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Answer {
        x: f64,
    }

    impl Report for Answer {
        fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
            writeln!(out, "x = {}", self.x)
        }
    }

    #[test]
    fn json_and_text_and_lines() {
        let mut json = Vec::new();
        write(&mut json, &Answer { x: -1.5 }, true).expect("writes");
        assert_eq!(json, b"{\"x\":-1.5}\n");
        let mut text = Vec::new();
        write(&mut text, &Answer { x: 2.0 }, false).expect("writes");
        assert_eq!(text, b"x = 2\n");
        let mut lines = JsonLines::new(Vec::new());
        lines.write(&Answer { x: 1.0 }).expect("writes");
        let error = LabError::bad_input("c must have 3 values");
        lines.write(&ErrorLine::new(&error, 2)).expect("writes");
        assert_eq!(
            String::from_utf8_lossy(&lines.into_inner()),
            "{\"x\":1.0}\n{\"error\":\"c must have 3 values\",\"kind\":\"bad_input\",\"line\":2}\n"
        );
    }

    /// A text that quotes the user's input (here a name with an ESC sequence) reaches the
    /// terminal escaped; newlines stay.
    #[test]
    fn the_text_escapes_control_characters() {
        struct Named(&'static str);
        impl Serialize for Named {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.0)
            }
        }
        impl Report for Named {
            fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
                writeln!(out, "results in {}", self.0)
            }
        }
        let mut text = Vec::new();
        write(&mut text, &Named("z\u{1b}]0;PWNED\u{7}"), false).expect("writes");
        assert_eq!(
            String::from_utf8_lossy(&text),
            "results in z\\u{1b}]0;PWNED\\u{7}\n"
        );
        let mut json = Vec::new();
        write(&mut json, &Named("z\u{1b}"), true).expect("writes");
        assert_eq!(json, b"\"z\\u001b\"\n");
    }
}
