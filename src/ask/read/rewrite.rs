//! The text made plainer before it is read: a condition's state said as
//! its outcome ("path clear stayed true"), a path of names as the uid it
//! names.

use super::*;

/// A path ("go insert large gear/look at chuck") picks a node as it does
/// everywhere in btx: the longest that picks one is written as its #uid.
/// "Was the path clear?", "if the path had been clear", "why was the
/// battery not ok": a condition named as a thing and its state ("path
/// clear", "battery ok") said with a verb between them is the condition
/// succeeding, or failing with "not". The span is said as the reader reads
/// outcomes: "did path clear succeed", "path clear failed".
pub(super) fn states_as_outcomes(tree: &Tree, text: &str) -> String {
    const BE: &[&str] = &[
        "is", "was", "were", "are", "be", "been", "being", "had", "has", "have", "isnt", "wasnt",
        "werent", "arent", "not", "never", "stayed", "stay", "stays", "remained", "remain",
        "remains", "still", "last", "reported", "as",
    ];
    // "How many times did it find the path clear?".
    const FOUND: &[&str] = &["find", "found", "finds", "saw", "see", "sees"];
    const ASKING: &[&str] = &[
        "is", "was", "were", "are", "isnt", "wasnt", "werent", "arent",
    ];
    const NOT: &[&str] = &["not", "never", "isnt", "wasnt", "werent", "arent"];
    let toks: Vec<&str> = text.split_whitespace().collect();
    let low: Vec<String> = toks
        .iter()
        .map(|t| {
            t.chars()
                .filter(|c| c.is_alphanumeric())
                .collect::<String>()
                .to_lowercase()
        })
        .collect();
    let article = |i: usize| matches!(low[i].as_str(), "the" | "a" | "an" | "its");
    for n in tree.nodes.iter().filter(|n| n.kind == Kind::Condition) {
        let d = tree.description(n.uid);
        let name: Vec<String> = d
            .split(|c: char| c.is_whitespace() || c == '_')
            .filter(|w| !w.is_empty())
            .map(str::to_lowercase)
            .collect();
        if name.len() < 2 {
            continue;
        }
        let (thing, state) = name.split_at(name.len() - 1);
        for i in 0..low.len().saturating_sub(thing.len()) {
            if low[i..i + thing.len()] != *thing {
                continue;
            }
            let mut start = i;
            if start > 0 && article(start - 1) {
                start -= 1;
            }
            // "was the path (not) clear": asked, the verb first.
            let after = i + thing.len();
            let not_after = low.get(after).is_some_and(|w| NOT.contains(&w.as_str()));
            let end = after + usize::from(not_after);
            // Not "was path clear checked": the name, then a passive verb.
            let passive = low.get(end + 1).is_some_and(|w| w.ends_with("ed"));
            if start > 0
                && ASKING.contains(&low[start - 1].as_str())
                && low.get(end) == Some(&state[0])
                && !passive
            {
                let failed = not_after || NOT.contains(&low[start - 1].as_str());
                let said = format!("did {d} {}", if failed { "fail" } else { "succeed" });
                return spliced(&toks, start - 1, end + 1, &said);
            }
            if start > 0
                && FOUND.contains(&low[start - 1].as_str())
                && low.get(after) == Some(&state[0])
            {
                let said = format!("{d} succeeded");
                return spliced(&toks, start - 1, after + 1, &said);
            }
            // "the path had (not) been clear": told, the verb between.
            let mut j = after;
            let mut failed = false;
            while j < low.len() && BE.contains(&low[j].as_str()) {
                failed |= NOT.contains(&low[j].as_str());
                j += 1;
            }
            if j > after && low.get(j) == Some(&state[0]) {
                let said = format!("{d} {}", if failed { "failed" } else { "succeeded" });
                return spliced(&toks, start, j + 1, &said);
            }
        }
    }
    text.to_string()
}

/// `toks` with `toks[from..to]` said as `said`, the last token's closing
/// punctuation kept.
fn spliced(toks: &[&str], from: usize, to: usize, said: &str) -> String {
    let tail: String = toks[to - 1]
        .chars()
        .rev()
        .take_while(|c| !c.is_alphanumeric())
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    let mut out: Vec<String> = toks[..from].iter().map(|t| t.to_string()).collect();
    out.push(format!("{said}{tail}"));
    out.extend(toks[to..].iter().map(|t| t.to_string()));
    out.join(" ")
}

/// A name written as code writes it ("detect_chuck", "DetectChuck") is
/// the one node whose ID or name is written so, where the words alone
/// would name several ("detect chuck" is also the Sequence above it). A
/// built-in's ID ("ReactiveSequence") names its kind, not a node.
pub(super) fn ids_as_uids(tree: &Tree, text: &str) -> String {
    let as_code = |t: &str| {
        t.contains('_')
            || t.as_bytes()
                .windows(2)
                .any(|w| w[0].is_ascii_lowercase() && w[1].is_ascii_uppercase())
    };
    if !text.split_whitespace().any(as_code) {
        return text.to_string();
    }
    let toks: Vec<String> = text
        .split_whitespace()
        .map(|t| {
            let bare = t.trim_matches(|c: char| "?!.,;'\"()".contains(c));
            if !as_code(bare) {
                return t.to_string();
            }
            if tree
                .nodes
                .iter()
                .any(|n| n.builtin.is_some() && n.id == bare)
            {
                return t.to_string();
            }
            let mut written = tree.nodes.iter().filter(|n| n.id == bare || n.name == bare);
            let (Some(n), None) = (written.next(), written.next()) else {
                return t.to_string();
            };
            let said = words::name_words(bare);
            let alike = tree
                .nodes
                .iter()
                .filter(|m| words::name_words(&m.name) == said || words::name_words(&m.id) == said)
                .count();
            if alike > 1 {
                t.replace(bare, &format!("#{}", n.uid))
            } else {
                t.to_string()
            }
        })
        .collect();
    toks.join(" ")
}

pub(super) fn paths_as_uids(tree: &Tree, text: &str) -> String {
    if !text.contains('/') {
        return text.to_string();
    }
    let toks: Vec<&str> = text.split_whitespace().collect();
    for len in (1..=toks.len().min(12)).rev() {
        for i in 0..=toks.len() - len {
            let span = toks[i..i + len].join(" ");
            if !span.contains('/') {
                continue;
            }
            let bare = span.trim_matches(|c: char| "?!.,'\"".contains(c));
            if let Ok(uid) = crate::pick::pick(tree, bare) {
                let mut out: Vec<String> = toks[..i].iter().map(|t| t.to_string()).collect();
                out.push(format!("#{uid}"));
                out.extend(toks[i + len..].iter().map(|t| t.to_string()));
                return out.join(" ");
            }
        }
    }
    text.to_string()
}
