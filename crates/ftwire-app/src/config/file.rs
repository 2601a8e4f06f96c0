//! Reading a settings file: the TOML text of a wire, sensor, rig or mounting file into its settings,
//! and the errors that name the file, the line and the key.

use std::path::Path;

use serde::de::DeserializeOwned;
use thiserror::Error;

/// Why a sensor or rig could not be had.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SetupError {
    /// Neither a preset nor a name of a file (a path, a `.toml` name, or an existing entry).
    #[error("unknown {kind} {given:?}: give {allowed}")]
    Unknown {
        /// `"sensor"` or `"rig"`.
        kind: &'static str,
        /// What was given.
        given: String,
        /// What is allowed.
        allowed: String,
    },
    /// The file could not be read.
    #[error("cannot read {kind} file {path}: {message}")]
    Read {
        /// `"sensor"` or `"rig"`.
        kind: &'static str,
        /// The file.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The file is not valid TOML of its kind, or holds a value out of range (the message names
    /// the line and the key).
    #[error("bad {kind} file {path}: {message}")]
    Bad {
        /// `"sensor"` or `"rig"`.
        kind: &'static str,
        /// The file.
        path: String,
        /// What was wrong, with the line and the key.
        message: String,
    },
}

/// Reads a TOML file of `kind` into `T` (unknown keys rejected by `T`'s `deny_unknown_fields`).
///
/// # Errors
/// [`SetupError::Read`] or [`SetupError::Bad`] naming the file, with `toml`'s line and key.
pub fn read_toml<T: DeserializeOwned>(
    kind: &'static str,
    path: &Path,
) -> Result<(T, String), SetupError> {
    let file = path.display().to_string();
    let text = ftwire_core::text::read_text(path).map_err(|e| match e {
        ftwire_core::CoreError::Unreadable { message } => SetupError::Read {
            kind,
            path: file.clone(),
            message,
        },
        e => SetupError::Bad {
            kind,
            path: file.clone(),
            message: e.to_string(),
        },
    })?;
    let value = parse_toml(kind, &text, &file)?;
    Ok((value, text))
}

/// Whether `given`, which is not a preset's name, is to be read as a file: it looks like a path
/// (a path separator, or a `.toml` name), or something exists there, a link that leads nowhere
/// or round in a loop included. Such a name is read, and the system's error is reported when it
/// cannot be; any other name is a misspelt preset. Used by `--wire` and `--sensor`.
pub fn names_a_file(given: &str) -> bool {
    let path = Path::new(given);
    given.contains(std::path::MAIN_SEPARATOR)
        || given.contains('/')
        || path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
        || std::fs::symlink_metadata(path).is_ok()
}

/// Parses the text of a TOML file of `kind` (`path` names it in errors).
///
/// # Errors
/// [`SetupError::Bad`] with `toml`'s line, column and key.
pub fn parse_toml<T: DeserializeOwned>(
    kind: &'static str,
    text: &str,
    path: &str,
) -> Result<T, SetupError> {
    toml::from_str(text).map_err(|e| SetupError::Bad {
        kind,
        path: path.to_owned(),
        message: short_lines(e.to_string().trim_end()),
    })
}

/// `message` with each line cut to its first [`crate::output::ECHO_CHARS`] characters: the
/// TOML parser quotes the offending line whole, which may be a file's every byte.
fn short_lines(message: &str) -> String {
    message
        .lines()
        .map(crate::output::cut)
        .collect::<Vec<_>>()
        .join("\n")
}

/// A value error of a file of `kind`: the library's `message` names the key; the key is the
/// first word of the message that is one of `defaults`' keys (at any depth), and the line of
/// its first `key = …` in `text` is added when the file sets it (a default can fail a check only
/// together with the file's other values, and has no line).
pub fn value_error(
    kind: &'static str,
    (path, text): (&str, &str),
    defaults: &impl serde::Serialize,
    message: String,
) -> SetupError {
    let keys = toml::Table::try_from(defaults)
        .map(|table| leaf_keys(&table))
        .unwrap_or_default();
    let key = message
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .find(|word| keys.iter().any(|k| k == word));
    let message = match key {
        Some(key) => match line_of(text, key) {
            Some(line) => format!("line {line}, key {key}: {message}"),
            None => format!("key {key} (its default, with the file's other values): {message}"),
        },
        None => message,
    };
    SetupError::Bad {
        kind,
        path: path.to_owned(),
        message,
    }
}

/// Every key of `table`, nested tables' keys included.
fn leaf_keys(table: &toml::Table) -> Vec<String> {
    table
        .iter()
        .flat_map(|(key, value)| match value {
            toml::Value::Table(inner) => leaf_keys(inner),
            _ => vec![key.clone()],
        })
        .collect()
}

/// The 1-based line of the first `key = …` in `text`, if any (also used for wire files).
pub fn line_of(text: &str, key: &str) -> Option<usize> {
    if key.is_empty() {
        return None;
    }
    text.lines()
        .position(|line| {
            line.trim_start()
                .strip_prefix(key)
                .is_some_and(|rest| rest.trim_start().starts_with('='))
        })
        .map(|i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_or_a_toml_name_is_a_file_and_a_bare_word_a_preset() {
        assert!(names_a_file("loop.toml"));
        assert!(names_a_file("loop.TOML"));
        assert!(names_a_file("configs/wire"));
        assert!(names_a_file("/nonexistent"));
        assert!(!names_a_file("nitinol-2mm"));
        assert!(!names_a_file("copper"));
    }

    #[test]
    fn the_line_of_a_key_is_found_at_its_assignment_only() {
        let text = "# noise_std = 1\nrate = 5\n  noise_std= [1]\n";
        assert_eq!(line_of(text, "noise_std"), Some(3));
        assert_eq!(line_of(text, "rate"), Some(2));
        assert_eq!(line_of(text, "gain"), None);
    }

    /// A malformed line of 200 kB is quoted by its first characters, not whole.
    #[test]
    fn a_long_bad_line_is_quoted_short() {
        let text = format!("c = [{}\n", "1, ".repeat(70_000));
        let error = parse_toml::<toml::Table>("wire", &text, "w.toml").expect_err("malformed");
        let message = error.to_string();
        assert!(
            message.len() < 2000 && message.contains("characters)"),
            "{} bytes",
            message.len()
        );
    }
}
