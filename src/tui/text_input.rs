//! The one text input every prompt uses (the finder, the ask prompt, "Can
//! you …?", the timeline's filter, the export path): a line of text and
//! its cursor, edited as a line editor edits.

/// The characters a prompt holds: a question is a sentence, and what is
/// typed is read and completed at each key (each linear in the text).
pub const PROMPT_MAX: usize = 1000;

/// One edit of a prompt's text.
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

/// A line of text being typed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TextInput {
    pub text: String,
    /// Characters from the start; `None`: at the end.
    pub cursor: Option<usize>,
}

/// What an edit did: whether the text changed, and how many pasted
/// characters were left out past [`PROMPT_MAX`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edited {
    pub changed: bool,
    pub cut: Option<usize>,
}

impl TextInput {
    pub fn new(text: impl Into<String>) -> TextInput {
        TextInput {
            text: text.into(),
            cursor: None,
        }
    }

    /// Replaces the text, the cursor at its end.
    pub fn set(&mut self, text: String) {
        self.text = text;
        self.cursor = None;
    }

    /// One edit at the cursor, which `Left`/`Right`/`Home`/`End` move.
    pub fn edit(&mut self, e: Edit) -> Edited {
        let text = &mut self.text;
        let n = text.chars().count();
        let at = self.cursor.unwrap_or(n).min(n);
        let byte = |s: &str, i: usize| s.char_indices().nth(i).map_or(s.len(), |(b, _)| b);
        let mut cut = None;
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
        self.cursor = (to < end).then_some(to);
        Edited { changed, cut }
    }

    /// The text around the cursor in `width` characters (see [`window`]).
    pub fn window(&self, width: usize) -> String {
        window(&self.text, self.cursor, width)
    }

    /// The input in a block's title: `prefix` then the text, within a block
    /// `width` columns wide. The text keeps at least half the room; the
    /// prefix (a node's description, which may be long) is cut first.
    pub fn title(&self, prefix: &str, width: u16) -> String {
        title(prefix, &self.text, self.cursor, width)
    }
}

/// The part of a text around its cursor that fits in `width` characters,
/// `…` where it is cut: a terminal cuts a long line on the right, so what
/// is typed past the edge would be typed blind.
pub fn window(text: &str, cursor: Option<usize>, width: usize) -> String {
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

/// `prefix` and a text with its cursor, as a block's title `width` wide.
pub fn title(prefix: &str, text: &str, cursor: Option<usize>, width: u16) -> String {
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
    format!(" {prefix}{} ", window(text, cursor, left))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_prompt_shows_the_text_around_its_cursor() {
        assert_eq!(window("why", None, 10), "why▏");
        assert_eq!(window("why", Some(1), 10), "w▏hy");
        let long = "why did look at chuck fail";
        // Typing at the end: what was just typed stays in sight.
        assert_eq!(window(long, None, 10), "…uck fail▏");
        // At the start, the rest is cut on the right.
        assert_eq!(window(long, Some(0), 10), "▏why did …");
        // Within: the cursor, what is before it, and a cut on each side.
        assert_eq!(window(long, Some(15), 10), "…look at▏…");
        for at in 0..=long.len() {
            let w = window(long, Some(at), 10);
            assert!(w.chars().count() <= 10, "{at}: {w}");
            assert_eq!(w.matches('▏').count(), 1, "{at}: {w}");
        }
    }

    #[test]
    fn edits_happen_at_the_cursor() {
        let mut t = TextInput::new("why fail");
        t.edit(Edit::Left);
        t.edit(Edit::Left);
        t.edit(Edit::Left);
        t.edit(Edit::Left);
        assert_eq!(t.cursor, Some(4));
        assert!(t.edit(Edit::Insert("did it ".into())).changed);
        assert_eq!(t.text, "why did it fail");
        assert!(t.edit(Edit::WordBack).changed);
        assert_eq!(t.text, "why did fail");
        assert!(!t.edit(Edit::Home).changed);
        assert!(!t.edit(Edit::Backspace).changed);
        t.edit(Edit::End);
        assert_eq!(t.cursor, None);
        let e = t.edit(Edit::Insert("x".repeat(PROMPT_MAX)));
        assert_eq!(e.cut, Some(12));
        assert_eq!(t.text.chars().count(), PROMPT_MAX);
        assert!(t.edit(Edit::ToStart).changed);
        assert_eq!(t.text, "");
    }
}
