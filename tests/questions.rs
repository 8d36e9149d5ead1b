//! Questions written by people who had not seen btx's reader
//! (`tests/fixtures/questions/corpus.jsonl`, written blind over seven runs;
//! `corpus2.jsonl`, 260 more written blind later by another writer, who
//! checked each label against the run's log; and `forums.jsonl`, questions users wrote in BehaviorTree.CPP, Nav2 and
//! Groot issue threads, each with its thread), each labelled with what it
//! asks: the intent, the node, the event and the moment. The corpus is
//! split in two by a hash of the question: the reader was tuned on the
//! first half only; the figures of the second are the ones reported.
//! `corpus3.jsonl`, 320 more written blind by a third writer once the
//! reader stood, was held out until `corpus4.jsonl` (320 by a fourth
//! writer) came, corpus4 until `corpus5.jsonl` (280 by a fifth), corpus5
//! until `corpus6.jsonl` (280 by a sixth), corpus6 until `corpus7.jsonl`
//! (280 by a seventh), corpus7 until `corpus8.jsonl` (280 by an eighth),
//! corpus8 until `corpus9.jsonl` (280 by a ninth, who checked each label
//! against the run's tree and log with a script of their own), corpus9
//! until `corpus10.jsonl` (280 by a tenth, asked for sloppy, long,
//! incident-time wording, labels checked the same way), corpus10 until
//! `corpus11.jsonl` (280 by an eleventh, asked for a mix of careful
//! engineers, hurried operators and forum posters), corpus11 until
//! `corpus12.jsonl` (280 by a twelfth, asked for engineers whose English
//! is good but not idiomatic), corpus12 until `corpus13.jsonl` (280 by a
//! thirteenth, each question from one of the tool's users: a Nav2
//! integrator, a cell operator, a student of the papers, a game-AI
//! programmer, a QA engineer, a manager), corpus13 until `corpus14.jsonl`
//! (280 by a fourteenth, asked for users who quote the log beside the chat
//! (uids, statuses in capitals, moments as the log prints them, XML tags)
//! and for follow-ups in a running conversation), corpus14 until
//! `corpus15.jsonl` (280 by a fifteenth, asked for questions spoken to the
//! tool and written down by speech-to-text: no punctuation, numbers
//! spelled out, fillers, self-corrections, misheard names), corpus15 until
//! `corpus16.jsonl` (280 by a sixteenth, asked for an on-call chat's
//! shorthand: dropped words, the team's abbreviations, arrows and symbols,
//! glued names, pasted log rows), corpus16 until `corpus17.jsonl` (280 by
//! a seventeenth, asked for newcomers who describe what they see the robot
//! do rather than name its nodes), corpus17 until `corpus18.jsonl` (280
//! by an eighteenth, asked for integrators who name nodes by what the XML
//! says of them: ports and their values, blackboard keys, classes, places
//! among their siblings), corpus18 until `corpus19.jsonl` (280 by a
//! nineteenth, asked for safety auditors: formal, hedged, passive,
//! conditional, findings numbered and requirements quoted), corpus19 until
//! `corpus20.jsonl` (280 by a twentieth, asked for field technicians on a
//! phone or tablet: touch typos, autocorrect's damage, dropped words),
//! corpus20 until `corpus21.jsonl` (280 by a twenty-first, asked for
//! students of the two papers, in their vocabulary: Q1 to Q5,
//! interventions, counterfactuals, the explanation model), corpus21 until
//! `corpus22.jsonl` (280 by a twenty-second, asked for game-AI
//! programmers who ask in their engine's words: tasks, selectors,
//! frames, aborts, the pawn), corpus22 until `corpus23.jsonl` (280 by a
//! twenty-third, asked for roboticists from ROS 1 who ask in py_trees' and
//! SMACH's words: the tip, the chooser, states and outcomes, preempted),
//! corpus23 until `corpus24.jsonl` (280 by a twenty-fourth, asked for
//! people who type into a search box: keyword fragments, no grammar,
//! quoted names, "vs" and a minus for a contrast), corpus24 until
//! `corpus25.jsonl` (280 by a twenty-fifth, asked for testers who write
//! each question as a bug report: expected, actual, repro, root cause,
//! statuses in capitals), corpus25 until `corpus26.jsonl` (280 by a
//! twenty-sixth, asked for a robot vendor's customers writing to its
//! support desk: polite, roundabout, what they saw rather than names,
//! short follow-ups), corpus26 until `corpus27.jsonl` (280 by a
//! twenty-seventh, asked for engineers who abbreviate every name: LAC,
//! FP, CPTP, "det chuck", statuses as S/F, ticks as t9 or @9), corpus27
//! until `corpus28.jsonl` (280 by a twenty-eighth, asked for instructors
//! writing exam and worksheet tasks: "Identify", "Account for", "Justify",
//! "(2 marks)", true or false, a scenario before the task), corpus28
//! until `corpus29.jsonl` (280 by a twenty-ninth, asked for Groot2's
//! users: the colours of the boxes, the timeline slider, the blackboard
//! panel, "the box under X"), corpus29 until `corpus30.jsonl` (280 by a
//! thirtieth, asked for reliability engineers and analysts who ask in
//! counts, ranges and firsts: "count(fail) of FollowPath", "the 2nd time",
//! "between tick 3 and 7"), corpus30 until `corpus31.jsonl` (280 by a
//! thirty-first, asked for operators and floor staff who watch the robot,
//! not the tree: what they saw it do, "right after it beeped", a wrong
//! guess at a name), corpus31 until `corpus32.jsonl` (280 by a thirty-second,
//! asked for managers and account leads who ask in business terms: delays,
//! "the order", "root cause for the report", nodes read off a screen
//! share), corpus32 until `corpus33.jsonl` (280 by a thirty-third, asked
//! for people who are not roboticists at all, lab visitors, relatives and
//! journalists, who speak of the robot as a person: "was it confused?",
//! "did it give up on the gear?", "what was it thinking when it
//! stopped?"), corpus33 until `corpus34.jsonl` (280 by a thirty-fourth,
//! asked for members of a robotics competition team typing in their chat
//! while debugging before a match: slang, all caps, emoji, "our bot",
//! nicknames half remembered, the judges), corpus34 until `corpus35.jsonl`
//! (280 by a thirty-fifth, asked for people posting on a robotics help
//! forum: context first, then the question, "Hi all", "Thanks in advance",
//! what they expected or already tried, "EDIT:"), corpus35 until
//! `corpus36.jsonl` (280 by a thirty-sixth, asked for engineers who write
//! in another language and paste a machine translator's English: literal
//! word order, false friends, articles dropped, a term left untranslated);
//! corpus36 until `corpus37.jsonl` (280 by a thirty-seventh, asked for
//! test and acceptance engineers who think in behaviour-driven
//! development: Given / When / Then, "Verify:", test-case titles,
//! preconditions stated first, expected against actual); corpus37 until
//! `corpus38.jsonl` (280 by a thirty-eighth, asked for people thinking
//! aloud as they type: false starts, self-corrections, asides, the label
//! what they mean in the end); corpus38 until `corpus39.jsonl` (280 by
//! a thirty-ninth, asked for remote operators talking over radio or an
//! ops chat: call signs, procedure words, "say", "confirm", "negative",
//! "sitrep", articles dropped); corpus39 until `corpus40.jsonl` (280 by
//! a fortieth, asked for frustrated, impatient or sarcastic users venting
//! after a robot wasted their afternoon: caps, "seriously", "AGAIN", the
//! question buried in the complaint); corpus40 until `corpus41.jsonl` (280
//! by a forty-first, asked for English as it is spoken in many places:
//! Indian, Scottish, Irish, Australian, Nigerian, Singlish, Southern US,
//! Jamaican, South African, each with its own words and turns); corpus41
//! until `corpus42.jsonl` (280 by a forty-second, asked for people who
//! write long: background first, hedges, asides in parentheses, the one
//! question in the middle of a paragraph); corpus42 until
//! `corpus43.jsonl` (280 by a forty-third, asked for the voice of a formal
//! report: passive, impersonal, "state", "specify", "it is requested that");
//! corpus43 is never tuned on: its figures are the fresh ones, and its
//! failures are never printed (`BTX_SHOW_FRESH` shows those of the
//! corpora tuned on).
//!
//! `cargo test --test questions -- --nocapture` prints the figures;
//! `BTX_DUMP_FATES=FILE` appends each question's fate and reading to FILE,
//! so that two versions of the reader can be compared question by question
//! (a change meant to keep every reading keeps the file byte for byte).

use btx::ask::parse::{Event, Intent, Subject, Which};
use btx::ask::read;
use btx::ask::{ask, Context};
use btx::explain::{Question, RunQuestion, TreeQuestion};
use btx::input::{open, Input};
use btx::session::Moment;
use btx::xml::LoadOptions;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

/// The runs the questions are about, by the corpus's names.
fn run(name: &str) -> Input {
    let r = root();
    let (file, opts) = match name {
        "kitting" => (
            "sessions/kitting-lookat-fails-once.jsonl",
            LoadOptions::default(),
        ),
        "nav2" => (
            "tests/fixtures/questions/nav2-followpath-fails-twice.jsonl",
            LoadOptions::default(),
        ),
        "detect" => (
            "tests/fixtures/logs/kitting_detect_chuck_always_fails.btlog",
            LoadOptions::default(),
        ),
        "taxi" => (
            "tests/fixtures/logs/taxi_nominal.btlog",
            LoadOptions::default(),
        ),
        "bag" => (
            "tests/fixtures/rosbag/two_goals",
            LoadOptions {
                run_tree: Some(r.join("tests/fixtures/rosbag/navigator.xml")),
                run: Some(1),
                ..LoadOptions::default()
            },
        ),
        "patrol" => (
            "tests/fixtures/questions/patrol.jsonl",
            LoadOptions::default(),
        ),
        "case" => ("sessions/case-study.jsonl", LoadOptions::default()),
        other => panic!("no run {other}"),
    };
    open(&r.join(file), &opts).unwrap_or_else(|e| panic!("{file}: {e:?}"))
}

/// How a question fared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Fate {
    /// Read as meant and answered so.
    Understood,
    /// Read as meant, and btx asked back ("did you mean") all the same.
    AskedBackRight,
    /// Read otherwise, and btx said it was not sure ("did you mean").
    AskedBackWrong,
    /// "I don't know how to answer that."
    Refused,
    /// Answered as another question or node, without saying so.
    Misread,
}

struct Case {
    run: String,
    at: String,
    q: String,
    intent: String,
    node: Value,
    node2: Value,
    event: Value,
    which: Value,
    moment: Value,
    source: Option<String>,
}

fn cases(file: &str) -> Vec<Case> {
    let text = std::fs::read_to_string(root().join("tests/fixtures/questions").join(file)).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap_or_else(|e| panic!("{file}: {e}: {l}"));
            let s = |k: &str| v[k].as_str().unwrap_or_default().to_string();
            Case {
                run: s("run"),
                at: s("at"),
                q: s("q"),
                intent: s("intent"),
                node: v["node"].clone(),
                node2: v["node2"].clone(),
                event: v["event"].clone(),
                which: v["which"].clone(),
                moment: v["moment"].clone(),
                source: v["source"].as_str().map(str::to_string),
            }
        })
        .collect()
}

/// The half a question falls in: 0 (tuned on) or 1 (held out).
fn half(q: &str) -> usize {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in q.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    (h % 2) as usize
}

fn event_name(e: Event) -> &'static str {
    match e {
        Event::Fail => "fail",
        Event::Succeed => "succeed",
        Event::Run => "run",
        Event::NotRun => "not-run",
        Event::Skipped => "skipped",
        Event::Halted => "halted",
        Event::KeepRunning => "keep-running",
        Event::Finish => "finish",
    }
}

/// The corpus's name of an intent, its event and its "which".
fn label(i: &Intent) -> (&'static str, Option<&'static str>, Option<&'static str>) {
    let which = |w: Which| match w {
        Which::First => Some("first"),
        Which::Last => Some("last"),
        Which::Every => None,
    };
    match i {
        Intent::Fixed(Question::Tree(t)) => (
            match t {
                TreeQuestion::Doing => "doing",
                TreeQuestion::Why => "why-doing",
                TreeQuestion::Subgoal => "subgoal",
                TreeQuestion::Goal => "goal",
                TreeQuestion::HowSubgoal => "how-subgoal",
                TreeQuestion::HowGoal => "how-goal",
            },
            None,
            None,
        ),
        Intent::Fixed(Question::Run(r)) => (
            match r {
                RunQuestion::WhatWentWrong => "wrong",
                RunQuestion::AnythingWrong => "anything-wrong",
                RunQuestion::Handled => "handled",
            },
            None,
            None,
        ),
        Intent::Fixed(Question::CanYou(_)) => ("can-you", None, None),
        Intent::Why { event, .. } => ("why", Some(event_name(*event)), None),
        Intent::WhyNot { .. } => ("why-instead", None, None),
        Intent::When {
            event, which: w, ..
        } => ("when", Some(event_name(*event)), which(*w)),
        Intent::HowOften { event, .. } => ("how-often", Some(event_name(*event)), None),
        Intent::Tick(_) => ("tick", None, None),
        Intent::Next => ("next", None, None),
        Intent::WhatIf { event, .. } => ("what-if", Some(event_name(*event)), None),
        Intent::Recovered => ("recovered", None, None),
    }
}

struct Outcome {
    fate: Fate,
    said: String,
}

fn judge(c: &Case, input: &Input) -> Outcome {
    let tree = input.tree();
    let s = input.session().expect("a run");
    let m = if c.at == "end" || c.at.is_empty() {
        Moment {
            tick: s.index.ticks(),
            step: None,
        }
    } else {
        Moment::parse_within(&c.at, s.index.ticks()).unwrap()
    };
    let m0 = m;
    let cx = Context {
        tree,
        session: Some(s),
        at: Some(s.at(m).unwrap()),
        tick: Some(m.tick),
        node: None,
        detail: Default::default(),
        last: Default::default(),
    };
    let reply = ask(&cx, &c.q);
    let reading = read::read(&read::Vocabulary::new(tree), tree, &c.q);
    let said = format!(
        "{:?} → {:?} about {:?} nodes {:?} ({}): {}",
        c.q,
        reading.as_ref().map(|r| (&r.intent, r.when, r.confidence)),
        reply.about,
        reply.nodes,
        c.intent,
        reply.text().lines().take(3).collect::<Vec<_>>().join(" | ")
    );
    let refused = !reply.answered && reply.short.is_none();
    if c.intent == "unanswerable" {
        let fate = if refused {
            Fate::Understood
        } else if reply.unsure() {
            Fate::AskedBackWrong
        } else {
            Fate::Misread
        };
        return Outcome { fate, said };
    }
    if refused {
        return Outcome {
            fate: Fate::Refused,
            said,
        };
    }
    let Some(reading) = reading else {
        return Outcome {
            fate: Fate::Refused,
            said,
        };
    };
    let (intent, event, which) = label(&reading.intent);
    let mut right = intent == c.intent;
    if let Some(e) = c.event.as_str() {
        right &= event == Some(e);
    }
    if c.intent == "when" {
        right &= which == c.which.as_str();
    }
    // The node: the one answered about; several named alike must all be
    // answered, each in its line.
    let named = |v: &Value| -> Vec<u32> {
        match v {
            Value::Number(n) => vec![n.as_u64().unwrap() as u32],
            Value::Array(a) => a.iter().map(|n| n.as_u64().unwrap() as u32).collect(),
            _ => Vec::new(),
        }
    };
    // A SubTree and the Sequence inside it named alike are one behaviour,
    // answered as the outermost (docs/commands.md): a label naming both is
    // met by an answer about the SubTree.
    let want = read::mentions::outermost(tree, named(&c.node));
    let subject_named = matches!(
        &reading.intent,
        Intent::Why { .. }
            | Intent::WhyNot { .. }
            | Intent::When { .. }
            | Intent::HowOften { .. }
            | Intent::WhatIf { .. }
    );
    if subject_named && !want.is_empty() && c.intent != "why-instead" {
        if want.len() == 1 {
            right &= reply.about == Some(want[0]);
        } else {
            right &= want.iter().all(|u| reply.nodes.contains(u));
        }
    }
    if c.intent == "why-instead" {
        if let Intent::WhyNot { done, instead } = &reading.intent {
            // The outermost of nodes named alike, as for the node above.
            let has = |s: &Subject, v: &Value| match s {
                Subject::Nodes(us, _) => read::mentions::outermost(tree, named(v))
                    .iter()
                    .all(|u| us.contains(u)),
                _ => false,
            };
            right = intent == "why-instead" && has(done, &c.node) && has(instead, &c.node2);
        }
    }
    if c.intent == "can-you" {
        if let (Intent::Fixed(Question::CanYou(x)), Some(&u)) = (&reading.intent, want.first()) {
            let d = tree.description(u).to_lowercase();
            right &= x.to_lowercase() == d || x.to_lowercase() == tree.spoken(u).to_lowercase();
        }
    }
    if let Some(m) = c.moment.as_str() {
        // The moment the question named, found in the run as btx finds it,
        // against the labelled one (a tick for "what happened at/in …").
        let at = s
            .at(Moment {
                tick: s.index.ticks(),
                step: None,
            })
            .unwrap();
        let got = reading
            .when
            .and_then(|w| btx::ask::moment_of(tree, &at, w).ok())
            .map(|p| s.index.moment(p));
        let want = Moment::parse_within(m, s.index.ticks()).unwrap();
        let asked_at = s.index.moment(s.index.position(m0).unwrap());
        right &= match (&reading.intent, got) {
            (Intent::Tick(n), g) => {
                let n = if *n == 0 {
                    g.map_or(asked_at.tick, |g| g.tick)
                } else {
                    *n
                };
                n == want.tick
            }
            (_, Some(g)) => s.index.position(g).ok() == s.index.position(want).ok(),
            (_, None) => false,
        };
    }
    let fate = match (right, reply.unsure()) {
        (true, false) => Fate::Understood,
        (true, true) => Fate::AskedBackRight,
        (false, true) => Fate::AskedBackWrong,
        (false, false) => Fate::Misread,
    };
    Outcome { fate, said }
}

struct Tally {
    counts: BTreeMap<Fate, usize>,
    total: usize,
    wrong: Vec<String>,
}

fn tally(files: &[&str], keep: impl Fn(&Case) -> bool) -> Tally {
    let mut runs: BTreeMap<String, Input> = BTreeMap::new();
    let mut t = Tally {
        counts: BTreeMap::new(),
        total: 0,
        wrong: Vec::new(),
    };
    for f in files {
        for c in cases(f).into_iter().filter(|c| keep(c)) {
            let input = runs.entry(c.run.clone()).or_insert_with(|| run(&c.run));
            let o = judge(&c, input);
            *t.counts.entry(o.fate).or_default() += 1;
            t.total += 1;
            if o.fate != Fate::Understood {
                t.wrong.push(format!("{:?} [{}] {}", o.fate, c.run, o.said));
            }
            if let Some(dump) = std::env::var_os("BTX_DUMP_FATES") {
                use std::io::Write;
                let mut out = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(dump)
                    .unwrap();
                writeln!(out, "{f}\t{:?}\t[{}] {}", o.fate, c.run, o.said).unwrap();
            }
        }
    }
    t
}

/// The share read as meant and the share misread without saying so.
fn report(name: &str, t: &Tally) -> (f64, f64) {
    let n = |f: Fate| t.counts.get(&f).copied().unwrap_or(0);
    let pct = |k: usize| 100.0 * k as f64 / t.total.max(1) as f64;
    println!(
        "{name}: {} questions; understood as meant {:.1}% ({}); asked back {:.1}% ({} right, {} wrong); refused {:.1}% ({}); misread without saying so {:.1}% ({})",
        t.total,
        pct(n(Fate::Understood)),
        n(Fate::Understood),
        pct(n(Fate::AskedBackRight) + n(Fate::AskedBackWrong)),
        n(Fate::AskedBackRight),
        n(Fate::AskedBackWrong),
        pct(n(Fate::Refused)),
        n(Fate::Refused),
        pct(n(Fate::Misread)),
        n(Fate::Misread),
    );
    (pct(n(Fate::Understood)), pct(n(Fate::Misread)))
}

#[test]
fn the_corpus_is_large_varied_and_labelled() {
    let all = cases("corpus.jsonl");
    assert!(all.len() >= 600, "{}", all.len());
    let runs: std::collections::BTreeSet<&str> = all.iter().map(|c| c.run.as_str()).collect();
    assert!(runs.len() >= 6, "{runs:?}");
    let forums = cases("forums.jsonl");
    assert!(forums.len() >= 50);
    assert!(forums.iter().all(|c| c
        .source
        .as_deref()
        .is_some_and(|s| s.starts_with("https://"))));
}

#[test]
fn questions_tuned_on_are_read_as_meant() {
    let t = tally(&["corpus.jsonl", "corpus2.jsonl", "forums.jsonl"], |c| {
        half(&c.q) == 0
    });
    let (understood, misread) = report("tuned-on half", &t);
    if std::env::var_os("BTX_SHOW_MISREADS").is_some() {
        for w in &t.wrong {
            println!("{w}");
        }
    }
    assert!(
        understood >= DEV_FLOOR && misread <= DEV_MISREAD,
        "{understood:.1}% understood, {misread:.1}% misread:\n{}",
        t.wrong.join("\n")
    );
}

#[test]
fn questions_held_out_are_read_as_meant() {
    let t = tally(&["corpus.jsonl", "corpus2.jsonl", "forums.jsonl"], |c| {
        half(&c.q) == 1
    });
    let (understood, misread) = report("held-out half", &t);
    if std::env::var_os("BTX_SHOW_MISREADS").is_some() {
        for w in &t.wrong {
            println!("{w}");
        }
    }
    assert!(
        understood >= HELD_FLOOR && misread <= HELD_MISREAD,
        "{understood:.1}% understood, {misread:.1}% misread"
    );
}

#[test]
fn questions_written_after_the_reader_are_read_as_meant() {
    let t3 = tally(
        &[
            "corpus3.jsonl",
            "corpus4.jsonl",
            "corpus5.jsonl",
            "corpus6.jsonl",
            "corpus7.jsonl",
            "corpus8.jsonl",
            "corpus9.jsonl",
            "corpus10.jsonl",
            "corpus11.jsonl",
            "corpus12.jsonl",
            "corpus13.jsonl",
            "corpus14.jsonl",
            "corpus15.jsonl",
            "corpus16.jsonl",
            "corpus17.jsonl",
            "corpus18.jsonl",
            "corpus19.jsonl",
            "corpus20.jsonl",
            "corpus21.jsonl",
            "corpus22.jsonl",
            "corpus23.jsonl",
            "corpus24.jsonl",
            "corpus25.jsonl",
            "corpus26.jsonl",
            "corpus27.jsonl",
            "corpus28.jsonl",
            "corpus29.jsonl",
            "corpus30.jsonl",
            "corpus31.jsonl",
            "corpus32.jsonl",
            "corpus33.jsonl",
            "corpus34.jsonl",
            "corpus35.jsonl",
            "corpus36.jsonl",
            "corpus37.jsonl",
            "corpus38.jsonl",
            "corpus39.jsonl",
            "corpus40.jsonl",
            "corpus41.jsonl",
            "corpus42.jsonl",
        ],
        |_| true,
    );
    let (understood3, misread3) = report("corpus3 to corpus42 (tuned on)", &t3);
    let t = tally(&["corpus43.jsonl"], |_| true);
    let (understood, misread) = report("written after (corpus43)", &t);
    if std::env::var_os("BTX_SHOW_FRESH").is_some() {
        for w in &t3.wrong {
            println!("{w}");
        }
    }
    assert!(
        t3.total >= 11_280 && t.total >= 280,
        "{} {}",
        t3.total,
        t.total
    );
    assert!(
        understood3 >= C3_FLOOR && misread3 <= C3_MISREAD,
        "corpus3 to corpus42: {understood3:.1}% understood, {misread3:.1}% misread"
    );
    assert!(
        understood >= FRESH_FLOOR && misread <= FRESH_MISREAD,
        "{understood:.1}% understood, {misread:.1}% misread"
    );
}

/// Floors and ceilings just beyond the figures measured at the last change
/// of the reader (92.4 % and 1.6 % tuned on, 89.2 % and 3.7 % on the second
/// half, with corpus2's questions in both halves; since corpus3 came, the
/// second half is tuned on too): a change that reads fewer questions as
/// meant, or misreads more, fails.
const DEV_FLOOR: f64 = 92.2;
const DEV_MISREAD: f64 = 1.7;
const HELD_FLOOR: f64 = 89.0;
const HELD_MISREAD: f64 = 3.8;
/// corpus3 to corpus42 as tuned on (88.5 % understood, 4.1 % misread, when
/// corpus42 joined; first read 72.2 %/8.4 %, 77.2 %/5.6 %, 74.6 %/5.4 %, 76.8 %/5.7 %, 69.3 %/10.0 %, 83.6 %/9.6 %, 95.0 %/1.8 %,
/// 78.2 %/8.2 %, 91.1 %/5.4 %, 88.6 %/6.4 %, 92.1 %/4.6 %, 83.6 %/11.1 %,
/// 81.1 %/7.9 %, 85.0 %/8.2 %, 79.3 %/8.6 %, 81.8 %/7.5 %, 58.9 %/11.4 %,
/// 85.4 %/7.9 %, 77.9 %/9.3 %, 69.6 %/15.0 %, 78.9 %/5.7 %, 83.9 %/7.5 %,
/// 86.8 %/7.1 %, 68.6 %/13.2 %, 63.6 %/20.4 %, 57.1 %/10.7 %, 73.2 %/11.8 %, 81.4 %/7.9 %, 75.4 %/10.4 %, 82.9 %/7.1 %, 68.9 %/13.6 %, 81.4 %/9.3 %, 85.7 %/7.5 %, 63.6 %/11.8 %, 84.3 %/8.6 %, 85.0 %/9.6 %, 78.9 %/8.6 %, 87.5 %/6.4 %, 84.3 %/7.9 % and 69.3 %/6.8 %; corpus40 95.4 %/2.1 %, corpus41 96.4 %/2.5 % and corpus42 78.6 %/5.0 % after their own;
/// 89.0 %/4.1 % in all after corpus41's rules, 88.8 %/4.1 % after corpus42's),
/// and corpus43, never tuned on (58.9 % and 18.2 % when it was first read,
/// 7.5 % refused: a formal report's passive, impersonal requests).
const C3_FLOOR: f64 = 88.7;
const C3_MISREAD: f64 = 4.1;
const FRESH_FLOOR: f64 = 58.8;
const FRESH_MISREAD: f64 = 18.3;
