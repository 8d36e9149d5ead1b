//! An engineer's shorthand spelled out before the text is read: a node's
//! initials ("LAC" for look at chuck, "CPTP" for ComputePathToPose), a
//! status as its letter or a verb made of it ("F", "S'd", "NOK'd"), a
//! tick after "@" ("@t9").

use super::words;
use crate::model::Tree;

/// Small words a writer leaves out of a name's initials ("TEI" for trial
/// and error insert).
const LEFT_OUT: &[&str] = &[
    "a", "an", "the", "at", "to", "of", "and", "with", "on", "in", "for", "from", "if", "or",
];

/// Capitals that are words of their own, never a node's initials.
const NOT_INITIALS: &[&str] = &[
    "OK", "NOK", "BT", "BTS", "ID", "UID", "XML", "ROS", "AI", "FSM", "LLM", "TUI", "CLI", "PR",
    "UTC", "RAM", "CPU", "GPU", "API", "QA", "FAQ", "ETA", "TBD", "FYI", "ASAP", "IIRC", "AFAIK",
    "IMO", "TL", "DR", "PLS", "BC", "RN", "NB", "PS", "US", "UK", "EU", "IT", "OR", "AND", "NOT",
    "IS", "IF", "DO", "AT", "TO", "OF", "ON", "IN", "NO", "SO", "AM", "PM", "LOG", "RUN", "WHY",
    "HOW", "WHAT", "WHEN", "IDLE", "FAIL", "SKIP", "TRUE", "FALSE", "DONE", "STOP", "HELP", "NOTE",
    "TODO", "WARN", "INFO", "ERROR", "DEBUG", "AMR", "AGV", "PLC", "HMI", "UI", "UX", "SLAM",
    "LIDAR", "IMU", "GPS", "MPC", "DWB", "RPP", "TEB", "BTCPP", "NAV",
];

/// The text with its shorthand spelled out; the text itself where it has
/// none.
pub(super) fn spelled_out(tree: &Tree, text: &str) -> String {
    let text = ticks_after_at(text);
    let shorthand = |t: &str| {
        let b = bare(t);
        status_letters(b).is_some() || Initials::shaped(b).is_some()
    };
    if !text.split_whitespace().any(shorthand) {
        return text;
    }
    let names = Initials::of(tree);
    text.split_whitespace()
        .map(|t| {
            let b = bare(t);
            match status_letters(b).or_else(|| names.name(b)) {
                Some(said) => t.replacen(b, &said, 1),
                None => t.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Capitals shaped as a node's initials that name no one node.
pub struct Unread {
    /// Said to the asker: none fits, or which could.
    pub told: String,
    /// Whether several names fit (none did otherwise).
    pub several: bool,
}

/// What capitals that look like a node's initials and name none of its
/// nodes, or several, are ("CPTP" asked of the kitting tree): said so,
/// rather than read as the whole task.
pub fn initials_naming_nothing(tree: &Tree, text: &str) -> Option<Unread> {
    let names = Initials::of(tree);
    let tree_words: Vec<String> = tree
        .nodes
        .iter()
        .flat_map(|n| words::words(&n.name).into_iter().chain(words::words(&n.id)))
        .map(|w| w.text)
        .collect();
    text.split_whitespace().map(bare).find_map(|b| {
        let shaped = Initials::shaped(b)?;
        if status_letters(b).is_some() || tree_words.contains(&shaped.to_ascii_lowercase()) {
            return None;
        }
        match &names.all_named(&shaped)[..] {
            [] => Some(Unread {
                told: format!("No node of this tree has the initials {b}: say its name or #uid."),
                several: false,
            }),
            [_] => None,
            several => Some(Unread {
                told: format!("{b} could be {}: say which.", several.join(" or ")),
                several: true,
            }),
        }
    })
}

/// A token without the marks around it.
fn bare(t: &str) -> &str {
    t.trim_matches(|c: char| "?!.,;:()[]\"-".contains(c))
}

/// "@9", "@ t9", "@9:2": at tick 9, at 9:2.
fn ticks_after_at(text: &str) -> String {
    if !text.contains('@') {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len() + 16);
    let mut rest = text;
    while let Some(i) = rest.find('@') {
        out.push_str(&rest[..i]);
        let after = rest[i + 1..].trim_start();
        let digits = after.strip_prefix(['t', 'T']).unwrap_or(after);
        if digits.starts_with(|c: char| c.is_ascii_digit()) {
            out.push_str(" at tick ");
            rest = digits;
        } else {
            out.push('@');
            rest = &rest[i + 1..];
        }
    }
    out.push_str(rest);
    out
}

/// A status written as its letter, or a verb made of it: "LAC F @10",
/// "FP S'd", "NWR NOK'd", "is R". Only capitals: "f" and "s" are not.
fn status_letters(b: &str) -> Option<String> {
    let b = b.replace(['’', '‘', '`', '´'], "'");
    let said = match b.as_str() {
        "F" | "F'd" | "F'D" | "NOK" | "NOK'd" | "NOK'D" | "NOKd" => "failed",
        "S" | "S'd" | "S'D" | "OK'd" | "OK'D" | "OKd" => "succeeded",
        "R" => "running",
        _ => return None,
    };
    Some(said.to_string())
}

/// A node's name or ID by its initials: those of every word, and those
/// without the small words.
struct Named {
    every_word: String,
    content_words: String,
    said: Vec<String>,
    written: String,
}

/// Names to look among, and which of their initials.
type Level<'a> = (&'a [Named], fn(&Named) -> &str);

/// The tree's names, then its IDs, each by its initials.
struct Initials {
    names: Vec<Named>,
    ids: Vec<Named>,
}

impl Initials {
    fn of(tree: &Tree) -> Initials {
        let mut names = Vec::new();
        let mut ids = Vec::new();
        for n in &tree.nodes {
            for (list, written) in [(&mut names, &n.name), (&mut ids, &n.id)] {
                let said = words::words(written);
                let initials = |keep: &dyn Fn(&str) -> bool| -> String {
                    said.iter()
                        .filter(|w| keep(&w.text))
                        .filter_map(|w| w.text.chars().next())
                        .collect()
                };
                let said: Vec<String> = said.iter().map(|w| w.text.clone()).collect();
                if said.len() < 2 || list.iter().any(|m: &Named| m.said == said) {
                    continue;
                }
                list.push(Named {
                    every_word: initials(&|_| true),
                    content_words: initials(&|w| !LEFT_OUT.contains(&w)),
                    said,
                    written: written.clone(),
                });
            }
        }
        Initials { names, ids }
    }

    /// Capitals shaped as initials ("LAC", "W&W", "CPTP's"), as capitals
    /// of the initials alone.
    fn shaped(b: &str) -> Option<String> {
        // "W&W": watch and walk.
        let b = b.replace('&', "A");
        let b = b
            .strip_suffix("'s")
            .or_else(|| b.strip_suffix("s"))
            .filter(|s| s.len() >= 2)
            .unwrap_or(&b);
        ((2..=6).contains(&b.len())
            && b.bytes().all(|c| c.is_ascii_uppercase())
            && !NOT_INITIALS.contains(&b))
        .then(|| b.to_string())
    }

    /// Every name these initials fit at the first level any fits.
    fn all_named(&self, shaped: &str) -> Vec<String> {
        let low = shaped.to_ascii_lowercase();
        self.levels()
            .into_iter()
            .map(|(list, initials)| {
                list.iter()
                    .filter(|n| initials(n) == low)
                    .map(|n| n.written.clone())
                    .collect::<Vec<_>>()
            })
            .find(|them| !them.is_empty())
            .unwrap_or_default()
    }

    fn levels(&self) -> [Level<'_>; 4] {
        [
            (&self.names, |n| &n.every_word),
            (&self.names, |n| &n.content_words),
            (&self.ids, |n| &n.every_word),
            (&self.ids, |n| &n.content_words),
        ]
    }

    /// The one name whose initials these capitals are ("LAC": look at
    /// chuck): names before IDs, the initials of every word before those
    /// without the small words; none where two names have them.
    fn name(&self, b: &str) -> Option<String> {
        match &self.all_named(&Initials::shaped(b)?)[..] {
            [n] => Some(n.clone()),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tick_after_an_at_sign_is_said_as_one() {
        assert_eq!(ticks_after_at("subgoal @30?"), "subgoal  at tick 30?");
        assert_eq!(ticks_after_at("FP F @ t7"), "FP F  at tick 7");
        assert_eq!(ticks_after_at("mail me @ home"), "mail me @ home");
    }

    fn tree() -> Tree {
        crate::xml::load_str(
            std::path::Path::new("t.xml"),
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="go">
                 <Action ID="LookAt" name="look at chuck"/>
                 <Action ID="LiftCart" name="lift cart"/>
                 <Action ID="LoadCart" name="load cart"/>
                 <Action ID="trial_and_error_insert" name="trial and error insert"/>
               </Sequence></BehaviorTree></root>"#,
            &crate::xml::LoadOptions::default(),
        )
        .unwrap()
        .tree
    }

    #[test]
    fn initials_name_the_one_node_whose_words_they_begin() {
        let t = tree();
        assert_eq!(
            spelled_out(&t, "why did LAC F @t3?"),
            "why did look at chuck failed at tick 3?"
        );
        // Without its small words, and its name and ID one name.
        assert_eq!(spelled_out(&t, "TEI R"), "trial and error insert running");
        // Two names fit: neither is picked, and the asker is told.
        assert_eq!(spelled_out(&t, "LC S'd"), "LC succeeded");
        assert_eq!(
            initials_naming_nothing(&t, "how often did LC run")
                .map(|u| u.told)
                .as_deref(),
            Some("LC could be lift cart or load cart: say which.")
        );
        assert!(initials_naming_nothing(&t, "how often did FYI run").is_none());
    }

    #[test]
    fn a_status_letter_is_a_status_only_in_capitals() {
        assert_eq!(status_letters("F'd").as_deref(), Some("failed"));
        assert_eq!(status_letters("R").as_deref(), Some("running"));
        assert_eq!(status_letters("f"), None);
        assert_eq!(status_letters("OK"), None);
    }
}
