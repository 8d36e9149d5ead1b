//! Opening whatever a person points btx at: a tree file, a session or a
//! BehaviorTree.CPP `.btlog`, recognised by content, not by extension.

use crate::model::Tree;
use crate::session::Session;
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use std::path::Path;

pub enum Input {
    Tree { tree: Tree, warnings: Vec<Warning> },
    Session(Box<Session>),
}

impl Input {
    pub fn tree(&self) -> &Tree {
        match self {
            Input::Tree { tree, .. } => tree,
            Input::Session(s) => &s.tree,
        }
    }

    pub fn warnings(&self) -> &[Warning] {
        match self {
            Input::Tree { warnings, .. } => warnings,
            Input::Session(s) => &s.warnings,
        }
    }

    pub fn session(&self) -> Option<&Session> {
        match self {
            Input::Session(s) => Some(s),
            Input::Tree { .. } => None,
        }
    }
}

/// `LOG.db3#N`: session N of a SqliteLogger database, when no file has
/// that very name.
fn db3_session(path: &Path) -> Option<(&Path, i64)> {
    if path.exists() {
        return None;
    }
    let s = path.to_str()?;
    let (file, n) = s.rsplit_once('#')?;
    let n: i64 = n.parse().ok()?;
    let file = Path::new(file);
    file.is_file().then_some((file, n))
}

pub fn open(path: &Path, opts: &LoadOptions) -> Result<Input, Located> {
    if let Some((file, n)) = db3_session(path) {
        return Ok(Input::Session(Box::new(crate::logs::open_db3(
            file,
            Some(n),
        )?)));
    }
    let bytes = crate::source::read_input(path, crate::source::INPUT_SIZE_MAX, "the file")?;
    if crate::logs::db3::is_db3(&bytes) {
        return Ok(Input::Session(Box::new(crate::logs::open_db3(path, None)?)));
    }
    if crate::logs::btlog::is_btlog(&bytes) {
        return Ok(Input::Session(Box::new(crate::logs::open_btlog(
            path, &bytes,
        )?)));
    }
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(Located::file(
            path,
            "byte offset 0: the file is UTF-16 text; btx and BehaviorTree.CPP read UTF-8: save it as UTF-8",
        ));
    }
    let first = bytes.iter().position(|b| !b.is_ascii_whitespace());
    if !matches!(first.map(|i| bytes[i]), Some(b'{' | b'<' | 0xEF))
        && crate::logs::fbl::is_fbl(&bytes)
    {
        return Ok(Input::Session(Box::new(crate::logs::open_fbl(
            path, &bytes,
        )?)));
    }
    let kind = first.map(|i| bytes[i]);
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fbl"))
    {
        return Err(Located::file(path, crate::logs::fbl::not_fbl(&bytes)));
    }
    if let Some(b) = kind.filter(|b| !matches!(b, b'{' | b'<' | 0xEF)) {
        return Err(Located::file(
            path,
            format!(
                "not a BehaviorTree.CPP XML tree nor a btx session (byte offset {} is 0x{b:02x})",
                first.unwrap_or(0)
            ),
        ));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        Located::file(
            path,
            format!(
                "not UTF-8 text (byte offset {}): not a tree or a session",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    match kind {
        Some(b'{') if crate::logs::btcm::is_btcm(&text) => Ok(Input::Session(Box::new(
            crate::logs::btcm::open_btcm(path, &text)?,
        ))),
        Some(b'{') => Ok(Input::Session(Box::new(Session::parse(path, &text)?))),
        Some(_) => {
            let l = load_str(path, &text, opts)?;
            Ok(Input::Tree {
                tree: l.tree,
                warnings: l.warnings,
            })
        }
        None => Err(Located::file(path, "the file is empty")),
    }
}

/// Follows a log (or a session) that is still being written: each `poll`
/// reads it again if it grew or changed. The whole file is read again, so
/// ticks stay reconstructed from the whole run, and a half-written last
/// record is left out until it is whole.
pub struct Follow {
    path: std::path::PathBuf,
    /// The file (inode), its length and time when last read: a file
    /// replaced by another of the same length and time is read again too.
    seen: Option<(u64, u64, Option<std::time::SystemTime>)>,
}

impl Follow {
    pub fn new(path: &Path) -> Follow {
        Follow {
            path: path.to_path_buf(),
            seen: None,
        }
    }

    /// The run as it is now, if the file changed since the last poll.
    pub fn poll(&mut self) -> Result<Option<Session>, Located> {
        let meta = std::fs::metadata(&self.path)
            .map_err(|e| Located::file(&self.path, format!("cannot read: {e}")))?;
        let stamp = (
            std::os::unix::fs::MetadataExt::ino(&meta),
            meta.len(),
            meta.modified().ok(),
        );
        if self.seen == Some(stamp) {
            return Ok(None);
        }
        match open(&self.path, &LoadOptions::default())? {
            Input::Session(s) => {
                self.seen = Some(stamp);
                Ok(Some(*s))
            }
            Input::Tree { .. } => Err(Located::file(
                &self.path,
                "this is a tree: --follow follows a log or a session as it grows",
            )),
        }
    }
}
