//! The explorer: a terminal UI over trees and runs. State and `update` are
//! in `app`, drawing in `view`, keys in `keymap`; this module runs the loop.

mod abort;
pub mod app;
pub mod choices;
pub mod diff;
pub mod fleet;
pub mod graph_view;
pub mod keymap;
pub mod panes;
pub mod pick_list;
pub mod shared;
pub mod svg;
pub mod text_input;
mod unmoved;
pub mod view;

pub use app::App;
pub use keymap::Action;

use crate::session::Session;
use crate::source::Located;
use crate::xml::LoadOptions;
use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind, MouseEventKind};
use std::path::Path;
use std::time::Duration;

const DEMO_SESSION: &str = include_str!("../../sessions/kitting-lookat-fails-once.jsonl");

/// The bundled demo: the kitting tree and its `look at chuck fails once` run.
pub fn demo() -> App {
    let session = Session::parse(
        Path::new("demo: kitting, look at chuck fails once"),
        DEMO_SESSION,
    )
    .expect("the bundled session loads");
    let tree = session.tree.clone();
    App::new(
        tree,
        Some(session),
        "demo: kitting, look at chuck fails once".into(),
    )
}

/// Opens a tree, a session, or a tree with a session of it.
pub fn open(first: &Path, second: Option<&Path>, opts: &LoadOptions) -> Result<App, Located> {
    use crate::input::{open as open_input, Input};
    if second.is_none() && opts.run.is_none() && crate::logs::rosbag::is_bag(first) {
        return open_runs(first, opts);
    }
    if second.is_none() {
        if let Some(part) = crate::input::open_first(first, opts, crate::input::FIRST_RECORDS)? {
            let mut app = App::new(part.tree.clone(), Some(part), title_of(first));
            app.shared.reading = Some(crate::input::Reading::start(first, opts));
            return Ok(app);
        }
    }
    let a = open_input(first, opts)?;
    let b = match second {
        Some(p) => Some(open_input(p, opts)?),
        None => None,
    };
    let title = title_of(first);
    match (a, b) {
        (Input::Session(s), None) => {
            let tree = s.tree.clone();
            Ok(App::new(tree, Some(*s), title))
        }
        (Input::Tree { tree, .. }, None) => Ok(App::new(tree, None, title)),
        (Input::Tree { tree, .. }, Some(Input::Session(s))) => {
            let diff = crate::logs::tree_mismatch(&tree, &s.tree, 8);
            if !diff.is_empty() {
                return Err(Located::file(
                    second.expect("given"),
                    format!("not a run of {}:\n  {}", first.display(), diff.join("\n  ")),
                ));
            }
            Ok(App::new(tree, Some(*s), title))
        }
        _ => Err(Located::file(
            first,
            "give a tree and then a session of it, or just one of them",
        )),
    }
}

/// The explorer's title for a file: its name.
fn title_of(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// A log of several runs (a rosbag's goals), showing the last, with the
/// others to pick from (`R`).
fn open_runs(path: &Path, opts: &LoadOptions) -> Result<App, Located> {
    let name = title_of(path);
    let mut runs = Vec::new();
    crate::input::each_run(path, opts, |k, n, s| {
        let span = s.span_us.map_or(String::new(), |(a, b)| {
            format!(
                "  {} UTC, {:.3} s",
                crate::clock::utc(a),
                (b - a) as f64 / 1e6
            )
        });
        let label = format!(
            "run {k}{span} · {} ticks · {} transitions · {}",
            s.index.ticks(),
            s.index.transitions.len(),
            s.ending()
        );
        runs.push((label, format!("{name} · run {k} of {n}"), s));
        Ok(())
    })?;
    let last = runs.len().saturating_sub(1);
    let mut choices = choices::Choices::runs(runs, last);
    let choices::Choices::Runs { runs, .. } = &mut choices else {
        unreachable!("made as runs")
    };
    let shown = &mut runs[last];
    let s = shown.session.take().expect("each run is a session");
    let mut app = App::new(s.tree.clone(), Some(s), shown.title.clone());
    if choices.len() > 1 {
        app.shared.choices = Some(choices);
    }
    Ok(app)
}

/// How often a followed log is read again, in milliseconds.
const FOLLOW_MS: u64 = 500;
/// How often the explorer takes a live run's news, in milliseconds.
const LIVE_MS: u64 = 100;
/// How often the live thread hands the run over.
pub const LIVE_EVERY: Duration = Duration::from_millis(200);

/// A screen the loop can drive: the explorer, or the side-by-side diff.
pub trait Screen {
    fn draw(&self, f: &mut ratatui::Frame);
    fn event(&mut self, ev: Event, size: (u16, u16));
    fn done(&self) -> bool;
    /// While playing, how long to wait between automatic steps.
    fn play_every(&self) -> Option<Duration> {
        None
    }
    fn play_step(&mut self) {}
    /// Text to put on the clipboard, once.
    fn take_clipboard(&mut self) -> Option<String> {
        None
    }
    /// Work done while no key is pending, a few milliseconds at a time.
    fn idle(&mut self) -> Idle {
        Idle::Done
    }
}

/// What a screen's work between keys did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Idle {
    /// Nothing is left to do: wait for a key.
    Done,
    /// Some was done, more is left, and the screen is the same.
    More,
    /// What is on screen changed; there may be more.
    Changed,
}

/// The OSC 52 sequence that asks the terminal to put `text` on the
/// clipboard: it travels with the output, so it works over SSH.
pub fn osc52(text: &str) -> String {
    use base64::Engine;
    format!(
        "\x1b]52;c;{}\x07",
        base64::engine::general_purpose::STANDARD.encode(text)
    )
}

impl Screen for App {
    fn draw(&self, f: &mut ratatui::Frame) {
        App::draw(self, f)
    }
    fn event(&mut self, ev: Event, size: (u16, u16)) {
        handle(self, ev, size)
    }
    fn done(&self) -> bool {
        self.quit
    }
    fn play_every(&self) -> Option<Duration> {
        let sh = &self.shared;
        match (sh.playing, sh.follow.is_some()) {
            (true, _) => Some(Duration::from_millis(sh.play_ms)),
            _ if sh.live.is_some() => Some(Duration::from_millis(LIVE_MS)),
            (false, true) => Some(Duration::from_millis(FOLLOW_MS)),
            _ => None,
        }
    }
    fn play_step(&mut self) {
        if self.shared.playing {
            App::play_step(self)
        }
        self.follow_poll()
    }
    fn take_clipboard(&mut self) -> Option<String> {
        self.shared.clipboard.take()
    }
    fn idle(&mut self) -> Idle {
        if self.shared.reading.is_some() {
            return match self.take_read(IDLE_SLICE) {
                true => Idle::Changed,
                false => Idle::More,
            };
        }
        // The replay's marks, so that a question late in a long run is
        // answered from the nearest (a live run is still growing).
        match (&self.shared.session, &self.shared.live) {
            (Some(s), None) if crate::causal::facts::lay_marks(s, IDLE_SLICE) => Idle::More,
            _ => Idle::Done,
        }
    }
}

/// The longest a key waits for the work done between keys.
const IDLE_SLICE: Duration = Duration::from_millis(8);

impl Screen for diff::DiffApp {
    fn draw(&self, f: &mut ratatui::Frame) {
        self.view(f)
    }
    fn event(&mut self, ev: Event, size: (u16, u16)) {
        let act = match ev {
            Event::Key(k) if k.kind == KeyEventKind::Press => self.keymap.action_for(&k),
            Event::Mouse(m) => match m.kind {
                MouseEventKind::ScrollDown => Some(Action::Down),
                MouseEventKind::ScrollUp => Some(Action::Up),
                _ => None,
            },
            _ => None,
        };
        if let Some(a) = act {
            self.shared.message = None;
            let before = render(self, size.0, size.1);
            self.update(a);
            if !self.quit && self.shared.message.is_none() && render(self, size.0, size.1) == before
            {
                let key = match ev {
                    Event::Key(k) => keymap::key_name(&k).unwrap_or_default(),
                    _ => "the wheel".into(),
                };
                self.shared.message = Some(unmoved::diff_reason(self, a, &key));
            }
        }
    }
    fn done(&self) -> bool {
        self.quit
    }
}

impl Screen for fleet::FleetApp {
    fn draw(&self, f: &mut ratatui::Frame) {
        self.view(f)
    }
    fn event(&mut self, ev: Event, size: (u16, u16)) {
        // A run opened from the fleet has the keys until it quits, which
        // comes back to the fleet.
        if let Some(run) = self.opened.as_mut() {
            handle(run, ev, size);
            if run.quit {
                self.opened = None;
            }
            return;
        }
        if let Event::Key(k) = ev {
            if k.kind == KeyEventKind::Press {
                if let Some(a) = self.keymap.action_for(&k) {
                    self.update(a);
                }
            }
        }
    }
    fn done(&self) -> bool {
        self.quit
    }
    fn play_every(&self) -> Option<Duration> {
        self.opened.as_ref().and_then(|r| r.play_every())
    }
    fn play_step(&mut self) {
        if let Some(r) = self.opened.as_mut() {
            Screen::play_step(r.as_mut());
        }
    }
    fn take_clipboard(&mut self) -> Option<String> {
        self.opened.as_mut().and_then(|r| r.take_clipboard())
    }
}

/// `btx open --diff A B`: two trees, two runs, or a tree and a run, side by side.
pub fn open_diff(a: &Path, b: &Path, opts: &LoadOptions) -> Result<diff::DiffApp, Located> {
    use crate::input::{open as open_input, Input};
    let side = |p: &Path| -> Result<(String, crate::model::Tree, Option<Session>), Located> {
        Ok(match open_input(p, opts)? {
            Input::Tree { tree, .. } => (p.display().to_string(), tree, None),
            Input::Session(s) => (p.display().to_string(), s.tree.clone(), Some(*s)),
        })
    };
    Ok(diff::DiffApp::new(side(a)?, side(b)?))
}

/// Maps one terminal event to state changes.
pub fn handle(app: &mut App, ev: Event, size: (u16, u16)) {
    match ev {
        Event::Key(k) if k.kind == KeyEventKind::Press => {
            if app.typing() {
                if let Some(e) = line_edit(&k) {
                    app.shared.message = None;
                    let before = render(app, size.0, size.1);
                    app.edit(e.clone());
                    if app.shared.message.is_none() && render(app, size.0, size.1) == before {
                        app.shared.message = Some(unmoved::edit_reason(app, &e));
                    }
                    return;
                }
            }
            if let Some(a) = app.shared.keymap.action_for(&k) {
                // A key that changes nothing on screen says why (#27 item 2).
                app.shared.message = None;
                let before = render(app, size.0, size.1);
                app.update(a);
                if !app.quit
                    && app.shared.message.is_none()
                    && render(app, size.0, size.1) == before
                {
                    let key = keymap::key_name(&k).unwrap_or_default();
                    app.shared.message = Some(unmoved::reason(app, a, &key));
                }
            }
        }
        // A paste, where the terminal marks one, goes into the prompt whole.
        Event::Paste(text) if app.typing() => app.edit(text_input::Edit::Insert(text)),
        Event::Mouse(m) => mouse(app, m, size),
        _ => {}
    }
}

/// Every prompt edits as a line editor does: the edit a key makes.
fn line_edit(k: &event::KeyEvent) -> Option<text_input::Edit> {
    use text_input::Edit;
    let ctrl = k.modifiers.contains(event::KeyModifiers::CONTROL);
    match k.code {
        KeyCode::Char(c) if !ctrl => Some(Edit::Insert(c.to_string())),
        KeyCode::Char('w') if ctrl => Some(Edit::WordBack),
        KeyCode::Char('u') if ctrl => Some(Edit::ToStart),
        KeyCode::Backspace => Some(Edit::Backspace),
        KeyCode::Left => Some(Edit::Left),
        KeyCode::Right => Some(Edit::Right),
        KeyCode::Home => Some(Edit::Home),
        KeyCode::End => Some(Edit::End),
        _ => None,
    }
}

/// A click picks the tree's row under it; the wheel scrolls the pane under
/// the pointer.
fn mouse(app: &mut App, m: event::MouseEvent, size: (u16, u16)) {
    let areas = view::layout(ratatui::layout::Rect::new(0, 0, size.0, size.1), app.split);
    let t = areas.tree;
    match m.kind {
        MouseEventKind::Down(_)
            if m.column > t.x
                && m.column < t.x + t.width
                && m.row > t.y
                && m.row < t.y + t.height - 1 =>
        {
            let first = view::first_row(&app.shared, t.height.saturating_sub(2) as usize);
            app.click_row((m.row - t.y - 1) as usize, first);
        }
        MouseEventKind::ScrollDown | MouseEventKind::ScrollUp => {
            let inside = |r: ratatui::layout::Rect| {
                m.column >= r.x
                    && m.column < r.x + r.width
                    && m.row >= r.y
                    && m.row < r.y + r.height
            };
            let pane = if inside(areas.details) {
                app::Pane::Details
            } else if inside(areas.ask) {
                app::Pane::Ask
            } else if inside(areas.timeline) {
                app::Pane::Timeline
            } else {
                app::Pane::Tree
            };
            app.wheel(pane, matches!(m.kind, MouseEventKind::ScrollDown));
        }
        _ => {}
    }
}

/// Ctrl-Z: in raw mode it is a key, not the terminal's suspend.
fn is_suspend(ev: &Event) -> bool {
    matches!(ev, Event::Key(k) if k.kind == KeyEventKind::Press
        && k.code == KeyCode::Char('z')
        && k.modifiers.contains(event::KeyModifiers::CONTROL))
}

/// Gives the terminal back and stops as the shell's job control expects;
/// returns when `fg` continues btx.
fn suspend() -> std::io::Result<()> {
    let _ = ratatui::crossterm::execute!(
        std::io::stdout(),
        event::DisableMouseCapture,
        ratatui::crossterm::cursor::Show
    );
    ratatui::restore();
    signal_hook::low_level::raise(signal_hook::consts::SIGTSTP)
}

/// Runs the explorer until the person quits. The terminal is restored on
/// quit, on error and on panic (ratatui's hook).
pub fn run(mut app: impl Screen) -> std::io::Result<()> {
    run_with(&mut app, false)
}

/// The signs the explorer draws, as ASCII (`--ascii`): box drawing, arrows,
/// glyphs and marks. Text from the tree and the run (names in any script)
/// is data and stays as it is.
pub fn ascii_of(sym: &str) -> Option<&'static str> {
    Some(match sym {
        "─" | "═" => "-",
        // The focused pane's thick border stays apart from the others.
        "━" => "=",
        "┏" | "┓" | "┗" | "┛" => "#",
        "│" | "┃" | "║" => "|",
        "┌" | "┐" | "└" | "┘" | "├" | "┤" | "┬" | "┴" | "┼" | "┣" | "┫" | "┳" | "┻" | "╋" => {
            "+"
        }
        "▾" => "v",
        "▸" | "▶" | "→" | "⇉" | "›" => ">",
        "◀" | "‹" | "◂" => "<",
        "▼" | "↓" => "v",
        "↑" => "^",
        "↕" => "|",
        "▣" => "#",
        "▢" => "o",
        "◯" => "c",
        "◇" | "◆" => "*",
        "…" | "⋯" => "~",
        "≠" => "!",
        "★" => "*",
        "◎" => "@",
        "▏" => "_",
        "·" => ".",
        "▆" => "R",
        "▃" => "F",
        "▂" => "S",
        "×" => "x",
        "⊘" => "H",
        "╵" => "'",
        "←" => "<",
        _ => return None,
    })
}

fn asciify(buf: &mut ratatui::buffer::Buffer) {
    for cell in buf.content.iter_mut() {
        if let Some(a) = ascii_of(cell.symbol()) {
            cell.set_symbol(a);
        }
    }
}

/// `run`, drawing only ASCII signs when `ascii` is set.
pub fn run_with(app: &mut impl Screen, ascii: bool) -> std::io::Result<()> {
    let watcher = restore_on_signals()?;
    abort::guard();
    let mut terminal = ratatui::try_init()?;
    // ratatui's panic hook leaves the alternate screen and raw mode; mouse
    // reporting, which btx turned on, is turned off first.
    let ratatui_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let _ = ratatui::crossterm::execute!(
            std::io::stdout(),
            event::DisableMouseCapture,
            ratatui::crossterm::cursor::Show
        );
        ratatui_hook(info);
    }));
    let _ = ratatui::crossterm::execute!(std::io::stdout(), event::EnableMouseCapture);
    let result = event_loop(app, &mut terminal, ascii);
    let _ = ratatui::crossterm::execute!(std::io::stdout(), event::DisableMouseCapture);
    ratatui::restore();
    watcher.close();
    result
}

/// SIGTERM (and SIGHUP) while the loop blocks on input: put the terminal
/// back from a watcher thread, then leave as a killed process would. An
/// external SIGINT or SIGQUIT too (Ctrl-C itself is a key in raw mode).
fn restore_on_signals() -> std::io::Result<signal_hook::iterator::Handle> {
    let mut signals = signal_hook::iterator::Signals::new([
        signal_hook::consts::SIGTERM,
        signal_hook::consts::SIGHUP,
        signal_hook::consts::SIGINT,
        signal_hook::consts::SIGQUIT,
    ])?;
    let watcher = signals.handle();
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            let _ = ratatui::crossterm::execute!(
                std::io::stdout(),
                event::DisableMouseCapture,
                ratatui::crossterm::cursor::Show
            );
            ratatui::restore();
            std::process::exit(128 + sig);
        }
    });
    Ok(watcher)
}

/// Draws when something changed, then waits for a key (or the next step
/// while playing, or does idle work while there is some) and hands it to
/// the screen, until the screen is done.
fn event_loop(
    app: &mut impl Screen,
    terminal: &mut ratatui::DefaultTerminal,
    ascii: bool,
) -> std::io::Result<()> {
    // The end-to-end tests crash the explorer on purpose, to see the panic
    // path give the terminal back; nothing else sets this.
    let crash = std::env::var_os(CRASH_ENV).is_some();
    let abort = std::env::var_os(ABORT_ENV).is_some();
    let mut dirty = true;
    while !app.done() {
        if dirty {
            terminal.draw(|f| {
                app.draw(f);
                if ascii {
                    asciify(f.buffer_mut());
                }
            })?;
            dirty = false;
            if crash {
                panic!("{CRASH_ENV} is set: crashing on purpose after the first frame");
            }
            if abort {
                std::process::abort();
            }
        }
        // Block until input; wake on a timer only while playing.
        let ev = if let Some(every) = app.play_every() {
            if event::poll(every)? {
                Some(event::read()?)
            } else {
                app.play_step();
                dirty = true;
                None
            }
        } else if event::poll(Duration::ZERO)? {
            Some(event::read()?)
        } else {
            match app.idle() {
                Idle::Done => Some(event::read()?),
                Idle::More => None,
                Idle::Changed => {
                    dirty = true;
                    None
                }
            }
        };
        let Some(ev) = ev else { continue };
        if is_suspend(&ev) {
            suspend()?;
            *terminal = ratatui::try_init()?;
            let _ = ratatui::crossterm::execute!(std::io::stdout(), event::EnableMouseCapture);
            terminal.clear()?;
            dirty = true;
            continue;
        }
        let size = terminal.size()?;
        app.event(ev, (size.width, size.height));
        if let Some(t) = app.take_clipboard() {
            use std::io::Write;
            let mut out = std::io::stdout();
            let _ = out
                .write_all(osc52(&t).as_bytes())
                .and_then(|()| out.flush());
        }
        dirty = true;
    }
    Ok(())
}

/// Set, the explorer panics once it has drawn its first frame (a test hook
/// for the panic path).
pub const CRASH_ENV: &str = "BTX_CRASH_AFTER_DRAW";
/// Set, the explorer aborts (as on exhausted memory) once it has drawn its
/// first frame (a test hook for the abort path).
pub const ABORT_ENV: &str = "BTX_ABORT_AFTER_DRAW";

/// The scripted scenes of `btx screenshot --demo SCENE`.
pub const SCENES: [&str; 7] = [
    "failure", "framed", "answer", "finder", "help", "graph", "filtered",
];

/// The demo after a scene's key presses.
pub fn scene(name: &str) -> Result<App, String> {
    let mut app = demo();
    match name {
        "failure" => app.update(Action::NextFailure),
        "framed" => {
            app.update(Action::NextFailure);
            app.update(Action::ToggleFramed);
        }
        "answer" => {
            app.update(Action::NextFailure);
            app.update(Action::Ask);
            let i = app
                .shared
                .questions()
                .iter()
                .position(|q| {
                    *q == crate::explain::Question::Run(crate::explain::RunQuestion::WhatWentWrong)
                })
                .expect("a run has the failure questions");
            for _ in 0..i {
                app.update(Action::Down);
            }
            app.update(Action::Toggle);
        }
        "finder" => {
            app.update(Action::Find);
            for c in "look chuck".chars() {
                app.type_char(c);
            }
        }
        "help" => app.update(Action::Help),
        "graph" => {
            // f lands on look at chuck; why did it fail? Its causal graph.
            app.update(Action::NextFailure);
            app.update(Action::Why);
            app.update(Action::Toggle);
            app.update(Action::Graph);
            app.focus = app::Pane::Details;
            app.update(Action::Expand);
        }
        "filtered" => {
            app.update(Action::NextFailure);
            app.focus = app::Pane::Timeline;
            app.update(Action::HideResets);
            for _ in 0..3 {
                app.update(Action::OnlyStatus);
            }
        }
        other => {
            return Err(format!(
                "no scene \"{other}\"; the scenes are {}",
                SCENES.join(", ")
            ))
        }
    }
    Ok(app)
}

/// Draws the app into an off-screen buffer.
pub fn render(app: &impl Screen, width: u16, height: u16) -> ratatui::buffer::Buffer {
    let mut t = ratatui::Terminal::new(ratatui::backend::TestBackend::new(width, height))
        .expect("a test backend");
    t.draw(|f| app.draw(f)).expect("drawing into memory");
    t.backend().buffer().clone()
}
