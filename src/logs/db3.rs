//! SqliteLogger databases (`.db3`, `.btdb`; BehaviorTree.CPP ≥ 4.1.1):
//! `Definitions(session_id, date, xml_tree)`, `Nodes(session_id, fullpath,
//! node_uid)` and `Transitions(timestamp, session_id, node_uid, duration,
//! state, extra_data)`, one session per `session_id`.
//!
//! The database is opened read-only through SQLite's `unix-none` VFS, which
//! takes no lock at all: the library's writer sets no busy timeout, so a
//! reader's lock makes its next INSERT fail and the robot process abort.

use super::btlog::Record;
use crate::run::Status;
use crate::source::Located;
use rusqlite::{Connection, OpenFlags};
use std::path::Path;

/// The first 16 bytes of every SQLite 3 database.
pub const MAGIC: &[u8] = b"SQLite format 3\0";

pub fn is_db3(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

/// Whether the database's header says WAL mode (its read and write
/// versions, bytes 18 and 19, are 2).
fn is_wal(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 20];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && (head[18] == 2 || head[19] == 2)
}

/// A database file shorter than its header says.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Cut {
    /// The file's length, and the length its header says.
    pub len: u64,
    pub whole: u64,
    pub page: u64,
}

impl Cut {
    /// Said after an error about a file cut short: what it lost may be
    /// any table's.
    pub fn note(&self) -> String {
        format!(
            " (the file is cut short: it ends at byte {} of the {} its header says)",
            self.len, self.whole
        )
    }
}

/// Where a database file is cut short: its header's length (valid when
/// bytes 92..96 equal the change counter at 24..28, as SQLite checks) past
/// the file's end.
pub(crate) fn cut_short(path: &Path) -> Option<Cut> {
    use std::io::Read;
    let mut head = [0u8; 100];
    let mut f = std::fs::File::open(path).ok()?;
    f.read_exact(&mut head).ok()?;
    let word = |at: usize| u32::from_be_bytes([head[at], head[at + 1], head[at + 2], head[at + 3]]);
    let page = match u16::from_be_bytes([head[16], head[17]]) {
        1 => 65_536,
        p => u64::from(p),
    };
    let len = f.metadata().ok()?.len();
    let whole = u64::from(word(28)) * page;
    (page > 0 && word(24) == word(92) && whole > len).then_some(Cut { len, whole, page })
}

/// A copy of a WAL-mode database and its `-wal` file, or of the whole pages
/// of a database cut short, removed when dropped.
pub(crate) struct WalCopy {
    dir: std::path::PathBuf,
    db: std::path::PathBuf,
}

impl WalCopy {
    fn of(path: &Path, pages: Option<u64>) -> std::io::Result<WalCopy> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static N: AtomicU64 = AtomicU64::new(0);
        let dir = std::env::temp_dir().join(format!(
            "btx-db3-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir)?;
        let copy = WalCopy {
            db: dir.join("copy.db3"),
            dir,
        };
        match pages {
            Some(n) => {
                let src = std::fs::File::open(path)?;
                let mut dst = std::fs::File::create(&copy.db)?;
                std::io::copy(&mut std::io::Read::take(src, n), &mut dst)?;
            }
            None => {
                std::fs::copy(path, &copy.db)?;
            }
        }
        let mut wal = path.as_os_str().to_owned();
        wal.push("-wal");
        let wal = std::path::PathBuf::from(wal);
        if wal.is_file() {
            copy_sparse(&wal, &copy.dir.join("copy.db3-wal"))?;
        }
        Ok(copy)
    }
}

/// The most data a `-wal` file may hold to be read (SQLite checkpoints a
/// WAL at about 4 MiB by default).
pub const WAL_MAX: u64 = 1 << 30;

/// Copies a file's data, keeping its holes: a sparse 3 GB `-wal` of 24 KB
/// on disk is 24 KB copied, not 3 GB. Past `WAL_MAX` of data, refused.
fn copy_sparse(from: &Path, to: &Path) -> std::io::Result<()> {
    use std::io::{Read, Seek, SeekFrom, Write};
    use std::os::unix::fs::MetadataExt;
    use std::os::unix::io::AsRawFd;
    let mut src = std::fs::File::open(from)?;
    let meta = src.metadata()?;
    let on_disk = meta.blocks().saturating_mul(512);
    if on_disk.min(meta.len()) > WAL_MAX {
        return Err(std::io::Error::other(format!(
            "{} holds {} MiB, more than the {} MiB btx reads of a WAL",
            from.display(),
            on_disk >> 20,
            WAL_MAX >> 20
        )));
    }
    let mut dst = std::fs::File::create(to)?;
    dst.set_len(meta.len())?;
    let len = i64::try_from(meta.len()).unwrap_or(i64::MAX);
    let fd = src.as_raw_fd();
    let mut at: i64 = 0;
    let mut buf = vec![0u8; 1 << 16];
    while at < len {
        // SAFETY: lseek on our own open descriptor; it touches no memory.
        let data = unsafe { libc::lseek(fd, at, libc::SEEK_DATA) };
        if data < 0 {
            break; // only a hole is left (ENXIO)
        }
        let hole = unsafe { libc::lseek(fd, data, libc::SEEK_HOLE) }.max(data);
        src.seek(SeekFrom::Start(data as u64))?;
        dst.seek(SeekFrom::Start(data as u64))?;
        let mut left = (hole.min(len) - data) as u64;
        while left > 0 {
            let want = left.min(buf.len() as u64) as usize;
            let n = src.read(&mut buf[..want])?;
            if n == 0 {
                break;
            }
            dst.write_all(&buf[..n])?;
            left -= n as u64;
        }
        at = hole.max(data + 1);
    }
    Ok(())
}

impl Drop for WalCopy {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// One run of the database.
#[derive(Debug, Clone)]
pub struct Db3Session {
    pub id: i64,
    pub date: String,
    pub xml: String,
    /// `offset` is the row's place among the session's transitions (from 1).
    pub records: Vec<Record>,
    /// The Nodes table: (uid, full path) as the logger named them.
    pub nodes: Vec<(u32, String)>,
}

/// A database opened to read, never to lock or change (a rosbag's too): a
/// copy of it and its WAL file when it is in WAL mode, which lives as long
/// as the connection is used.
pub(crate) fn open_read_only(path: &Path) -> Result<(Connection, Option<WalCopy>), Located> {
    open(path, true)
}

/// The database opened to read its schema: a file cut within a page is
/// read in place, its last page's lost part as zeros.
pub(crate) fn open_schema(path: &Path) -> Result<(Connection, Option<WalCopy>), Located> {
    open(path, false)
}

fn open(path: &Path, whole_pages: bool) -> Result<(Connection, Option<WalCopy>), Located> {
    let fail = |m: String| Located::file(path, m);
    let sql = |what: &str, e: rusqlite::Error| fail(format!("{what}: {e}"));
    // A database in WAL mode keeps recent rows in `FILE-wal` and needs a
    // shared-memory file to read them, which a lock-free read-only open
    // cannot make: read a copy of the two files instead (SQLite checks each
    // WAL frame's checksum, so a frame the robot is still writing is left
    // out), and never touch the originals.
    //
    // SQLite reads a page past a file's end, or the part of one, as zeros,
    // and says nothing of a row spilling onto one: a file cut within a
    // page is read from a copy of its whole pages.
    let cut = cut_short(path);
    let pages = cut
        .filter(|c| whole_pages && c.len % c.page != 0)
        .map(|c| c.len / c.page * c.page);
    let mut copy = None;
    let conn = if is_wal(path) || pages.is_some() {
        let c = WalCopy::of(path, pages)
            .map_err(|e| fail(format!("cannot copy the database to read it: {e}")))?;
        let conn = Connection::open_with_flags(
            &c.db,
            OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX,
        );
        copy = Some(c);
        conn
    } else {
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        #[cfg(unix)]
        let conn = Connection::open_with_flags_and_vfs(path, flags, "unix-none");
        #[cfg(not(unix))]
        let conn = Connection::open_with_flags(path, flags);
        conn
    };
    let conn = conn.map_err(|e| sql("cannot open the database", e))?;
    if cut.is_some() {
        // SQLite refuses a file shorter than its header says, though the
        // pages before the cut are whole; with the schema writable (read
        // only, or our copy) it takes the file's length and errs at a page
        // past it.
        conn.pragma_update(None, "writable_schema", true)
            .map_err(|e| sql("cannot open the database", e))?;
    }
    Ok((conn, copy))
}

/// Every session id in the file, oldest first, and the one asked for (the
/// last if `which` is `None`), read.
pub fn read(path: &Path, which: Option<i64>) -> Result<(Vec<i64>, Db3Session), Located> {
    let e = Said {
        path,
        // What a file cut short lost may be any table's: said with each error.
        cut: cut_short(path).map_or(String::new(), |c| c.note()),
    };
    let (conn, _copy) = open_read_only(path)?;
    for table in ["Definitions", "Nodes", "Transitions"] {
        let n: i64 = conn
            .query_row(
                "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1",
                [table],
                |r| r.get(0),
            )
            .map_err(|x| e.sql("not a readable SQLite database", x))?;
        if n == 0 {
            return Err(e.fail(format!(
                "not a BehaviorTree.CPP SqliteLogger database: it has no table {table}{}",
                e.cut
            )));
        }
    }
    let ids = session_ids(&conn, &e)?;
    let Some(last) = ids.last() else {
        return Err(e.fail(
            "the database has no session (table Definitions is empty): the logger wrote nothing"
                .into(),
        ));
    };
    let id = which.unwrap_or(last.0);
    let Some((_, date)) = ids.iter().find(|x| x.0 == id).cloned() else {
        return Err(e.fail(format!(
            "no session {id} in table Definitions; it has {}",
            ids.iter()
                .map(|x| x.0.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    let xml: String = conn
        .query_row(
            "SELECT xml_tree FROM Definitions WHERE session_id = ?1",
            [id],
            |r| r.get::<_, Option<String>>(0),
        )
        .map_err(|x| e.sql(&format!("table Definitions, session {id}"), x))?
        .ok_or_else(|| {
            e.fail(format!(
                "table Definitions, session {id}: xml_tree is empty"
            ))
        })?;
    let nodes = nodes_of(&conn, id, &e)?;
    let records = transitions_of(&conn, id, &e)?;
    Ok((
        ids.iter().map(|x| x.0).collect(),
        Db3Session {
            id,
            date,
            xml,
            records,
            nodes,
        },
    ))
}

/// How an error of the file is said: with its path, and what a file cut
/// short lost.
struct Said<'a> {
    path: &'a Path,
    cut: String,
}

impl Said<'_> {
    fn fail(&self, m: String) -> Located {
        Located::file(self.path, m)
    }

    fn sql(&self, what: &str, e: rusqlite::Error) -> Located {
        self.fail(format!("{what}: {e}{}", self.cut))
    }
}

/// The sessions of table Definitions, oldest first, with their dates.
fn session_ids(conn: &rusqlite::Connection, e: &Said) -> Result<Vec<(i64, String)>, Located> {
    let mut ids = Vec::new();
    let mut st = conn
        .prepare("SELECT session_id, coalesce(date, '') FROM Definitions ORDER BY session_id")
        .map_err(|x| e.sql("table Definitions", x))?;
    let rows = st
        .query_map([], |r| Ok((r.get::<_, i64>(0)?, r.get::<_, String>(1)?)))
        .map_err(|x| e.sql("table Definitions", x))?;
    for row in rows {
        ids.push(row.map_err(|x| e.sql("table Definitions", x))?);
    }
    Ok(ids)
}

/// Session `id`'s nodes of table Nodes, in order: uid and full path.
fn nodes_of(conn: &rusqlite::Connection, id: i64, e: &Said) -> Result<Vec<(u32, String)>, Located> {
    let mut nodes = Vec::new();
    let mut st = conn
        .prepare("SELECT node_uid, fullpath FROM Nodes WHERE session_id = ?1 ORDER BY rowid")
        .map_err(|x| e.sql("table Nodes", x))?;
    let rows = st
        .query_map([id], |r| {
            Ok((r.get::<_, i64>(0)?, r.get::<_, Option<String>>(1)?))
        })
        .map_err(|x| e.sql("table Nodes", x))?;
    for (i, row) in rows.enumerate() {
        let (uid, p) = row.map_err(|x| e.sql(&format!("table Nodes, row {}", i + 1), x))?;
        let uid = u32::try_from(uid).map_err(|_| {
            e.fail(format!(
                "table Nodes, row {}: node_uid {uid} is not a uid",
                i + 1
            ))
        })?;
        nodes.push((uid, p.unwrap_or_default()));
    }
    Ok(nodes)
}

/// Session `id`'s transitions of table Transitions, by time, each checked.
fn transitions_of(conn: &rusqlite::Connection, id: i64, e: &Said) -> Result<Vec<Record>, Located> {
    let mut records = Vec::new();
    let mut st = conn
        .prepare(
            "SELECT timestamp, node_uid, state FROM Transitions WHERE session_id = ?1 ORDER BY timestamp",
        )
        .map_err(|x| e.sql("table Transitions", x))?;
    let rows = st
        .query_map([id], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, i64>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })
        .map_err(|x| e.sql("table Transitions", x))?;
    for (i, row) in rows.enumerate() {
        let n = i + 1;
        let (time_us, uid, state) =
            row.map_err(|x| e.sql(&format!("table Transitions, session {id}, row {n}"), x))?;
        let status = u8::try_from(state)
            .ok()
            .and_then(Status::from_code)
            .ok_or_else(|| {
                e.fail(format!(
                    "table Transitions, session {id}, row {n} (timestamp {time_us}): state {state} is not a status (0-4)"
                ))
            })?;
        let uid = u32::try_from(uid).map_err(|_| {
            e.fail(format!(
                "table Transitions, session {id}, row {n} (timestamp {time_us}): node_uid {uid} is not a uid"
            ))
        })?;
        records.push(Record {
            time_us,
            uid,
            status,
            offset: n,
        });
    }
    Ok(records)
}
