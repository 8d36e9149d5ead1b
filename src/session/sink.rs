//! Where a session file's records go as it is read: the session's index
//! (`build`), or a copy in the other format (`columnar`).

use super::format::{Header, Record};
use crate::source::Located;
use std::path::Path;

/// An error about the record being read, located in its file.
pub(super) type Locate<'a> = &'a dyn Fn(String) -> Located;

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
