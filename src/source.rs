//! Source positions and located errors: every error about an input names the
//! file and line:column (or byte offset) and can show the offending line.

use miette::{Diagnostic, NamedSource, SourceSpan};
use std::path::Path;

/// 1-based line and column (in characters) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = floor_char_boundary(text, offset.min(text.len()));
    let before = &text[..offset];
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let col = text[line_start..offset].chars().count() + 1;
    (line, col)
}

pub(crate) fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    while i > 0 && !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// An error located in an input file.
#[derive(Debug, thiserror::Error, Diagnostic)]
#[error("{location}: {message}")]
pub struct Located {
    /// `file:line:column`, or just the file when there is no position.
    pub location: String,
    pub message: String,
    #[source_code]
    pub source_code: Option<NamedSource<String>>,
    #[label("{label}")]
    pub span: Option<SourceSpan>,
    pub label: String,
    #[help]
    pub help: Option<String>,
}

impl Located {
    /// An error at a byte range of a file whose text we have.
    pub fn at(
        path: &Path,
        text: &str,
        start: usize,
        end: usize,
        message: impl Into<String>,
    ) -> Self {
        let start = start.min(text.len());
        let end = end.clamp(start, text.len());
        let (line, col) = line_col(text, start);
        let name = path.display().to_string();
        Located {
            location: format!("{name}:{line}:{col}"),
            message: message.into(),
            source_code: Some(NamedSource::new(name, text.to_string())),
            span: Some(SourceSpan::from((start, end - start))),
            label: "here".into(),
            help: None,
        }
    }

    /// An error about a whole file (unreadable, missing, ...).
    pub fn file(path: &Path, message: impl Into<String>) -> Self {
        Located {
            location: crate::text::path(path),
            message: message.into(),
            source_code: None,
            span: None,
            label: String::new(),
            help: None,
        }
    }

    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    pub fn with_label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }
}

/// The largest input file btx reads (a session of 10^7 transitions is
/// about a GiB; a tree of that size is an attack, not a tree).
pub const INPUT_SIZE_MAX: u64 = 2 << 30;

/// The largest plan, domain, keymap or tree file btx reads.
pub const TEXT_SIZE_MAX: u64 = 64 << 20;

/// Reads an input file: a regular file (not a FIFO that blocks forever,
/// not `/dev/zero` read until memory runs out), of at most `max` bytes.
pub fn read_input(path: &Path, max: u64, what: &str) -> Result<Vec<u8>, Located> {
    let len = check_input(path, max, what)?;
    use std::io::Read;
    let mut bytes = crate::pages::with_capacity(len as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(max + 1).read_to_end(&mut bytes))
        .map_err(|e| Located::file(path, format!("cannot read {what}: {e}")))?;
    if bytes.len() as u64 > max {
        return Err(Located::file(
            path,
            format!("{what} grew past the {max} bytes btx reads while it was read"),
        ));
    }
    Ok(bytes)
}

/// Checks an input file before it is opened: a regular file (opening a
/// FIFO would block) of at most `max` bytes; gives its length.
pub fn check_input(path: &Path, max: u64, what: &str) -> Result<u64, Located> {
    let meta = std::fs::metadata(path)
        .map_err(|e| Located::file(path, format!("cannot read {what}: {e}")))?;
    if !meta.is_file() {
        return Err(Located::file(
            path,
            format!("cannot read {what}: not a regular file (a device, a FIFO or a directory)"),
        ));
    }
    if meta.len() > max {
        return Err(Located::file(
            path,
            format!(
                "{what} is {} bytes, more than the {max} bytes btx reads",
                meta.len()
            ),
        ));
    }
    Ok(meta.len())
}

/// Reads a text input: a regular file of at most `max` bytes, UTF-8.
pub fn read_text(path: &Path, max: u64, what: &str) -> Result<String, Located> {
    let bytes = read_input(path, max, what)?;
    String::from_utf8(bytes).map_err(|e| {
        Located::file(
            path,
            format!(
                "{what} is not UTF-8 text (byte offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// A non-fatal finding, printed as `warning: file:line:col: message`.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Warning {
    pub location: String,
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "warning: {}: {}", self.location, self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based_and_count_chars() {
        let t = "ab\ncé<x";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 3), (2, 1));
        assert_eq!(line_col(t, t.find('<').unwrap()), (2, 3));
        assert_eq!(line_col(t, 999), (2, 5));
    }

    #[test]
    fn located_error_names_file_line_and_column() {
        let e = Located::at(Path::new("t.xml"), "<root>\n  <Bad/>", 9, 15, "unknown");
        assert_eq!(e.to_string(), "t.xml:2:3: unknown");
    }
}
