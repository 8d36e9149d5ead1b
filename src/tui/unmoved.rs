//! A key that changed nothing on screen says why, in the status bar (#27
//! item 2: "a key that cannot act says why"). The key's handler knows
//! what it did; what it could not do is read here from where the
//! explorer stands (the window open, the pane focused, the moment).

use super::app::{App, Pane};
use super::diff::DiffApp;
use super::keymap::Action;
use super::panes::overlays::Overlay;
use super::text_input::Edit;
use crate::model::Tree;

/// Why `key` (bound to `a`) changed nothing in the explorer.
pub fn reason(app: &App, a: Action, key: &str) -> String {
    match &app.overlay {
        None => {}
        Some(Overlay::Help(_)) => {
            return match a {
                Action::Up | Action::Start | Action::PageUp => "at the top of the help".into(),
                Action::Down | Action::End | Action::PageDown => "at the end of the help".into(),
                _ => format!("{key}: the help is open; ↑↓ scroll it, Esc or ? closes it"),
            }
        }
        Some(Overlay::CanYou(_) | Overlay::Words(_) | Overlay::Filter(_)) => {
            return format!("{key}: you are typing; Enter takes the text, Esc cancels");
        }
        Some(Overlay::Export(_)) => {
            return format!("{key}: you are typing a file name; Enter writes, Esc cancels");
        }
        _ => {
            return match a {
                Action::Up | Action::Start | Action::PageUp => "at the top of the list".into(),
                Action::Down | Action::End | Action::PageDown => "at the end of the list".into(),
                _ => format!("{key}: a list is open; ↑↓ choose, Enter picks, Esc closes it"),
            }
        }
    }
    let sh = &app.shared;
    let name = |u| format!("{} #{u}", sh.tree.description(u));
    let end = sh.pos >= sh.positions();
    let start = sh.pos == 0;
    let pane = match app.focus {
        Pane::Tree => "tree",
        Pane::Timeline => "timeline",
        Pane::Details => "details",
        Pane::Ask => "answer",
    };
    match a {
        Action::Back => "nothing to close (q quits)".into(),
        Action::Expand | Action::Toggle if sh.tree.node(sh.selected).children.is_empty() => {
            format!("{} is a leaf: nothing to open", name(sh.selected))
        }
        Action::Expand | Action::Toggle => format!("{} is open already", name(sh.selected)),
        Action::Collapse if sh.selected == Tree::ROOT => {
            format!("{} is the root: it has no parent", name(sh.selected))
        }
        Action::StepForward | Action::TickForward | Action::End if end => {
            "at the end of the run".into()
        }
        Action::StepBack | Action::TickBack | Action::Start if start => {
            "at the start of the run".into()
        }
        Action::Up | Action::PageUp | Action::Start if app.focus != Pane::Tree => {
            format!("at the top of the {pane} pane")
        }
        Action::Down | Action::PageDown | Action::End if app.focus != Pane::Tree => {
            format!("at the end of the {pane} pane")
        }
        Action::Up | Action::PageUp => format!("{} is the first node", name(sh.selected)),
        Action::Down | Action::PageDown => format!("{} is the last node", name(sh.selected)),
        _ => format!("{key}: nothing to do here ({})", a.help()),
    }
}

/// Why `key` (bound to `a`) changed nothing in the side-by-side diff.
pub fn diff_reason(app: &DiffApp, a: Action, key: &str) -> String {
    if app.help.is_some() {
        return format!("{key}: the help is open; Esc or ? closes it");
    }
    match a {
        Action::Back => "nothing to close (q quits)".into(),
        Action::Up | Action::PageUp | Action::Start => "at the top".into(),
        Action::Down | Action::PageDown | Action::End => "at the end".into(),
        _ => format!("{key}: nothing to do here ({})", a.help()),
    }
}

/// Why an edit of the prompt changed nothing.
pub fn edit_reason(app: &App, e: &Edit) -> String {
    if app.prompt_text().is_none_or(str::is_empty) {
        return "nothing typed yet: type, Enter takes it, Esc cancels".into();
    }
    match e {
        Edit::Right | Edit::End => "at the end of the text".into(),
        _ => "at the start of the text".into(),
    }
}
