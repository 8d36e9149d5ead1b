//! A session's transitions as a table, like Groot's replay table.

use crate::model::Uid;
use crate::run::Status;
use crate::session::Session;
use serde_json::{json, Value};

pub struct LogRow {
    pub tick: u32,
    pub step: u32,
    pub uid: Uid,
    pub prev: Status,
    pub status: Status,
    pub decision: Option<String>,
}

/// The rows of `btx log`, filtered to one node and/or without →IDLE.
pub fn log_rows(s: &Session, only: Option<Uid>, no_idle: bool) -> Vec<LogRow> {
    let idx = &s.index;
    let mut rows = Vec::new();
    for tick in 1..=idx.ticks() {
        let r = idx.tick_range(tick);
        for (k, i) in r.clone().enumerate() {
            let t = idx.transitions[i];
            if only.is_some_and(|u| u != t.uid) || (no_idle && t.status == Status::Idle) {
                continue;
            }
            let decision = idx.transition_decision(i);
            rows.push(LogRow {
                tick,
                step: k as u32 + 1,
                uid: t.uid,
                prev: t.prev,
                status: t.status,
                decision: decision.map(str::to_string),
            });
        }
    }
    rows
}

pub fn log_text(s: &Session, rows: &[LogRow]) -> String {
    let mut out = format!(
        "{:>5} {:>5} {:>5}  {:<40} {:<8}    {:<8} {}\n",
        "tick", "step", "uid", "node", "prev", "status", "decision"
    );
    for r in rows {
        let mut name = s.tree.description(r.uid).to_string();
        if name.chars().count() > 40 {
            name = name.chars().take(39).collect::<String>() + "…";
        }
        out.push_str(&format!(
            "{:>5} {:>5} {:>5}  {:<40} {:<8} -> {:<8} {}\n",
            r.tick,
            r.step,
            r.uid,
            name,
            r.prev,
            r.status,
            if r.prev == Status::Running && r.status == Status::Idle {
                "(halted)"
            } else {
                r.decision.as_deref().unwrap_or("")
            }
        ));
    }
    out
}

/// One JSON object a line, for a log followed as it grows.
pub fn log_json_lines(s: &Session, rows: &[LogRow]) -> String {
    let mut out = String::new();
    if let Some(all) = log_json(s, rows)["transitions"].as_array() {
        for r in all {
            out.push_str(&r.to_string());
            out.push('\n');
        }
    }
    out
}

pub fn log_json(s: &Session, rows: &[LogRow]) -> Value {
    json!({
        "schema": "btx.log/1",
        "session": s.path.display().to_string(),
        "ticks": s.index.ticks(),
        "transitions": rows.iter().map(|r| json!({
            "tick": r.tick,
            "step": r.step,
            "uid": r.uid,
            "node": s.tree.description(r.uid),
            "type": s.tree.type_name(r.uid),
            "prev": r.prev,
            "status": r.status,
            "decision": r.decision,
            "halted": r.prev == Status::Running && r.status == Status::Idle,
        })).collect::<Vec<_>>(),
    })
}
