//! The explorer's components, as gitui has them: each owns its state, its
//! keys and its drawing. `App::update` only routes an action to them, and
//! `view` draws each from the state with a pure function.
//!
//! - `tree`: the tree (full or framed), the selection and folding;
//! - `timeline`: time (stepping, ticks, failures, playing) and the list of
//!   transitions with its filters;
//! - `details`: the selected node's ports and state, or the causal graph;
//! - `answers`: questions, why-answers and their history;
//! - `overlays`: the help, the finder, the question lists and the prompts.

pub mod answers;
pub mod details;
pub mod overlays;
pub mod timeline;
pub mod tree;

use crate::tui::app::PAGE;
use crate::tui::keymap::Action;

/// Up, Down, a page, Home and End over the lines of a pane scrolled by
/// `pos`, at most `max` (how far it could scroll when last drawn).
pub fn scroll_lines(pos: &mut usize, a: Action, max: usize) -> bool {
    *pos = match a {
        Action::Start => 0,
        Action::End => max,
        Action::Up => pos.saturating_sub(1),
        Action::PageUp => pos.saturating_sub(PAGE),
        Action::Down => (*pos + 1).min(max),
        Action::PageDown => (*pos + PAGE).min(max),
        _ => return false,
    };
    true
}
