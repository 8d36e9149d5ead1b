//! An instructor's task read as the question it sets: the marks, the
//! part labels and the instructions to justify are not what is asked
//! ("Part (a): … (3 marks)", "Justify your answer using the log."); a
//! verb that sets the task ("State", "Identify", "Predict") asks as "tell
//! me" does; "Account for X" asks why X; "True or false: S" asks whether
//! S. A node's settings quoted beside its name ("NavigateRecovery (root,
//! number_of_retries=6)") say which node is meant, not what is asked.

/// Words that label a part of a worksheet, before its number or letter.
const LABELS: &[&str] = &[
    "part",
    "question",
    "q",
    "task",
    "exercise",
    "problem",
    "lab",
    "sheet",
    "worksheet",
    "scenario",
    "hypothetical",
    "bonus",
];

/// Verbs that set a task, asking what "tell me" asks.
const SETS: &[&str] = &[
    "state",
    "identify",
    "name",
    "determine",
    "predict",
    "decide",
    "sketch",
    "indicate",
    "specify",
];

/// Openings that put a claim to be judged: what follows is asked as a
/// question.
const CLAIMS: &[&str] = &[
    "true or false:",
    "true or false?",
    "agree or disagree:",
    "test this claim against the log:",
    "test this claim:",
    "decide whether the following statement is correct, giving evidence:",
    "decide whether the following statement is correct:",
    "is the following statement correct:",
];

/// Instructions that ask for nothing more than what the task asks.
const INSTRUCTIONS: &[&str] = &[
    "justify",
    "explain.",
    "explain your",
    "discuss",
    "support your",
    "give evidence",
    "show your",
    "name the node",
    "identify the node",
    "use the log",
];

/// Phrases that say how to answer, not what.
const HOW_TO_ANSWER: &[&str] = &[
    ", giving evidence",
    " giving evidence",
    " with reference to the log",
    " with reference to the tree",
    " using the log",
    " using the tree",
    " in one line,",
    " in a single sentence,",
    " in one sentence,",
    ", in a single sentence,",
    " briefly",
];

/// The text as the task it sets asks it; the text itself where it sets
/// none.
pub(super) fn as_asked(text: &str) -> String {
    if !text.is_ascii() {
        return text.to_string();
    }
    let mut t = without_marks_or_settings(text);
    t = without_a_case_id(&t).to_string();
    t = without_labels(&t);
    t = claim_asked(&t);
    t = format!(" {}", without_instructions(&t));
    // ASCII (above): the lowercase copy keeps the text's offsets.
    let mut lower = t.to_ascii_lowercase();
    for p in HOW_TO_ANSWER {
        while let Some(i) = lower.find(p) {
            let keep = if p.ends_with(',') { "," } else { "" };
            t.replace_range(i..i + p.len(), keep);
            lower.replace_range(i..i + p.len(), keep);
        }
    }
    let t = replaced_words(&t);
    let t = t.trim().trim_start_matches([',', ' ']).to_string();
    if t.is_empty() {
        text.to_string()
    } else {
        t
    }
}

/// "(2 marks)", "[1 mark]", "(3 pts)", "(number_of_retries=1)" taken out.
fn without_marks_or_settings(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find(['(', '[']) {
        let close = if rest.as_bytes()[i] == b'(' { ')' } else { ']' };
        let Some(j) = rest[i..].find(close).map(|j| i + j) else {
            break;
        };
        let inner = rest[i + 1..j].trim().to_lowercase();
        let marks = inner.split_once(' ').is_some_and(|(n, w)| {
            n.chars().all(|c| c.is_ascii_digit())
                && ["mark", "marks", "pt", "pts", "point", "points"].contains(&w)
        });
        // A port set as the XML sets it: "name=value", no space between.
        let setting = inner.split_once('=').is_some_and(|(k, v)| {
            k.ends_with(|c: char| c.is_alphanumeric() || c == '_')
                && !v.is_empty()
                && !v.starts_with(' ')
        });
        out.push_str(&rest[..i]);
        if !marks && !setting {
            out.push_str(&rest[i..=j]);
        }
        rest = &rest[j + 1..];
    }
    out.push_str(rest);
    out
}

/// "Part (a):", "Q6 (hypothetical).", "Lab sheet 3:", "Scenario:" taken
/// from the start.
fn without_labels(text: &str) -> String {
    let mut t = text.trim_start();
    loop {
        let toks: Vec<&str> = t.split_whitespace().take(4).collect();
        let labelish = |w: &str| {
            let b = w
                .trim_end_matches([':', '.', ')', '-'])
                .trim_start_matches('(')
                .trim_end_matches(')')
                .to_lowercase();
            LABELS.contains(&b.as_str())
                || !b.is_empty() && b.chars().all(|c| c.is_ascii_digit())
                || b.len() == 1 && w.starts_with('(')
                || b.starts_with('q') && b.len() > 1 && b[1..].chars().all(|c| c.is_ascii_digit())
        };
        let ends = |w: &str| w.ends_with(':') || w.ends_with('.') || w.ends_with(')');
        let first_is_label = toks.first().is_some_and(|w| {
            let b = w.trim_end_matches([':', '.']).to_lowercase();
            LABELS.contains(&b.as_str())
                || b.starts_with('q') && b.len() > 1 && b[1..].chars().all(|c| c.is_ascii_digit())
        });
        let Some(n) = (1..=toks.len())
            .find(|&n| toks[..n].iter().all(|w| labelish(w)) && ends(toks[n - 1]))
            .filter(|_| first_is_label)
        else {
            return t.to_string();
        };
        let cut = toks[..n]
            .iter()
            .map(|w| t.find(w).unwrap_or(0) + w.len())
            .max()
            .unwrap_or(0);
        t = t[cut..].trim_start();
    }
}

/// A test case's id and title ("TC-T28:", "BT-7 'retry on fail':") are
/// not asked: "TC-T28: in which tick did X succeed?" names no tick 28.
fn without_a_case_id(text: &str) -> &str {
    let t = text.trim_start();
    let Some(id) = t.split_whitespace().next() else {
        return text;
    };
    let bare = id.trim_end_matches(':');
    let is_id = bare.split_once('-').is_some_and(|(letters, rest)| {
        (1..=4).contains(&letters.len())
            && letters.chars().all(|c| c.is_ascii_alphabetic())
            && rest.chars().any(|c| c.is_ascii_digit())
            && rest.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')
    });
    if !is_id {
        return text;
    }
    let after = t[id.len()..].trim_start();
    if id.ends_with(':') {
        return after;
    }
    // A quoted title, then the colon.
    match after.chars().next() {
        Some(q @ ('\'' | '"')) => after[1..]
            .find(q)
            .and_then(|end| after[end + 2..].strip_prefix(':'))
            .map_or(text, str::trim_start),
        Some(':') => after[1..].trim_start(),
        _ => text,
    }
}

/// "True or false: L0 failed. Justify." asks "L0 failed?".
fn claim_asked(text: &str) -> String {
    let lower = text.to_lowercase();
    let Some(c) = CLAIMS.iter().find(|c| lower.starts_with(*c)) else {
        return text.to_string();
    };
    let rest = text[c.len()..].trim();
    let (claim, after) = match rest.find(". ") {
        Some(i) => (&rest[..i], &rest[i + 1..]),
        None => (rest.trim_end_matches('.'), ""),
    };
    let claim = claim
        .trim_matches(['\'', '"', ' ', '.'])
        .trim_end_matches(['\'', '"', '.']);
    format!("{claim}?{after}")
}

/// Sentences that only instruct ("Justify your answer using the log.")
/// taken out, where another sentence is left.
fn without_instructions(text: &str) -> String {
    let mut sentences: Vec<&str> = Vec::new();
    let mut start = 0;
    let b = text.as_bytes();
    for i in 0..b.len() {
        if matches!(b[i], b'.' | b'?' | b'!') && (i + 1 == b.len() || b[i + 1] == b' ') {
            sentences.push(&text[start..=i]);
            start = i + 1;
        }
    }
    if start < text.len() {
        sentences.push(&text[start..]);
    }
    let instructs = |s: &str| {
        let l = s.trim().to_lowercase();
        INSTRUCTIONS.iter().any(|i| l.starts_with(i))
            && l.split_whitespace().count() <= 12
            && !l.contains("why")
            && !l.contains("how")
    };
    let kept: Vec<&str> = sentences
        .iter()
        .copied()
        .filter(|s| !instructs(s))
        .collect();
    if kept.is_empty() || kept.len() == sentences.len() {
        return text.to_string();
    }
    kept.concat()
}

/// "Account for" asks why; a verb that sets the task at a sentence's
/// start asks as "tell me"; "with reference to tick 10" is at tick 10.
fn replaced_words(text: &str) -> String {
    let toks: Vec<&str> = text.split_whitespace().collect();
    let mut out: Vec<String> = Vec::with_capacity(toks.len());
    let mut i = 0;
    while i < toks.len() {
        let w = toks[i].to_lowercase();
        let opens = i == 0 || toks[i - 1].ends_with(['.', '?', '!', ':']);
        let next = toks
            .get(i + 1)
            .map(|n| n.to_lowercase())
            .unwrap_or_default();
        if w == "account" && next == "for" {
            // "Account for the transitions in tick 6" asks what happened.
            let then = toks
                .get(i + 3)
                .map(|n| n.to_lowercase())
                .unwrap_or_default();
            let happened = ["transitions", "events", "changes", "sequence"]
                .iter()
                .any(|h| then.starts_with(h));
            out.push(if happened { "describe" } else { "explain" }.into());
            i += 2;
            continue;
        }
        if w == "with" && next == "reference" && toks.get(i + 2) == Some(&"to") {
            let then = toks
                .get(i + 3)
                .map(|n| n.to_lowercase())
                .unwrap_or_default();
            if then == "tick" || then == "step" {
                out.push("at".into());
                i += 3;
                continue;
            }
        }
        if opens && SETS.contains(&w.as_str()) {
            out.push("tell me".into());
            i += 1;
            continue;
        }
        out.push(toks[i].to_string());
        i += 1;
    }
    out.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tasks_marks_labels_and_instructions_are_not_asked() {
        assert_eq!(
            as_asked("Part (a): In one line, what is this whole navigate_to_pose tree for?"),
            "what is this whole navigate_to_pose tree for?"
        );
        assert_eq!(
            as_asked("Explain why drive is still RUNNING at the end of tick 4. (2 marks)"),
            "Explain why drive is still RUNNING at the end of tick 4."
        );
        assert_eq!(
            as_asked("Q6 (hypothetical). Had it returned FAILURE, what then?"),
            "Had it returned FAILURE, what then?"
        );
        assert_eq!(
            as_asked("Lab sheet 3: pause the replay at tick 33"),
            "pause the replay at tick 33"
        );
        assert_eq!(
            as_asked("True or false: the patrol completed successfully. Justify with reference to the log."),
            "the patrol completed successfully?"
        );
        assert_eq!(
            as_asked("Account for the FAILURE of the FollowPath RecoveryNode at tick 6."),
            "explain the FAILURE of the FollowPath RecoveryNode at tick 6."
        );
        assert_eq!(
            as_asked("State which leaf action the arm is executing."),
            "tell me which leaf action the arm is executing."
        );
        assert_eq!(
            as_asked("With reference to tick 12, describe each transition"),
            "at tick 12, describe each transition"
        );
        assert_eq!(
            as_asked("what is NavigateRecovery (root, number_of_retries=6) there to achieve?"),
            "what is NavigateRecovery there to achieve?"
        );
    }

    #[test]
    fn a_question_that_sets_no_task_is_left_as_it_is() {
        for q in [
            "why did look at chuck fail?",
            "what is the state of drive (#7)?",
            "name?",
            "Justify why look at chuck failed.",
            "q",
            // A status compared, not a port set.
            "first tick where detect chuck (= FAILURE)?",
        ] {
            assert_eq!(as_asked(q), q);
        }
    }
}
