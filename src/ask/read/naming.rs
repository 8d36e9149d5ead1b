//! Which words of a sentence name nodes: the mentions found, joined,
//! told by uid, and the words that name nothing (Han's framing, a tag, a
//! measure of the world outside the run).

use super::*;

/// The moment a question names and the nodes it names, each with the
/// words it takes: "at tick 9", "#18", "look at chuck", and the clauses
/// that pick among nodes named alike or say when ("before FollowPath
/// failed").
pub(super) fn named_parts<'a>(
    vocabulary: &'a Vocabulary,
    tree: &Tree,
    q: &'a [Word],
) -> (Sentence<'a>, Option<When>) {
    let mut s = Sentence {
        q,
        tree_words: vocabulary.stems(),
        used: vec![false; q.len()],
        nodes: Vec::new(),
    };
    let mut when = when::find(q).map(|(w, used)| {
        for i in used {
            if i < s.used.len() {
                s.used[i] = true;
            }
        }
        w
    });
    for i in naming_nothing(q) {
        s.used[i] = true;
    }
    for m in uids_said(tree, q, &s.used) {
        s.used[m.start] = true;
        s.nodes.push(m);
    }
    let mut mentions = vocabulary.mentions(tree, &free_words(q, &s.used), &asks);
    // "What were you doing just before look at chuck failed?", "describe
    // the tick where the spin failed": the clause says when; what is asked
    // is the rest.
    type Clause = fn(&Tree, &[Word], &[bool], &[Mention]) -> Option<(When, Vec<usize>)>;
    for clause in [
        failure_clause as Clause,
        tick_of_a_failure,
        moment_of_an_event,
    ] {
        if when.is_some() {
            break;
        }
        if let Some((w, used)) = clause(tree, q, &s.used, &mentions) {
            when = Some(w);
            for i in used {
                s.used[i] = true;
            }
            mentions.retain(|m| !(m.start..m.end).any(|i| s.used[i]));
        }
    }
    s.nodes.extend(mentions);
    s.nodes = right_as_a_tag(q, std::mem::take(&mut s.nodes));
    s.nodes = uids_told_of_names(std::mem::take(&mut s.nodes));
    s.nodes.sort_by_key(|m| m.start);
    s.nodes = halves_joined(std::mem::take(&mut s.nodes));
    s.nodes = children_by_place(tree, q, std::mem::take(&mut s.nodes));
    s.nodes = scoped(tree, q, std::mem::take(&mut s.nodes));
    s.nodes = governing_verbs_dropped(q, std::mem::take(&mut s.nodes));
    s.nodes = counted_among_alike(tree, q, std::mem::take(&mut s.nodes));
    if let Some(m) = elided_foil(vocabulary, tree, q, &s.nodes) {
        s.nodes.push(m);
    }
    (s, when)
}

/// "Clear costmap": parts of one name side by side, each found alone
/// (ClearLocalCostmap's first word and its last), are one mention.
pub(super) fn halves_joined(nodes: Vec<Mention>) -> Vec<Mention> {
    let mut out: Vec<Mention> = Vec::with_capacity(nodes.len());
    for m in nodes {
        match out.last_mut() {
            Some(p) if p.end == m.start && p.uids == m.uids && !p.weak && !m.weak => {
                p.end = m.end;
                p.score = p.score.min(m.score);
                p.phrase = format!("{} {}", p.phrase, m.phrase);
            }
            _ => out.push(m),
        }
    }
    out
}

/// Words that name no node and ask nothing of their own: Han's framing
/// named, a bag's goal by number, "right" saying when.
pub(super) fn naming_nothing(q: &[Word]) -> Vec<usize> {
    let mut used = han_framing(q);
    for i in 0..q.len().saturating_sub(1) {
        let next = q[i + 1].text.as_str();
        // "In goal 1", "the first tick of goal 2": a bag's goals by number
        // name the run, not the goal asked about.
        if q[i].text == "goal" && next.bytes().all(|b| b.is_ascii_digit()) {
            used.extend([i, i + 1]);
        }
        // "Right now", "right after": "right" says when, it names no move.
        if q[i].text == "right"
            && ["now", "away", "after", "before", "then", "there", "here"].contains(&next)
        {
            used.push(i);
        }
    }
    used
}

/// "#18": a uid, as everywhere in btx, among the words not yet read.
pub(super) fn uids_said(tree: &Tree, q: &[Word], used: &[bool]) -> Vec<Mention> {
    q.iter()
        .enumerate()
        .filter(|(i, _)| !used[*i])
        .filter_map(|(i, w)| {
            let uid = w.text.strip_prefix('#')?.parse::<Uid>().ok()?;
            tree.get(uid)?;
            Some(Mention {
                start: i,
                end: i + 1,
                uids: vec![uid],
                score: 1.0,
                weak: false,
                phrase: w.text.clone(),
            })
        })
        .collect()
}

/// "In the goal/subgoals/steps/actions framing", "Han et al. partition
/// the tree into {goal, subgoals, steps, actions}": the framing's four
/// words in a row name the framing, not one of its questions.
pub(super) fn han_framing(q: &[Word]) -> Vec<usize> {
    const PARTS: &[&str] = &["goal", "subgoal", "step", "action"];
    let part = |w: &Word| PARTS.contains(&w.stem.as_str());
    let mut used = Vec::new();
    let mut i = 0;
    while i < q.len() {
        let mut j = i;
        while j < q.len() && (part(&q[j]) || q[j].text == "and" && j > i) {
            j += 1;
        }
        let kinds: rustc_hash::FxHashSet<&str> = q[i..j]
            .iter()
            .filter(|w| part(w))
            .map(|w| w.stem.as_str())
            .collect();
        if kinds.len() >= 3 {
            used.extend(i..j);
        }
        i = j.max(i + 1);
    }
    used
}

/// "No errors, right?": a last "right" that names nothing else in the
/// question asks yes or no; it is no move right ("… go right?" is).
pub(super) fn right_as_a_tag(q: &[Word], mut nodes: Vec<Mention>) -> Vec<Mention> {
    const MOVED: &[&str] = &[
        "move", "moves", "moved", "moving", "go", "goes", "went", "going", "turn", "turned",
        "turning", "the", "to", "and", "or", "than", "of",
    ];
    let tag = |m: &Mention| {
        m.end == q.len()
            && m.start + 1 == m.end
            && q[m.start].text == "right"
            && m.start > 0
            && !MOVED.contains(&q[m.start - 1].text.as_str())
    };
    if let [only] = &nodes[..] {
        if tag(only) {
            nodes.clear();
        }
    }
    nodes
}

/// "The move right at the start of navigate to destination (#15)": a uid
/// the asker adds to a name shared by several nodes says which of them
/// is meant; the name is that node, said once.
pub(super) fn uids_told_of_names(mut nodes: Vec<Mention>) -> Vec<Mention> {
    let told: Vec<Uid> = nodes
        .iter()
        .filter(|m| m.phrase.starts_with('#'))
        .map(|m| m.uids[0])
        .collect();
    let mut merged = Vec::new();
    for m in nodes.iter_mut().filter(|m| !m.phrase.starts_with('#')) {
        if m.uids.len() > 1 {
            if let Some(&u) = told.iter().find(|u| m.uids.contains(u)) {
                m.uids = vec![u];
                merged.push(u);
            }
        }
    }
    nodes.retain(|m| !(m.phrase.starts_with('#') && merged.contains(&m.uids[0])));
    nodes
}

/// Advice ("what should I set num_attempts to?", "should I use
/// py_trees?") and the robot's world where no node but the task is named
/// ("what was the temperature in the cell?"): no run holds the answer.
pub(super) fn not_of_the_run(tree: &Tree, q: &[Word], s: &Sentence, in_mention: &[bool]) -> bool {
    // "… or should I start worrying?" asks whether all is well.
    let worried = q.iter().any(|w| {
        ["worri", "worry", "panic", "concern"]
            .iter()
            .any(|p| w.stem.starts_with(p))
    });
    let advice = q
        .windows(2)
        .any(|p| p[0].text == "should" && ["i", "we"].contains(&p[1].text.as_str()))
        && !worried
        || q.iter().any(|w| ADVICE.contains(&w.text.as_str()));
    // "How much battery did it burn?": an amount the run does not hold
    // ("how much time" it does).
    let amount = q.windows(3).any(|p| {
        p[0].text == "how"
            && p[1].text == "much"
            && !["time", "longer"].contains(&p[2].text.as_str())
    });
    // "How far did it walk?": a distance in the world.
    let far = q
        .windows(2)
        .any(|p| p[0].text == "how" && p[1].text == "far");
    // "How many meters did the base drive?": a measure of the world,
    // whatever node the question names.
    let measure = q.windows(3).any(|p| {
        p[0].text == "how" && p[1].text == "many" && MEASURES.contains(&p[2].text.as_str())
    });
    // "Is Nav2 going to deprecate the Spin behavior?", "how frustrated was
    // the operator?": the world's future and feelings, whatever is named.
    // A node's own words ("feel surface") are not the world's.
    let outside = q
        .iter()
        .enumerate()
        .any(|(i, w)| !in_mention[i] && OUTSIDE.contains(&w.text.as_str()) && !hedge(q, i))
        // "Is the next Nav2 release going to fix this?".
        || q.windows(2).any(|p| {
            p[0].text == "next" && ["release", "version", "sprint"].contains(&p[1].text.as_str())
        });
    // "What was the battery level when the goal was reached?", "which
    // operator was on shift": the robot's world ("can you charge your
    // battery?" asks what it can do).
    let can_ask = q
        .first()
        .is_some_and(|w| ["can", "could"].contains(&w.text.as_str()));
    let world_state = !can_ask
        && q.iter()
            .enumerate()
            .any(|(i, w)| !in_mention[i] && w.text == "battery")
        || q.windows(2)
            .any(|p| p[0].text == "on" && p[1].text == "shift")
        || of_the_setup(q);
    advice
        || measure
        || outside
        || a_sensed_value(q, in_mention)
        || which_hardware(q, in_mention)
        || far
        || s.nodes
            .iter()
            .filter(|m| !m.weak)
            .all(|m| m.uids == [tree.root().uid])
            && (amount
                || world_state
                || q.iter()
                    .enumerate()
                    .any(|(i, w)| !in_mention[i] && about_the_world(&w.text)))
}

/// "Feels like a lot", "I feel it failed too often": the asker hedging,
/// not a feeling asked about.
fn hedge(q: &[Word], i: usize) -> bool {
    let feel = ["feel", "feels"].contains(&q[i].text.as_str());
    let by_asker = i > 0 && ["i", "we"].contains(&q[i - 1].text.as_str());
    let like = q.get(i + 1).is_some_and(|w| w.text == "like");
    feel && (by_asker || like)
}

/// "What robot is this running on?", "which map was loaded?", "who sent
/// this goal?": the setup around the run, which its log does not hold.
fn of_the_setup(q: &[Word]) -> bool {
    let asked = |what: &[&str]| {
        q.windows(2).any(|p| {
            ["what", "which"].contains(&p[0].text.as_str()) && what.contains(&p[1].text.as_str())
        })
    };
    let said = |w: &str| q.iter().any(|x| x.text == w);
    // "What's the real-world robot this runs on?": the thing asked for a
    // few words after "what".
    let asked_near = |what: &[&str]| {
        q.iter().enumerate().any(|(i, w)| {
            ["what", "which", "whats"].contains(&w.text.as_str())
                && q[i + 1..]
                    .iter()
                    .take(5)
                    .any(|x| what.contains(&x.text.as_str()))
        })
    };
    // "Who recorded this bag?", "who bought it?": people and purchases.
    let who_did = said("who")
        && q.iter().any(|w| {
            [
                "recorded",
                "bought",
                "built",
                "made",
                "wrote",
                "programmed",
                "installed",
                "configured",
                "deployed",
                "purchased",
            ]
            .contains(&w.text.as_str())
        });
    let runs_on = q.len() > 2
        && q[q.len() - 1].text == "on"
        && ["run", "runs", "running", "ran", "based", "deployed"]
            .contains(&q[q.len() - 2].text.as_str());
    asked_near(&["robot", "platform", "machine", "computer", "hardware"]) && runs_on
        || asked(&["map", "maps"])
        || said("sent") && (said("who") || said("whos") || said("operator"))
        || who_did
        // "What colour is the taxi?": the robot's body.
        || asked(&["colour", "color"])
            && q.iter().any(|w| ["taxi", "robot", "car", "vehicle", "rover", "bot"].contains(&w.text.as_str()))
}

/// "What was the gripper motor's temperature during the screw grasp?",
/// "what was the lidar point count while it was spinning?", "what's the
/// part number of the chuck?": a value the robot sensed or a fact of a
/// part, asked by "what", whatever node the question names.
fn a_sensed_value(q: &[Word], in_mention: &[bool]) -> bool {
    const SENSED: &[&str] = &[
        "temperature",
        "percentage",
        "voltage",
        "pressure",
        "humidity",
        "torque",
        "weight",
        "obstacle",
        "fare",
    ];
    let named = |w: &str| {
        q.iter()
            .enumerate()
            .any(|(i, x)| !in_mention[i] && x.text == w)
    };
    let counted = ["point", "part", "serial"].iter().any(|w| {
        q.windows(2)
            .any(|p| p[0].text == *w && ["count", "number"].contains(&p[1].text.as_str()))
    });
    let what = ["what", "whats", "which"].iter().any(|w| named(w));
    what && (counted || SENSED.iter().any(|w| named(w)))
}

/// "Is L0 checking a laser or a camera?": which sensor, a choice of the
/// robot's hardware, which no run holds.
fn which_hardware(q: &[Word], in_mention: &[bool]) -> bool {
    const SENSORS: &[&str] = &[
        "laser",
        "camera",
        "lidar",
        "sonar",
        "radar",
        "gps",
        "imu",
        "encoder",
        "ultrasonic",
        "infrared",
    ];
    let sensors = q
        .iter()
        .enumerate()
        .filter(|(i, w)| !in_mention[*i] && SENSORS.contains(&w.text.as_str()))
        .count();
    sensors >= 2 && q.iter().any(|w| w.text == "or")
}

/// Units of the world's measures ("how many meters"; "how many frames"
/// is ticks, `words` says).
pub(super) const MEASURES: &[&str] = &[
    "meters",
    "metres",
    "kilometers",
    "kilometres",
    "km",
    "miles",
    "feet",
    "centimeters",
    "cm",
    "mm",
    "millimeters",
    "degrees",
    "radians",
    "volts",
    "amps",
    "watts",
    "joules",
    "kwh",
    "calories",
    "pixels",
];

/// Words of the world's future and of feelings, which no run holds.
pub(super) const OUTSIDE: &[&str] = &[
    "deprecate",
    "deprecated",
    "deprecation",
    "roadmap",
    "funding",
    "funded",
    "frustrated",
    "frustration",
    "salary",
    "budget",
    "firmware",
    "serial",
    "warranty",
    "cheap",
    "expensive",
    "pricey",
    "price",
    "bought",
    "purchased",
    "feel",
    "feels",
    "feeling",
    "feelings",
    "sprint",
];

/// The words not read yet; those read are blanked.
pub(super) fn free_words(q: &[Word], used: &[bool]) -> Vec<Word> {
    q.iter()
        .enumerate()
        .map(|(i, w)| {
            if used[i] {
                Word {
                    text: "\u{0}".into(),
                    stem: "\u{0}".into(),
                }
            } else {
                w.clone()
            }
        })
        .collect()
}
