//! Levels of detail: `brief` is the restated question and one sentence,
//! the cause; `normal` the answer as it is; `full` every explanation and,
//! for each node it rests on, what the run shows of it: its transitions
//! in the tick with their tick:step, its ports with the blackboard values
//! they read, and a loop's attempts.

use crate::model::{PortValue, Tree, Uid};
use crate::run::blackboard::Blackboard;
use crate::session::At;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Detail {
    Brief,
    #[default]
    Normal,
    Full,
}

impl Detail {
    pub fn parse(s: &str) -> Option<Detail> {
        match s {
            "brief" => Some(Detail::Brief),
            "normal" => Some(Detail::Normal),
            "full" => Some(Detail::Full),
            _ => None,
        }
    }
}

/// The sentence of an answer a brief one keeps: the first that gives a
/// cause ("… because …"), else the first (numbering of an explanation
/// list left out).
pub fn first_sentence(answer: &str) -> String {
    let line = answer.lines().next().unwrap_or("");
    let line = match line.split_once(". ") {
        Some((n, rest)) if n.chars().all(|c| c.is_ascii_digit()) => rest,
        _ => line,
    };
    let mut sentences = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find(". ") {
        sentences.push(&rest[..=i]);
        rest = &rest[i + 2..];
    }
    if !rest.is_empty() {
        sentences.push(rest);
    }
    sentences
        .iter()
        .find(|s| s.contains(" because "))
        .or(sentences.first())
        .map_or(String::new(), |s| s.to_string())
}

/// What the run shows of each node, at the moment, in its tick.
pub fn facts(tree: &Tree, at: &At, nodes: &[Uid]) -> Vec<String> {
    let tick = at.moment().tick;
    let range = at.index.tick_range(tick);
    let bb = Blackboard::new(tree);
    let mut out = Vec::new();
    for &u in nodes {
        let n = tree.node(u);
        let moves: Vec<String> = at
            .index
            .changes_of(u)
            .iter()
            .copied()
            .filter(|&p| range.contains(&(p as usize - 1)) && p <= at.pos)
            .map(|p| {
                let t = at.index.transitions[p as usize - 1];
                let step = p - range.start as u32;
                format!(
                    "{} → {} at {tick}:{step}",
                    t.prev.as_str(),
                    t.status.as_str()
                )
            })
            .collect();
        let mut line = format!("{}: ", tree.told(u));
        line.push_str(&if moves.is_empty() {
            format!(
                "no transition in tick {tick}; {} then",
                at.status(u).as_str()
            )
        } else {
            moves.join(", ")
        });
        let ports: Vec<String> = n
            .ports
            .iter()
            .map(|p| {
                let read = bb
                    .port_entry(tree, n.scope, &p.value)
                    .and_then(|e| at.entry(&e).map(|v| format!(" = {v}")))
                    .unwrap_or_default();
                match &p.value {
                    PortValue::Literal(s) => format!("{}={s:?}", p.name),
                    v => format!("{}={}{read}", p.name, v.to_xml()),
                }
            })
            .collect();
        if !ports.is_empty() {
            line.push_str(&format!("; ports {}", ports.join(", ")));
        }
        if matches!(
            n.builtin,
            Some(crate::model::Builtin::RetryUntilSuccessful | crate::model::Builtin::Repeat)
        ) {
            line.push_str(&format!("; attempts so far {}", at.attempts(u)));
        }
        out.push(line);
    }
    out
}

/// The robot's time of day at each moment `text` names (`10:1`, "tick
/// 26"), where the run keeps it: "Times (the robot's clock, UTC): 9:2
/// 01:55:41.791, …".
pub fn times_of(text: &str, session: &crate::session::Session) -> Option<String> {
    use crate::session::Moment;
    let times = &session.times_us;
    if times.is_empty() {
        return None;
    }
    let words: Vec<&str> = text
        .split_whitespace()
        .map(|w| w.trim_matches(|c: char| !c.is_ascii_alphanumeric()))
        .collect();
    let mut said: Vec<String> = Vec::new();
    for (i, w) in words.iter().enumerate() {
        // TICK:STEP (a time of day, 01:55:41.796, has two colons), or
        // "tick N", the end of that tick.
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        let (label, m) = match w.split_once(':') {
            Some((t, s)) if digits(t) && digits(s) => match Moment::parse(w) {
                Ok(m) => (w.to_string(), m),
                Err(_) => continue,
            },
            None if *w == "tick" => match words.get(i + 1).and_then(|n| n.parse().ok()) {
                Some(tick) => (format!("tick {tick}"), Moment { tick, step: None }),
                None => continue,
            },
            _ => continue,
        };
        let Ok(p) = session.index.position(m) else {
            continue;
        };
        let Some(&us) = (p as usize).checked_sub(1).and_then(|k| times.get(k)) else {
            continue;
        };
        let t = format!("{label} {}", crate::clock::clock(us));
        if !said.contains(&t) {
            said.push(t);
        }
    }
    (!said.is_empty()).then(|| format!("Times (the robot's clock, UTC): {}.", said.join(", ")))
}

/// A `why` answer at a level of detail, its question line first: brief,
/// the first explanation's sentence; normal, three explanations and how
/// many more; full, every one and the facts of the nodes they rest on.
pub fn why_text(
    w: &mut crate::causal::Why,
    session: &crate::session::Session,
    d: Detail,
) -> String {
    let moment = crate::session::Moment::parse(&w.moment).ok();
    match d {
        Detail::Brief => {
            let text = w.text();
            let (asked, body) = text.split_once('\n').unwrap_or((text.as_str(), ""));
            // A cause found at a call the model does not hold comes first.
            let sentences: Vec<String> = w
                .call_sentences()
                .into_iter()
                .chain(w.sentences())
                .collect();
            let first = first_sentence(sentences.first().map_or(body, String::as_str));
            format!("{asked}\n{first}\n")
        }
        Detail::Normal => {
            w.shown = Some(3);
            w.text()
        }
        Detail::Full => {
            w.shown = None;
            w.full = true;
            let mut text = w.text();
            let mut nodes: Vec<Uid> = Vec::new();
            for g in 0..w.groups().len() {
                for u in w.reason_nodes(g) {
                    if !nodes.contains(&u) {
                        nodes.push(u);
                    }
                }
            }
            let at = moment.and_then(|m| session.at(m).ok());
            if let (Some(at), false) = (at, nodes.is_empty()) {
                text.push_str("What the run shows of the nodes these rest on:\n");
                for l in facts(&session.tree, &at, &nodes) {
                    text.push_str(&format!("  {l}\n"));
                }
            }
            if let Some(times) = times_of(&text, session) {
                text.push_str(&times);
                text.push('\n');
            }
            text
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_sentence_leaves_out_numbering_and_what_follows() {
        assert_eq!(
            first_sentence("1. L0 failed because X_a was false. If X_a had been true, L0 would have succeeded.\n   formally: X_a^0 = false"),
            "L0 failed because X_a was false."
        );
        assert_eq!(first_sentence("I lift torso."), "I lift torso.");
        assert_eq!(
            first_sentence("I am retrying for attempt 1 to go insert large gear. I could not insert large gear because look at chuck failed."),
            "I could not insert large gear because look at chuck failed."
        );
        assert_eq!(Detail::parse("full"), Some(Detail::Full));
        assert_eq!(Detail::parse("loud"), None);
    }
}
