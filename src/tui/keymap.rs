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
    /// A question typed in the user's own words.
    AskWords,
    /// A why-question (counterfactual) about the selected node.
    Why,
    /// Show the why-answer's causal model in the details pane.
    Graph,
    /// Write the why-answer's causal model as a DOT file.
    ExportGraph,
    Find,
    /// Whether stepping selects the current node.
    Follow,
    ToggleFramed,
    Help,
    Play,
    Faster,
    Slower,
    Quit,
    /// Close an overlay or clear an answer.
    Back,
    /// In the side-by-side diff: the next or previous divergence.
    NextDivergence,
    PrevDivergence,
    /// Give the tree pane more or less of the width.
    Wider,
    Narrower,
    /// A page up or down in the focused pane.
    PageUp,
    PageDown,
    /// The focused pane on the whole screen, or back.
    Zoom,
    /// The transition list's filters: resets, the selected subtree, a status.
    HideResets,
    OnlyBelow,
    OnlyStatus,
    /// Pick from the nodes RUNNING at this moment.
    Running,
    /// The run's faults as they happened, each with its handling.
    Faults,
    /// Copy the answer on screen to the clipboard (OSC 52).
    Copy,
    /// Pick another run of the log, or another robot watched.
    Pick,
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
        help: "end of the next tick with a fault",
        hint: "failure",
    },
    Binding {
        keys: &["F"],
        action: Action::PrevFailure,
        help: "end of the previous tick with a fault",
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
        help: "ask: the questions about the node, or type your own",
        hint: "ask",
    },
    Binding {
        keys: &["A"],
        action: Action::AskWords,
        help: "ask (the same prompt as a)",
        hint: "",
    },
    Binding {
        keys: &["w"],
        action: Action::Why,
        help: "why? about the node (Enter on a reason: why that?)",
        hint: "why",
    },
    Binding {
        keys: &["m"],
        action: Action::Graph,
        help: "show or hide the causal model of the why-answer",
        hint: "",
    },
    Binding {
        keys: &["x"],
        action: Action::ExportGraph,
        help: "write the why-answer's causal model as DOT",
        hint: "",
    },
    Binding {
        keys: &["PageUp", "Ctrl-u"],
        action: Action::PageUp,
        help: "a page up in the focused pane",
        hint: "",
    },
    Binding {
        keys: &["PageDown", "Ctrl-d"],
        action: Action::PageDown,
        help: "a page down in the focused pane",
        hint: "",
    },
    Binding {
        keys: &["i"],
        action: Action::HideResets,
        help: "transitions: hide or show resets (→ IDLE)",
        hint: "",
    },
    Binding {
        keys: &["."],
        action: Action::OnlyBelow,
        help: "transitions: only the selected node and below, or all",
        hint: "",
    },
    Binding {
        keys: &["S"],
        action: Action::OnlyStatus,
        help: "transitions: only to RUNNING, SUCCESS, FAILURE, or all",
        hint: "",
    },
    Binding {
        keys: &["r"],
        action: Action::Running,
        help: "pick from the nodes RUNNING at this moment",
        hint: "",
    },
    Binding {
        keys: &["e"],
        action: Action::Faults,
        help: "the run's faults as they happened: Enter goes to one",
        hint: "",
    },
    Binding {
        keys: &["R"],
        action: Action::Pick,
        help: "another run of a rosbag, or another robot watched",
        hint: "",
    },
    Binding {
        keys: &["y"],
        action: Action::Copy,
        help: "copy the answer to the clipboard (OSC 52: also over SSH)",
        hint: "",
    },
    Binding {
        keys: &["z"],
        action: Action::Zoom,
        help: "the focused pane on the whole screen, or back",
        hint: "",
    },
    Binding {
        keys: &["o"],
        action: Action::Follow,
        help: "follow the current node while stepping (on/off)",
        hint: "",
    },
    Binding {
        keys: &["/"],
        action: Action::Find,
        help: "find a node (timeline focused: filter it by name)",
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
        keys: &[">"],
        action: Action::Wider,
        help: "widen the tree pane",
        hint: "",
    },
    Binding {
        keys: &["<"],
        action: Action::Narrower,
        help: "narrow the tree pane",
        hint: "",
    },
    Binding {
        keys: &["d"],
        action: Action::NextDivergence,
        help: "side-by-side diff: next divergence",
        hint: "",
    },
    Binding {
        keys: &["D"],
        action: Action::PrevDivergence,
        help: "side-by-side diff: previous divergence",
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
/// The keys with names, as `key_name` writes them.
const NAMED_KEYS: &[&str] = &[
    "Up",
    "Down",
    "Left",
    "Right",
    "Enter",
    "Tab",
    "Esc",
    "Home",
    "End",
    "Backspace",
    "Space",
];

/// Whether `key_name` can ever give this name.
fn is_key(k: &str) -> bool {
    let base = k.strip_prefix("Ctrl-").unwrap_or(k);
    NAMED_KEYS.contains(&base) || (base.chars().count() == 1 && base != " ")
}

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
        KeyCode::PageUp => "PageUp".to_string(),
        KeyCode::PageDown => "PageDown".to_string(),
        KeyCode::Char(' ') => "Space".to_string(),
        KeyCode::Char(c) => c.to_string(),
        _ => return None,
    };
    Some(if ctrl { format!("Ctrl-{base}") } else { base })
}

impl Action {
    /// Whether the action only moves through what is on screen (the tree,
    /// the moment, the panes), so that it means the same on the first part
    /// of a log as on the whole; an answer, a search, a list or the next
    /// failure is about the whole run.
    pub fn moves_only(self) -> bool {
        use Action::*;
        matches!(
            self,
            Up | Down
                | Collapse
                | Expand
                | Toggle
                | NextPane
                | StepForward
                | StepBack
                | TickForward
                | TickBack
                | Start
                | End
                | PageUp
                | PageDown
                | Wider
                | Narrower
                | Zoom
                | Help
                | Quit
                | Back
                | Follow
                | ToggleFramed
        )
    }

    /// What the help says the action does.
    pub fn help(self) -> &'static str {
        KEYMAP
            .iter()
            .find(|b| b.action == self)
            .map_or("", |b| b.help)
    }

    /// The name a keymap file uses: `step_forward`, `next_failure`, ...
    pub fn name(self) -> String {
        let dbg = format!("{self:?}");
        let mut out = String::new();
        for (i, c) in dbg.chars().enumerate() {
            if c.is_uppercase() && i > 0 {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
        }
        out
    }
}

/// The bindings in force: the table, with a person's keymap file laid over it.
#[derive(Debug, Clone)]
pub struct Keymap {
    pub keys: Vec<(Vec<String>, Action, &'static str, &'static str)>,
}

impl Default for Keymap {
    fn default() -> Self {
        Keymap {
            keys: KEYMAP
                .iter()
                .map(|b| {
                    (
                        b.keys.iter().map(|k| k.to_string()).collect(),
                        b.action,
                        b.help,
                        b.hint,
                    )
                })
                .collect(),
        }
    }
}

impl Keymap {
    /// Reads `action = ["key", ...]` lines (TOML) over the defaults; the
    /// listed actions get exactly the listed keys.
    pub fn with_file(path: &std::path::Path) -> Result<Keymap, crate::source::Located> {
        let text = crate::source::read_text(path, crate::source::TEXT_SIZE_MAX, "the keymap")?;
        Keymap::parse(path, &text)
    }

    /// A keymap file's text (`path` names it in errors).
    pub fn parse(path: &std::path::Path, text: &str) -> Result<Keymap, crate::source::Located> {
        let text = text.to_string();
        let table: std::collections::BTreeMap<String, toml::Spanned<Vec<String>>> =
            toml::from_str(&text).map_err(|e| {
                let r = e.span().unwrap_or(0..0);
                crate::source::Located::at(
                    path,
                    &text,
                    r.start,
                    r.end.max(r.start + 1),
                    format!("not a keymap: {}", e.message().trim()),
                )
            })?;
        let mut km = Keymap::default();
        let at = |r: std::ops::Range<usize>, msg: String| {
            crate::source::Located::at(path, &text, r.start, r.end.max(r.start + 1), msg)
        };
        let mut from_file: Vec<(Action, std::ops::Range<usize>)> = Vec::new();
        for (name, keys) in table {
            let r = keys.span();
            let Some(entry) = km.keys.iter_mut().find(|k| k.1.name() == name) else {
                let known: Vec<String> = KEYMAP.iter().map(|b| b.action.name()).collect();
                return Err(at(r, format!("\"{name}\" is not an action"))
                    .with_help(format!("the actions are: {}", known.join(", "))));
            };
            for k in keys.get_ref() {
                if !is_key(k) {
                    return Err(at(r, format!("\"{k}\" is not a key")).with_help(format!(
                        "a key is one character, Ctrl- and one character, or one of {}",
                        NAMED_KEYS.join(", ")
                    )));
                }
                if k == "Ctrl-c" && entry.1 != Action::Quit {
                    return Err(at(
                        r,
                        format!("Ctrl-c is bound to {name}, and Ctrl-c always quits"),
                    ));
                }
            }
            from_file.push((entry.1, r));
            entry.0 = keys.into_inner();
        }
        // A key bound twice would do one thing and the help would show both.
        for (action, r) in &from_file {
            let keys = &km.keys.iter().find(|b| b.1 == *action).expect("bound").0;
            for k in keys {
                if let Some(other) = km.keys.iter().find(|b| b.1 != *action && b.0.contains(k)) {
                    let whose = if from_file.iter().any(|(a, _)| *a == other.1) {
                        "in this file"
                    } else {
                        "built in"
                    };
                    return Err(at(
                        r.clone(),
                        format!(
                            "\"{k}\" is bound to both {} and {} ({whose})",
                            action.name(),
                            other.1.name()
                        ),
                    )
                    .with_help(format!("give {} other keys too", other.1.name())));
                }
            }
        }
        if km.key_of(Action::Quit).is_none() {
            let r = from_file
                .iter()
                .find(|(a, _)| *a == Action::Quit)
                .map_or(0..0, |(_, r)| r.clone());
            return Err(at(
                r,
                "quit has no key: the keymap would leave no way out".into(),
            )
            .with_help("give quit a key (Ctrl-c quits too, always)"));
        }
        Ok(km)
    }

    pub fn action_for(&self, k: &KeyEvent) -> Option<Action> {
        let name = key_name(k)?;
        if name == "Ctrl-c" {
            return Some(Action::Quit);
        }
        self.keys.iter().find(|b| b.0.contains(&name)).map(|b| b.1)
    }
    /// The first key bound to an action, if any.
    pub fn key_of(&self, a: Action) -> Option<&str> {
        self.keys
            .iter()
            .find(|b| b.1 == a)
            .and_then(|b| b.0.first())
            .map(String::as_str)
    }

    /// The status bar's word for an action, as its first binding says it.
    fn hint_of(&self, a: Action) -> Option<&'static str> {
        self.keys.iter().find(|b| b.1 == a).map(|b| b.3)
    }

    /// The same keys, with an action said otherwise (in the status bar and
    /// the help): q in a run opened from the fleet goes back to the fleet.
    pub fn saying(mut self, a: Action, hint: &'static str, help: &'static str) -> Keymap {
        for b in self.keys.iter_mut().filter(|b| b.1 == a) {
            b.2 = help;
            b.3 = hint;
        }
        self
    }

    /// `hints` in at most `width` columns, after the focused pane's own
    /// `first` hints: hints are dropped from the end, but help and quit stay.
    pub fn hints_within(&self, first: &[(Action, &str)], width: usize) -> String {
        let key = |a: Action| self.key_of(a).map(str::to_string);
        // What a narrow bar drops first: the arrows (they say themselves),
        // then play, framed, find, stepping; the headline questions last.
        let weight = |a: Action| match a {
            Action::Ask | Action::Why => 6,
            Action::Down | Action::Expand | Action::Collapse => 1,
            _ if first.iter().any(|(f, _)| *f == a) => 5,
            Action::NextFailure => 4,
            Action::StepForward | Action::TickForward => 3,
            Action::Find => 2,
            _ => 1,
        };
        let mut all: Vec<(String, u8)> = first
            .iter()
            .filter_map(|&(a, what)| key(a).map(|k| (format!("{k} {what}"), weight(a))))
            .collect();
        all.extend(
            self.keys
                .iter()
                .filter(|b| !b.3.is_empty() && !b.0.is_empty())
                .filter(|b| !matches!(b.1, Action::Help | Action::Quit))
                .filter(|b| !first.iter().any(|(a, _)| *a == b.1))
                .map(|b| (format!("{} {}", b.0[0], b.3), weight(b.1))),
        );
        // `?` always last.
        let end: Vec<String> = [Action::Quit, Action::Help]
            .iter()
            .filter_map(|&a| Some(format!("{} {}", key(a)?, self.hint_of(a)?)))
            .collect();
        let cols = |v: &mut dyn Iterator<Item = &String>| {
            v.map(|s| s.chars().count() + 2)
                .sum::<usize>()
                .saturating_sub(2)
        };
        while !all.is_empty()
            && cols(&mut all.iter().map(|x| &x.0)) + 2 + cols(&mut end.iter()) > width
        {
            // The last of the lightest goes.
            let lightest = all.iter().map(|x| x.1).min().unwrap_or(0);
            let at = all.iter().rposition(|x| x.1 == lightest).unwrap_or(0);
            all.remove(at);
        }
        let mut out: Vec<String> = all.into_iter().map(|x| x.0).collect();
        out.extend(end);
        out.join("  ")
    }

    /// The status bar's hints: `n step  N tick  f failure ...`.
    pub fn hints(&self) -> String {
        self.keys
            .iter()
            .filter(|b| !b.3.is_empty() && !b.0.is_empty())
            .map(|b| format!("{} {}", b.0[0], b.3))
            .collect::<Vec<_>>()
            .join("  ")
    }
}
