//! A session written again in the other format (`btx import RUN.jsonl
//! --out RUN.parquet`, and back): record for record, the header to the
//! byte, each record checked as any reader checks it before the copy is
//! given its name.

use super::build::Building;
use super::format::{Header, Record};
use super::sink::Locate;
use super::sink::Sink;
use super::write::SessionWriter;
use super::Session;
use crate::source::Located;
use std::path::{Path, PathBuf};

/// Copies the session at `from` to `out`, in the format `out`'s name asks
/// for; gives the copy's path and the session read.
pub fn copy(from: &Path, out: &Path) -> Result<(PathBuf, Session), Located> {
    let mut c = Copying {
        out,
        check: Building::default(),
        writer: None,
    };
    let read = super::read::file(from, &mut c);
    let Copying { check, writer, .. } = c;
    match (read, writer) {
        (Ok(()), Some(w)) => Ok((w.finish_copy()?, check.session())),
        (Err(e), w) => {
            if let Some(w) = w {
                w.discard();
            }
            Err(e)
        }
        (Ok(()), None) => Err(Located::file(from, "the session has no header")),
    }
}

/// Reads into a session (every check a reader makes) and into the copy.
struct Copying<'a> {
    out: &'a Path,
    check: Building,
    writer: Option<SessionWriter>,
}

impl Sink for Copying<'_> {
    fn header(
        &mut self,
        path: &Path,
        text: &str,
        header: Header,
        err: Locate,
    ) -> Result<(), Located> {
        self.check.header(path, text, header, err)?;
        self.writer = Some(SessionWriter::create_as(self.out, text)?);
        Ok(())
    }

    fn record(&mut self, nth: usize, rec: Record, err: Locate) -> Result<(), Located> {
        let w = self.writer.as_mut().expect("the header came first");
        w.record(&rec)?;
        self.check.record(nth, rec, err)
    }

    fn warn(&mut self, location: String, message: String) {
        self.check.warn(location, message);
    }
}
