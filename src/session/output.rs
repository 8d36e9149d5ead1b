//! One writer per output: the session file a command writes (`--out`) is
//! claimed for the life of the command, before any work starts, so that two
//! btx aimed at one file never interleave or rename over each other, and a
//! destination that cannot be written is said at once rather than after a
//! run of an hour.
//!
//! The claim is an exclusive `flock` on `OUT.btx-lock` beside the output
//! (the kernel drops it when the process dies, however it dies, so a killed
//! btx never leaves a claim behind). The lock file says who holds it.

use crate::source::Located;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// What a lock file starts with: a file without it is not btx's, and is
/// neither written nor removed.
const MAGIC: &str = "btx lock";

/// The claim on an output, released on drop.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
}

/// The lock file of an output.
pub fn lock_path(out: &Path) -> PathBuf {
    let mut p = out.as_os_str().to_owned();
    p.push(".btx-lock");
    PathBuf::from(p)
}

impl OutputLock {
    /// Claims `out` for `command` (`btx run`, `btx watch`, …): refused at
    /// once when another btx holds it (naming it), when the directory is
    /// missing or cannot be written, when the disk is full, or when `out` or
    /// `OUT.partial` is there already.
    pub fn take(out: &Path, command: &str) -> Result<OutputLock, Located> {
        let dir = match out.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !dir.is_dir() {
            return Err(Located::file(
                out,
                format!(
                    "cannot write here: the directory {} does not exist",
                    dir.display()
                ),
            ));
        }
        let path = lock_path(out);
        // The file is opened, locked, then checked to be still the one at
        // `path`: a holder removes it as it finishes, and a lock taken on
        // the removed file would claim nothing.
        for _ in 0..100 {
            let mut file = open_lock(&path, out)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let mut holder = String::new();
                    let _ = file.read_to_string(&mut holder);
                    let holder = holder.strip_prefix(MAGIC).unwrap_or("").trim();
                    return Err(Located::file(
                        out,
                        format!(
                            "another btx is writing this session ({})",
                            if holder.is_empty() {
                                "starting"
                            } else {
                                holder
                            }
                        ),
                    )
                    .with_help("wait for it to finish, or choose another --out"));
                }
                Err(TryLockError::Error(e)) => {
                    return Err(Located::file(&path, format!("cannot lock the output: {e}")))
                }
            }
            if !same_file(&file, &path) {
                continue;
            }
            let mut lock = OutputLock { file, path };
            lock.say(command)?;
            refuse_existing(out)?;
            return Ok(lock);
        }
        Err(Located::file(
            &path,
            "the lock file kept being replaced by another process",
        ))
    }

    /// Writes who holds the lock, and so finds at once a disk that is full.
    fn say(&mut self, command: &str) -> Result<(), Located> {
        let line = format!("{MAGIC} {command} (pid {})\n", std::process::id());
        let f = &mut self.file;
        f.set_len(0)
            .and_then(|()| f.rewind())
            .and_then(|()| f.write_all(line.as_bytes()))
            .and_then(|()| f.sync_data())
            .map_err(|e| unwritable(&self.path, e))
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still locked, so a process that opened it meanwhile
        // finds it gone (`same_file`) and makes a new one. Whoever made it,
        // it holds this process's line: two btx starting together may each
        // make or open it, and the one that locks it last removes it.
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
        let _ = self.file.unlock();
    }
}

/// Opens the lock file, making it if need be.
fn open_lock(path: &Path, out: &Path) -> Result<File, Located> {
    match OpenOptions::new()
        .read(true)
        .write(true)
        .create_new(true)
        .open(path)
    {
        Ok(f) => return Ok(f),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
        Err(e) => return Err(unwritable(out, e)),
    }
    // Never waits, never follows: a FIFO put there would hold an open for
    // ever, a link would lock another file.
    let mut f = {
        use std::os::unix::fs::OpenOptionsExt;
        OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK | libc::O_NOFOLLOW)
            .open(path)
    }
    .map_err(|e| match e.raw_os_error() {
        Some(libc::ELOOP) => Located::file(
            path,
            "a link is here, where btx keeps the lock of this output: btx locks no file a link leads to",
        )
        .with_help("choose another --out, or remove that link"),
        _ => unwritable(path, e),
    })?;
    if !f.metadata().is_ok_and(|m| m.is_file()) {
        return Err(Located::file(
            path,
            "something that is not a regular file (a FIFO, a device, a directory) is here, where btx keeps the lock of this output",
        )
        .with_help("choose another --out, or move it away"));
    }
    let mut head = [0u8; MAGIC.len()];
    let n = f.read(&mut head).unwrap_or(0);
    // An empty file is a lock whose maker died before it said who it was.
    if n != 0 && &head[..n] != MAGIC.as_bytes() {
        return Err(Located::file(
            path,
            "a file that is not btx's is here, where btx keeps the lock of this output",
        )
        .with_help("choose another --out, or move that file away"));
    }
    f.rewind().map_err(|e| unwritable(path, e))?;
    Ok(f)
}

/// Whether `path` still names the open file `f`.
fn same_file(f: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (f.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// An output that cannot be written.
fn unwritable(path: &Path, e: std::io::Error) -> Located {
    Located::file(
        path,
        format!("cannot write here: {}", super::write::why(&e)),
    )
    .with_help("choose another --out; nothing was run or recorded")
}

/// Refuses an output already there, or a run's partial left beside it.
fn refuse_existing(out: &Path) -> Result<(), Located> {
    super::SessionWriter::refuse_existing(out)?;
    let partial = super::SessionWriter::partial_path(out);
    if std::fs::symlink_metadata(&partial).is_ok() {
        return Err(Located::file(
            &partial,
            "the run of an earlier btx that did not finish is here",
        )
        .with_help(
            "open it with btx to see what it recorded, then remove it, or choose another --out",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_claim_is_refused_naming_the_first() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("s.jsonl");
        let first = OutputLock::take(&out, "btx run").unwrap();
        let e = OutputLock::take(&out, "btx watch").unwrap_err();
        assert!(
            e.message
                .contains("another btx is writing this session (btx run (pid"),
            "{}",
            e.message
        );
        drop(first);
        assert!(
            !lock_path(&out).exists(),
            "the lock file is removed by its maker"
        );
        OutputLock::take(&out, "btx watch").unwrap();
    }

    #[test]
    fn a_file_of_someone_else_is_neither_written_nor_removed() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("s.jsonl");
        std::fs::write(lock_path(&out), "mine").unwrap();
        let e = OutputLock::take(&out, "btx run").unwrap_err();
        assert!(e.message.contains("not btx's"), "{}", e.message);
        assert_eq!(std::fs::read_to_string(lock_path(&out)).unwrap(), "mine");
    }

    #[test]
    fn a_lock_left_by_a_killed_btx_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("s.jsonl");
        std::fs::write(lock_path(&out), "btx lock btx run (pid 1)\n").unwrap();
        let lock = OutputLock::take(&out, "btx watch").unwrap();
        let said = std::fs::read_to_string(lock_path(&out)).unwrap();
        assert!(said.starts_with("btx lock btx watch (pid "), "{said}");
        drop(lock);
        assert!(
            !lock_path(&out).exists(),
            "btx's own lock holds no one's data"
        );
    }

    #[test]
    fn missing_directories_and_existing_outputs_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let e = OutputLock::take(&dir.path().join("no/s.jsonl"), "btx run").unwrap_err();
        assert!(e.message.contains("does not exist"), "{}", e.message);
        let out = dir.path().join("s.jsonl");
        std::fs::write(&out, "x").unwrap();
        let e = OutputLock::take(&out, "btx run").unwrap_err();
        assert!(
            e.message.contains("not a btx session is here"),
            "{}",
            e.message
        );
        assert!(!lock_path(&out).exists());
    }
}
