//! What Groot2's users see, said as the status it shows: a box that went
//! red failed, one that is orange runs, one that stayed grey never ran
//! ("why is drive orange?" is "why is drive RUNNING?").

use crate::model::Tree;

/// Words before a colour that say a box shows it.
const SHOWS: &[&str] = &[
    "go",
    "goes",
    "going",
    "went",
    "gone",
    "turn",
    "turns",
    "turned",
    "turning",
    "become",
    "becomes",
    "became",
    "is",
    "was",
    "are",
    "were",
    "be",
    "been",
    "being",
    "stay",
    "stays",
    "stayed",
    "staying",
    "remain",
    "remains",
    "remained",
    "still",
    "lit",
    "light",
    "lights",
    "flash",
    "flashes",
    "flashed",
    "glow",
    "glows",
    "glowed",
    "show",
    "shows",
    "showed",
    "all",
    "everything",
    "of",
    "than",
    "and",
    "or",
    "not",
    "end",
    "ends",
    "ended",
    "finish",
    "finishes",
    "finished",
    "any",
];

/// Words after a colour that say it is a box's: "any red boxes?".
const BOXES: &[&str] = &["box", "boxes", "node", "nodes", "one", "ones"];

/// Verbs of a box left as it was: grey all along is never run.
const STAYS: &[&str] = &[
    "stay", "stays", "stayed", "staying", "remain", "remains", "remained",
];

/// A box that `verb` (went, turns, …) `colour`, said as the change it
/// shows in the verb's tense: "went red" is "failed", "turns green"
/// "succeeds", "going orange" "starting".
fn became(verb: &str, colour: &str) -> Option<String> {
    const PAST: &[&str] = &[
        "went", "gone", "turned", "became", "flashed", "lit", "glowed", "showed", "ended",
        "finished",
    ];
    const BASE: &[&str] = &[
        "go", "turn", "become", "flash", "light", "glow", "show", "end", "finish",
    ];
    const THIRD: &[&str] = &[
        "goes", "turns", "becomes", "flashes", "lights", "glows", "shows", "ends", "finishes",
    ];
    const ING: &[&str] = &[
        "going", "turning", "becoming", "flashing", "lighting", "glowing",
    ];
    let (base, past, third, ing) = match colour {
        "red" => ("fail", "failed", "fails", "failing"),
        "green" => ("succeed", "succeeded", "succeeds", "succeeding"),
        "orange" | "yellow" | "amber" => ("start", "started", "starts", "starting"),
        _ => return None,
    };
    Some(
        if PAST.contains(&verb) {
            past
        } else if BASE.contains(&verb) {
            base
        } else if THIRD.contains(&verb) {
            third
        } else if ING.contains(&verb) {
            ing
        } else {
            return None;
        }
        .to_string(),
    )
}

/// The status a colour shows.
fn status(colour: &str) -> Option<&'static str> {
    Some(match colour {
        "red" => "FAILURE",
        "green" => "SUCCESS",
        "orange" | "yellow" | "amber" => "RUNNING",
        "grey" | "gray" | "white" => "IDLE",
        _ => return None,
    })
}

/// The text with each colour a box shows said as its status; the text
/// itself where it says none, or where the tree names a node by the colour.
pub(super) fn as_statuses(tree: &Tree, text: &str) -> String {
    let lower = text.to_lowercase();
    // Most questions say no colour: they are read as they are, with no
    // word split out (this runs on each part of every question).
    const COLOURS: &[&str] = &[
        "red", "green", "orange", "yellow", "amber", "grey", "gray", "white",
    ];
    if !COLOURS.iter().any(|c| lower.contains(c)) {
        return text.to_string();
    }
    let said = |w: &str| {
        w.trim_matches(|c: char| !c.is_ascii_alphabetic())
            .to_string()
    };
    let toks: Vec<&str> = text.split_whitespace().collect();
    let lowered: Vec<String> = lower.split_whitespace().map(said).collect();
    if !lowered.iter().any(|w| status(w).is_some()) || lowered.len() != toks.len() {
        return text.to_string();
    }
    // "Red light" where a node is red_light: the colour begins a name.
    let named = |i: usize| {
        let (c, next) = (&lowered[i], lowered.get(i + 1));
        tree.nodes.iter().any(|n| {
            [&n.name, &n.id].iter().any(|x| {
                let ws: Vec<String> = x
                    .to_lowercase()
                    .split(['_', ' ', '-'])
                    .map(str::to_string)
                    .collect();
                ws.windows(2).any(|p| &p[0] == c && Some(&p[1]) == next)
            })
        })
    };
    let mut out: Vec<String> = Vec::with_capacity(toks.len());
    for (i, t) in toks.iter().enumerate() {
        let c = &lowered[i];
        let before = |k: usize| i.checked_sub(k).map(|j| lowered[j].as_str());
        let boxed = lowered
            .get(i + 1)
            .is_some_and(|n| BOXES.contains(&n.as_str()));
        let shown = boxed
            || [before(1), before(2)]
                .iter()
                .flatten()
                .any(|b| SHOWS.contains(b));
        let verb = before(1).and_then(|b| became(b, c));
        match status(c).filter(|_| shown && !named(i)) {
            Some("IDLE") if before(1).is_some_and(|b| STAYS.contains(&b)) => {
                out.pop();
                out.push("never ran".into());
            }
            // "Went red" is failed: the verb of the change, in its tense.
            Some(_) if verb.is_some() => {
                out.pop();
                let tail = &t[t
                    .to_lowercase()
                    .find(c.as_str())
                    .map_or(t.len(), |k| k + c.len())..];
                out.push(format!("{}{tail}", verb.unwrap_or_default()));
            }
            // "Any red boxes?" is any failed ones.
            Some(s) if boxed && verb.is_none() => {
                let adjective = match s {
                    "FAILURE" => "failed",
                    "SUCCESS" => "succeeded",
                    "RUNNING" => "running",
                    _ => "idle",
                };
                out.push(t.to_lowercase().replacen(c.as_str(), adjective, 1))
            }
            Some(s) => out.push(t.to_lowercase().replacen(c.as_str(), s, 1)),
            None => out.push(t.to_string()),
        }
    }
    out.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree() -> Tree {
        crate::xml::load_str(
            std::path::Path::new("t.xml"),
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><Action ID="drive"/><Condition ID="red_light"/></Sequence></BehaviorTree></root>"#,
            &crate::xml::LoadOptions::default(),
        )
        .unwrap()
        .tree
    }

    #[test]
    fn a_boxs_colour_is_its_status() {
        let t = tree();
        for (said, read) in [
            ("why is drive orange?", "why is drive RUNNING?"),
            ("why did drive go red at 5", "why did drive fail at 5"),
            (
                "what if drive had gone green instead of red",
                "what if drive had succeeded instead of FAILURE",
            ),
            ("any red boxes at all?", "any failed boxes at all?"),
            (
                "root ends green, so is everything fine?",
                "root succeeds, so is everything fine?",
            ),
            (
                "drive just went orange, what now?",
                "drive just started, what now?",
            ),
            (
                "Spin and Wait stay grey the whole run - why",
                "Spin and Wait never ran the whole run - why",
            ),
        ] {
            assert_eq!(as_statuses(&t, said), read);
        }
    }

    #[test]
    fn a_colour_that_names_a_node_or_shows_nothing_is_left() {
        let t = tree();
        for q in [
            "why did red light fail",
            "is the red light on",
            "why did it fail",
        ] {
            assert_eq!(as_statuses(&t, q), q);
        }
    }
}
