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

/// "The look_at with pose={object pose}", "the action with
/// controller_id=\"FollowPath\"": a port and its value, as the XML writes
/// them, pick the nodes that have it. Where a name said just before is one
/// of those nodes' (or no name is said and the port picks one node), the
/// name and the port are written as that node's #uid.
pub(super) fn ports_as_uids(tree: &Tree, text: &str) -> String {
    if !text.contains('=') {
        return text.to_string();
    }
    let mut toks: Vec<String> = text.split_whitespace().map(str::to_string).collect();
    let mut i = 0;
    while i < toks.len() {
        let Some((key, value, end, tail)) = port_said(&toks, i) else {
            i += 1;
            continue;
        };
        let having: Vec<Uid> = tree
            .nodes
            .iter()
            .filter(|n| has_port(n, &key, &value))
            .map(|n| n.uid)
            .collect();
        let Some(said) = said_with(tree, &toks, i, &having) else {
            i = end;
            continue;
        };
        let (from, uid) = said;
        // What the port was said with goes: "(the one with", "with", ")".
        let mut out: Vec<String> = toks[..from].to_vec();
        out.push(format!("#{uid}"));
        if !tail.is_empty() {
            out.push(tail.to_string());
        }
        let next = out.len();
        out.extend(toks[end..].iter().cloned());
        toks = out;
        i = next;
    }
    toks.join(" ")
}

/// The port said at token `i` ("pose={object", "pose})"): its key (without
/// `in:` or `out:`), its value, the token after it, and what its last
/// token holds after the value (")?").
fn port_said(toks: &[String], i: usize) -> Option<(String, String, usize, String)> {
    let t = toks[i].trim_start_matches(['(', '[', ',']);
    let (key, rest) = t.split_once('=')?;
    let key = key.rsplit(':').next()?.to_lowercase();
    if key.is_empty() || !key.chars().all(|c| c.is_alphanumeric() || c == '_') {
        return None;
    }
    let close = match rest.chars().next()? {
        '"' => '"',
        '\'' => '\'',
        '{' => '}',
        _ => {
            let v = rest.trim_end_matches(|c: char| ")],;?!.".contains(c));
            let tail = rest[v.len()..].trim_start_matches(')').to_string();
            return (!v.is_empty()).then(|| (key, v.to_lowercase(), i + 1, tail));
        }
    };
    let mut value = rest[1..].to_string();
    let mut end = i + 1;
    while !value.contains(close) {
        let next = toks.get(end)?;
        value.push(' ');
        value.push_str(next);
        end += 1;
        if end - i > 12 {
            return None;
        }
    }
    let at = value.find(close)?;
    let tail = value[at + 1..].trim_start_matches(')').to_string();
    Some((key, value[..at].trim().to_lowercase(), end, tail))
}

fn has_port(n: &crate::model::Node, key: &str, value: &str) -> bool {
    let plain = |v: &str| {
        v.trim_matches(|c: char| "{}\"' ".contains(c))
            .to_lowercase()
    };
    n.ports
        .iter()
        .any(|p| p.name.to_lowercase() == key && plain(&p.value.to_xml()) == plain(value))
}

/// The node of `having` a port picks, and the token its words start at:
/// a name said within the few words before the port that is one of
/// theirs, or the port alone where it picks one node (then the words that
/// lead to it, "the node with", go with it).
fn said_with(tree: &Tree, toks: &[String], i: usize, having: &[Uid]) -> Option<(usize, Uid)> {
    if having.is_empty() {
        return None;
    }
    let mut start = i;
    while start > 0 && i - start < 10 {
        let t = &toks[start - 1];
        if t.ends_with(['.', '?', '!', ';']) {
            break;
        }
        start -= 1;
    }
    let before: Vec<(usize, String)> = (start..i)
        .flat_map(|k| words::name_words(&toks[k]).into_iter().map(move |w| (k, w)))
        .collect();
    // "The one with", "node (in:", "-": only words that lead to a port
    // may come between the name and it ("detect_chuck again - the one
    // with" says more than which node; "has" makes a statement of it).
    let lead = |t: &str| {
        let t = t
            .trim_matches(|c: char| "(),-–—:".contains(c))
            .to_lowercase();
        t.is_empty()
            || [
                "with", "having", "whose", "one", "node", "the", "a", "an", "in", "out", "inout",
            ]
            .contains(&t.as_str())
            || super::mentions::is_kind_word(&t)
    };
    let named_at = |u: Uid| {
        let n = tree.node(u);
        [&n.name, &n.id].into_iter().find_map(|s| {
            let said = words::name_words(s);
            if said.is_empty() || said.len() > before.len() {
                return None;
            }
            (0..=before.len() - said.len())
                .rev()
                .find(|&k| {
                    before[k..k + said.len()]
                        .iter()
                        .map(|b| &b.1)
                        .eq(said.iter())
                        && toks[before[k + said.len() - 1].0 + 1..i]
                            .iter()
                            .all(|t| lead(t))
                })
                .map(|k| before[k].0)
        })
    };
    let named: Vec<(usize, Uid)> = having
        .iter()
        .filter_map(|&u| named_at(u).map(|k| (k, u)))
        .collect();
    match (&named[..], having) {
        ([one], _) => Some(*one),
        // "The node with", "the one with", "the action having": the port
        // picks the node ("has success_count=2" tells of it).
        ([], [u])
            if i > start
                && ["with", "having", "whose", "("]
                    .contains(&toks[i - 1].to_lowercase().as_str())
                || toks[i].starts_with('(') =>
        {
            let mut from = i;
            while from > start && lead(&toks[from - 1]) {
                from -= 1;
            }
            Some((from, *u))
        }
        _ => None,
    }
}

/// "The Act named FollowPath", "the Fallback called FollowPath": an ID (or
/// a kind word) and a name, as the XML's `ID` and `name` say them, are the
/// one node that has both.
pub(super) fn named_as_uids(tree: &Tree, text: &str) -> String {
    let toks: Vec<&str> = text.split_whitespace().collect();
    let Some(at) = toks
        .iter()
        .position(|t| ["named", "called"].contains(&t.to_lowercase().as_str()))
        .filter(|&at| at > 0)
    else {
        return text.to_string();
    };
    let kind = toks[at - 1].trim_matches(|c: char| !c.is_alphanumeric());
    let kind_said = words::name_words(kind);
    // The nodes of that ID or kind, each with its name's words, read once.
    let of_kind: Vec<(&crate::model::Node, Vec<String>)> = tree
        .nodes
        .iter()
        .filter(|n| {
            words::name_words(&n.id) == kind_said
                || super::mentions::of_kind(&kind.to_lowercase(), n)
        })
        .map(|n| (n, words::name_words(&n.name)))
        .collect();
    for len in (1..=4.min(toks.len() - at - 1)).rev() {
        let name = toks[at + 1..at + 1 + len].join(" ");
        let bare = name.trim_end_matches(|c: char| "?!.,;:)'\"".contains(c));
        let name_said = words::name_words(bare);
        let mut both = of_kind
            .iter()
            .filter(|(_, said)| *said == name_said)
            .map(|(n, _)| n);
        if let (Some(n), None) = (both.next(), both.next()) {
            let mut out: Vec<String> = toks[..at - 1].iter().map(|t| t.to_string()).collect();
            out.push(format!("#{}{}", n.uid, &name[bare.len()..]));
            out.extend(toks[at + 1 + len..].iter().map(|t| t.to_string()));
            return out.join(" ");
        }
    }
    text.to_string()
}
