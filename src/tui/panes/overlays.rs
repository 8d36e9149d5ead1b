//! The windows over the panes: the help, the finder, the lists of
//! questions, why-targets and running nodes, and the prompts ("Can you
//! …?", the transition filter, the export path). Each holds its own state
//! in [`Overlay`] and takes every key while open.

use crate::explain::Question;
use crate::tui::app::{App, Overlay};
use crate::tui::keymap::Action;
use crate::tui::view::*;
use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph};
use ratatui::Frame;

/// The characters a prompt holds: a question is a sentence, and what is
/// typed is read and completed at each key (each linear in the text).
pub const PROMPT_MAX: usize = 1000;

/// The ask prompt's row that opens "Can you …?".
pub const CAN_YOU_ROW: &str = "Can you …? (type any subgoal or step)";

/// One edit of a prompt's text (`App::edit`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Edit {
    /// Typed or pasted text (control characters left out).
    Insert(String),
    Backspace,
    /// Ctrl-w: the word before the cursor.
    WordBack,
    /// Ctrl-u: everything before the cursor.
    ToStart,
    Left,
    Right,
    Home,
    End,
}

/// The part of a prompt's text around the cursor that fits in `width`
/// characters, `…` where it is cut: a terminal cuts a long line on the
/// right, so what is typed past the edge would be typed blind.
pub(crate) fn prompt_window(text: &str, cursor: Option<usize>, width: usize) -> String {
    let chars: Vec<char> = crate::text::visible(text).chars().collect();
    let n = chars.len();
    let at = cursor.unwrap_or(n).min(n);
    let part = |a: usize, b: usize| chars[a..b].iter().collect::<String>();
    let width = width.max(4);
    if n < width {
        return format!("{}▏{}", part(0, at), part(at, n));
    }
    // Room for the text beside the cursor and a `…` at each cut end.
    if at + 2 < width {
        let end = width - 2;
        return format!("{}▏{}…", part(0, at), part(at, end));
    }
    let after = usize::from(at < n);
    let start = at - (width - 2 - after);
    let tail = if at < n { "…" } else { "" };
    format!("…{}▏{tail}", part(start, at))
}

/// A prompt in a block's title: `prefix` then the text, within a block
/// `width` columns wide. The text keeps at least half the room; the
/// prefix (a node's description, which may be long) is cut first.
fn prompt_title(prefix: &str, text: &str, cursor: Option<usize>, width: u16) -> String {
    let room = usize::from(width).saturating_sub(4);
    let prefix = crate::text::visible(prefix);
    let keep = (room / 2).max(room.saturating_sub(text.chars().count() + 1));
    let prefix: String = if prefix.chars().count() > keep {
        let cut: String = prefix.chars().take(keep.saturating_sub(1)).collect();
        format!("{cut}…")
    } else {
        prefix.into_owned()
    };
    let left = room.saturating_sub(prefix.chars().count());
    format!(" {prefix}{} ", prompt_window(text, cursor, left))
}

impl App {
    /// A key while an overlay is open: the overlay takes it.
    pub(crate) fn overlay_key(&mut self, a: Action) {
        match self.overlay {
            Overlay::Help { .. } => self.help_key(a),
            Overlay::Finder { .. }
            | Overlay::Why { .. }
            | Overlay::Running { .. }
            | Overlay::Faults { .. }
            | Overlay::Pick { .. } => self.update_list(a),
            Overlay::CanYou { .. } => self.can_you_key(a),
            Overlay::Words { .. } => self.words_key(a),
            Overlay::Filter { .. } => self.filter_key(a),
            Overlay::Export { .. } => self.export_key(a),
            Overlay::None => {}
        }
    }

    /// The help scrolls, and closes.
    fn help_key(&mut self, a: Action) {
        let Overlay::Help { scroll } = &mut self.overlay else {
            return;
        };
        match a {
            Action::Back | Action::Help | Action::Quit | Action::Toggle => {
                self.overlay = Overlay::None
            }
            Action::Down => *scroll += 1,
            Action::Up => *scroll = scroll.saturating_sub(1),
            Action::End => *scroll = usize::MAX,
            Action::Start => *scroll = 0,
            _ => {}
        }
    }

    /// "Can you …?": ↑↓ pick a completion, Enter asks.
    fn can_you_key(&mut self, a: Action) {
        let Overlay::CanYou { text, .. } = &self.overlay else {
            return;
        };
        let text = text.clone();
        let n = self.can_you_candidates(&text).len();
        let Overlay::CanYou { selected, .. } = &mut self.overlay else {
            return;
        };
        match a {
            Action::Back | Action::Quit => self.overlay = Overlay::None,
            Action::Up => *selected = selected.saturating_sub(1),
            Action::Down => *selected = (*selected + 1).min(n.saturating_sub(1)),
            Action::Toggle => {
                let i = *selected;
                let x = self
                    .can_you_candidates(&text)
                    .get(i)
                    .cloned()
                    .unwrap_or(text);
                self.overlay = Overlay::None;
                if !x.trim().is_empty() {
                    self.ask(&Question::CanYou(x.trim().to_string()));
                }
            }
            _ => {}
        }
    }

    /// The ask prompt: ↑↓ choose a completion, Tab takes it into the
    /// text, Enter asks the one chosen (with ↑↓, or the first when nothing
    /// is typed), else what was typed as typed.
    fn words_key(&mut self, a: Action) {
        let Overlay::Words {
            text,
            selected,
            picked,
        } = &self.overlay
        else {
            return;
        };
        let (text, i, picked) = (text.clone(), *selected, *picked);
        let completions = self.ask_completions(&text);
        let Overlay::Words {
            text: typed,
            selected,
            picked: chose,
        } = &mut self.overlay
        else {
            return;
        };
        match a {
            Action::Back | Action::Quit => {
                self.overlay = Overlay::None;
                self.did_you_mean.clear();
            }
            Action::Up => {
                *selected = selected.saturating_sub(1);
                *chose = true;
            }
            Action::Down => {
                *selected = (*selected + 1).min(completions.len().saturating_sub(1));
                *chose = true;
            }
            Action::NextPane => {
                if let Some(c) = completions.get(i) {
                    if *c != CAN_YOU_ROW {
                        *typed = c.clone();
                        *selected = 0;
                        *chose = false;
                        self.cursor = None;
                    }
                }
            }
            Action::Toggle => {
                let q = if picked || text.trim().is_empty() {
                    completions.get(i).cloned().unwrap_or(text)
                } else {
                    text
                };
                self.overlay = Overlay::None;
                self.did_you_mean.clear();
                if q == CAN_YOU_ROW {
                    self.overlay = Overlay::CanYou {
                        text: String::new(),
                        selected: 0,
                    };
                    return;
                }
                // A question of the list is answered as the list answers it.
                if let Some(known) = self.questions().into_iter().find(|k| k.wording() == q) {
                    self.ask(&known);
                } else if !q.trim().is_empty() {
                    self.ask_words(&q);
                }
            }
            _ => {}
        }
    }

    /// What the ask prompt offers for `text`: with nothing typed, the
    /// questions about the selected node; as one types, the whole
    /// questions that complete it (node names after a lead) and those of
    /// the list that match.
    pub fn ask_completions(&self, text: &str) -> Vec<String> {
        let listed: Vec<String> = self
            .questions()
            .iter()
            .map(|q| match q {
                Question::CanYou(x) if x.is_empty() => CAN_YOU_ROW.to_string(),
                q => q.wording(),
            })
            .collect();
        if text.trim().is_empty() {
            if !self.did_you_mean.is_empty() {
                return self.did_you_mean.clone();
            }
            return listed;
        }
        let mut out = crate::ask::complete::complete(&self.tree, text, 8);
        let keyed: Vec<(String, String)> = listed
            .iter()
            .filter(|l| *l != CAN_YOU_ROW)
            .map(|l| (l.clone(), l.clone()))
            .collect();
        for c in crate::rank::rank(text, &keyed, 8) {
            if !out.contains(&c) {
                out.push(c);
            }
        }
        out.truncate(8);
        out
    }

    /// The transition filter's text: Enter applies it.
    fn filter_key(&mut self, a: Action) {
        let Overlay::Filter { text } = &mut self.overlay else {
            return;
        };
        match a {
            Action::Back | Action::Quit => self.overlay = Overlay::None,
            Action::Toggle => {
                self.timeline.filter.text = std::mem::take(text);
                self.overlay = Overlay::None;
                self.timeline.scroll = 0;
            }
            _ => {}
        }
    }

    /// The export path: Enter writes (or asks before replacing).
    fn export_key(&mut self, a: Action) {
        let Overlay::Export { path, replace } = &self.overlay else {
            return;
        };
        match a {
            Action::Back | Action::Quit => self.overlay = Overlay::None,
            Action::Toggle => {
                let (path, replace) = (path.clone(), *replace);
                self.export_to(path, replace);
            }
            _ => {}
        }
    }

    /// Typing into the finder or a prompt.
    pub fn type_char(&mut self, c: char) {
        self.edit(Edit::Insert(c.to_string()));
    }

    pub fn backspace(&mut self) {
        self.edit(Edit::Backspace);
    }

    /// One edit of the open prompt's text, every prompt alike (the finder,
    /// "Can you …?", your own words, the timeline's filter, the export
    /// path): at the cursor, which `Left`/`Right`/`Home`/`End` move.
    pub fn edit(&mut self, e: Edit) {
        let cursor = self.cursor;
        let mut cut = None;
        let text = match &mut self.overlay {
            Overlay::Finder { query, .. } => query,
            Overlay::Export { path, .. } => path,
            Overlay::Filter { text }
            | Overlay::CanYou { text, .. }
            | Overlay::Words { text, .. } => text,
            _ => return,
        };
        let n = text.chars().count();
        let at = cursor.unwrap_or(n).min(n);
        let byte = |s: &str, i: usize| s.char_indices().nth(i).map_or(s.len(), |(b, _)| b);
        let (changed, to) = match e {
            Edit::Insert(s) => {
                // A paste of pages is cut at the bound, and said.
                let room = PROMPT_MAX.saturating_sub(n);
                let all = s.chars().filter(|c| !c.is_control()).count();
                let s: String = s.chars().filter(|c| !c.is_control()).take(room).collect();
                if all > room {
                    cut = Some(all - room);
                }
                text.insert_str(byte(text, at), &s);
                (true, at + s.chars().count())
            }
            Edit::Backspace if at > 0 => {
                text.remove(byte(text, at - 1));
                (true, at - 1)
            }
            Edit::WordBack => {
                let chars: Vec<char> = text.chars().collect();
                let mut from = at;
                while from > 0 && chars[from - 1] == ' ' {
                    from -= 1;
                }
                while from > 0 && chars[from - 1] != ' ' {
                    from -= 1;
                }
                text.replace_range(byte(text, from)..byte(text, at), "");
                (from != at, from)
            }
            Edit::ToStart => {
                text.replace_range(..byte(text, at), "");
                (at > 0, 0)
            }
            Edit::Left => (false, at.saturating_sub(1)),
            Edit::Right => (false, (at + 1).min(n)),
            Edit::Home => (false, 0),
            Edit::Backspace => (false, at),
            Edit::End => (false, n),
        };
        let end = text.chars().count();
        if changed {
            if let Overlay::Words { picked, .. } = &mut self.overlay {
                *picked = false;
            }
        }
        let (selected, replace) = match &mut self.overlay {
            Overlay::Finder { selected, .. }
            | Overlay::CanYou { selected, .. }
            | Overlay::Words { selected, .. } => (Some(selected), None),
            Overlay::Export { replace, .. } => (None, Some(replace)),
            _ => (None, None),
        };
        if changed {
            if let Some(s) = selected {
                *s = 0;
            }
            if let Some(r) = replace {
                *r = false;
            }
        }
        self.cursor = (to < end).then_some(to);
        if let Some(n) = cut {
            self.message = Some(format!(
                "a question or a search is at most {PROMPT_MAX} characters: the {n} past them were left out"
            ));
        }
    }

    /// The text of the prompt being typed, if one is.
    pub fn prompt_text(&self) -> Option<&str> {
        match &self.overlay {
            Overlay::Finder { query: t, .. }
            | Overlay::Export { path: t, .. }
            | Overlay::Filter { text: t }
            | Overlay::CanYou { text: t, .. }
            | Overlay::Words { text: t, .. } => Some(t),
            _ => None,
        }
    }

    /// Whether keys type text: the finder and every prompt (a letter there
    /// is text, not a key's action).
    pub fn typing(&self) -> bool {
        matches!(
            self.overlay,
            Overlay::Finder { .. }
                | Overlay::Export { .. }
                | Overlay::CanYou { .. }
                | Overlay::Words { .. }
                | Overlay::Filter { .. }
        )
    }

    fn update_list(&mut self, a: Action) {
        let len = match &self.overlay {
            Overlay::Finder { query, .. } => self.finder_results(query).len(),
            Overlay::Why { targets, .. } => targets.len(),
            Overlay::Running { .. } => self.running_nodes().len(),
            Overlay::Faults { lines, .. } => lines.len(),
            Overlay::Pick { .. } => self.choices.as_ref().map_or(0, |c| c.len()),
            _ => 0,
        };
        let choice = match &mut self.overlay {
            Overlay::Finder { selected, .. }
            | Overlay::Why { selected, .. }
            | Overlay::Running { selected }
            | Overlay::Faults { selected, .. }
            | Overlay::Pick { selected } => selected,
            _ => return,
        };
        match a {
            Action::Up => *choice = choice.saturating_sub(1),
            Action::Down => *choice = (*choice + 1).min(len.saturating_sub(1)),
            Action::Back | Action::Quit => self.overlay = Overlay::None,
            Action::Toggle => {
                let i = *choice;
                match std::mem::replace(&mut self.overlay, Overlay::None) {
                    Overlay::Finder { query, .. } => {
                        if let Some((u, _)) = self.finder_results(&query).get(i) {
                            let u = *u;
                            self.reveal(u);
                            self.selected = self.visible_for(u);
                            self.follow_node = false;
                        }
                    }
                    Overlay::Why { targets, .. } => {
                        if let (Some((t, _)), Some(m)) = (targets.get(i), self.moment()) {
                            self.ask_why(t.clone(), Vec::new(), m);
                        }
                    }
                    Overlay::Pick { .. } => self.pick(i),
                    Overlay::Faults { lines, .. } => {
                        if let Some(&(_, p, u)) = lines.get(i) {
                            self.goto(p);
                            self.reveal(u);
                            self.selected = self.visible_for(u);
                            self.follow_node = false;
                        }
                    }
                    Overlay::Running { .. } => {
                        if let Some(&u) = self.running_nodes().get(i) {
                            self.reveal(u);
                            self.selected = self.visible_for(u);
                            self.follow_node = false;
                        }
                    }
                    other => self.overlay = other,
                }
            }
            _ => {}
        }
    }
}

pub(crate) fn draw(app: &App, f: &mut Frame, area: Rect) {
    match &app.overlay {
        Overlay::None => {}
        Overlay::Help { scroll } => draw_help(app, f, area, scroll),
        Overlay::Finder { query, selected } => draw_finder(app, f, area, query, selected),
        Overlay::Running { selected } => draw_running(app, f, area, selected),
        Overlay::Faults { selected, lines } => draw_faults(f, area, selected, lines),
        Overlay::Pick { selected } => draw_pick(app, f, area, selected),
        Overlay::CanYou { text, selected } => draw_can_you(app, f, area, text, selected),
        Overlay::Words { text, selected, .. } => draw_words(app, f, area, text, *selected),
        Overlay::Filter { text } => draw_filter(app, f, area, text),
        Overlay::Export { path, replace } => draw_export(app, f, area, path, replace),
        Overlay::Why { selected, targets } => draw_why(app, f, area, selected, targets),
    }
}

/// The keys and the signs, scrolled.
fn draw_help(app: &App, f: &mut Frame, area: Rect, scroll: &usize) {
    let mut lines: Vec<Line> = app
        .keymap
        .keys
        .iter()
        .map(|b| {
            Line::from(vec![
                Span::styled(
                    format!("{:<16}", b.0.join(" ")),
                    Style::default().fg(Color::Yellow),
                ),
                Span::raw(b.2),
            ])
        })
        .collect();
    lines.push(Line::from(""));
    for (sign, what) in LEGEND {
        lines.push(Line::from(vec![
            Span::styled(format!("{sign:<16}"), Style::default().fg(Color::Yellow)),
            Span::raw(*what),
        ]));
    }
    let r = centered(area, 76, lines.len() as u16 + 2);
    let shown = r.height.saturating_sub(2) as usize;
    let top = (*scroll).min(lines.len().saturating_sub(shown));
    let more = if top + shown < lines.len() {
        " ↓ more "
    } else {
        ""
    };
    f.render_widget(Clear, r);
    f.render_widget(
        Paragraph::new(lines).scroll((top as u16, 0)).block(
            Block::default()
                .borders(Borders::ALL)
                .title(" keys and signs (↑↓ scroll, ? or Esc to close) ")
                .title_bottom(more),
        ),
        r,
    );
}

/// The finder: the query, and the nodes it matches.
fn draw_finder(app: &App, f: &mut Frame, area: Rect, query: &str, selected: &usize) {
    let r = centered(
        area,
        area.width.saturating_sub(8),
        area.height.saturating_sub(4),
    );
    f.render_widget(Clear, r);
    let b = Block::default()
        .borders(Borders::ALL)
        .title(prompt_title("find: ", query, app.cursor, r.width));
    let inner = b.inner(r);
    f.render_widget(b, r);
    let results = app.finder_results(query);
    let h = inner.height as usize;
    let first = selected.saturating_sub(h.saturating_sub(1));
    let mut lines = Vec::new();
    for (i, (u, idx)) in results.iter().enumerate().skip(first).take(h) {
        let label = app.finder_label(*u);
        // A row too long ends in … (its path, usually), never cut bare.
        let (n, w) = (label.chars().count(), inner.width as usize);
        let keep = if n > w { w.saturating_sub(1) } else { n };
        let mut spans = Vec::new();
        for (ci, ch) in label.chars().enumerate().take(keep) {
            let mut st = Style::default();
            if idx.contains(&ci) {
                st = st.fg(Color::Yellow).add_modifier(Modifier::BOLD);
            }
            if i == *selected {
                st = st.add_modifier(Modifier::REVERSED);
            }
            spans.push(Span::styled(ch.to_string(), st));
        }
        if keep < n {
            spans.push(Span::raw("…"));
        }
        lines.push(Line::from(spans));
    }
    f.render_widget(Paragraph::new(lines), inner);
}

/// The nodes RUNNING now, to pick one.
fn draw_running(app: &App, f: &mut Frame, area: Rect, selected: &usize) {
    let rows: Vec<String> = app
        .running_nodes()
        .iter()
        .map(|&u| {
            format!(
                "{} #{u}  {}",
                crate::text::visible(app.tree.description(u)),
                app.tree.type_name(u)
            )
        })
        .collect();
    list(
        f,
        area,
        70,
        &rows,
        *selected,
        " RUNNING now: Enter selects ",
    );
}

/// The faults, newest first, to go to one.
fn draw_faults(
    f: &mut Frame,
    area: Rect,
    selected: &usize,
    lines: &[(String, u32, crate::model::Uid)],
) {
    let rows: Vec<String> = lines
        .iter()
        .map(|(l, _, _)| crate::text::visible(l).to_string())
        .collect();
    let width = area.width.saturating_sub(4).min(140);
    list(
        f,
        area,
        width,
        &rows,
        *selected,
        " Faults, newest first: Enter goes to one ",
    );
}

/// A list to pick a run, a robot or a session from.
fn draw_pick(app: &App, f: &mut Frame, area: Rect, selected: &usize) {
    let Some(c) = &app.choices else { return };
    let rows: Vec<String> = c
        .lines(app.live.as_ref())
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let mark = if i == c.current() { "▸ " } else { "  " };
            format!("{mark}{}", crate::text::visible(row))
        })
        .collect();
    let width = area.width.saturating_sub(4).min(110);
    list(f, area, width, &rows, *selected, c.title());
}

/// "Can you …?": the prompt, and the subgoals it completes to.
fn draw_can_you(app: &App, f: &mut Frame, area: Rect, text: &str, selected: &usize) {
    let r = centered(
        area,
        area.width.saturating_sub(8).min(70),
        area.height.saturating_sub(4).min(16),
    );
    f.render_widget(Clear, r);
    let b = Block::default().borders(Borders::ALL).title(prompt_title(
        "Can you ",
        &format!("{text}?"),
        Some(app.cursor.unwrap_or(text.chars().count())),
        r.width,
    ));
    let inner = b.inner(r);
    f.render_widget(b, r);
    let h = inner.height as usize;
    let first = selected.saturating_sub(h.saturating_sub(1));
    let lines: Vec<Line> = app
        .can_you_candidates(text)
        .into_iter()
        .enumerate()
        .skip(first)
        .take(h)
        .map(|(i, d)| {
            let st = if i == *selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            Line::from(Span::styled(crate::text::visible(&d).into_owned(), st))
        })
        .collect();
    f.render_widget(Paragraph::new(lines), inner);
}

/// The timeline's name filter.
fn draw_filter(app: &App, f: &mut Frame, area: Rect, text: &str) {
    let r = centered(area, area.width.saturating_sub(8).min(70), 3);
    f.render_widget(Clear, r);
    f.render_widget(
        Paragraph::new(prompt_window(
            text,
            app.cursor,
            usize::from(r.width.saturating_sub(2)),
        ))
        .block(
            Block::default()
                .borders(Borders::ALL)
                .title(" show transitions of nodes named: Enter applies, empty for all "),
        ),
        r,
    );
}

/// Where to write the causal model.
fn draw_export(app: &App, f: &mut Frame, area: Rect, path: &str, replace: &bool) {
    let r = centered(area, area.width.saturating_sub(8).min(90), 4);
    f.render_widget(Clear, r);
    let title = if *replace {
        " a file is there: Enter replaces it, Esc keeps it "
    } else {
        " write the causal model (DOT) to: Enter writes, Esc cancels "
    };
    let note = app.message.clone().unwrap_or_default();
    f.render_widget(
        Paragraph::new(vec![
            Line::from(prompt_window(
                path,
                app.cursor,
                usize::from(r.width.saturating_sub(2)),
            )),
            Line::from(crate::text::visible(&note).into_owned()),
        ])
        .block(Block::default().borders(Borders::ALL).title(title)),
        r,
    );
}

/// The why-questions about the node, each whole.
fn draw_why(app: &App, f: &mut Frame, area: Rect, selected: &usize, targets: &[(String, String)]) {
    // As wide as the longest question, up to the screen; a longer
    // one wraps under itself, never cut.
    let longest = targets.iter().map(|(_, q)| q.chars().count()).max();
    let width = (longest.unwrap_or(0) as u16 + 2)
        .max(70)
        .min(area.width.saturating_sub(4));
    let inner = usize::from(width.saturating_sub(2)).max(1);
    let mut lines: Vec<Line> = Vec::new();
    for (i, (_, q)) in targets.iter().enumerate() {
        let st = if i == *selected {
            Style::default().add_modifier(Modifier::REVERSED)
        } else {
            Style::default()
        };
        for row in textwrap::wrap(q, inner) {
            lines.push(Line::from(Span::styled(row.into_owned(), st)));
        }
    }
    let r = centered(area, width, lines.len() as u16 + 2);
    f.render_widget(Clear, r);
    let title = format!(
        " why? about {} ",
        crate::text::visible(app.tree.description(app.asked_node()))
    );
    f.render_widget(
        Paragraph::new(lines).block(Block::default().borders(Borders::ALL).title(title)),
        r,
    );
}

/// The prompt of a question in the user's own words, with its completions.
fn draw_words(app: &App, f: &mut Frame, area: Rect, text: &str, selected: usize) {
    let rows = app.ask_completions(text);
    let r = centered(
        area,
        area.width.saturating_sub(8).min(80),
        (rows.len() as u16 + 2)
            .max(4)
            .min(area.height.saturating_sub(2)),
    );
    f.render_widget(Clear, r);
    let about = format!("ask about {}: ", app.tree.description(app.asked_node()));
    let b = Block::default()
        .borders(Borders::ALL)
        .title(prompt_title(&about, text, app.cursor, r.width));
    let inner = b.inner(r);
    f.render_widget(b, r);
    let h = inner.height as usize;
    let first = selected.saturating_sub(h.saturating_sub(1));
    let lines: Vec<Line> = rows
        .into_iter()
        .enumerate()
        .skip(first)
        .take(h)
        .map(|(i, q)| {
            let st = if i == selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            Line::from(Span::styled(fit(&q, inner.width as usize), st))
        })
        .collect();
    f.render_widget(Paragraph::new(lines), inner);
}

/// A list to pick from, centred, `width` wide, scrolled to `selected`
/// (reversed); each row cut with `…` where it does not fit.
fn list(f: &mut Frame, area: Rect, width: u16, rows: &[String], selected: usize, title: &str) {
    let r = centered(
        area,
        width,
        (rows.len() as u16 + 2).min(area.height.saturating_sub(2)),
    );
    f.render_widget(Clear, r);
    let h = r.height.saturating_sub(2) as usize;
    let first = selected.saturating_sub(h.saturating_sub(1));
    let lines: Vec<Line> = rows
        .iter()
        .enumerate()
        .skip(first)
        .take(h)
        .map(|(i, row)| {
            let st = if i == selected {
                Style::default().add_modifier(Modifier::REVERSED)
            } else {
                Style::default()
            };
            Line::from(Span::styled(
                fit(row, r.width.saturating_sub(2) as usize),
                st,
            ))
        })
        .collect();
    f.render_widget(
        Paragraph::new(lines).block(
            Block::default()
                .borders(Borders::ALL)
                .title(title.to_string()),
        ),
        r,
    );
}

#[cfg(test)]
mod tests {
    use super::prompt_window;

    #[test]
    fn a_prompt_shows_the_text_around_its_cursor() {
        assert_eq!(prompt_window("why", None, 10), "why▏");
        assert_eq!(prompt_window("why", Some(1), 10), "w▏hy");
        let long = "why did look at chuck fail";
        // Typing at the end: what was just typed stays in sight.
        assert_eq!(prompt_window(long, None, 10), "…uck fail▏");
        // At the start, the rest is cut on the right.
        assert_eq!(prompt_window(long, Some(0), 10), "▏why did …");
        // Within: the cursor, what is before it, and a cut on each side.
        assert_eq!(prompt_window(long, Some(15), 10), "…look at▏…");
        for at in 0..=long.len() {
            let w = prompt_window(long, Some(at), 10);
            assert!(w.chars().count() <= 10, "{at}: {w}");
            assert_eq!(w.matches('▏').count(), 1, "{at}: {w}");
        }
    }
}
