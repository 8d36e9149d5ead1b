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

/// A session's bytes, by their format.
pub fn any(path: &Path, bytes: Vec<u8>, sink: &mut dyn Sink) -> Result<(), Located> {
    if super::columnar::is_parquet(&bytes) {
        return super::columnar::read(path, bytes, sink);
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

/// A header's text, checked before it is parsed.
pub fn header(path: &Path, text: &str, err: Locate) -> Result<Header, Located> {
    if text.len() > format::HEADER_MAX {
        return Err(Located::file(
            path,
            format!(
                "line 1: a session header of {} bytes: a header (the tree, its blackboard and the nodes' states) is at most {} MiB",
                text.len(),
                format::HEADER_MAX >> 20
            ),
        ));
    }
    serde_json::from_str(text).map_err(|e| err(format!("not a btx session header: {e}")))
}

/// A session's JSON lines: a header line, then one record a line; a last
/// line cut off half way is left out with a warning.
pub fn jsonl(path: &Path, text: &str, sink: &mut dyn Sink) -> Result<(), Located> {
    let mut lines = Vec::new();
    let mut offset = 0;
    for l in text.split_inclusive('\n') {
        lines.push((offset, l));
        offset += l.len();
    }
    let err_at =
        |start: usize, len: usize, msg: String| Located::at(path, text, start, start + len, msg);
    let Some(&(_, first)) = lines.first() else {
        return Err(Located::at(path, text, 0, 0, "the session is empty"));
    };
    let first = first.trim_end();
    let in_header = |m| err_at(0, first.len(), m);
    let h = header(path, first, &in_header)?;
    sink.header(path, first, h, &in_header)?;
    let n = lines.len();
    for (i, &(start, line)) in lines.iter().enumerate().skip(1) {
        let body = line.trim_end();
        if body.is_empty() {
            continue;
        }
        if body.len() > format::RECORD_MAX {
            return Err(err_at(
                start,
                body.len(),
                format!(
                    "a record of {} bytes: a session's records (after the header) are at most {} MiB",
                    body.len(),
                    format::RECORD_MAX >> 20
                ),
            ));
        }
        let rec = match format::parse_record(body) {
            Ok(r) => r,
            Err(e) if i == n - 1 && !line.ends_with('\n') => {
                sink.warn(
                    format!("{}:{}:1", path.display(), i + 1),
                    format!("the last record was cut off half way ({e}); it is left out"),
                );
                break;
            }
            Err(e) => {
                return Err(err_at(
                    start,
                    body.len(),
                    format!("not a session record: {e}"),
                ))
            }
        };
        sink.record(i, rec, &|m| err_at(start, body.len(), m))?;
    }
    Ok(())
}
