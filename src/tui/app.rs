//! The explorer: it routes each key to the window open or to the panes,
//! and holds what they share. The components are in `tui::panes`; what
//! they share, and the questions it asks the library, in `tui::shared`.

use super::choices::Choices;
use super::keymap::Action;
use super::panes::answers::Answers;
use super::panes::details::Details;
use super::panes::overlays::Overlay;
use super::panes::timeline::{self, Timeline};
use super::panes::tree::TreePane;
use super::panes::{Component, Handled, Hints, KeyHelp};
use super::shared::Shared;
use super::text_input::Edit;
use super::view::{fit, layout};
use crate::model::Tree;
use crate::session::Session;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::Span;
use ratatui::widgets::Paragraph;
use ratatui::Frame;

/// The pane that has the focus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pane {
    Tree,
    Timeline,
    Details,
    Ask,
}

/// The four panes, each its own component.
#[derive(Default)]
pub struct Panes {
    pub tree: TreePane,
    pub timeline: Timeline,
    pub details: Details,
    pub answers: Answers,
}

impl Panes {
    fn get(&self, p: Pane) -> &dyn Component {
        match p {
            Pane::Tree => &self.tree,
            Pane::Timeline => &self.timeline,
            Pane::Details => &self.details,
            Pane::Ask => &self.answers,
        }
    }

    /// The help: the explorer's own keys, then each pane's.
    pub fn help(&self) -> Vec<KeyHelp> {
        let mut parts = vec![OWN_KEYS];
        parts.extend(
            [Pane::Tree, Pane::Timeline, Pane::Ask, Pane::Details].map(|p| self.get(p).help()),
        );
        parts
    }

    fn get_mut(&mut self, p: Pane) -> &mut dyn Component {
        match p {
            Pane::Tree => &mut self.tree,
            Pane::Timeline => &mut self.timeline,
            Pane::Details => &mut self.details,
            Pane::Ask => &mut self.answers,
        }
    }
}

/// The keys the app takes itself ([`App::own_key`]), for the help.
pub const OWN_KEYS: KeyHelp = KeyHelp {
    name: "the explorer",
    anywhere: &[
        (Action::Help, ""),
        (Action::Quit, ""),
        (Action::NextPane, ""),
        (Action::Zoom, ""),
        (Action::Wider, ""),
        (Action::Narrower, ""),
        (Action::Find, ""),
        (Action::Pick, ""),
        (Action::NextDivergence, ""),
        (Action::PrevDivergence, ""),
    ],
    focused: &[],
};

pub struct App {
    /// The run, the moment, the selection and the conversation.
    pub shared: Shared,
    pub panes: Panes,
    /// The window open over the panes, which takes every key.
    pub overlay: Option<Overlay>,
    pub focus: Pane,
    /// The focused pane fills the screen.
    pub zoom: bool,
    /// The tree pane's share of the width, in percent.
    pub split: u16,
    pub quit: bool,
    /// Why the explorer stopped, where the run it read whole was broken.
    pub failed: Option<crate::source::Located>,
}

impl App {
    pub fn new(tree: Tree, session: Option<Session>, title: String) -> App {
        App {
            shared: Shared::new(tree, session, title),
            panes: Panes::default(),
            overlay: None,
            focus: Pane::Tree,
            zoom: false,
            split: 58,
            quit: false,
            failed: None,
        }
    }

    /// Routes an action: to the window if one is open; else to the focused
    /// pane, then to every pane for the keys that act wherever the focus
    /// is (the tree's selection, the timeline's time, the answers'
    /// questions), and last to the explorer's own keys.
    pub fn update(&mut self, a: Action) {
        if self.shared.reading.is_some() && !a.moves_only() {
            // An answer, a search or a list is about the whole run.
            self.read_whole();
            if self.quit {
                return;
            }
        }
        if let Some(o) = &mut self.overlay {
            let h = o.key(a, &mut self.shared, true);
            return self.apply(h);
        }
        let sh = &mut self.shared;
        // On a live robot, End (G) is "back to live" from any pane, not a
        // scroll of the pane that has the focus (#27 item 2).
        if a == Action::End && sh.live.is_some() && sh.session.is_some() {
            sh.goto(sh.positions());
            sh.follow_node = true;
            sh.follow_current();
            return;
        }
        sh.message = None;
        if sh.session.is_none() && timeline::needs_run(a) {
            sh.message = Some(
                "this is a tree, not a run: open a session or a robot's log to step through one"
                    .into(),
            );
            return;
        }
        let order = [Pane::Tree, Pane::Timeline, Pane::Ask, Pane::Details];
        let focused =
            std::iter::once(self.focus).chain(order.into_iter().filter(|&p| p != self.focus));
        for p in focused {
            let h = self
                .panes
                .get_mut(p)
                .key(a, &mut self.shared, p == self.focus);
            if h != Handled::Ignored {
                return self.apply(h);
            }
        }
        self.own_key(a);
    }

    /// The explorer's own keys: quitting, the focus, the finder, the help,
    /// the layout and the picker.
    fn own_key(&mut self, a: Action) {
        match a {
            Action::Quit => self.quit = true,
            Action::NextPane => {
                self.focus = match self.focus {
                    Pane::Tree => Pane::Timeline,
                    Pane::Timeline => Pane::Details,
                    Pane::Details => Pane::Ask,
                    Pane::Ask => Pane::Tree,
                }
            }
            Action::Find => self.overlay = Some(Overlay::finder()),
            Action::Help => self.overlay = Some(Overlay::help(self.panes.help())),
            Action::NextDivergence | Action::PrevDivergence => {
                self.shared.message = Some("divergences are shown by btx open --diff A B".into())
            }
            Action::Zoom => self.zoom = !self.zoom,
            Action::Pick => self.open_picker(),
            Action::Wider => self.split = (self.split + 5).min(85),
            Action::Narrower => self.split = self.split.saturating_sub(5).max(25),
            _ => {}
        }
    }

    /// Does what a component asked for.
    fn apply(&mut self, h: Handled) {
        match h {
            Handled::Ignored | Handled::Taken => {}
            Handled::Open(o) => self.overlay = Some(o),
            Handled::Close => self.overlay = None,
            Handled::Filter(text) => {
                self.overlay = None;
                self.panes.timeline.set_filter(text, &self.shared);
            }
            Handled::Pick(i) => {
                self.overlay = None;
                self.pick(i);
            }
        }
    }

    /// The mouse wheel over a pane: the tree moves its selection, the
    /// others scroll, whichever pane has the focus.
    pub fn wheel(&mut self, pane: Pane, down: bool) {
        let a = if down { Action::Down } else { Action::Up };
        if self.overlay.is_some() {
            return self.update(a);
        }
        let sh = &self.shared;
        match pane {
            Pane::Tree => self.update(a),
            Pane::Timeline => {
                self.panes.timeline.scroll(a, sh);
            }
            Pane::Details => {
                self.panes.details.scroll(a, sh);
            }
            Pane::Ask => {
                self.panes.answers.scroll(a, sh);
            }
        }
    }

    /// Typing into the finder or a prompt.
    pub fn type_char(&mut self, c: char) {
        self.edit(Edit::Insert(c.to_string()));
    }

    pub fn backspace(&mut self) {
        self.edit(Edit::Backspace);
    }

    /// One edit of the open prompt's text, every prompt alike.
    pub fn edit(&mut self, e: Edit) {
        let Some(edited) = self.overlay.as_mut().and_then(|o| o.edit(e)) else {
            return;
        };
        if let Some(n) = edited.cut {
            self.shared.message = Some(format!(
                "a question or a search is at most {} characters: the {n} past them were left out",
                super::text_input::PROMPT_MAX
            ));
        }
    }

    /// The text of the prompt being typed, if one is.
    pub fn prompt_text(&self) -> Option<&str> {
        Some(self.overlay.as_ref()?.input()?.text.as_str())
    }

    /// Whether keys type text: the finder and every prompt (a letter there
    /// is text, not a key's action).
    pub fn typing(&self) -> bool {
        self.overlay.as_ref().is_some_and(|o| o.input().is_some())
    }

    /// `R`: the picker, when there is more than one run to pick from.
    fn open_picker(&mut self) {
        match &self.shared.choices {
            Some(c) if c.len() > 1 => self.overlay = Some(Overlay::pick(c.current())),
            _ => {
                self.shared.message = Some(
                    "one run here: R picks among a rosbag's runs (goals) or the robots of btx open --live A B"
                        .into(),
                )
            }
        }
    }

    /// Shows choice `i`: its run in a fresh view, the keys, the layout and
    /// the other choices kept.
    pub(crate) fn pick(&mut self, i: usize) {
        let sh = &mut self.shared;
        let Some(mut choices) = sh.choices.take() else {
            return;
        };
        let stay = i == choices.current() || i >= choices.len();
        let shown = match &mut choices {
            _ if stay => Err(None),
            Choices::Runs { runs, current } => {
                runs[*current].session = sh.session.take();
                *current = i;
                let s = runs[i].session.take().expect("a run not shown is kept");
                Ok((s.tree.clone(), s, runs[i].title.clone(), None))
            }
            Choices::Robots { robots, current } => match robots[i].feed.take() {
                None => Err(Some(format!(
                    "{} could not be reached when the explorer opened",
                    robots[i].endpoint
                ))),
                Some(feed) => match feed.session() {
                    Ok(s) => {
                        robots[*current].feed = sh.live.take();
                        *current = i;
                        let title = format!("live {}", robots[i].endpoint);
                        Ok((s.tree.clone(), s, title, Some(feed)))
                    }
                    Err(e) => {
                        let m = e.to_string();
                        robots[i].feed = Some(feed);
                        Err(Some(m))
                    }
                },
            },
        };
        match shown {
            Ok((tree, session, title, feed)) => {
                let mut next = App::new(tree, Some(session), title);
                next.shared.keymap = std::mem::take(&mut sh.keymap);
                next.split = self.split;
                next.shared.live = feed.or_else(|| sh.live.take());
                next.shared.choices = Some(choices);
                if next.shared.live.is_some() {
                    // A robot is followed at its present.
                    next.update(Action::End);
                }
                *self = next;
            }
            Err(message) => {
                sh.choices = Some(choices);
                sh.message = message;
            }
        }
    }

    /// Reads a followed log again: the timeline grows; the moment stays
    /// where the person put it, or keeps to the end if it was there.
    pub fn follow_poll(&mut self) {
        let sh = &mut self.shared;
        if let Some(c) = sh.choices.as_mut() {
            c.poll();
        }
        if let Some(l) = &sh.live {
            // The robot's blackboard is fetched only while details shows it.
            let shown = !self.zoom || self.focus == Pane::Details;
            l.want_blackboard(
                shown.then(|| sh.tree.blackboard_name(sh.tree.node(sh.selected).scope)),
            );
        }
        match sh.live.as_mut().and_then(|l| l.news(super::LIVE_EVERY)) {
            Some(Ok(s)) => self.grow(s),
            Some(Err(e)) => sh.message = Some(e.to_string()),
            None => {}
        }
        let Some(f) = self.shared.follow.as_mut() else {
            return;
        };
        match f.poll() {
            Ok(None) => {}
            Ok(Some(s)) => self.grow(s),
            // A log caught mid-write reads again at the next poll.
            Err(e) => self.shared.message = Some(format!("following: {e}")),
        }
    }

    /// Waits for the log read whole, and takes it in place of its first part.
    pub fn read_whole(&mut self) {
        if let Some(r) = self.shared.reading.take() {
            self.took(r.wait());
        }
    }

    /// Takes the log read whole if it is read within `wait`: whether it came.
    pub fn take_read(&mut self, wait: std::time::Duration) -> bool {
        let Some(run) = self.shared.reading.as_ref().and_then(|r| r.take(wait)) else {
            return false;
        };
        self.shared.reading = None;
        self.took(run);
        true
    }

    /// The whole run in place of its first part; a log broken further on
    /// stops the explorer with the error, as `btx open` gives it for a
    /// log broken at its start.
    fn took(&mut self, run: Result<Session, crate::source::Located>) {
        match run {
            Ok(s) => self.grow(s),
            Err(e) => {
                self.failed = Some(e);
                self.quit = true;
            }
        }
    }

    /// Takes a newer reading of the same run; the faults list, open on a
    /// live run, grows with it.
    pub fn grow(&mut self, s: Session) {
        if self.shared.grow(s) {
            if let Some(Overlay::Faults(f)) = &mut self.overlay {
                f.renew(self.shared.fault_lines());
            }
        }
    }

    pub fn play_step(&mut self) {
        self.shared.play_step()
    }

    /// A mouse click on tree row `row` (counted from the pane's first row).
    pub fn click_row(&mut self, row: usize, first: usize) {
        self.shared.click_row(row, first)
    }

    /// Draws the whole screen: the panes (the focused one alone when
    /// zoomed), the status bar, and the window open over them.
    pub fn draw(&self, f: &mut Frame) {
        let sh = &self.shared;
        let a = layout(f.area(), self.split);
        if self.zoom {
            let whole = Rect {
                height: f.area().height.saturating_sub(1),
                ..f.area()
            };
            self.panes.get(self.focus).draw(sh, f, whole, true);
        } else {
            for (p, area) in [
                (Pane::Tree, a.tree),
                (Pane::Details, a.details),
                (Pane::Ask, a.ask),
                (Pane::Timeline, a.timeline),
            ] {
                self.panes.get(p).draw(sh, f, area, p == self.focus);
            }
        }
        let cols = a.status.width as usize;
        // The keys of the window open, not the panes' under it.
        let hints = match &self.overlay {
            Some(o) => o.hints(sh),
            None => self.panes.get(self.focus).hints(sh),
        };
        let status = match (&sh.message, hints) {
            (Some(m), _) => Span::styled(fit(m, cols), Style::default().fg(Color::Yellow)),
            (None, Hints::Text(keys)) => {
                Span::styled(fit(keys, cols), Style::default().fg(Color::DarkGray))
            }
            (None, Hints::Keys(first)) => Span::styled(
                sh.keymap.hints_within(first, cols),
                Style::default().fg(Color::DarkGray),
            ),
        };
        f.render_widget(Paragraph::new(status), a.status);
        if let Some(o) = &self.overlay {
            o.draw(sh, f, f.area(), true);
        }
    }
}
