//! The details pane: the selected node's ports, state and the run's end, or
//! the why-answer's causal model, as a list or as the graph view.

use super::{Component, Handled, Hints, KeyHelp, Lines};
use crate::tui::keymap::Action;
use crate::tui::shared::{Shared, WhyView};
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::Frame;

/// The details pane's own state.
#[derive(Debug, Clone, Default)]
pub struct Details {
    /// Scrolled at the moment.
    lines: Lines,
}

impl Details {
    /// Up, Down, a page, Home and End within the pane.
    pub fn scroll(&mut self, a: Action, sh: &Shared) -> bool {
        self.lines.key(a, sh.moved)
    }
}

impl Component for Details {
    /// Keys while the details pane has the focus: the graph view's, then
    /// scrolling.
    fn key(&mut self, a: Action, sh: &mut Shared, focused: bool) -> Handled {
        Handled::taken(focused && (graph_key(a, sh) || self.scroll(a, sh)))
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Keys(&[(Action::NextPane, "next pane")])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "details",
            anywhere: &[],
            focused: &[
                (Action::Up, "scroll up"),
                (Action::Down, "scroll down"),
                (Action::Start, "the first line"),
                (Action::End, "the last line"),
                (Action::PageUp, "a page up"),
                (Action::PageDown, "a page down"),
                (Action::Expand, "the causal graph: the next neighbour"),
                (Action::Collapse, "the causal graph: the previous neighbour"),
                (
                    Action::Toggle,
                    "the causal graph: centre on the neighbour picked",
                ),
                (
                    Action::Back,
                    "the causal graph: back to the variable asked about",
                ),
            ],
        }
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        if let Some(w) = sh.why.as_ref().filter(|w| w.graph) {
            return self.model_pane(sh, w, f, area, focused);
        }
        self.node_pane(sh, f, area, focused)
    }
}

/// Keys of the causal graph view: ←→ pick a neighbour, Enter centres on
/// it, Esc goes back to the variable asked about. Whether the key was
/// taken.
fn graph_key(a: Action, sh: &mut Shared) -> bool {
    if !matches!(
        a,
        Action::Expand | Action::Collapse | Action::Toggle | Action::Back
    ) {
        return false;
    }
    let Some(w) = sh.why.as_mut().filter(|w| w.graph) else {
        return false;
    };
    let centre = w.centre.unwrap_or(w.why.query.targets[0]);
    let n = w.why.neighbourhood(centre, w.selected);
    let count = n.parents.len() + n.children.len();
    match a {
        Action::Expand if count > 0 => {
            w.pick = Some(w.pick.map_or(0, |p| (p + 1) % count));
        }
        Action::Collapse if count > 0 => {
            w.pick = Some(w.pick.map_or(count - 1, |p| (p + count - 1) % count));
        }
        Action::Toggle => {
            if let Some(x) = w
                .pick
                .and_then(|p| n.parents.iter().chain(&n.children).nth(p))
            {
                w.centre = Some(x.var);
                w.pick = None;
            }
        }
        Action::Back if w.centre.is_some() => {
            w.centre = None;
            w.pick = None;
        }
        _ => return false,
    }
    true
}

impl Details {
    /// The why-answer's causal model as a graph: the variable in the centre
    /// (the one asked about, until another is picked), its causes above and its
    /// effects below, edges in box characters (`graph_view`).
    fn model_pane(&self, sh: &Shared, w: &WhyView, f: &mut Frame, area: Rect, focused: bool) {
        let m = &w.why.model;
        let b = block(
            format!(
                " causal graph · tick {} · {} variables, {} edges (m to hide) ",
                m.facts.tick,
                m.vars.len(),
                m.edge_count()
            ),
            focused,
        );
        let inner = b.inner(area);
        let centre = w.centre.unwrap_or(w.why.query.targets[0]);
        let n = w.why.neighbourhood(centre, w.selected);
        let lines = crate::tui::graph_view::draw(&n, w.pick, inner.width as usize);
        let p = self.lines.paragraph(lines, sh.moved, area);
        f.render_widget(p.block(b), area);
    }

    /// The selected node: its kind, path, status at the moment, ports and
    /// blackboard, and how the run ended.
    fn node_pane(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        let b = block(" details ".into(), focused);
        let u = sh.selected;
        let n = sh.tree.node(u);
        let mut lines = vec![
            Line::from(format!(
                "{}  #{}",
                crate::text::visible(sh.tree.description(u)),
                u
            )),
            Line::from(format!(
                "{} {}  name {:?}",
                n.kind.as_str(),
                sh.tree.type_name(u),
                n.name
            )),
        ];
        // The path breaks after a `/`, not inside a name.
        let width = area.width.saturating_sub(2) as usize;
        lines.extend(
            wrap_path(&sh.tree.display_path(u), width)
                .into_iter()
                .map(Line::from),
        );
        lines.extend(at_the_moment(sh, u));
        if let Some(s) = &sh.session {
            lines.push(Line::from(run_ending(sh, s)));
        }
        for (k, v) in &n.metadata {
            lines.push(Line::from(Span::styled(
                format!("{k} {}", crate::text::visible(v)),
                Style::default().add_modifier(Modifier::DIM),
            )));
        }
        lines.extend(ports_and_state(sh, u));
        if let Some(l) = &sh.live {
            lines.extend(live_blackboard(l, &sh.tree.blackboard_name(n.scope)));
        }
        let p = self.lines.paragraph(lines, sh.moved, area);
        f.render_widget(p.block(b), area);
    }
}

/// The node at the moment: its status, when it last completed, a loop's
/// attempts and an action's decision.
fn at_the_moment(sh: &Shared, u: crate::model::Uid) -> Vec<Line<'static>> {
    let Some(a) = sh.at() else {
        return Vec::new();
    };
    let last = a
        .last_completed(u)
        .map_or("never".to_string(), |s| s.to_string());
    let mut lines = vec![Line::from(vec![
        Span::raw("status "),
        Span::styled(
            a.status(u).to_string(),
            Style::default().fg(status_color(a.status(u))),
        ),
        Span::raw(format!("  last completed {last}")),
    ])];
    if matches!(
        sh.tree.node(u).builtin,
        Some(crate::model::Builtin::RetryUntilSuccessful | crate::model::Builtin::Repeat)
    ) {
        lines.push(Line::from(format!("attempts so far {}", a.attempts(u))));
    }
    if let Some(d) = a.decision(u) {
        lines.push(Line::from(format!("decision {d}")));
    }
    lines
}

/// How the run ended; a robot watched now: its run is not cut off, it
/// goes on.
fn run_ending(sh: &Shared, s: &crate::session::Session) -> String {
    let e = s.ending();
    let going = sh
        .live
        .as_ref()
        .is_some_and(|l| l.status.finished.is_none() && s.end.is_none());
    match e.strip_prefix("no end recorded") {
        Some(_) if going => format!("The run goes on (tick {}).", s.index.ticks()),
        Some(rest) => format!("The run has no end recorded{rest}."),
        None => format!("The run {e}."),
    }
}

/// The node's ports with the values their entries hold at the moment, and
/// the top-level state.
fn ports_and_state(sh: &Shared, u: crate::model::Uid) -> Vec<Line<'static>> {
    let n = sh.tree.node(u);
    let at = sh.at();
    let mut lines = Vec::new();
    let bb = crate::run::blackboard::Blackboard::new(&sh.tree);
    for p in &n.ports {
        let mut s = crate::export::port_label(p);
        if let (Some(a), Some(e)) = (&at, bb.port_entry(&sh.tree, n.scope, &p.value)) {
            if let Some(v) = a.entry(&e) {
                s.push_str(&format!(" = {v}"));
            }
        }
        lines.push(Line::from(s));
    }
    if let Some(a) = &at {
        let state: Vec<String> = a
            .entries()
            .iter()
            .filter(|(e, _)| e.scope == 0)
            .map(|(e, v)| format!("{}={}", e.key, v))
            .collect();
        if !state.is_empty() {
            lines.push(Line::from(Span::styled(
                "state",
                Style::default().add_modifier(Modifier::BOLD),
            )));
            lines.push(Line::from(state.join("  ")));
        }
    }
    lines
}

/// The robot's blackboard of the node's scope (`B`), as last fetched.
fn live_blackboard(l: &crate::live::Feed, name: &str) -> Vec<Line<'static>> {
    let mut lines = vec![Line::from(Span::styled(
        format!("blackboard {} (live)", crate::text::visible(name)),
        Style::default().add_modifier(Modifier::BOLD),
    ))];
    // A robot gone, or not connected now, is not being asked.
    let gone = match (&l.status.finished, l.status.connected) {
        (Some(f), _) => Some(format!("{f}: its blackboard is no longer read")),
        (None, false) => Some("not connected: read again once btx reconnects".to_string()),
        _ => None,
    };
    let got = l.blackboard().filter(|b| b.name == name).map(|b| b.entries);
    let had = got.is_some();
    let mut text = match got {
        None => vec![gone
            .clone()
            .unwrap_or_else(|| "asking the robot…".to_string())],
        Some(Err(e)) => vec![e],
        Some(Ok(serde_json::Value::Object(m))) if m.is_empty() => vec!["(no entries)".to_string()],
        Some(Ok(serde_json::Value::Object(m))) => {
            m.iter().map(|(k, v)| format!("{k} = {v}")).collect()
        }
        Some(Ok(v)) => vec![v.to_string()],
    };
    if let (true, Some(g)) = (had, gone) {
        text.push(format!("(as last read; {g})"));
    }
    lines.extend(
        text.into_iter()
            .map(|t| Line::from(crate::text::visible(&t).into_owned())),
    );
    lines
}

/// `path a/b/c` in lines of at most `width` columns, each broken after a
/// `/` (a name longer than a line is left to the paragraph's wrapping).
fn wrap_path(path: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::from("path ")];
    for seg in path.split_inclusive('/') {
        let last = lines.last_mut().expect("one line at least");
        let used = last.chars().count();
        if used > 5 && used + seg.chars().count() > width {
            lines.push(format!("     {seg}"));
        } else {
            last.push_str(seg);
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_path_breaks_after_a_slash() {
        let p = "NavigateRecovery/NavigateWithReplanning/FollowPath/FollowPath";
        assert_eq!(
            super::wrap_path(p, 44),
            vec![
                "path NavigateRecovery/",
                "     NavigateWithReplanning/FollowPath/",
                "     FollowPath"
            ]
        );
        assert_eq!(super::wrap_path("a/b", 80), vec!["path a/b"]);
    }
}
