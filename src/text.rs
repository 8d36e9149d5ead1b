//! Text that reaches a terminal: data from files (node names, IDs, ports,
//! log decisions, script messages) must never drive the terminal, so every
//! control character is shown as a visible escape. JSON needs none of this:
//! it escapes control characters by its own rules.

use std::borrow::Cow;

/// A character a terminal would act on, or that would make a name read
/// as another: C0 but newline and tab, DEL, C1, and Unicode's format
/// characters that reorder or hide text (bidi embeddings, overrides and
/// isolates, zero-width spaces and joiners, the word joiner, the byte order
/// mark, the line and paragraph separators): `as\u{200b}k` is not `ask`.
fn is_hostile(c: char) -> bool {
    (c < ' ' && c != '\n' && c != '\t')
        || c == '\u{7f}'
        || ('\u{80}'..='\u{9f}').contains(&c)
        || ('\u{200b}'..='\u{200f}').contains(&c)
        || ('\u{202a}'..='\u{202e}').contains(&c)
        || ('\u{2060}'..='\u{2064}').contains(&c)
        || ('\u{2066}'..='\u{2069}').contains(&c)
        || c == '\u{2028}'
        || c == '\u{2029}'
        || c == '\u{feff}'
}

/// `s` with every control character shown as an escape: ESC as `\x1b`,
/// C1 as `\u{9b}`.
pub fn visible(s: &str) -> Cow<'_, str> {
    // Printable ASCII, line breaks and tabs are most of what btx prints
    // (a log's table of millions of rows): a byte test settles it.
    let plain = |b: &u8| (b' '..0x7f).contains(b) || *b == b'\n' || *b == b'\t';
    if s.as_bytes().iter().all(plain) || !s.chars().any(is_hostile) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if !is_hostile(c) {
            out.push(c);
        } else if (c as u32) < 0x80 {
            out.push_str(&format!("\\x{:02x}", c as u32));
        } else {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        }
    }
    Cow::Owned(out)
}

/// A file's name as btx says it: its line breaks and tabs as `\n`, `\r`
/// and `\t`, so that a name can never start a line of a report or an
/// error of its own (the rest is escaped wherever btx prints, `visible`).
pub fn path(p: &std::path::Path) -> String {
    one_line(&p.display().to_string())
}

/// `s` with its line breaks and tabs as `\n`, `\r` and `\t`: a place
/// named in a message (a file's name in it) keeps to its line.
pub fn one_line(s: &str) -> String {
    s.replace('\n', "\\n")
        .replace('\r', "\\r")
        .replace('\t', "\\t")
}

/// `s` with every control character replaced by `?`s of the same length in
/// bytes, so that byte offsets into it (an error's span) stay right.
pub fn same_length(s: &str) -> Cow<'_, str> {
    if !s.chars().any(is_hostile) {
        return Cow::Borrowed(s);
    }
    Cow::Owned(
        s.chars()
            .map(|c| {
                if is_hostile(c) {
                    "?".repeat(c.len_utf8())
                } else {
                    c.to_string()
                }
            })
            .collect(),
    )
}

/// At most the first `max` bytes of `s` (on a character boundary), with
/// `…` and the length when it was cut: what an error quotes of a long input.
pub fn clip(s: &str, max: usize) -> Cow<'_, str> {
    if s.len() <= max {
        return Cow::Borrowed(s);
    }
    let mut end = max;
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    Cow::Owned(format!("{}… ({} bytes in all)", &s[..end], s.len()))
}

/// "1 run", "1,234 transitions": a count of things, its digits grouped.
pub fn counted(n: usize, what: &str) -> String {
    let digits = n.to_string();
    let mut grouped = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            grouped.push(',');
        }
        grouped.push(c);
    }
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{grouped} {what}s")
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn counts_group_their_digits_and_agree_in_number() {
        assert_eq!(super::counted(1, "run"), "1 run");
        assert_eq!(super::counted(0, "run"), "0 runs");
        assert_eq!(super::counted(999, "tick"), "999 ticks");
        assert_eq!(
            super::counted(1_234_567, "transition"),
            "1,234,567 transitions"
        );
    }

    use super::*;

    #[test]
    fn control_characters_become_visible() {
        assert_eq!(visible("plain\ttext\n"), "plain\ttext\n");
        assert_eq!(visible("a\u{1b}]0;title\u{7}b"), "a\\x1b]0;title\\x07b");
        assert_eq!(visible("\u{9b}2J\u{7f}"), "\\u{9b}2J\\x7f");
        assert_eq!(visible("é ✓ 中"), "é ✓ 中");
        // Format characters that reorder or hide text.
        assert_eq!(visible("as\u{200b}k"), "as\\u{200b}k");
        assert_eq!(visible("\u{202e}evil"), "\\u{202e}evil");
        assert_eq!(
            visible("a\u{2066}b\u{2069}\u{2028}"),
            "a\\u{2066}b\\u{2069}\\u{2028}"
        );
    }

    #[test]
    fn clip_cuts_long_text_on_a_character_boundary() {
        assert_eq!(clip("short", 10), "short");
        assert_eq!(clip("ééé", 3), "é… (6 bytes in all)");
    }

    #[test]
    fn same_length_keeps_offsets() {
        let s = "x\u{1b}[2J\u{9b}y";
        let t = same_length(s);
        assert_eq!(t.len(), s.len());
        assert_eq!(t, "x?[2J??y");
    }
}

/// A label as Mermaid reads it inside `["…"]`: quotes and the characters
/// Mermaid or its HTML would take as syntax become entity codes.
pub fn mermaid_label(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' => out.push_str("#quot;"),
            '#' => out.push_str("#35;"),
            '<' => out.push_str("#lt;"),
            '>' => out.push_str("#gt;"),
            '&' => out.push_str("#amp;"),
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod mermaid_tests {
    #[test]
    fn labels_cannot_break_out_of_their_quotes() {
        assert_eq!(
            super::mermaid_label(r#"say "hi" #2 <b>&"#),
            "say #quot;hi#quot; #35;2 #lt;b#gt;#amp;"
        );
    }
}
