//! Every key binding, in one table: it drives the keys, the help screen and
//! the hints in the status bar, so they cannot drift apart.

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Everything a person can ask the explorer to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    Up,
    Down,
    Collapse,
    Expand,
    Toggle,
    NextPane,
    StepForward,
    StepBack,
    TickForward,
    TickBack,
    Start,
    End,
    NextFailure,
    PrevFailure,
    NextChange,
    PrevChange,
    Ask,
    Find,
    ToggleFramed,
    Help,
    Play,
    Faster,
    Slower,
    Quit,
    /// Close an overlay or clear an answer.
    Back,
}

/// One binding: the keys, the action, what the help says, and a short hint
/// for the status bar (empty: not shown there).
pub struct Binding {
    pub keys: &'static [&'static str],
    pub action: Action,
    pub help: &'static str,
    pub hint: &'static str,
}

pub const KEYMAP: &[Binding] = &[
    Binding {
        keys: &["Up", "k"],
        action: Action::Up,
        help: "select the node above",
        hint: "",
    },
    Binding {
        keys: &["Down", "j"],
        action: Action::Down,
        help: "select the node below",
        hint: "",
    },
    Binding {
        keys: &["Left", "h"],
        action: Action::Collapse,
        help: "collapse, or go to the parent",
        hint: "",
    },
    Binding {
        keys: &["Right", "l"],
        action: Action::Expand,
        help: "expand, or go to the first child",
        hint: "",
    },
    Binding {
        keys: &["Enter", "Space"],
        action: Action::Toggle,
        help: "expand or collapse; in a list, choose",
        hint: "",
    },
    Binding {
        keys: &["Tab"],
        action: Action::NextPane,
        help: "next pane",
        hint: "",
    },
    Binding {
        keys: &["n"],
        action: Action::StepForward,
        help: "next transition",
        hint: "step",
    },
    Binding {
        keys: &["p"],
        action: Action::StepBack,
        help: "previous transition",
        hint: "",
    },
    Binding {
        keys: &["N"],
        action: Action::TickForward,
        help: "next tick",
        hint: "tick",
    },
    Binding {
        keys: &["P"],
        action: Action::TickBack,
        help: "previous tick",
        hint: "",
    },
    Binding {
        keys: &["g", "Home"],
        action: Action::Start,
        help: "start of the run",
        hint: "",
    },
    Binding {
        keys: &["G", "End"],
        action: Action::End,
        help: "end of the run",
        hint: "",
    },
    Binding {
        keys: &["f"],
        action: Action::NextFailure,
        help: "end of the next tick where a leaf failed",
        hint: "failure",
    },
    Binding {
        keys: &["F"],
        action: Action::PrevFailure,
        help: "end of the previous tick where a leaf failed",
        hint: "",
    },
    Binding {
        keys: &["c"],
        action: Action::NextChange,
        help: "next change of the selected node",
        hint: "",
    },
    Binding {
        keys: &["C"],
        action: Action::PrevChange,
        help: "previous change of the selected node",
        hint: "",
    },
    Binding {
        keys: &["a"],
        action: Action::Ask,
        help: "ask about the selected node",
        hint: "ask",
    },
    Binding {
        keys: &["/"],
        action: Action::Find,
        help: "find a node",
        hint: "find",
    },
    Binding {
        keys: &["t"],
        action: Action::ToggleFramed,
        help: "full or framed tree",
        hint: "framed",
    },
    Binding {
        keys: &["s"],
        action: Action::Play,
        help: "play or pause the run",
        hint: "play",
    },
    Binding {
        keys: &["+"],
        action: Action::Faster,
        help: "play faster",
        hint: "",
    },
    Binding {
        keys: &["-"],
        action: Action::Slower,
        help: "play slower",
        hint: "",
    },
    Binding {
        keys: &["?"],
        action: Action::Help,
        help: "this help",
        hint: "help",
    },
    Binding {
        keys: &["Esc"],
        action: Action::Back,
        help: "close a window, clear the answer",
        hint: "",
    },
    Binding {
        keys: &["q", "Ctrl-c"],
        action: Action::Quit,
        help: "quit",
        hint: "quit",
    },
];

/// The name of a key press as the table writes it.
pub fn key_name(k: &KeyEvent) -> Option<String> {
    let ctrl = k.modifiers.contains(KeyModifiers::CONTROL);
    let base = match k.code {
        KeyCode::Up => "Up".to_string(),
        KeyCode::Down => "Down".to_string(),
        KeyCode::Left => "Left".to_string(),
        KeyCode::Right => "Right".to_string(),
        KeyCode::Enter => "Enter".to_string(),
        KeyCode::Tab => "Tab".to_string(),
        KeyCode::Esc => "Esc".to_string(),
        KeyCode::Home => "Home".to_string(),
        KeyCode::End => "End".to_string(),
        KeyCode::Backspace => "Backspace".to_string(),
        KeyCode::Char(' ') => "Space".to_string(),
        KeyCode::Char(c) => c.to_string(),
        _ => return None,
    };
    Some(if ctrl { format!("Ctrl-{base}") } else { base })
}

/// The action bound to a key press.
pub fn action_for(k: &KeyEvent) -> Option<Action> {
    let name = key_name(k)?;
    KEYMAP
        .iter()
        .find(|b| b.keys.contains(&name.as_str()))
        .map(|b| b.action)
}

/// The status bar's hints: `n step  N tick  f failure ...`.
pub fn hints() -> String {
    KEYMAP
        .iter()
        .filter(|b| !b.hint.is_empty())
        .map(|b| format!("{} {}", b.keys[0], b.hint))
        .collect::<Vec<_>>()
        .join("  ")
}
