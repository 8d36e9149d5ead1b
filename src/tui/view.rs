//! What every screen draws with: the layout, the status colours and
//! glyphs, blocks, and text cut or scrolled to fit. Widgets are built only
//! for what is visible; nothing here explains.

use super::shared::Shared;
use crate::model::{Kind, Uid};
use crate::run::Status;
use ratatui::layout::{Constraint, Direction, Layout, Rect};
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Wrap};

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

pub(crate) fn glyph(sh: &Shared, uid: Uid) -> &'static str {
    tree_glyph(&sh.tree, uid)
}

/// What every sign on screen means, for the help.
pub(crate) const LEGEND: &[(&str, &str)] = &[
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
        "▆ ▃ ▂ ⊘",
        "strip, a tick it ran: running, failed, succeeded, halted",
    ),
    ("·", "strip: not ticked that tick (blank: not run yet)"),
    ("★", "causal model: a reason of the picked explanation"),
    (
        "≠ › ·",
        "side-by-side diff: a divergent leaf, its parent, a leaf that only follows",
    ),
    (
        "⋯ gap",
        "live run: transitions may be missing before this one",
    ),
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
pub fn first_row(sh: &Shared, height: usize) -> usize {
    first_shown(sh.row_of(sh.selected).unwrap_or(0), sh.rows().len(), height)
}

/// The first of `len` rows shown in `height` so that row `selected` stays
/// in view, in the middle when it can.
pub fn first_shown(selected: usize, len: usize, height: usize) -> usize {
    let h = height.max(1);
    if selected < h / 2 {
        0
    } else {
        (selected - h / 2).min(len.saturating_sub(h))
    }
}

/// The first of `texts` (longest first) that fits in `cols` columns, or
/// none: a hint is shown whole or shorter, never cut mid-word.
pub fn first_fitting<'a>(texts: &[&'a str], cols: usize) -> &'a str {
    texts
        .iter()
        .copied()
        .find(|t| t.chars().count() <= cols)
        .unwrap_or("")
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

/// Wrapped lines scrolled down `by` lines, at most to the last page (the
/// wrapped height less the pane's), which is also returned.
pub(crate) fn scrolled(
    lines: Vec<Line<'static>>,
    by: usize,
    area: Rect,
) -> (Paragraph<'static>, usize) {
    let p = Paragraph::new(lines).wrap(Wrap { trim: false });
    let inner = (
        area.width.saturating_sub(2),
        area.height.saturating_sub(2) as usize,
    );
    let last = p.line_count(inner.0).saturating_sub(inner.1);
    let by = by.min(last);
    (p.scroll((by.min(u16::MAX as usize) as u16, 0)), last)
}

pub(crate) fn truncate(s: &str, n: usize) -> String {
    if s.chars().count() <= n {
        s.to_string()
    } else {
        s.chars().take(n - 1).collect::<String>() + "…"
    }
}

pub(crate) fn centered(area: Rect, w: u16, h: u16) -> Rect {
    let w = w.min(area.width);
    let h = h.min(area.height);
    Rect {
        x: area.x + (area.width - w) / 2,
        y: area.y + (area.height - h) / 2,
        width: w,
        height: h,
    }
}
