//! The JSON-lines session file as a source: its header, then a record a
//! line at a time, into a [`Sink`].

use super::format::{self, Header};
use super::sink::{Locate, Sink};
use crate::source::Located;
use std::path::Path;

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
