//! `view(&App)`: draws the panes from the state, building widgets only for
//! what is visible. It computes nothing that explains.

use super::app::{App, Overlay, Pane};
use crate::model::{Kind, Uid};
use crate::run::Status;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};
use ratatui::Frame;

/// Where each pane is, for drawing and for mouse clicks.
pub struct Areas {
    pub tree: Rect,
    pub details: Rect,
    pub timeline: Rect,
    pub ask: Rect,
    pub status: Rect,
}

pub fn layout(area: Rect, split: u16) -> Areas {
    let v = Layout::default()
        .direction(Direction::Vertical)
        .constraints([
            Constraint::Min(6),
            // The timeline grows with the terminal: a third of it, 8 to 20 rows.
            Constraint::Length((area.height / 3).clamp(8, 20)),
            Constraint::Length(1),
        ])
        .split(area);
    let top = Layout::default()
        .direction(Direction::Horizontal)
        .constraints([
            Constraint::Percentage(split),
            Constraint::Percentage(100 - split),
        ])
        .split(v[0]);
    let right = Layout::default()
        .direction(Direction::Vertical)
        .constraints([Constraint::Percentage(55), Constraint::Percentage(45)])
        .split(top[1]);
    Areas {
        tree: top[0],
        details: right[0],
        ask: right[1],
        timeline: v[1],
        status: v[2],
    }
}

/// Groot's colours.
pub fn status_color(s: Status) -> Color {
    match s {
        Status::Running => Color::Yellow,
        Status::Success => Color::Green,
        Status::Failure => Color::Red,
        Status::Idle | Status::Skipped => Color::DarkGray,
    }
}

fn glyph(app: &App, uid: Uid) -> &'static str {
    tree_glyph(&app.tree, uid)
}

/// What every sign on screen means, for the help.
const LEGEND: &[(&str, &str)] = &[
    (
        "R S F",
        "status now: RUNNING, SUCCESS, FAILURE (blank: IDLE)",
    ),
    ("H", "halted: was RUNNING, reset to IDLE by its parent"),
    ("x", "IDLE now, and its last completion was FAILURE"),
    ("▣ ▢ ◯", "subtree, action, condition"),
    ("→ ? ⇉", "sequence, fallback, parallel"),
    ("◇ ◆", "decorator, other control node"),
    ("▾ ▸", "expanded, collapsed"),
    ("◀ now", "the current node (the leaf last ticked)"),
    ("‹", "a row that begins left of the view (deep trees)"),
    (
        "▆ ▃ ▂ ·",
        "strip, per tick: running, failed, succeeded, idle",
    ),
    ("★", "causal model: a reason of the picked explanation"),
    ("≠ ›", "side-by-side diff: a divergent leaf, its parent"),
];

/// A node's kind at a glance: ▣ subtree, ▢ action, ◯ condition, → sequence…
pub fn tree_glyph(tree: &crate::model::Tree, uid: Uid) -> &'static str {
    let n = tree.node(uid);
    match n.kind {
        Kind::SubTree => "▣",
        Kind::Action => "▢",
        Kind::Condition => "◯",
        Kind::Decorator => "◇",
        Kind::Control => match tree.type_name(uid) {
            t if t.contains("Fallback") => "?",
            t if t.contains("Sequence") => "→",
            t if t.contains("Parallel") => "⇉",
            _ => "◆",
        },
    }
}

pub(super) fn block(title: String, focused: bool) -> Block<'static> {
    // The focused pane's border is thick as well as cyan: it shows without
    // colour (NO_COLOR).
    let (style, kind) = if focused {
        (
            Style::default().fg(Color::Cyan),
            ratatui::widgets::BorderType::Thick,
        )
    } else {
        (Style::default(), ratatui::widgets::BorderType::Plain)
    };
    Block::default()
        .borders(Borders::ALL)
        .border_type(kind)
        .border_style(style)
        .title(title)
}

/// The first row shown so that the selection stays in view.
pub fn first_row(app: &App, height: usize) -> usize {
    let sel = app.row_of(app.selected).unwrap_or(0);
    let h = height.max(1);
    if sel < h / 2 {
        0
    } else {
        (sel - h / 2).min(app.rows().len().saturating_sub(h))
    }
}

/// `text` in at most `cols` columns: cut with `…` when it does not fit.
pub fn fit(text: &str, cols: usize) -> String {
    if Span::raw(text).width() <= cols {
        return text.to_string();
    }
    let mut out = String::new();
    let mut w = 0;
    for c in text.chars() {
        let cw = Span::raw(c.to_string()).width();
        if w + cw + 1 > cols {
            break;
        }
        out.push(c);
        w += cw;
    }
    if cols > 0 {
        out.push('…');
    }
    out
}

fn tree_pane(app: &App, f: &mut Frame, area: Rect) {
    let title = format!(
        " {} tree · {} ",
        if app.framed_view { "framed" } else { "full" },
        app.title
    );
    let b = block(title, app.focus == Pane::Tree);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let h = inner.height as usize;
    let first = first_row(app, h);
    let at = app.at();
    let current = at.and_then(|a| a.current());
    let highlighted: Vec<Uid> = app.highlighted();
    let width = inner.width as usize;
    // Deep rows scroll sideways with the selection: its indentation is kept
    // within half the pane, and rows that start left of the view show `‹`.
    let sel_depth = app
        .rows()
        .iter()
        .find(|r| r.uid == app.selected)
        .map_or(0, |r| r.depth);
    let shift = (2 * sel_depth).saturating_sub(width / 2);
    let mut lines = Vec::with_capacity(h);
    for r in app.rows().iter().skip(first).take(h) {
        let status = app.status(r.uid);
        let mut marker = match status {
            Status::Idle => " ".to_string(),
            s => s.as_str()[..1].to_string(),
        };
        let mut mstyle = Style::default()
            .fg(status_color(status))
            .add_modifier(Modifier::BOLD);
        if let Some(a) = &at {
            if status == Status::Idle {
                let t = a
                    .index
                    .changes_of(r.uid)
                    .iter()
                    .rev()
                    .find(|&&p| p <= a.pos)
                    .map(|&p| a.index.transitions[p as usize - 1]);
                if t.is_some_and(|t| t.prev == Status::Running) {
                    marker = "H".into();
                    mstyle = Style::default().fg(Color::Magenta);
                } else if a.failed(r.uid) {
                    marker = "x".into();
                    mstyle = Style::default().fg(Color::Red);
                }
            }
        }
        let fold = if !r.has_children {
            "  "
        } else if app.collapsed.contains(&r.uid) {
            "▸ "
        } else {
            "▾ "
        };
        let mut name_style = Style::default();
        if highlighted.contains(&r.uid) {
            name_style = name_style
                .fg(Color::Cyan)
                .add_modifier(Modifier::UNDERLINED);
        }
        if Some(r.uid) == current {
            name_style = name_style.add_modifier(Modifier::BOLD);
        }
        if r.uid == app.selected {
            name_style = name_style.add_modifier(Modifier::REVERSED);
        }
        let role = if app.framed_view {
            match app
                .framed
                .nodes
                .iter()
                .find(|x| x.uid == r.uid)
                .map(|x| x.role)
            {
                Some(crate::frame::Role::Goal) => "goal ",
                Some(crate::frame::Role::Subgoal) => "subgoal ",
                Some(crate::frame::Role::Step) => "step ",
                _ => "",
            }
        } else {
            ""
        };
        let indent = match (2 * r.depth).checked_sub(shift) {
            Some(n) if shift == 0 => " ".repeat(n),
            Some(n) => format!("‹{}", " ".repeat(n.saturating_sub(1))),
            None => "‹".to_string(),
        };
        let head = vec![
            Span::styled(format!("{marker} "), mstyle),
            Span::raw(indent),
            Span::raw(fold),
            Span::styled(
                format!("{} ", glyph(app, r.uid)),
                Style::default().fg(Color::Blue),
            ),
        ];
        let tail = [
            Span::styled(format!(" #{}", r.uid), Style::default().fg(Color::DarkGray)),
            Span::raw(if Some(r.uid) == current {
                "  ◀ now"
            } else {
                ""
            }),
        ];
        // The name gives way, with an ellipsis, so the uid always shows.
        let used: usize = head.iter().chain(&tail[..1]).map(Span::width).sum();
        let name = fit(
            &format!("{role}{}", app.tree.description(r.uid)),
            width.saturating_sub(used),
        );
        let mut spans = head;
        spans.push(Span::styled(name, name_style));
        spans.extend(tail);
        lines.push(Line::from(spans));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

/// The why-answer's causal model as a graph: the variable in the centre
/// (the one asked about, until another is picked), its causes above and its
/// effects below, edges in box characters (`graph_view`).
fn model_pane(app: &App, w: &super::app::WhyView, f: &mut Frame, area: Rect) {
    let m = &w.why.model;
    let b = block(
        format!(
            " causal graph · tick {} · {} variables, {} edges (m to hide) ",
            m.facts.tick,
            m.vars.len(),
            m.edge_count()
        ),
        app.focus == Pane::Details,
    );
    let inner = b.inner(area);
    let centre = w.centre.unwrap_or(w.why.query.targets[0]);
    let n = w.why.neighbourhood(centre, w.selected);
    let lines = super::graph_view::draw(&n, w.pick, inner.width as usize);
    let (p, last) = scrolled(lines, app.scroll_details, area);
    note_max(app, true, last);
    f.render_widget(p.block(b), area);
}

/// Wrapped lines scrolled down `by` lines, at most to the last page (the
/// wrapped height less the pane's), which is also returned.
fn scrolled(lines: Vec<Line<'static>>, by: usize, area: Rect) -> (Paragraph<'static>, usize) {
    let p = Paragraph::new(lines).wrap(Wrap { trim: false });
    let inner = (
        area.width.saturating_sub(2),
        area.height.saturating_sub(2) as usize,
    );
    let last = p.line_count(inner.0).saturating_sub(inner.1);
    let by = by.min(last);
    (p.scroll((by.min(u16::MAX as usize) as u16, 0)), last)
}

/// Notes how far the details (`details`) or the ask pane can scroll.
fn note_max(app: &App, details: bool, last: usize) {
    let (d, a) = app.scroll_max.get();
    app.scroll_max
        .set(if details { (last, a) } else { (d, last) });
}

fn details_pane(app: &App, f: &mut Frame, area: Rect) {
    if let Some(w) = app.why.as_ref().filter(|w| w.graph) {
        return model_pane(app, w, f, area);
    }
    let b = block(" details ".into(), app.focus == Pane::Details);
    let u = app.selected;
    let n = app.tree.node(u);
    let at = app.at();
    let mut lines = vec![
        Line::from(format!("{}  #{}", app.tree.description(u), u)),
        Line::from(format!(
            "{} {}  name {:?}",
            n.kind.as_str(),
            app.tree.type_name(u),
            n.name
        )),
        Line::from(format!("path {}", app.tree.display_path(u))),
    ];
    if let Some(a) = &at {
        let last = a
            .last_completed(u)
            .map_or("never".to_string(), |s| s.to_string());
        lines.push(Line::from(vec![
            Span::raw("status "),
            Span::styled(
                a.status(u).to_string(),
                Style::default().fg(status_color(a.status(u))),
            ),
            Span::raw(format!("  last completed {last}")),
        ]));
        if matches!(
            n.builtin,
            Some(crate::model::Builtin::RetryUntilSuccessful | crate::model::Builtin::Repeat)
        ) {
            lines.push(Line::from(format!("attempts so far {}", a.attempts(u))));
        }
        if let Some(d) = a.decision(u) {
            lines.push(Line::from(format!("decision {d}")));
        }
    }
    if let Some(s) = &app.session {
        lines.push(Line::from(format!("run {}", s.ending())));
    }
    let bb = crate::run::blackboard::Blackboard::new(&app.tree);
    for p in &n.ports {
        let mut s = crate::export::port_label(p);
        if let (Some(a), Some(e)) = (&at, bb.port_entry(&app.tree, n.scope, &p.value)) {
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
    let (p, last) = scrolled(lines, app.scroll_details, area);
    note_max(app, true, last);
    f.render_widget(p.block(b), area);
}

/// The indices of the transitions the list shows: `rows` of those the
/// filters keep, the moment's (or the last kept before it) in the middle,
/// moved by the pane's scroll. Only as far from the moment as it must look.
fn shown_transitions(app: &App, s: &crate::session::Session, rows: usize) -> Vec<usize> {
    let total = s.index.transitions.len();
    let f = &app.log_filter;
    let keeps = |i: usize| f.keeps(&s.tree, &s.index.transitions[i]);
    let pos = app.pos as usize;
    // Kept transitions at or before the moment, nearest first, and after it.
    let before: Vec<usize> = (0..pos.min(total))
        .rev()
        .filter(|&i| keeps(i))
        .take(rows + 1 + app.scroll_timeline.unsigned_abs() as usize)
        .collect();
    let after: Vec<usize> = (pos.min(total)..total)
        .filter(|&i| keeps(i))
        .take(rows + app.scroll_timeline.max(0) as usize)
        .collect();
    let mut all: Vec<usize> = before.into_iter().rev().collect();
    let here = all.len();
    all.extend(after);
    let start = (here as i64 - (rows / 2) as i64 + app.scroll_timeline)
        .clamp(0, all.len().saturating_sub(rows) as i64) as usize;
    all.into_iter().skip(start).take(rows).collect()
}

/// Earlier answers under the one on screen (scroll down to read them).
fn push_history(app: &App, lines: &mut Vec<Line<'static>>) {
    if app.history.is_empty() {
        return;
    }
    lines.push(Line::from(Span::styled(
        format!("── {} earlier (PageDown) ──", app.history.len()),
        Style::default().fg(Color::DarkGray),
    )));
    for h in &app.history {
        for (i, l) in h.lines().enumerate() {
            let st = if i == 0 {
                Style::default().fg(Color::DarkGray)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(l.to_string(), st)));
        }
    }
}

fn timeline_pane(app: &App, f: &mut Frame, area: Rect) {
    let mut title = match &app.session {
        Some(s) => format!(" timeline · run {} ", crate::text::visible(&s.ending())),
        None => " timeline ".into(),
    };
    let lf = &app.log_filter;
    if !lf.is_empty() {
        let mut parts = Vec::new();
        if lf.no_idle {
            parts.push("no resets".to_string());
        }
        if let Some(u) = lf.below {
            parts.push(format!("#{u} and below"));
        }
        if let Some(st) = lf.status {
            parts.push(format!("to {}", st.as_str()));
        }
        if !lf.text.is_empty() {
            parts.push(format!("\"{}\"", crate::text::visible(&lf.text)));
        }
        title.push_str(&format!("· showing {} ", parts.join(", ")));
    }
    let b = block(title, app.focus == Pane::Timeline);
    let inner = b.inner(area);
    f.render_widget(b, area);
    let Some(s) = &app.session else {
        f.render_widget(
            Paragraph::new("no run: open a session to step through it"),
            inner,
        );
        return;
    };
    let m = app
        .shown_moment()
        .unwrap_or_else(|| s.index.at(app.pos).moment());
    let ticks = s.index.ticks();
    let total = s.index.transitions.len();
    let mut play = if app.playing {
        format!("  ▶ playing every {} ms", app.play_ms)
    } else {
        String::new()
    };
    if app.follow.is_some() {
        play.push_str("  · following the log");
    }
    let head = format!(
        "moment {m}  ·  tick {} of {ticks}  ·  transition {} of {total}{play}",
        m.tick, app.pos
    );
    let legend = "strip: ▆ running ▃ failed ▂ succeeded · idle";
    let room = (inner.width as usize).saturating_sub(head.chars().count() + 4);
    let mut lines = vec![Line::from(vec![
        Span::raw(head),
        Span::styled(
            if room >= legend.chars().count() {
                format!("    {legend}")
            } else {
                String::new()
            },
            Style::default().fg(Color::DarkGray),
        ),
    ])];
    // A strip of the selected node's status at the end of each tick around now.
    let width = inner.width.saturating_sub(10) as u32;
    let start = m.tick.saturating_sub(width / 2).max(1);
    let mut strip = vec![Span::raw(format!("#{:<4} ", app.selected))];
    for t in start..=(start + width).min(ticks) {
        let p = s
            .index
            .position(crate::session::Moment {
                tick: t,
                step: None,
            })
            .unwrap_or(0);
        let st = s.index.at(p).status(app.selected);
        let done = s.index.at(p).last_completed(app.selected);
        let c = match (st, done) {
            (Status::Running, _) => '▆',
            (Status::Idle, Some(Status::Failure)) | (Status::Failure, _) => '▃',
            (Status::Success, _) | (Status::Idle, Some(Status::Success)) => '▂',
            _ => '·',
        };
        let color = match (st, done) {
            (Status::Idle, Some(x)) => status_color(x),
            (x, _) => status_color(x),
        };
        let mut style = Style::default().fg(color);
        if t == m.tick {
            style = style.add_modifier(Modifier::REVERSED);
        }
        strip.push(Span::styled(c.to_string(), style));
    }
    lines.push(Line::from(strip));
    // Its tick axis: a mark and the number every ten ticks.
    let mut axis = String::from("tick  ");
    let mut t = start;
    while t <= (start + width).min(ticks) {
        if t.is_multiple_of(10) || t == 1 {
            let label = format!("╵{t}");
            axis.push_str(&label);
            let skip = label.chars().count() as u32;
            t += skip;
        } else {
            axis.push(' ');
            t += 1;
        }
    }
    lines.push(Line::from(Span::styled(
        axis,
        Style::default().fg(Color::DarkGray),
    )));
    // The transitions around the moment (those the filters keep).
    let around = (inner.height as usize).saturating_sub(3);
    for i in shown_transitions(app, s, around) {
        let t = s.index.transitions[i];
        let here = i + 1 == app.pos as usize;
        let style = if here {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default()
        };
        lines.push(Line::from(vec![
            Span::styled(
                format!(
                    "{:>5} #{:<4} {:<32} ",
                    t.tick,
                    t.uid,
                    truncate(s.tree.description(t.uid), 32)
                ),
                style,
            ),
            Span::styled(
                format!("{:<8}", t.prev.as_str()),
                Style::default().fg(status_color(t.prev)),
            ),
            Span::raw(" → "),
            Span::styled(
                t.status.as_str(),
                Style::default().fg(status_color(t.status)),
            ),
        ]));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

fn truncate(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        s.chars().take(n - 1).collect::<String>() + "…"
    }
}

fn ask_pane(app: &App, f: &mut Frame, area: Rect) {
    let b = block(" ask (a) ".into(), app.focus == Pane::Ask);
    // An answer on screen names what it was asked about, wherever the
    // selection has gone since.
    let about = match &app.asked {
        Some((u, at)) if app.answer.is_some() || app.why.is_some() => format!(
            "about {} #{u}{}",
            app.tree.description(*u),
            at.as_ref()
                .map_or(String::new(), |m| format!(" at moment {m}"))
        ),
        _ => format!(
            "about {} #{}",
            app.tree.description(app.asked_node()),
            app.asked_node()
        ),
    };
    let mut lines = vec![Line::from(Span::styled(
        about,
        Style::default().fg(Color::DarkGray),
    ))];
    if let Some(w) = &app.why {
        let q = &w.why;
        lines.push(Line::from(Span::styled(
            crate::causal::english::question(&q.model, &q.query),
            Style::default().add_modifier(Modifier::BOLD),
        )));
        let sentences = q.sentences();
        if sentences.is_empty() && q.answer.stopped.is_some() {
            let text = crate::causal::english::stopped_text(&q.answer);
            lines.push(Line::from(text.trim_end().to_string()));
        } else if sentences.is_empty() {
            lines.push(Line::from(format!(
                "No explanation up to depth {}.",
                q.answer.max_depth
            )));
        }
        for (i, s) in sentences.iter().enumerate() {
            let st = if i == w.selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(format!("{}. {s}", i + 1), st)));
        }
        lines.push(Line::from(Span::styled(
            "↑↓ pick · Enter: why that reason? · m: causal model · x: DOT file · y: copy",
            Style::default().fg(Color::DarkGray),
        )));
        push_history(app, &mut lines);
        f.render_widget(
            {
                let (p, last) = scrolled(lines, app.scroll_ask, area);
                note_max(app, false, last);
                p.block(block(" why (w) ".into(), app.focus == Pane::Ask))
            },
            area,
        );
        return;
    }
    match &app.answer {
        Some(a) => {
            lines.push(Line::from(Span::styled(
                a.question.wording(),
                Style::default().add_modifier(Modifier::BOLD),
            )));
            // Q5's steps come a line each.
            lines.extend(a.text.lines().map(|l| Line::from(l.to_string())));
            let used: Vec<String> = a.nodes.iter().map(|u| format!("#{u}")).collect();
            lines.push(Line::from(Span::styled(
                format!("from {}", used.join(" ")),
                Style::default().fg(Color::Cyan),
            )));
        }
        None => lines.push(Line::from(
            "press a to ask a question about the selected node",
        )),
    }
    push_history(app, &mut lines);
    let (p, last) = scrolled(lines, app.scroll_ask, area);
    note_max(app, false, last);
    f.render_widget(p.block(b), area);
}

fn centered(area: Rect, w: u16, h: u16) -> Rect {
    let w = w.min(area.width);
    let h = h.min(area.height);
    Rect {
        x: area.x + (area.width - w) / 2,
        y: area.y + (area.height - h) / 2,
        width: w,
        height: h,
    }
}

fn overlay(app: &App, f: &mut Frame, area: Rect) {
    match &app.overlay {
        Overlay::None => {}
        Overlay::Help { scroll } => {
            let mut lines: Vec<Line> = app
                .keymap
                .keys
                .iter()
                .map(|b| {
                    Line::from(vec![
                        Span::styled(
                            format!("{:<16}", b.0.join(" ")),
                            Style::default().fg(Color::Yellow),
                        ),
                        Span::raw(b.2),
                    ])
                })
                .collect();
            lines.push(Line::from(""));
            for (sign, what) in LEGEND {
                lines.push(Line::from(vec![
                    Span::styled(format!("{sign:<16}"), Style::default().fg(Color::Yellow)),
                    Span::raw(*what),
                ]));
            }
            let r = centered(area, 76, lines.len() as u16 + 2);
            let shown = r.height.saturating_sub(2) as usize;
            let top = (*scroll).min(lines.len().saturating_sub(shown));
            let more = if top + shown < lines.len() {
                " ↓ more "
            } else {
                ""
            };
            f.render_widget(Clear, r);
            f.render_widget(
                Paragraph::new(lines).scroll((top as u16, 0)).block(
                    Block::default()
                        .borders(Borders::ALL)
                        .title(" keys and signs (↑↓ scroll, ? or Esc to close) ")
                        .title_bottom(more),
                ),
                r,
            );
        }
        Overlay::Finder { query, selected } => {
            let r = centered(
                area,
                area.width.saturating_sub(8),
                area.height.saturating_sub(4),
            );
            f.render_widget(Clear, r);
            let b = Block::default()
                .borders(Borders::ALL)
                .title(format!(" find: {query}▏ "));
            let inner = b.inner(r);
            f.render_widget(b, r);
            let results = app.finder_results(query);
            let h = inner.height as usize;
            let first = selected.saturating_sub(h.saturating_sub(1));
            let mut lines = Vec::new();
            for (i, (u, idx)) in results.iter().enumerate().skip(first).take(h) {
                let label = app.finder_label(*u);
                let mut spans = Vec::new();
                for (ci, ch) in label.chars().enumerate() {
                    let mut st = Style::default();
                    if idx.contains(&ci) {
                        st = st.fg(Color::Yellow).add_modifier(Modifier::BOLD);
                    }
                    if i == *selected {
                        st = st.add_modifier(Modifier::REVERSED);
                    }
                    spans.push(Span::styled(ch.to_string(), st));
                }
                lines.push(Line::from(spans));
            }
            f.render_widget(Paragraph::new(lines), inner);
        }
        Overlay::Running { selected } => {
            let nodes = app.running_nodes();
            let r = centered(
                area,
                70,
                (nodes.len() as u16 + 2).min(area.height.saturating_sub(2)),
            );
            f.render_widget(Clear, r);
            let h = r.height.saturating_sub(2) as usize;
            let first = selected.saturating_sub(h.saturating_sub(1));
            let lines: Vec<Line> = nodes
                .iter()
                .enumerate()
                .skip(first)
                .take(h)
                .map(|(i, &u)| {
                    let st = if i == *selected {
                        Style::default().add_modifier(Modifier::REVERSED)
                    } else {
                        Style::default()
                    };
                    Line::from(Span::styled(
                        format!(
                            "{} #{u}  {}",
                            app.tree.description(u),
                            app.tree.type_name(u)
                        ),
                        st,
                    ))
                })
                .collect();
            f.render_widget(
                Paragraph::new(lines).block(
                    Block::default()
                        .borders(Borders::ALL)
                        .title(" RUNNING now: Enter selects "),
                ),
                r,
            );
        }
        Overlay::CanYou { text, selected } => {
            let r = centered(
                area,
                area.width.saturating_sub(8).min(70),
                area.height.saturating_sub(4).min(16),
            );
            f.render_widget(Clear, r);
            let b = Block::default()
                .borders(Borders::ALL)
                .title(format!(" Can you {}▏? ", crate::text::visible(text)));
            let inner = b.inner(r);
            f.render_widget(b, r);
            let h = inner.height as usize;
            let first = selected.saturating_sub(h.saturating_sub(1));
            let lines: Vec<Line> = app
                .can_you_candidates(text)
                .into_iter()
                .enumerate()
                .skip(first)
                .take(h)
                .map(|(i, d)| {
                    let st = if i == *selected {
                        Style::default().add_modifier(Modifier::REVERSED)
                    } else {
                        Style::default()
                    };
                    Line::from(Span::styled(crate::text::visible(&d).into_owned(), st))
                })
                .collect();
            f.render_widget(Paragraph::new(lines), inner);
        }
        Overlay::Filter { text } => {
            let r = centered(area, area.width.saturating_sub(8).min(70), 3);
            f.render_widget(Clear, r);
            f.render_widget(
                Paragraph::new(format!("{}▏", crate::text::visible(text))).block(
                    Block::default()
                        .borders(Borders::ALL)
                        .title(" show transitions of nodes named: Enter applies, empty for all "),
                ),
                r,
            );
        }
        Overlay::Export { path, replace } => {
            let r = centered(area, area.width.saturating_sub(8).min(90), 4);
            f.render_widget(Clear, r);
            let title = if *replace {
                " a file is there: Enter replaces it, Esc keeps it "
            } else {
                " write the causal model (DOT) to: Enter writes, Esc cancels "
            };
            let note = app.message.clone().unwrap_or_default();
            f.render_widget(
                Paragraph::new(vec![
                    Line::from(format!("{}▏", crate::text::visible(path))),
                    Line::from(crate::text::visible(&note).into_owned()),
                ])
                .block(Block::default().borders(Borders::ALL).title(title)),
                r,
            );
        }
        Overlay::Why { selected, targets } => {
            let r = centered(area, 70, targets.len() as u16 + 2);
            f.render_widget(Clear, r);
            let lines: Vec<Line> = targets
                .iter()
                .enumerate()
                .map(|(i, (_, q))| {
                    let st = if i == *selected {
                        Style::default().add_modifier(Modifier::REVERSED)
                    } else {
                        Style::default()
                    };
                    Line::from(Span::styled(q.clone(), st))
                })
                .collect();
            let title = format!(" why? about {} ", app.tree.description(app.asked_node()));
            f.render_widget(
                Paragraph::new(lines).block(Block::default().borders(Borders::ALL).title(title)),
                r,
            );
        }
        Overlay::Ask { selected } => {
            let qs = app.questions();
            let r = centered(area, 60, qs.len() as u16 + 2);
            f.render_widget(Clear, r);
            let lines: Vec<Line> = qs
                .iter()
                .enumerate()
                .map(|(i, q)| {
                    let st = if i == *selected {
                        Style::default().add_modifier(Modifier::REVERSED)
                    } else {
                        Style::default()
                    };
                    let text = match q {
                        crate::explain::Question::CanYou(x) if x.is_empty() => {
                            "Can you …? (type any subgoal or step)".to_string()
                        }
                        q => q.wording(),
                    };
                    Line::from(Span::styled(text, st))
                })
                .collect();
            let title = format!(" ask about {} ", app.tree.description(app.asked_node()));
            f.render_widget(
                Paragraph::new(lines).block(Block::default().borders(Borders::ALL).title(title)),
                r,
            );
        }
    }
}

/// Draws the whole screen.
pub fn view(app: &App, f: &mut Frame) {
    let a = layout(f.area(), app.split);
    if app.zoom {
        let whole = Rect {
            height: f.area().height.saturating_sub(1),
            ..f.area()
        };
        match app.focus {
            Pane::Tree => tree_pane(app, f, whole),
            Pane::Details => details_pane(app, f, whole),
            Pane::Ask => ask_pane(app, f, whole),
            Pane::Timeline => timeline_pane(app, f, whole),
        }
    } else {
        tree_pane(app, f, a.tree);
        details_pane(app, f, a.details);
        ask_pane(app, f, a.ask);
        timeline_pane(app, f, a.timeline);
    }
    let status = match &app.message {
        Some(m) => Span::styled(m.clone(), Style::default().fg(Color::Yellow)),
        None => {
            use super::keymap::Action as A;
            let first: &[(A, &str)] = match app.focus {
                Pane::Ask if app.why.is_some() => &[
                    (A::Down, "next explanation"),
                    (A::Toggle, "why that?"),
                    (A::Graph, "model"),
                    (A::ExportGraph, "export"),
                ],
                Pane::Tree => &[
                    (A::Down, "move"),
                    (A::Expand, "open"),
                    (A::Collapse, "close"),
                ],
                _ => &[(A::NextPane, "next pane")],
            };
            Span::styled(
                app.keymap.hints_within(first, a.status.width as usize),
                Style::default().fg(Color::DarkGray),
            )
        }
    };
    f.render_widget(Paragraph::new(status), a.status);
    overlay(app, f, f.area());
}
