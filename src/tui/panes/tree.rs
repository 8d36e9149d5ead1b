//! The tree pane: moving the selection, folding, and the framed view. The
//! selection is shared (every pane reads it), so these keys act whichever
//! pane has the focus (unless the focused pane took the key first).

use super::{Component, Handled, Hints, KeyHelp, PAGE};
use crate::model::Uid;
use crate::run::Status;
use crate::tui::keymap::Action;
use crate::tui::shared::Shared;
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

/// The tree pane. Its state is the selection and the folding, which every
/// pane reads: they are in [`Shared`].
#[derive(Debug, Clone, Copy, Default)]
pub struct TreePane;

impl Component for TreePane {
    fn key(&mut self, a: Action, sh: &mut Shared, _focused: bool) -> Handled {
        Handled::taken(Self::tree_key(a, sh))
    }

    fn hints(&self, _sh: &Shared) -> Hints {
        Hints::Keys(&[
            (Action::Down, "move"),
            (Action::Expand, "open"),
            (Action::Collapse, "close"),
        ])
    }

    fn help(&self) -> KeyHelp {
        KeyHelp {
            name: "tree",
            anywhere: &[
                (Action::Up, ""),
                (Action::Down, ""),
                (Action::Collapse, ""),
                (Action::Expand, ""),
                (Action::Toggle, ""),
                (Action::PageUp, "select the node a page above"),
                (Action::PageDown, "select the node a page below"),
                (Action::ToggleFramed, ""),
            ],
            focused: &[],
        }
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        let title = format!(
            " {} tree · {} ",
            if sh.framed_view { "framed" } else { "full" },
            sh.title
        );
        let b = block(title, focused);
        let inner = b.inner(area);
        f.render_widget(b, area);
        let h = inner.height as usize;
        let first = first_row(sh, h);
        let width = inner.width as usize;
        // Deep rows scroll sideways with the selection: its indentation is kept
        // within half the pane, and rows that start left of the view show `‹`.
        let sel_depth = sh
            .rows()
            .iter()
            .find(|r| r.uid == sh.selected)
            .map_or(0, |r| r.depth);
        let shift = (2 * sel_depth).saturating_sub(width / 2);
        let seen = Seen {
            at: sh.at(),
            highlighted: sh.highlighted(),
        };
        let lines: Vec<Line> = sh
            .rows()
            .iter()
            .skip(first)
            .take(h)
            .map(|r| row(sh, &seen, r, shift, width))
            .collect();
        f.render_widget(Paragraph::new(lines), inner);
    }
}

impl TreePane {
    /// The tree's keys. Whether the key was taken.
    fn tree_key(a: Action, sh: &mut Shared) -> bool {
        match a {
            Action::Up | Action::Down | Action::PageUp | Action::PageDown => {
                let i = sh.row_of(sh.selected).unwrap_or(0);
                let last = sh.rows.len().saturating_sub(1);
                let j = match a {
                    Action::Up => i.saturating_sub(1),
                    Action::Down => (i + 1).min(last),
                    Action::PageUp => i.saturating_sub(PAGE),
                    _ => (i + PAGE).min(last),
                };
                sh.selected = sh.rows[j].uid;
                sh.follow_node = false;
            }
            Action::Collapse => {
                if sh
                    .rows
                    .get(sh.row_of(sh.selected).unwrap_or(0))
                    .is_some_and(|r| r.has_children)
                    && !sh.collapsed.contains(&sh.selected)
                {
                    sh.collapsed.insert(sh.selected);
                    sh.rebuild_rows();
                } else if let Some(p) = sh
                    .tree
                    .ancestors(sh.selected)
                    .find(|p| sh.row_of(*p).is_some())
                {
                    sh.selected = p;
                    sh.follow_node = false;
                }
            }
            Action::Expand => {
                if sh.collapsed.remove(&sh.selected) {
                    sh.rebuild_rows();
                } else if let Some(i) = sh.row_of(sh.selected) {
                    if sh.rows[i].has_children {
                        if let Some(next) = sh.rows.get(i + 1) {
                            sh.selected = next.uid;
                            sh.follow_node = false;
                        }
                    }
                }
            }
            Action::Toggle => {
                if !sh.collapsed.remove(&sh.selected) {
                    sh.collapsed.insert(sh.selected);
                }
                sh.rebuild_rows();
            }
            Action::ToggleFramed => {
                sh.framed_view = !sh.framed_view;
                sh.selected = sh.visible_for(sh.selected);
                sh.rebuild_rows();
            }
            _ => return false,
        }
        true
    }
}

/// What every row is drawn against: the moment, and the nodes the answer
/// on screen highlights.
struct Seen<'a> {
    at: Option<crate::session::At<'a>>,
    highlighted: Vec<Uid>,
}

/// A node's row: its status letter, indentation shifted left by `shift`,
/// fold, glyph, role and name (cut so that its uid always shows) in
/// `width` columns.
fn row(
    sh: &Shared,
    seen: &Seen,
    r: &crate::tui::shared::Row,
    shift: usize,
    width: usize,
) -> Line<'static> {
    let current = seen.at.as_ref().and_then(|a| a.current());
    let (marker, mstyle) = marker(sh, seen, r.uid);
    let fold = if !r.has_children {
        "  "
    } else if sh.collapsed.contains(&r.uid) {
        "▸ "
    } else {
        "▾ "
    };
    let mut name_style = Style::default();
    if seen.highlighted.contains(&r.uid) {
        name_style = name_style
            .fg(Color::Cyan)
            .add_modifier(Modifier::UNDERLINED);
    }
    if Some(r.uid) == current {
        name_style = name_style.add_modifier(Modifier::BOLD);
    }
    if r.uid == sh.selected {
        name_style = name_style.add_modifier(Modifier::REVERSED);
    }
    let role = if sh.framed_view {
        match sh
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
            format!("{} ", glyph(sh, r.uid)),
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
        &format!("{role}{}", crate::text::visible(sh.tree.description(r.uid))),
        width.saturating_sub(used),
    );
    let mut spans = head;
    spans.push(Span::styled(name, name_style));
    spans.extend(tail);
    Line::from(spans)
}

/// A node's status letter at the moment: its status, or for an IDLE one
/// `H` if it was halted while RUNNING and `x` if it failed earlier.
fn marker(sh: &Shared, seen: &Seen, uid: Uid) -> (String, Style) {
    let status = sh.status(uid);
    let mut marker = match status {
        Status::Idle => " ".to_string(),
        s => s.as_str()[..1].to_string(),
    };
    let mut mstyle = Style::default()
        .fg(status_color(status))
        .add_modifier(Modifier::BOLD);
    if let Some(a) = &seen.at {
        if status == Status::Idle {
            let t = a
                .index
                .changes_of(uid)
                .iter()
                .rev()
                .find(|&&p| p <= a.pos)
                .map(|&p| a.index.transitions[p as usize - 1]);
            if t.is_some_and(|t| t.prev == Status::Running) {
                marker = "H".into();
                mstyle = Style::default().fg(Color::Magenta);
            } else if a.failed(uid) {
                marker = "x".into();
                mstyle = Style::default().fg(Color::Red);
            }
        }
    }
    (marker, mstyle)
}
