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

/// Opens a tree, a session or a log. With `opts.run_tree` (`--tree FILE`),
/// a run (a log or a session) has the tree the robot ran in place of the
/// one it embeds, after checking that the two are the same node for node;
/// a tree file is refused then, having no tree to replace.
pub fn open(path: &Path, opts: &LoadOptions) -> Result<Input, Located> {
    match open_to_print(path, opts)? {
        Printable::Input(input) => Ok(input),
        Printable::Numbered(n) => Ok(Input::Session(Box::new(n.into_session()))),
    }
}

/// What `btx log` prints from: a `.btlog` numbered into ticks but not
/// indexed (indexing millions of transitions costs more than printing
/// them), or whatever else `open` opens.
pub enum Printable {
    Numbered(Box<crate::logs::Numbered>),
    Input(Input),
}

/// `open`, leaving a `.btlog` unindexed.
pub fn open_to_print(path: &Path, opts: &LoadOptions) -> Result<Printable, Located> {
    let mut opened = open_unsaid(path, opts)?;
    if let (Printable::Numbered(log), None) = (&mut opened, opts.run) {
        log.say_runs();
    }
    Ok(opened)
}

/// `open_to_print`, not saying that a log read whole holds several runs.
fn open_unsaid(path: &Path, opts: &LoadOptions) -> Result<Printable, Located> {
    let tree = run_tree(opts)?;
    let Some(given) = given(&tree, opts) else {
        return open_as(path, opts, None);
    };
    match open_as(path, opts, Some(given))? {
        Printable::Input(Input::Tree { .. }) => Err(Located::file(
            path,
            "--tree replaces the tree a log or a session embeds; this is a tree file",
        )),
        run => Ok(run),
    }
}

/// Every run a log holds, one at a time, to `f` with its number and the
/// count: a rosbag's goals; any other log or session is one run.
pub fn each_run(
    path: &Path,
    opts: &LoadOptions,
    mut f: impl FnMut(usize, usize, Session) -> Result<(), Box<Located>>,
) -> Result<(), Located> {
    if !crate::logs::rosbag::is_bag(path) {
        return match open(path, opts)? {
            Input::Session(s) => f(1, 1, *s).map_err(|e| *e),
            Input::Tree { .. } => Err(Located::file(path, "a tree file holds no run")),
        };
    }
    let tree = run_tree(opts)?;
    let runs = crate::logs::BagRuns::read(path, given(&tree, opts))?;
    for k in 1..=runs.len() {
        f(k, runs.len(), runs.session(k)?).map_err(|e| *e)?;
    }
    Ok(())
}

/// Each run of a log as `each_run` gives them, a `.btlog` of several runs
/// too (`logs::ends_a_run`: the robot's tree started again after it
/// completed), each with its ticks from 1. Elsewhere (a fleet, an import)
/// a `.btlog` is one run: a robot's log of thousands of runs is one file.
pub fn each_log_run(
    path: &Path,
    opts: &LoadOptions,
    mut f: impl FnMut(usize, usize, Session) -> Result<(), Box<Located>>,
) -> Result<(), Located> {
    if opts.run.is_some() || crate::logs::rosbag::is_bag(path) {
        return each_run(path, opts, f);
    }
    match open_unsaid(path, opts)? {
        Printable::Numbered(log) => {
            let starts = log.run_starts();
            let n = starts.len();
            for k in 1..=n {
                let run = log.run_of(&starts, k)?;
                f(k, n, run.into_session()).map_err(|e| *e)?;
            }
            Ok(())
        }
        Printable::Input(Input::Session(s)) => f(1, 1, *s).map_err(|e| *e),
        Printable::Input(Input::Tree { .. }) => {
            Err(Located::file(path, "a tree file holds no run"))
        }
    }
}

/// Each run of a log as `each_run` gives them, a bag of several robots'
/// logs (one `behavior_tree_log` topic each, no `--topic` given) read
/// robot by robot: `f` is told the topic of each then.
pub fn each_robot_run(
    path: &Path,
    opts: &LoadOptions,
    mut f: impl FnMut(Option<&str>, usize, usize, Session) -> Result<(), Box<Located>>,
) -> Result<(), Located> {
    let topics = if opts.topic.is_none() && crate::logs::rosbag::is_bag(path) {
        crate::logs::rosbag::log_topics(path)?
    } else {
        Vec::new()
    };
    if topics.len() < 2 {
        return each_run(path, opts, |k, n, s| f(None, k, n, s));
    }
    for t in &topics {
        let opts = LoadOptions {
            topic: Some(t.clone()),
            ..opts.clone()
        };
        each_run(path, &opts, |k, n, s| f(Some(t), k, n, s))?;
    }
    Ok(())
}

/// The tree file `--tree` names, read.
fn run_tree(opts: &LoadOptions) -> Result<Option<Tree>, Located> {
    opts.run_tree
        .as_deref()
        .map(|file| crate::xml::load_file(file, opts).map(|l| l.tree))
        .transpose()
}

/// The `--tree` tree as a log's given tree.
fn given<'a>(tree: &'a Option<Tree>, opts: &'a LoadOptions) -> Option<crate::logs::GivenTree<'a>> {
    tree.as_ref()
        .zip(opts.run_tree.as_deref())
        .map(|(tree, path)| crate::logs::GivenTree {
            tree,
            path,
            topic: opts.topic.as_deref(),
        })
}

/// `BAG#N`: run N of a rosbag, when no file has that very name.
fn bag_run(path: &Path) -> Option<(&Path, usize)> {
    if path.exists() {
        return None;
    }
    let (file, n) = path.to_str()?.rsplit_once('#')?;
    let n: usize = n.parse().ok()?;
    let file = Path::new(file);
    crate::logs::rosbag::is_bag(file).then_some((file, n))
}

fn open_as(
    path: &Path,
    opts: &LoadOptions,
    given: Option<crate::logs::GivenTree>,
) -> Result<Printable, Located> {
    if let Some(input) = open_by_name(path, opts, given)? {
        return Ok(Printable::Input(input));
    }
    let bytes = crate::source::read_input(path, crate::source::INPUT_SIZE_MAX, "the file")?;
    if crate::logs::btlog::is_btlog(&bytes) {
        let mut log = crate::logs::number_btlog(path, bytes, given)?;
        if let Some(k) = opts.run {
            log = log.run(k)?;
        }
        return Ok(Printable::Numbered(Box::new(log)));
    }
    open_bytes(path, opts, bytes, given).map(Printable::Input)
}

/// A file recognised by its name: a bag, a run of a SqliteLogger
/// database, a btx session.
fn open_by_name(
    path: &Path,
    opts: &LoadOptions,
    given: Option<crate::logs::GivenTree>,
) -> Result<Option<Input>, Located> {
    if let Some((bag, n)) = bag_run(path) {
        let s = crate::logs::open_rosbag(bag, Some(n), given)?;
        return Ok(Some(Input::Session(Box::new(s))));
    }
    if crate::logs::rosbag::is_bag(path) {
        let s = crate::logs::open_rosbag(path, opts.run, given)?;
        return Ok(Some(Input::Session(Box::new(s))));
    }
    if let Some((file, n)) = db3_session(path) {
        return Ok(Some(Input::Session(Box::new(crate::logs::open_db3_as(
            file,
            Some(n),
            given,
        )?))));
    }
    // A btx session is read as it is read anywhere (a line at a time).
    if crate::session::read::format_of(path).is_some() {
        let mut s = Session::load(path)?;
        if let Some(g) = given {
            g.put_in(&mut s)?;
        }
        return Ok(Some(Input::Session(Box::new(s))));
    }
    Ok(None)
}

/// A file `open_by_name` did not recognise, by its content.
fn open_bytes(
    path: &Path,
    opts: &LoadOptions,
    bytes: Vec<u8>,
    given: Option<crate::logs::GivenTree>,
) -> Result<Input, Located> {
    if crate::session::columnar::is_parquet(&bytes) {
        // Not a session (that was seen above): its reader says what it is.
        return Ok(Input::Session(Box::new(Session::from_bytes(path, bytes)?)));
    }
    if crate::logs::db3::is_db3(&bytes) {
        return Ok(Input::Session(Box::new(crate::logs::open_db3_as(
            path, None, given,
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
        return Ok(Input::Session(Box::new(crate::logs::open_fbl_as(
            path, &bytes, given,
        )?)));
    }
    if let Some(e) = not_text(path, &bytes, first) {
        return Err(e);
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
    open_text(path, opts, &text, first.map(|i| text.as_bytes()[i]), given)
}

/// Why a file that is no binary format btx reads is not a tree or a
/// session either, where it does not open as one (`first`: its first byte
/// that is not white space).
fn not_text(path: &Path, bytes: &[u8], first: Option<usize>) -> Option<Located> {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fbl"))
    {
        return Some(Located::file(path, crate::logs::fbl::not_fbl(bytes)));
    }
    let b = first
        .map(|i| bytes[i])
        .filter(|b| !matches!(b, b'{' | b'<' | 0xEF))?;
    let what = std::str::from_utf8(bytes)
        .ok()
        .and_then(|text| what_file(path, text));
    Some(Located::file(
        path,
        match what {
            Some(w) => format!("not a tree or a session: {w}"),
            None => format!(
                "not a BehaviorTree.CPP XML tree nor a btx session (byte offset {} is 0x{b:02x})",
                first.unwrap_or(0)
            ),
        },
    ))
}

/// A text file by its first byte (`kind`): a btcm log or a btx session
/// (`{`), else a tree.
fn open_text(
    path: &Path,
    opts: &LoadOptions,
    text: &str,
    kind: Option<u8>,
    given: Option<crate::logs::GivenTree>,
) -> Result<Input, Located> {
    // btx's own sessions and btcm's logs: their index does not rest on the
    // tree's scripts, so a given tree is put in after.
    let with_given = |mut s: Session| -> Result<Input, Located> {
        if let Some(g) = given {
            g.put_in(&mut s)?;
        }
        Ok(Input::Session(Box::new(s)))
    };
    match kind {
        Some(b'{') if crate::logs::btcm::is_btcm(text) => {
            with_given(crate::logs::btcm::open_btcm(path, text)?)
        }
        Some(b'{') => with_given(Session::parse(path, text)?),
        Some(_) => {
            let l = load_str(path, text, opts)?;
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
    /// How the run is read (`--tree` among them).
    opts: LoadOptions,
}

impl Follow {
    pub fn new(path: &Path) -> Follow {
        Follow::with(path, LoadOptions::default())
    }

    /// Following a run read with these options.
    pub fn with(path: &Path, opts: LoadOptions) -> Follow {
        Follow {
            path: path.to_path_buf(),
            seen: None,
            opts,
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
        match open(&self.path, &self.opts)? {
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

/// What a text file given where a tree or a session is expected is, and
/// where it goes: a domain file, another TOML file (a keymap), or a plan.
fn what_file(path: &Path, text: &str) -> Option<String> {
    if let Ok(table) = text.parse::<toml::Table>() {
        if table.contains_key("btx_domain") {
            return Some("this is a domain file; give it with --domain FILE".into());
        }
        let keys = !table.is_empty() && table.values().all(|v| v.is_array());
        if keys {
            return Some(
                "this is a TOML file of key lists, a keymap; give it to the explorer with --keys FILE"
                    .into(),
            );
        }
    }
    let plan = crate::run::plan::Plan::parse(path, text).ok()?;
    (!plan.entries.is_empty()).then(|| {
        "this is a plan (leaf = outcomes); give it with --plan FILE, with the tree it drives".into()
    })
}

/// How many records of a long `.btlog` the explorer shows while it reads
/// the rest: the first screens of the run, read in a few milliseconds.
pub const FIRST_RECORDS: usize = 1 << 16;

/// A long `.btlog`'s first `records` records as a run of their own, to
/// show at once while the whole is read (`Reading`), as a pager shows its
/// first page: None where the file is no `.btlog`, holds no more records
/// than that, or `--run` picks one of its runs (which may lie further on).
/// A file that cannot be read is None too: reading it whole says why.
pub fn open_first(
    path: &Path,
    opts: &LoadOptions,
    records: usize,
) -> Result<Option<Session>, Located> {
    use std::io::Read;
    let Ok(len) = crate::source::check_input(path, crate::source::INPUT_SIZE_MAX, "the file")
    else {
        return Ok(None);
    };
    let Ok(mut file) = std::fs::File::open(path) else {
        return Ok(None);
    };
    let mut head = [0u8; 23];
    if opts.run.is_some() || file.read_exact(&mut head).is_err() {
        return Ok(None);
    }
    let Some(first) = crate::logs::btlog::records_start(&head) else {
        return Ok(None);
    };
    let want = first + 9 * records;
    if len <= want as u64 {
        return Ok(None);
    }
    let mut bytes = vec![0; want];
    bytes[..23].copy_from_slice(&head);
    if file.read_exact(&mut bytes[23..]).is_err() {
        return Ok(None);
    }
    let tree = run_tree(opts)?;
    let log = crate::logs::number_btlog(path, bytes, given(&tree, opts))?;
    Ok(Some(log.into_session()))
}

/// A run read whole on a thread of its own, while a part of it is shown.
pub struct Reading {
    path: std::path::PathBuf,
    rx: std::sync::mpsc::Receiver<Result<Session, Located>>,
}

impl Reading {
    /// Starts reading the run in `path` whole, as `open` reads it.
    pub fn start(path: &Path, opts: &LoadOptions) -> Reading {
        let (tx, rx) = std::sync::mpsc::sync_channel(1);
        let (file, opts) = (path.to_path_buf(), opts.clone());
        std::thread::spawn(move || {
            let run = open(&file, &opts).and_then(|input| match input {
                Input::Session(s) => Ok(*s),
                Input::Tree { .. } => Err(Located::file(&file, "this is a tree, not a run")),
            });
            // The explorer may have quit; nobody is left to tell.
            let _ = tx.send(run);
        });
        Reading {
            path: path.to_path_buf(),
            rx,
        }
    }

    /// The whole run, if it is read within `wait`.
    pub fn take(&self, wait: std::time::Duration) -> Option<Result<Session, Located>> {
        use std::sync::mpsc::RecvTimeoutError;
        match self.rx.recv_timeout(wait) {
            Ok(run) => Some(run),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => Some(Err(self.stopped())),
        }
    }

    /// The whole run, once it is read.
    pub fn wait(&self) -> Result<Session, Located> {
        self.rx.recv().unwrap_or_else(|_| Err(self.stopped()))
    }

    fn stopped(&self) -> Located {
        Located::file(&self.path, "the reading stopped before the end of the file")
    }
}
