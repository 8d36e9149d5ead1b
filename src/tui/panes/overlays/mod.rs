//! The windows over the panes, one component each: the help, the finder,
//! the pick lists (why-questions, running nodes, faults, runs and robots)
//! and the prompts (your own words, "Can you …?", the transition filter,
//! the export path). A window open takes every key.

mod finder;
mod help;
mod lists;
mod prompts;

pub use finder::Finder;
pub use help::Help;
pub use lists::{Faults, Pick, Running, WhyList};
pub use prompts::{CanYou, Export, Filter, Words, CAN_YOU_ROW};

use super::{Component, Handled, Hints};
use crate::model::Uid;
use crate::tui::keymap::Action;
use crate::tui::pick_list::PickList;
use crate::tui::shared::Shared;
use crate::tui::text_input::{Edit, Edited, TextInput};
use ratatui::layout::Rect;
use ratatui::Frame;

/// `$e` of the window's component `$c`, whichever window it is.
macro_rules! each_window {
    ($w:expr, $c:ident => $e:expr) => {
        match $w {
            Overlay::Help($c) => $e,
            Overlay::Finder($c) => $e,
            Overlay::Why($c) => $e,
            Overlay::Running($c) => $e,
            Overlay::Faults($c) => $e,
            Overlay::Pick($c) => $e,
            Overlay::Words($c) => $e,
            Overlay::CanYou($c) => $e,
            Overlay::Filter($c) => $e,
            Overlay::Export($c) => $e,
        }
    };
}

/// A window over the panes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Overlay {
    Help(Help),
    Finder(Finder),
    Why(WhyList),
    Running(Running),
    Faults(Faults),
    Pick(Pick),
    Words(Words),
    CanYou(CanYou),
    Filter(Filter),
    Export(Export),
}

impl Overlay {
    /// The help, of the components `parts` name.
    pub fn help(parts: Vec<super::KeyHelp>) -> Overlay {
        Overlay::Help(Help {
            scroll: Default::default(),
            parts,
        })
    }

    pub fn finder() -> Overlay {
        Overlay::Finder(Finder::default())
    }

    /// The why-questions about the selected node: (target, question).
    pub fn why(targets: Vec<(String, String)>) -> Overlay {
        Overlay::Why(WhyList {
            list: PickList::default(),
            targets,
        })
    }

    pub fn running() -> Overlay {
        Overlay::Running(Running::default())
    }

    /// The faults, newest first, each with the position to go to and the
    /// node to select there.
    pub fn faults(lines: Vec<(String, u32, Uid)>) -> Overlay {
        Overlay::Faults(Faults {
            list: PickList::default(),
            lines,
        })
    }

    /// The runs or robots, the one shown selected.
    pub fn pick(current: usize) -> Overlay {
        Overlay::Pick(Pick {
            list: PickList::at(current),
        })
    }

    /// The ask prompt, empty.
    pub fn words() -> Overlay {
        Overlay::Words(Words::default())
    }

    pub fn can_you() -> Overlay {
        Overlay::CanYou(CanYou::default())
    }

    /// The timeline's filter prompt, with the filter in force.
    pub fn filter(text: &str) -> Overlay {
        Overlay::Filter(Filter {
            input: TextInput::new(text),
        })
    }

    /// Where to write the causal model, `path` proposed.
    pub fn export(path: String) -> Overlay {
        Overlay::Export(Export {
            input: TextInput::new(path),
            replace: false,
        })
    }

    fn component(&self) -> &dyn Component {
        each_window!(self, c => c)
    }

    fn component_mut(&mut self) -> &mut dyn Component {
        each_window!(self, c => c)
    }

    /// The text being typed, in a window that takes text (a letter there
    /// is text, not a key's action).
    pub fn input(&self) -> Option<&TextInput> {
        match self {
            Overlay::Finder(c) => Some(&c.input),
            Overlay::Words(c) => Some(&c.input),
            Overlay::CanYou(c) => Some(&c.input),
            Overlay::Filter(c) => Some(&c.input),
            Overlay::Export(c) => Some(&c.input),
            _ => None,
        }
    }

    /// One edit of the text typed; a change starts the window's list again
    /// from its top (and an export asks again before replacing a file).
    pub fn edit(&mut self, e: Edit) -> Option<Edited> {
        let (input, list) = match self {
            Overlay::Finder(c) => (&mut c.input, Some(&mut c.list)),
            Overlay::CanYou(c) => (&mut c.input, Some(&mut c.list)),
            Overlay::Words(c) => {
                let edited = c.input.edit(e);
                if edited.changed {
                    c.list.selected = 0;
                    c.picked = false;
                }
                return Some(edited);
            }
            Overlay::Filter(c) => (&mut c.input, None),
            Overlay::Export(c) => {
                let edited = c.input.edit(e);
                c.replace &= !edited.changed;
                return Some(edited);
            }
            _ => return None,
        };
        let edited = input.edit(e);
        if let (true, Some(l)) = (edited.changed, list) {
            l.selected = 0;
        }
        Some(edited)
    }
}

impl Component for Overlay {
    fn key(&mut self, a: Action, sh: &mut Shared, focused: bool) -> Handled {
        self.component_mut().key(a, sh, focused)
    }

    fn hints(&self, sh: &Shared) -> Hints {
        self.component().hints(sh)
    }

    fn draw(&self, sh: &Shared, f: &mut Frame, area: Rect, focused: bool) {
        self.component().draw(sh, f, area, focused)
    }
}

/// A pick list's keys: Enter hands the row chosen to `chosen`.
fn list_key(
    list: &mut PickList,
    a: Action,
    len: usize,
    chosen: impl FnOnce(usize) -> Handled,
) -> Handled {
    use crate::tui::pick_list::Picked;
    match list.key(a, len) {
        Picked::Moved | Picked::Ignored => Handled::Taken,
        Picked::Closed => Handled::Close,
        Picked::Chosen(i) => chosen(i),
    }
}
