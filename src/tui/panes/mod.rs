//! The explorer's components, as gitui has them: each owns its state,
//! takes a key and says whether it used it, names its keys for the status
//! bar, and draws from the shared state it is given, read-only. The app
//! routes keys to them and holds what they share ([`Shared`]); no
//! component knows the app.
//!
//! - `tree`: the tree (full or framed), the selection and folding;
//! - `timeline`: time (stepping, ticks, failures, playing) and the list of
//!   transitions with its filters;
//! - `details`: the selected node's ports and state, or the causal graph;
//! - `answers`: questions, why-answers and their history;
//! - `overlays`: the windows over the panes (the help, the finder, the
//!   pick lists and the prompts), one component each.

pub mod answers;
pub mod details;
pub mod overlays;
pub mod timeline;
pub mod tree;

use crate::tui::keymap::{Action, Keymap};
use crate::tui::shared::Shared;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::Frame;

/// Rows or lines a page key moves.
pub const PAGE: usize = 10;

/// What a component did with a key.
#[derive(Debug, PartialEq, Eq)]
pub enum Handled {
    /// Not its key: the next component may take it.
    Ignored,
    Taken,
    /// Taken, and this window is to open (over the panes, or in place of
    /// the window that took the key).
    Open(overlays::Overlay),
    /// Taken, and the window that took it is to close.
    Close,
    /// The timeline's filter prompt was answered: show only the
    /// transitions of nodes named so.
    Filter(String),
    /// Choice `i` of the runs or robots was picked.
    Pick(usize),
}

impl Handled {
    pub fn taken(taken: bool) -> Handled {
        if taken {
            Handled::Taken
        } else {
            Handled::Ignored
        }
    }
}

/// The keys a component names in the status bar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Hints {
    /// Its own actions first, then the explorer's, as far as they fit.
    Keys(&'static [(Action, &'static str)]),
    /// A window's keys, said whole (the panes' are not for it).
    Text(&'static str),
}

/// The keys a component names in the help: its heading, the actions it
/// takes wherever the focus is, and those it takes only when it has the
/// focus. Each action is said in the component's own words, or, where
/// they are empty, as the keymap says it (so a keymap file's `saying`
/// shows). `tests/components.rs` holds each list to the keys the
/// component really takes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KeyHelp {
    pub name: &'static str,
    pub anywhere: &'static [(Action, &'static str)],
    pub focused: &'static [(Action, &'static str)],
}

/// The help of a screen, built from its components' [`KeyHelp`]: the keys
/// that act wherever the focus is first, then each pane's own.
pub fn help_lines(keymap: &Keymap, parts: &[KeyHelp]) -> Vec<Line<'static>> {
    let heading = |s: String| {
        Line::from(Span::styled(
            s,
            Style::default().add_modifier(Modifier::BOLD),
        ))
    };
    let key_lines = |keys: &[(Action, &'static str)]| -> Vec<Line<'static>> {
        keys.iter()
            .filter_map(|&(a, own)| {
                let b = keymap.keys.iter().find(|b| b.1 == a && !b.0.is_empty())?;
                let words = if own.is_empty() { b.2 } else { own };
                Some(Line::from(vec![
                    Span::styled(
                        format!("  {:<16}", b.0.join(" ")),
                        Style::default().fg(Color::Yellow),
                    ),
                    Span::raw(words),
                ]))
            })
            .collect()
    };
    let mut lines = Vec::new();
    for p in parts.iter().filter(|p| !p.anywhere.is_empty()) {
        lines.push(heading(p.name.to_string()));
        lines.extend(key_lines(p.anywhere));
    }
    for p in parts.iter().filter(|p| !p.focused.is_empty()) {
        lines.push(heading(format!("{}, when it has the focus", p.name)));
        lines.extend(key_lines(p.focused));
    }
    lines
}

/// A help window: `lines` wrapped in a box `width` wide, centred, scrolled
/// by `scroll`, with a mark while more follows.
pub fn help_window(
    f: &mut Frame,
    area: Rect,
    width: u16,
    title: &str,
    lines: Vec<Line<'static>>,
    scroll: &Lines,
) {
    let r = crate::tui::view::centered(area, width, lines.len() as u16 + 2);
    let p = scroll.paragraph(lines, 0, r);
    let more = if scroll.more(0) { " ↓ more " } else { "" };
    f.render_widget(ratatui::widgets::Clear, r);
    f.render_widget(
        p.block(
            ratatui::widgets::Block::default()
                .borders(ratatui::widgets::Borders::ALL)
                .title(title.to_string())
                .title_bottom(more),
        ),
        r,
    );
}

/// A pane or a window of a screen: of the explorer, over what its panes
/// share ([`Shared`]), or of another screen over what that one's share
/// (the fleet view's `FleetShared`).
pub trait Component<S = Shared> {
    /// A key. `focused`: whether this pane has the focus (a pane's own
    /// keys, such as scrolling, act only then; the others wherever the
    /// focus is).
    fn key(&mut self, a: Action, sh: &mut S, focused: bool) -> Handled;
    /// The keys it names in the status bar.
    fn hints(&self, sh: &S) -> Hints;
    /// The keys it names in the help (a window says its keys in the status
    /// bar only: none).
    fn help(&self) -> KeyHelp {
        KeyHelp::default()
    }
    /// Draws it in `area`.
    fn draw(&self, sh: &S, f: &mut Frame, area: Rect, focused: bool);
}

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

/// A pane of wrapped lines, scrolled for one thing on screen (its
/// `epoch`), stopping where its last page shows.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Lines {
    scroll: Scrolled<usize>,
    /// How far it could scroll when last drawn (its wrapped height less the
    /// pane's).
    max: std::cell::Cell<usize>,
}

impl Lines {
    /// Up, Down, a page, Home and End.
    pub fn key(&mut self, a: Action, epoch: u64) -> bool {
        let max = self.max.get();
        scroll_lines(self.scroll.get_mut(epoch), a, max)
    }

    /// How far it is scrolled.
    pub fn get(&self, epoch: u64) -> usize {
        self.scroll.get(epoch)
    }

    /// Whether lines below the pane are hidden, as last drawn.
    pub fn more(&self, epoch: u64) -> bool {
        self.get(epoch) < self.max.get()
    }

    /// `lines` wrapped and scrolled in `area`, noting how far they can
    /// scroll.
    pub fn paragraph(
        &self,
        lines: Vec<ratatui::text::Line<'static>>,
        epoch: u64,
        area: Rect,
    ) -> ratatui::widgets::Paragraph<'static> {
        let (p, last) = crate::tui::view::scrolled(lines, self.get(epoch), area);
        self.max.set(last);
        p
    }
}

/// How far a pane is scrolled, for one thing on screen: when the thing
/// changes (a new moment, a new answer: its `epoch`), the pane is back at
/// its top.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Scrolled<T> {
    by: T,
    epoch: u64,
}

impl<T: Copy + Default> Scrolled<T> {
    /// How far it is scrolled for the thing of `epoch`.
    pub fn get(&self, epoch: u64) -> T {
        if self.epoch == epoch {
            self.by
        } else {
            T::default()
        }
    }

    /// The scroll for the thing of `epoch`, to change.
    pub fn get_mut(&mut self, epoch: u64) -> &mut T {
        if self.epoch != epoch {
            *self = Scrolled {
                by: T::default(),
                epoch,
            };
        }
        &mut self.by
    }
}
