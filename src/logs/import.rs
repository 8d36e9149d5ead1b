//! A log imported as a session file: its header (the tree and where it
//! came from), the ending said, the transitions written.

use crate::run::Status;
use crate::session::{format, Header, Session, Source, TreeRef};
use crate::source::Located;
use std::path::{Path, PathBuf};

/// Where a tree file and the tree a log recorded differ, uid by uid (the
/// node's kind, type and name), each as one line naming the tree file's
/// line; empty when they match. At most `max` lines, then a count.
pub fn tree_mismatch(
    file: &crate::model::Tree,
    log: &crate::model::Tree,
    max: usize,
) -> Vec<String> {
    let mut out = Vec::new();
    if file.len() != log.len() {
        out.push(format!(
            "the tree file has {} nodes and the log's tree {}",
            file.len(),
            log.len()
        ));
    }
    let mut more = 0;
    for uid in 1..=file.len().min(log.len()) as u32 {
        let (a, b) = (file.node(uid), log.node(uid));
        let what =
            |t: &crate::model::Tree| format!("{} \"{}\"", t.type_name(uid), t.description(uid));
        if a.kind != b.kind || file.type_name(uid) != log.type_name(uid) || a.name != b.name {
            if out.len() >= max {
                more += 1;
                continue;
            }
            let (f, line, col) = file.location(uid);
            out.push(format!(
                "#{uid}: {f}:{line}:{col} has {}, the log {}",
                what(file),
                what(log)
            ));
        }
    }
    if more > 0 {
        out.push(format!("and {more} more nodes differ"));
    }
    out
}

/// The header of a session read from a log: the log's tree, embedded.
pub(crate) fn import_header(
    path: &Path,
    tree: &crate::model::Tree,
    version: crate::model::Version,
    kind: &str,
    blackboard: Vec<(crate::run::blackboard::EntryId, serde_json::Value)>,
) -> Header {
    import_header_with(path, tree, version, kind, blackboard, None)
}

/// `import_header`, with the tree's XML where the caller has it already.
pub(super) fn import_header_with(
    path: &Path,
    tree: &crate::model::Tree,
    version: crate::model::Version,
    kind: &str,
    blackboard: Vec<(crate::run::blackboard::EntryId, serde_json::Value)>,
    xml: Option<String>,
) -> Header {
    Header {
        btx_session: format::FORMAT_VERSION,
        btx_version: env!("CARGO_PKG_VERSION").to_string(),
        tree: TreeRef {
            path: Some(path.display().to_string()),
            hash: None,
            xml: xml.unwrap_or_else(|| crate::xml::to_v4_xml(tree)),
            btcpp_format: version.number(),
            main_tree: tree.main_tree.clone(),
        },
        source: Source {
            kind: "import".into(),
            path: Some(path.display().to_string()),
            text: None,
            name: Some(kind.into()),
        },
        seed: None,
        tick_ms: 0,
        nav2: None,
        blackboard,
        before: Vec::new(),
    }
}

/// How a log's run ended, by the root's last transition: completed
/// (SUCCESS or FAILURE, or IDLE right after it, as BehaviorTree.CPP resets
/// a finished tree), or halted while RUNNING. A log that stops while the
/// root runs has no end: the run was cut off or is still going.
pub fn ending(index: &crate::session::Index) -> Option<(u32, Status, String)> {
    let last = index
        .transitions
        .iter()
        .rev()
        .find(|t| t.uid == crate::model::Tree::ROOT)?;
    let ticks = index.ticks();
    if let Some(done) = last.status.ended(last.prev) {
        return Some((ticks, done, "root completed".into()));
    }
    (last.prev == Status::Running && last.status == Status::Idle)
        .then(|| (ticks, Status::Idle, "root halted while RUNNING".into()))
}

/// Writes a session read from a log as a btx session file; a log that
/// stops while the root runs is written without an end.
pub fn write_session(s: &Session, out: &Path) -> Result<PathBuf, Located> {
    let mut w = crate::session::SessionWriter::create(out, &s.header)?;
    write_events(s, &mut w)?;
    match &s.end {
        Some((ticks, root, why)) => w.finish(*ticks, *root, why),
        None => w.finish_cut_off(),
    }
}

pub(super) fn write_events(
    s: &Session,
    w: &mut crate::session::SessionWriter,
) -> Result<(), Located> {
    let idx = &s.index;
    let (mut wi, mut di, mut gi) = (0, 0, 0);
    // The states read when recording began are in the header.
    let resyncs: Vec<_> = idx.resyncs().into_iter().filter(|r| r.0 > 0).collect();
    let mut ri = 0;
    // The log's times are kept with its transitions.
    let timed = s.times_us.len() == idx.transitions.len();
    for (i, t) in idx.transitions.iter().enumerate() {
        while let Some((_, why)) = idx.gaps.get(gi).filter(|g| g.0 as usize <= i) {
            w.gap(t.tick, why)?;
            gi += 1;
        }
        while let Some((_, states)) = resyncs.get(ri).filter(|r| r.0 as usize <= i) {
            w.resync(idx.transitions[i - 1].tick, states)?;
            ri += 1;
        }
        while let Some(x) = idx.writes.get(wi).filter(|x| x.pos as usize <= i) {
            w.event(&crate::run::Event::Write {
                tick: x.tick,
                uid: x.uid,
                entry: x.entry.clone(),
                value: x.value.clone(),
            })?;
            wi += 1;
        }
        while let Some((_, tick, uid, d)) = idx.decision_calls.get(di).filter(|x| x.0 as usize <= i)
        {
            w.event(&crate::run::Event::Decision {
                tick: *tick,
                uid: *uid,
                decision: d.clone(),
            })?;
            di += 1;
        }
        w.timed(s.times_us.get(i).copied().filter(|_| timed));
        w.event(&crate::run::Event::Transition {
            tick: t.tick,
            uid: t.uid,
            prev: t.prev,
            status: t.status,
            decision: idx.transition_decision(i).map(str::to_string),
        })?;
    }
    for (_, why) in &idx.gaps[gi..] {
        w.gap(idx.ticks().max(1), why)?;
    }
    for (_, states) in &resyncs[ri..] {
        w.resync(idx.ticks().max(1), states)?;
    }
    Ok(())
}
