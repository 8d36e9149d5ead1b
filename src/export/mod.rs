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
    trailing_gaps, write_log_json, Clock, LogFilter, LogRow, Table, TextRows, LOG_TEXT_HEADER,
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

/// Levels of indentation drawn (3 columns each): past them a line says
/// its level before the last ones' guides, so a chain thousands of levels
/// deep stays on a screen, and its text grows with its nodes, not with
/// the square of its depth.
pub const INDENT_MAX: usize = 40;

/// Draws a tree with box-drawing guides, iteratively (trees can be deep),
/// a line at a time into `line`. What is kept is a flag a level (whether
/// a sibling follows there), never a prefix string a node.
fn draw<F, C>(root: usize, children: C, mut label: F, line: &mut dyn FnMut(&str))
where
    C: Fn(usize) -> Vec<usize>,
    F: FnMut(usize) -> String,
{
    // (node, its level, whether it is the last of its siblings)
    let mut stack: Vec<(usize, usize, bool)> = vec![(root, 0, true)];
    // For each level from 1 above the node drawn: a sibling follows there.
    let mut more: Vec<bool> = Vec::new();
    let mut text = String::new();
    while let Some((x, level, last)) = stack.pop() {
        more.truncate(level.saturating_sub(1));
        text.clear();
        if level > 0 {
            let from = level.saturating_sub(INDENT_MAX);
            if from > 0 {
                text.push_str(&format!("[level {level}] "));
            }
            for &m in &more[from.min(more.len())..] {
                text.push_str(if m { "│  " } else { "   " });
            }
            text.push_str(if last { "└─ " } else { "├─ " });
        }
        text.push_str(&label(x));
        text.push('\n');
        line(&text);
        if level > 0 {
            more.push(!last);
        }
        let kids = children(x);
        let n = kids.len();
        for (i, &k) in kids.iter().enumerate().rev() {
            stack.push((k, level + 1, i + 1 == n));
        }
    }
}

#[cfg(test)]
mod draw_tests {
    use super::{draw, INDENT_MAX};

    fn drawn(children: impl Fn(usize) -> Vec<usize>) -> Vec<String> {
        let mut out = Vec::new();
        draw(0, children, |x| format!("n{x}"), &mut |l| {
            out.push(l.to_string())
        });
        out
    }

    #[test]
    fn guides_follow_siblings_and_a_deep_chain_says_its_level() {
        // 0 ─ 1 ─ 3, 0 ─ 2
        let t = drawn(|x| match x {
            0 => vec![1, 2],
            1 => vec![3],
            _ => vec![],
        });
        assert_eq!(t, ["n0\n", "├─ n1\n", "│  └─ n3\n", "└─ n2\n"]);
        let deep = 3 * INDENT_MAX;
        let t = drawn(|x| if x < deep { vec![x + 1] } else { vec![] });
        let last = t.last().unwrap();
        assert!(last.starts_with(&format!("[level {deep}]    ")), "{last}");
        assert!(t.iter().all(|l| l.chars().count() < 3 * INDENT_MAX + 30));
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
