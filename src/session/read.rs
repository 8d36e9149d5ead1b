//! Reading a session file, JSON lines or Parquet, into a [`Sink`]: which
//! format a file holds, and the source that reads it.

use super::jsonl::{jsonl, jsonl_file};
use super::sink::Sink;
use crate::source::Located;
use std::path::Path;

/// The two formats of a session file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    JsonLines,
    Parquet,
}

/// Whether the file at `path` is a btx session, and in which format, by
/// its first bytes (and a Parquet file's footer).
pub fn format_of(path: &Path) -> Option<Format> {
    use std::io::Read;
    if !std::fs::metadata(path).ok()?.is_file() {
        return None;
    }
    let mut head = Vec::with_capacity(64);
    std::fs::File::open(path)
        .ok()?
        .take(64)
        .read_to_end(&mut head)
        .ok()?;
    if head.starts_with(b"PAR1") {
        return super::columnar::is_session_file(path).then_some(Format::Parquet);
    }
    let start = head.iter().position(|b| !b.is_ascii_whitespace())?;
    head[start..]
        .starts_with(b"{\"btx_session\"")
        .then_some(Format::JsonLines)
}

/// The session file at `path`: JSON lines a line at a time, or Parquet.
pub fn file(path: &Path, sink: &mut dyn Sink) -> Result<(), Located> {
    crate::source::check_input(path, crate::source::INPUT_SIZE_MAX, "the session")?;
    match format_of(path) {
        Some(Format::JsonLines) => return jsonl_file(path, sink),
        // Read a row group at a time from the file, never whole.
        Some(Format::Parquet) => {
            let f = std::fs::File::open(path)
                .map_err(|e| Located::file(path, format!("cannot read the file: {e}")))?;
            return super::columnar::read(path, f, sink);
        }
        None => {}
    }
    let bytes = crate::source::read_input(path, crate::source::INPUT_SIZE_MAX, "the session")?;
    any(path, bytes, sink)
}

/// A session's bytes, by their format.
pub fn any(path: &Path, bytes: Vec<u8>, sink: &mut dyn Sink) -> Result<(), Located> {
    if super::columnar::is_parquet(&bytes) {
        return super::columnar::read(path, bytes::Bytes::from(bytes), sink);
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        Located::file(
            path,
            format!(
                "the session is not UTF-8 text (byte offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    jsonl(path, &text, sink)
}
