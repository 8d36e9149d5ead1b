//! Renderings of trees, framed trees and answers: indented text, Graphviz DOT
//! and JSON (schemas in docs/formats.md).

mod dot;
mod json;
mod log;
pub mod mermaid;
mod text;

pub use dot::{framed_dot, tree_dot};
pub use json::{alert_json, framed_json, tree_json, write_tree_json};
pub use log::{
    each_log_row, log_json, log_json_lines, log_rows, log_text, log_text_row, log_transitions,
    trailing_gaps, write_log_json, Clock, LogFilter, LogRow, LOG_TEXT_HEADER,
};
pub use mermaid::{framed_mermaid, tree_mermaid};
pub use text::{framed_text, tree_text, write_tree_text};

use crate::model::{Kind, Port, PortValue, Tree, Uid};
use std::path::Path;

/// What writing an exported file found at its path.
#[derive(Debug, PartialEq, Eq)]
pub enum Written {
    /// Written, as a new file or over the regular file there.
    Done,
    /// A regular file is there: write again with `replace` to replace it.
    Exists,
}

/// Writes an export without surprises: a new file is created only if
/// nothing is at `path` (so a link planted there is never followed); an
/// existing regular file is replaced only when asked, through a new file
/// renamed over it (rename replaces the entry, never a link's target).
/// A link, directory or device at `path` is refused.
pub fn write_file(path: &Path, bytes: &[u8], replace: bool) -> std::io::Result<Written> {
    use std::io::{Error, ErrorKind, Write};
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == ErrorKind::NotFound => {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(path)?;
            f.write_all(bytes)?;
            Ok(Written::Done)
        }
        Err(e) => Err(e),
        Ok(m) if m.file_type().is_symlink() => Err(Error::other(
            "a symbolic link is there; btx does not write through one",
        )),
        Ok(m) if !m.is_file() => Err(Error::other("something other than a file is there")),
        Ok(_) if !replace => Ok(Written::Exists),
        Ok(_) => {
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            let tmp = path.with_file_name(format!(".{name}.btx-{}", std::process::id()));
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&tmp)?;
            let done = f
                .write_all(bytes)
                .and_then(|()| std::fs::rename(&tmp, path));
            if done.is_err() {
                let _ = std::fs::remove_file(&tmp);
            }
            done.map(|()| Written::Done)
        }
    }
}

/// How a node's type reads: `Sequence`, `Action move_to`, `SubTree go_pick`.
pub fn kind_label(tree: &Tree, uid: Uid) -> String {
    let n = tree.node(uid);
    match (n.kind, n.builtin) {
        (Kind::SubTree, _) => format!("SubTree {}", n.id),
        (Kind::Action | Kind::Condition, _) => {
            format!("{} {}", n.kind.as_str(), tree.type_name(uid))
        }
        (_, Some(_)) => tree.type_name(uid).to_string(),
        (k, None) => format!("{} {}", k.as_str(), n.id),
    }
}

/// `in:place="chuck place"`, `out:output={object pose}`.
pub fn port_label(p: &Port) -> String {
    let value = match &p.value {
        PortValue::Literal(s) => format!("{s:?}"),
        other => other.to_xml(),
    };
    match p.direction {
        Some(d) => format!("{}:{}={}", d.as_str(), p.name, value),
        None => format!("{}={}", p.name, value),
    }
}

/// Draws a tree with box-drawing guides, iteratively (trees can be deep),
/// a line at a time into `line`: the indentation of a deep tree grows with
/// the square of its depth, so nothing holds it all.
fn draw<F, C>(root: usize, children: C, mut label: F, line: &mut dyn FnMut(&str))
where
    C: Fn(usize) -> Vec<usize>,
    F: FnMut(usize) -> String,
{
    // (node, prefix for its children, its own guide)
    let mut stack: Vec<(usize, String, String)> = vec![(root, String::new(), String::new())];
    let mut text = String::new();
    while let Some((x, prefix, guide)) = stack.pop() {
        text.clear();
        text.push_str(&guide);
        text.push_str(&label(x));
        text.push('\n');
        line(&text);
        let kids = children(x);
        let last = kids.len().saturating_sub(1);
        for (i, &k) in kids.iter().enumerate().rev() {
            let (g, p) = if i == last {
                ("└─ ", "   ")
            } else {
                ("├─ ", "│  ")
            };
            stack.push((k, format!("{prefix}{p}"), format!("{prefix}{g}")));
        }
    }
}

#[cfg(test)]
mod write_tests {
    use super::{write_file, Written};

    #[test]
    fn an_export_never_overwrites_unasked_nor_follows_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("m.dot");
        assert_eq!(write_file(&p, b"one", false).unwrap(), Written::Done);
        assert_eq!(write_file(&p, b"two", false).unwrap(), Written::Exists);
        assert_eq!(std::fs::read(&p).unwrap(), b"one");
        assert_eq!(write_file(&p, b"two", true).unwrap(), Written::Done);
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let target = dir.path().join("target");
        std::fs::write(&target, b"keep").unwrap();
        let link = dir.path().join("link.dot");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        for replace in [false, true] {
            let e = write_file(&link, b"evil", replace).unwrap_err();
            assert!(e.to_string().contains("symbolic link"), "{e}");
        }
        let dangling = dir.path().join("dangling.dot");
        std::os::unix::fs::symlink(dir.path().join("nowhere"), &dangling).unwrap();
        assert!(write_file(&dangling, b"evil", true).is_err());
        assert!(!dir.path().join("nowhere").exists());
        assert_eq!(std::fs::read(&target).unwrap(), b"keep");
        assert!(write_file(dir.path(), b"x", true).is_err());
    }
}
