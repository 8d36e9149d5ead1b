//! Reading a session file, JSON lines or Parquet, into a [`Sink`]: the
//! session's index, or a copy of it in the other format.

use super::build::Locate;
use super::format::{self, Header, Record};
use crate::source::Located;
use std::path::Path;

/// What a session file holds, in order: its header, then its records.
pub trait Sink {
    /// The header, and its text as the file holds it (JSON).
    fn header(
        &mut self,
        path: &Path,
        text: &str,
        header: Header,
        err: Locate,
    ) -> Result<(), Located>;
    /// Record number `nth`, counting the header as the first.
    fn record(&mut self, nth: usize, rec: Record, err: Locate) -> Result<(), Located>;
    /// Something about the file that is not an error.
    fn warn(&mut self, location: String, message: String);
}

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

fn header_too_long(path: &Path, len: usize) -> Located {
    Located::file(
        path,
        format!(
            "line 1: a session header of {len} bytes: a header (the tree, its blackboard and the nodes' states) is at most {} MiB",
            format::HEADER_MAX >> 20
        ),
    )
}

/// A header's text, checked before it is parsed.
pub fn header(path: &Path, text: &str, err: Locate) -> Result<Header, Located> {
    if text.len() > format::HEADER_MAX {
        return Err(header_too_long(path, text.len()));
    }
    serde_json::from_str(text).map_err(|e| {
        err(format!(
            "not a btx session header: {}",
            format::json_error(&e)
        ))
    })
}

/// Where the JSON lines come from: a text in memory, or a file read a
/// line at a time (read whole again only to show a line in an error).
pub enum Lines<'a> {
    Text(&'a str),
    File,
}

impl Lines<'_> {
    /// An error about the bytes `start..start + len` of the file.
    fn error(&self, path: &Path, start: usize, len: usize, msg: String) -> Located {
        let at = |text: &str| Located::at(path, text, start, start + len, msg.clone());
        match self {
            Lines::Text(text) => at(text),
            Lines::File => match std::fs::read(path) {
                Ok(bytes) => at(&String::from_utf8_lossy(&bytes)),
                Err(_) => Located::file(path, format!("byte offset {start}: {msg}")),
            },
        }
    }
}

/// Reads one line of at most `max` bytes (its newline aside), and whether
/// it ended with a newline; `None` at the end of the input.
fn line(
    r: &mut impl std::io::BufRead,
    buf: &mut Vec<u8>,
    max: usize,
) -> std::io::Result<Option<Line>> {
    buf.clear();
    std::io::BufRead::read_until(
        &mut std::io::Read::take(&mut *r, max as u64 + 2),
        b'\n',
        buf,
    )?;
    if buf.is_empty() {
        return Ok(None);
    }
    if buf.len() > max + 1 && !buf.ends_with(b"\n") {
        // Too long to hold: only its length (its newline aside) is wanted,
        // for the error.
        let mut len = buf.len();
        loop {
            let b = r.fill_buf()?;
            let (used, end) = match b.iter().position(|&c| c == b'\n') {
                Some(i) => (i + 1, Some(i)),
                None => (b.len(), None),
            };
            len += end.unwrap_or(used);
            r.consume(used);
            if end.is_some() || used == 0 {
                return Ok(Some(Line::TooLong(len)));
            }
        }
    }
    Ok(Some(Line::Read {
        ended: buf.ends_with(b"\n"),
    }))
}

/// A line read: whether it ended with a newline, or the length of one too
/// long to read.
enum Line {
    Read { ended: bool },
    TooLong(usize),
}

/// A session's JSON lines from a file, a line at a time: the file is never
/// held whole in memory.
pub fn jsonl_file(path: &Path, sink: &mut dyn Sink) -> Result<(), Located> {
    let file = std::fs::File::open(path)
        .map_err(|e| Located::file(path, format!("cannot read the session: {e}")))?;
    jsonl_from(path, std::io::BufReader::new(file), Lines::File, sink)
}

/// A session's JSON lines in memory.
pub fn jsonl(path: &Path, text: &str, sink: &mut dyn Sink) -> Result<(), Located> {
    jsonl_from(path, text.as_bytes(), Lines::Text(text), sink)
}

/// A session's JSON lines: a header line, then one record a line; a last
/// line cut off half way is left out with a warning.
fn jsonl_from(
    path: &Path,
    mut r: impl std::io::BufRead,
    lines: Lines,
    sink: &mut dyn Sink,
) -> Result<(), Located> {
    let io = |e: std::io::Error| Located::file(path, format!("cannot read the session: {e}"));
    let mut buf = Vec::new();
    match line(&mut r, &mut buf, format::HEADER_MAX).map_err(io)? {
        None => return Err(lines.error(path, 0, 0, "the session is empty".into())),
        Some(Line::TooLong(len)) => return Err(header_too_long(path, len)),
        Some(Line::Read { .. }) => {}
    }
    let text = |buf: &[u8], start: usize| -> Result<String, Located> {
        String::from_utf8(buf.to_vec()).map_err(|e| {
            Located::file(
                path,
                format!(
                    "the session is not UTF-8 text (byte offset {})",
                    start + e.utf8_error().valid_up_to()
                ),
            )
        })
    };
    let first = text(&buf, 0)?;
    let first = first.trim_end();
    let in_header = |m| lines.error(path, 0, first.len(), m);
    let h = header(path, first, &in_header)?;
    sink.header(path, first, h, &in_header)?;
    let mut start = buf.len();
    let mut nth = 1;
    while let Some(read) = line(&mut r, &mut buf, format::RECORD_MAX).map_err(io)? {
        let at = start;
        let ended = match read {
            Line::TooLong(len) => {
                return Err(lines.error(
                    path,
                    at,
                    len,
                    format!(
                        "a record of {len} bytes: a session's records (after the header) are at most {} MiB",
                        format::RECORD_MAX >> 20
                    ),
                ));
            }
            Line::Read { ended } => ended,
        };
        start += buf.len();
        let line = text(&buf, at)?;
        let body = line.trim_end();
        if body.is_empty() {
            nth += 1;
            continue;
        }
        let rec = match format::parse_record(body) {
            Ok(r) => r,
            Err(e) if !ended => {
                sink.warn(
                    format!("{}:{}:1", path.display(), nth + 1),
                    format!("the last record was cut off half way ({e}); it is left out"),
                );
                break;
            }
            Err(e) => {
                return Err(lines.error(path, at, body.len(), format!("not a session record: {e}")))
            }
        };
        sink.record(nth, rec, &|m| lines.error(path, at, body.len(), m))?;
        nth += 1;
    }
    Ok(())
}
