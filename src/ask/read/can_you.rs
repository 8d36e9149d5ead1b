//! "Can you X?" in its many forms ("is the taxi able to …", "is looking
//! around one of its capabilities?"): the behaviour asked for, and the
//! openings that wrap another question instead ("can you tell me why …").

use super::*;

/// Whether the words said name the behaviour the reader found: each word
/// of its name said, joined or apart ("the local cost map" names
/// ClearLocalCostmap's "costmap"), or with one letter wrong ("chuk"),
/// and not only a name that looks alike ("weld the gearbox housing" does
/// not name build a gearbox kit).
pub fn said_by(name: &str, said: &str) -> bool {
    let squeeze = |s: &str| -> String {
        s.chars()
            .filter(|c| c.is_alphanumeric())
            .flat_map(char::to_lowercase)
            .collect()
    };
    let joined = squeeze(said);
    let said_words: Vec<String> = said.split_whitespace().map(squeeze).collect();
    words::split_name(name)
        .split_whitespace()
        .map(squeeze)
        .filter(|w| !w.is_empty() && !["a", "an", "the"].contains(&w.as_str()))
        .all(|w| {
            joined.contains(&w)
                || w.len() >= 4
                    && said_words
                        .iter()
                        .any(|s| strsim::damerau_levenshtein(s, &w) <= 1)
        })
}

/// "Could you confirm how many times it failed", "can you check when
/// it stopped": a question put politely, not whether the robot can.
pub fn wraps_a_question(after: &[&str]) -> bool {
    const REPORT: &[&str] = &[
        "confirm", "check", "verify", "find", "figure", "see", "look", "work", "let", "count",
        "tell", "say", "show",
    ];
    // "Could you walk me through …", "can you explain the failure":
    // verbs that ask for an account whatever follows them.
    const ACCOUNT: &[&str] = &[
        "walk",
        "breakdown",
        "explain",
        "describe",
        "list",
        "summarize",
        "summarise",
        "remind",
        "clarify",
        "elaborate",
        "detail",
        "outline",
        // An auditor's: "could you state which …", "kindly indicate".
        "state",
        "indicate",
        "document",
        "quantify",
        "specify",
        "account",
    ];
    let Some((first, rest)) = after.split_first() else {
        return false;
    };
    let account = ACCOUNT.contains(first)
        && rest.first().is_some_and(|next| {
            // "can it walk" asks whether it can.
            *first != "walk" || ["me", "us", "through"].contains(next)
        });
    let asks = rest
        .iter()
        .any(|w| ["why", "when", "what", "which", "where", "how"].contains(w))
        || rest
            .windows(2)
            .any(|p| p[0] == "how" && ["many", "often", "much", "long"].contains(&p[1]));
    // "Could you confirm that no node failed": never a capability, where
    // "can it check whether the path is clear" is one.
    let confirm = *first == "confirm" && !rest.is_empty();
    account || REPORT.contains(first) && asks || confirm
}

/// What a robot is called in "can the taxi …": never a behaviour.
const ROBOTS: &[&str] = &[
    "robot",
    "bot",
    "taxi",
    "arm",
    "agent",
    "tree",
    "bt",
    "system",
    "car",
    "vehicle",
    "nav2",
    "navigator",
    "rover",
    "drone",
    "machine",
    "cab",
    "forklift",
    "amr",
    "turtlebot",
    "manipulator",
    // "Can this thing even dock?".
    "thing",
    "it",
];

/// The openings of "Can you X?", the robot called "robot" (see
/// [`robot_as_robot`]).
const OPENINGS: &[&[&str]] = &[
    &["can", "you"],
    &["could", "you"],
    &["can", "it"],
    &["could", "it"],
    &["are", "you", "able", "to"],
    &["is", "it", "able", "to"],
    &["are", "you", "able"],
    &["can", "robot"],
    &["could", "robot"],
    &["is", "robot", "able", "to"],
    &["are", "you", "capable", "of"],
    &["is", "robot", "capable", "of"],
    &["is", "it", "capable", "of"],
    &["do", "you", "know", "how", "to"],
    &["would", "you", "be", "able", "to"],
    &["will", "you", "be", "able", "to"],
    &["does", "robot", "know", "how", "to"],
    &["does", "robot", "have", "capability", "to"],
    &["does", "robot", "have", "ability", "to"],
    &["does", "robot", "make", "any", "provision", "for"],
    &["does", "robot", "include", "any", "means", "of"],
    &["does", "robot", "provide", "for"],
    // Translated: "is it in your capacity to", "are you capable to", "are
    // you in the condition to", "is it possible for you to", "do you have
    // the capacity of".
    &["is", "robot", "in", "capacity", "to"],
    &["are", "you", "capable", "to"],
    &["are", "you", "in", "condition", "to"],
    &["is", "robot", "possible", "for", "you", "to"],
    &["is", "robot", "possible", "to", "you", "to"],
    &["it", "is", "possible", "for", "you", "to"],
    &["do", "you", "have", "capacity", "of"],
    &["do", "you", "have", "capacity", "to"],
    &["you", "are", "able", "to"],
];

/// The words of the question that may open "Can you X?" or be its X:
/// leads, articles and a robot addressed first left out, each with its
/// place in the question.
fn free_words<'s>(s: &'s Sentence<'_>) -> Vec<(usize, &'s Word)> {
    // "Is the robot in this bag able to …", "can the bag's navigator …":
    // the record the robot is found in says which robot, not what it can.
    const RECORDS: &[&str] = &["bag", "log", "run", "recording", "rosbag", "replay"];
    let text = |i: usize| s.q.get(i).map_or("", |w: &Word| w.text.as_str());
    let of_a_record = |i: usize| {
        let record = |j: usize| RECORDS.contains(&text(j));
        let placed = |j: usize| ["in", "from", "of"].contains(&text(j));
        let article = |j: usize| ["this", "the", "that"].contains(&text(j));
        // "the bag's navigator": the record before the robot's word.
        record(i) && ROBOTS.contains(&text(i + 1))
            // "in this bag": each of its words.
            || placed(i) && (record(i + 1) || article(i + 1) && record(i + 2))
            || article(i) && i > 0 && placed(i - 1) && record(i + 1)
            || record(i) && i > 0 && (placed(i - 1) || article(i - 1) && i > 1 && placed(i - 2))
    };
    s.q.iter()
        .enumerate()
        .filter(|&(i, _)| !of_a_record(i))
        .filter(|(i, w)| {
            // "to" and "know" lead other questions ("I want to know"),
            // and are words of the openings here ("able to").
            (!LEAD.contains(&w.text.as_str()) || ["to", "know"].contains(&w.text.as_str()))
                && !["the", "a", "an", "this", "that", "your", "ur", "our", "my"]
                    .contains(&w.text.as_str())
                // "robot, can you pick a screw": the robot addressed.
                && (*i != 0 || !["robot", "bot"].contains(&w.text.as_str()))
        })
        .collect()
}

/// "Can the taxi refuel?", "does this BT know how to move down?": the
/// robot called by what it is, read as "robot"; "make the robot back up"
/// is the robot backing up. The words kept, and their texts so read
/// (`named`: whether the word at a place is in a node's name).
#[allow(clippy::type_complexity)]
fn robot_as_robot<'a>(
    free: &[(usize, &'a Word)],
    named: impl Fn(usize) -> bool,
) -> (Vec<(usize, &'a Word)>, Vec<&'a str>) {
    let asks =
        free.len() > 2 && ["can", "could", "does", "is", "will"].contains(&free[0].1.text.as_str());
    // "Can our patrol bot drive?": the robot called by a word and what it
    // is ("can reset arm fail?" names a node).
    let called = asks
        && free.len() > 3
        && free[2].1.text != "it"
        && !named(free[2].0)
        && ROBOTS.contains(&free[2].1.text.as_str())
        && !ROBOTS.contains(&free[1].1.text.as_str());
    let opens_on_robot = asks && (called || ROBOTS.contains(&free[1].1.text.as_str()));
    // Where the robot is named, its word before it left out.
    let robot = if called { 2 } else { 1 };
    let mut kept: Vec<(usize, &Word)> = Vec::with_capacity(free.len());
    let mut texts: Vec<&str> = Vec::with_capacity(free.len());
    let mut k = 0;
    while k < free.len() {
        if k == 1 && called {
            k += 1;
            continue;
        }
        let t = free[k].1.text.as_str();
        if k == robot + 1
            && opens_on_robot
            && ["make", "get", "have"].contains(&t)
            && free
                .get(k + 1)
                .is_some_and(|(_, w)| ROBOTS.contains(&w.text.as_str()))
        {
            k += 2;
            continue;
        }
        texts.push(if k == robot && opens_on_robot {
            "robot"
        } else {
            t
        });
        kept.push(free[k]);
        k += 1;
    }
    (kept, texts)
}

/// "Collision scan - can it", "welding capability?", "costmap clearing
/// possible?": X typed as into a search box, then a tag that asks whether
/// it can; nothing before the tag asks anything else.
fn tagged(s: &Sentence, tree: &Tree, free: &[(usize, &Word)], texts: &[&str]) -> Option<String> {
    const TAGS: &[&[&str]] = &[
        // "Clearing of the local costmap, is it possible for you?",
        // "walking, you can do it?".
        &["is", "it", "possible", "for", "you"],
        &["you", "can", "do", "it"],
        &["can", "it", "do", "that"],
        // "That" is read past as an article.
        &["can", "it", "do"],
        &["can", "it"],
        &["can", "you"],
        &["possible"],
        &["supported"],
        &["capability"],
    ];
    const ASKING: &[&str] = &[
        "what", "why", "how", "when", "which", "where", "who", "is", "are", "was", "were", "did",
        "does", "do", "has", "had", "will", "would", "can", "could", "not", "no", "never",
    ];
    let tag = TAGS.iter().find(|t| texts.ends_with(t))?;
    let before = &texts[..texts.len() - tag.len()];
    if before.is_empty() || before.iter().any(|w| ASKING.contains(w)) {
        return None;
    }
    let end = free[before.len()].0;
    // The node only where its name is all of X: "collision scan" is no
    // "allow partial collision".
    let whole = |m: &&Mention| {
        free[..before.len()]
            .iter()
            .all(|(i, _)| (m.start..m.end).contains(i))
    };
    if let Some(m) = s.nodes.iter().filter(|m| m.end <= end).find(whole) {
        return Some(tree.description(m.uids[0]).to_string());
    }
    // "Collision scan": the words of one name, in another order.
    // "Clearing of the local costmap": the small words are no name's.
    let said: Vec<&Word> = free[..before.len()]
        .iter()
        .map(|(_, w)| *w)
        .filter(|w| !["of", "for", "to", "the", "a", "an"].contains(&w.text.as_str()))
        .collect();
    let named = (1..=tree.len() as Uid).find(|&u| {
        let name = words::words(tree.description(u));
        said.len() > 1 && said.iter().all(|w| name.iter().any(|n| n.stem == w.stem))
    });
    Some(match named {
        Some(u) => tree.description(u).to_string(),
        None => before.join(" "),
    })
}

/// Words before "able to" that make it no call to the robot ("why was it
/// not able to", "who is able to").
const NOT_A_CALL_SIGN: &[&str] = &[
    "why", "was", "were", "is", "are", "not", "when", "how", "what", "who", "which", "be", "been",
    "never", "unable", "if", "so", "still",
];

/// How many words the opening of "Can you X?" takes, if the question
/// opens so: "Is the taxi able to …", "is this robot capable of …" name
/// the robot any way, in four words.
fn opening(texts: &[&str]) -> Option<usize> {
    // Radio talk drops the subject: "Able to spin? Over.", "Rover, able
    // to spin in place?" (a call sign first).
    let clipped = |k: usize| {
        texts.get(k..k + 2) == Some(&["able", "to"][..])
            && (k == 0 || !NOT_A_CALL_SIGN.contains(&texts[0]))
    };
    match OPENINGS.iter().find(|o| texts.starts_with(o)) {
        Some(o) => Some(o.len()),
        None if clipped(0) => Some(2),
        None if clipped(1) => Some(3),
        None if texts.len() > 4
            && ["is", "are"].contains(&texts[0])
            && (texts[2..4] == ["able", "to"] || texts[2..4] == ["capable", "of"]) =>
        {
            Some(4)
        }
        None => None,
    }
}

/// The words of "Can you X?" after its opening, or `None`.
pub(super) fn can_you(s: &Sentence, tree: &Tree) -> Option<String> {
    let named = |i: usize| s.nodes.iter().any(|m| (m.start..m.end).contains(&i));
    let (free, texts) = robot_as_robot(&free_words(s), named);
    // "Is looking around one of its capabilities?", "spinning in place: is
    // that something it can do?": the node named anywhere.
    let capability = texts
        .iter()
        .any(|w| w.starts_with("capabilit") || w.starts_with("abilit"))
        && texts.first() == Some(&"is")
        || texts.ends_with(&["can", "do"]) && texts.contains(&"something");
    if capability {
        if let Some(m) = s.nodes.first() {
            return Some(tree.description(m.uids[0]).to_string());
        }
    }
    // "Is clearing the local costmap something you can do?", "is detecting
    // screws something this robot can do?".
    if texts.first() == Some(&"is")
        && texts.ends_with(&["can", "do"])
        && texts.contains(&"something")
    {
        let from = free.get(1)?.0;
        let m = s.nodes.iter().find(|m| m.start >= from)?;
        return Some(tree.description(m.uids[0]).to_string());
    }
    if let Some(x) = tagged(s, tree, &free, &texts) {
        return Some(x);
    }
    let open = opening(&texts)?;
    // "can you tell me why …" asks what follows.
    // "Could you kindly explain …": the courtesy asks nothing.
    let open = open
        + texts[open.min(texts.len())..]
            .iter()
            .take_while(|w| ["please", "kindly", "pls"].contains(*w))
            .count();
    let next = texts.get(open).copied().unwrap_or("");
    if wraps_a_question(&texts[open.min(texts.len())..])
        || IMPERATIVE.contains(&next)
        || next == "justify"
        || ["still", "do"].contains(&next) && texts.len() == open + 1
    {
        return None;
    }
    let from = free.get(open)?.0;
    if let Some(m) = s.nodes.iter().find(|m| m.start >= from) {
        return Some(tree.description(m.uids[0]).to_string());
    }
    let rest: Vec<&str> = s.q[from..]
        .iter()
        .map(|w| w.text.as_str())
        .filter(|w| !["the", "a", "an", "please", "again", "itself", "yourself"].contains(w))
        .collect();
    (!rest.is_empty()).then(|| rest.join(" "))
}
