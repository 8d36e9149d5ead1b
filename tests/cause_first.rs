//! The cause first (#32 item 2): `why`'s explanations are ordered so that
//! the one a person would name comes first, and what explains nothing is
//! never shown. Checked on generated runs where exactly one leaf's failure
//! makes the task fail, and on every status question of the shipped runs.

mod common;

use btx::run::world::random::Rng;
use common::btx;

/// A tree over Sequence, Fallback, ForceSuccess, Inverter and
/// RetryUntilSuccessful, with uniquely named leaves `step N`.
fn node(rng: &mut Rng, depth: u32, leaves: &mut Vec<String>) -> String {
    if depth == 0 || rng.range(0, 3) == 0 {
        let name = format!("step {}", leaves.len() + 1);
        leaves.push(name.clone());
        return if rng.coin() {
            format!(r#"<Action ID="Do" name="{name}"/>"#)
        } else {
            format!(r#"<Condition ID="Check" name="{name}"/>"#)
        };
    }
    match rng.range(0, 5) {
        0 | 1 => {
            let kids: String = (0..rng.range(2, 3))
                .map(|_| node(rng, depth - 1, leaves))
                .collect();
            format!("<Sequence>{kids}</Sequence>")
        }
        2 | 3 => {
            let kids: String = (0..rng.range(2, 3))
                .map(|_| node(rng, depth - 1, leaves))
                .collect();
            format!("<Fallback>{kids}</Fallback>")
        }
        4 => format!(
            r#"<RetryUntilSuccessful num_attempts="2">{}</RetryUntilSuccessful>"#,
            node(rng, depth - 1, leaves)
        ),
        _ => format!("<Inverter>{}</Inverter>", node(rng, depth - 1, leaves)),
    }
}

/// Runs `xml` with every leaf succeeding but `failing`: the root's last
/// status, and the session.
fn run(dir: &std::path::Path, xml: &str, failing: Option<&str>) -> (bool, String) {
    std::fs::create_dir_all(dir).unwrap();
    let plan = format!(
        "@default_action = S\n@default_condition = S\n{}",
        failing.map(|f| format!("{f} = F\n")).unwrap_or_default()
    );
    let (ok, err, out) = common::run_planned(dir, xml, &plan);
    assert!(ok, "{err}");
    (err.contains("root FAILURE"), out.display().to_string())
}

#[test]
fn when_one_leaf_fails_the_task_the_first_explanation_names_it() {
    let mut rng = Rng::new(32);
    let dir = tempfile::tempdir().unwrap();
    let (mut asked, mut named, mut missed) = (0, 0, Vec::new());
    let (mut chained, mut unchained) = (0, Vec::new());
    for case in 0..400 {
        let mut leaves = Vec::new();
        let body = format!(
            "<Sequence>{}{}</Sequence>",
            node(&mut rng, 3, &mut leaves),
            node(&mut rng, 2, &mut leaves)
        );
        let xml = format!(
            r#"<root BTCPP_format="4"><BehaviorTree ID="Task">{body}</BehaviorTree></root>"#
        );
        let leaf = leaves[rng.range(0, leaves.len() - 1)].clone();
        let (nominal_failed, _) = run(&dir.path().join(format!("{case}n")), &xml, None);
        let (failed, session) = run(&dir.path().join(format!("{case}f")), &xml, Some(&leaf));
        if nominal_failed || !failed {
            continue;
        }
        asked += 1;
        let (_, out, err) = btx(&["ask", &session, "why did the task fail?"]);
        let first = out.lines().find(|l| l.starts_with("1. ")).unwrap_or("");
        if first.contains(&format!("{leaf} ")) || first.contains(&format!("{leaf}(")) {
            named += 1;
        } else {
            missed.push(format!("{leaf} in {xml}\n{out}{err}"));
        }
        // The answer's first sentence follows the failure down to the
        // leaf (#39 item 3): "… because step 4 (#9) returned FAILURE at …".
        let chain = out.lines().nth(1).unwrap_or("");
        if chain.contains(&format!("because {leaf} (#")) && chain.contains("returned FAILURE at") {
            chained += 1;
        } else {
            unchained.push(format!("{leaf} in {xml}\n{out}{err}"));
        }
    }
    eprintln!("the failing leaf named first in {named} of {asked} runs");
    for m in &missed {
        eprintln!("missed: {m}");
    }
    assert!(asked >= 100, "only {asked} runs failed through one leaf");
    eprintln!("the failing leaf first in the answer's chain in {chained} of {asked} runs");
    assert!(
        chained * 100 >= asked * 95,
        "chained to the leaf in {chained} of {asked}:\n{}",
        unchained
            .iter()
            .take(5)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n\n")
    );
    assert!(
        named * 100 >= asked * 95,
        "named first in {named} of {asked}:\n{}",
        missed
            .iter()
            .take(5)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n\n")
    );
}

#[test]
fn no_explanation_of_a_shipped_run_explains_a_fact_by_itself_or_twice() {
    for run in [
        "sessions/kitting-lookat-fails-once.jsonl",
        "sessions/kitting-grasp-check-fails-first.jsonl",
        "sessions/taxi.jsonl",
    ] {
        for (target, at) in [
            ("status(#1)", "-1"),
            ("status(#7)", "11"),
            ("status(#4)", "10"),
        ] {
            let (ok, out, _) = btx(&["why", run, target, "--at", at, "--all"]);
            if !ok {
                continue;
            }
            let sentences: Vec<&str> = out
                .lines()
                .filter(|l| l.starts_with(char::is_numeric))
                .collect();
            for (i, s) in sentences.iter().enumerate() {
                let text = s.split_once(". ").map_or(*s, |x| x.1);
                let (fact, reason) = text.split_once(" because ").unwrap_or((text, ""));
                // "… (#7) …": the node a clause is about, by its uid.
                let uid = |t: &str| {
                    t.split_once("(#")
                        .map(|x| x.1.split([')', ',']).next().unwrap_or("").to_string())
                };
                let reason = reason.split(". If ").next().unwrap_or(reason);
                // A loop's attempts are its own state, not its outcome.
                assert!(
                    uid(fact).is_none()
                        || uid(fact) != uid(reason)
                        || reason.contains(" had used "),
                    "{run} {target}: explained by itself: {s}"
                );
                for t in &sentences[..i] {
                    assert_ne!(
                        t.split_once(". ").map(|x| x.1),
                        Some(text),
                        "{run} {target}: said twice"
                    );
                }
            }
        }
    }
}

#[test]
fn interventions_that_cannot_happen_are_never_offered() {
    // The kitting tree's reset arm is a ForceFailure: it cannot succeed.
    let (ok, out, err) = btx(&[
        "why",
        "sessions/kitting-lookat-fails-once.jsonl",
        "status(#7)",
        "--at",
        "11",
        "--all",
    ]);
    assert!(ok, "{err}");
    assert!(
        !out.contains("If reset arm (#26, attempt 1) had succeeded"),
        "{out}"
    );
    // By default three, and how many more.
    let (_, out, _) = btx(&[
        "why",
        "sessions/kitting-lookat-fails-once.jsonl",
        "status(#1)",
    ]);
    assert!(out.contains("\n3. "), "{out}");
    assert!(!out.contains("\n4. "), "{out}");
    assert!(
        out.contains("more explanations (--all shows every one)."),
        "{out}"
    );
}

/// How many explanations a Nav2 user reads (#32 item 9): every Nav2
/// navigator of the corpus, run with its actions taking a tick and its
/// checks succeeding, and "why did X end as it did?" about every control
/// node and decorator at the end of the tick it last completed in. The figures are printed
/// (`cargo test --test cause_first -- --nocapture`); by default no more
/// than three are shown.
#[test]
fn on_real_trees_a_few_explanations_are_shown() {
    use btx::causal::{session_domain, why};
    use btx::session::{Moment, Session};
    let dir = tempfile::tempdir().unwrap();
    let plan = dir.path().join("p.plan");
    std::fs::write(&plan, "@default_action = 1RS\n@default_condition = S\n").unwrap();
    let (mut found, mut shown) = (Vec::new(), Vec::new());
    for (i, nav) in common::nav2_navigators().iter().enumerate() {
        let out = dir.path().join(format!("{i}.jsonl"));
        // Joined to an absolute path, each stays as it is.
        common::run_nav2(nav, &plan, &out);
        let s = Session::load(&out).unwrap();
        let d = session_domain(&s, None).unwrap();
        let end = s.index.at(s.index.transitions.len() as u32);
        // A leaf's outcome comes from the plan (no domain): only the
        // control nodes and decorators have causes in the tree.
        for u in 1..=s.tree.len() as u32 {
            if s.tree.node(u).kind.is_leaf() {
                continue;
            }
            let Some((p, _)) = end.last_completion(u) else {
                continue;
            };
            let tick = s.index.transitions[p as usize - 1].tick;
            let at = Moment { tick, step: None };
            // Every one is answered: a refusal here hid that the replay took
            // a Nav2 action's own RUNNING (TruncatePath, GetCurrentPose) for
            // its result, on 30 of 84 questions.
            let r = why(&s, d.clone(), &format!("status(#{u})"), &[], Some(at), 2);
            let r = r.map_err(|e| format!("{}: #{u}: {e}", nav.display()));
            {
                let mut w = r.unwrap();
                let n = w.groups().len();
                w.shown = Some(3);
                found.push(n);
                shown.push(
                    w.text()
                        .lines()
                        .filter(|l| l.starts_with(char::is_numeric))
                        .count(),
                );
            }
        }
    }
    let pct = |v: &mut Vec<usize>, q: f64| {
        v.sort_unstable();
        v[((v.len() - 1) as f64 * q).round() as usize]
    };
    let asked = found.len();
    eprintln!(
        "Nav2 navigators: {asked} questions; explanations found: median {}, 90th percentile {}, most {}; shown by default: median {}, 90th percentile {}",
        pct(&mut found, 0.5),
        pct(&mut found, 0.9),
        found.last().copied().unwrap_or(0),
        pct(&mut shown, 0.5),
        pct(&mut shown, 0.9)
    );
    assert!(asked >= 84, "{asked}");
    assert!(pct(&mut shown, 0.5) <= 3);
    assert!(shown.iter().all(|&n| n <= 3));
}

/// Nav2's selectors succeed every tick: a reason each, said after what
/// changed, and folded into one ("likewise for …").
#[test]
fn routine_siblings_fold_into_one_after_what_changed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gp.jsonl");
    common::run_nav2(
        "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",
        "nav2_followpath_fails_twice.plan",
        &out,
    );
    let (ok, text, err) = btx(&["why", out.to_str().unwrap(), "status(#1)"]);
    assert!(ok, "{err}");
    let lines: Vec<&str> = text.lines().collect();
    assert!(
        lines[1].starts_with("1. NavigateRecovery succeeded because FollowPath (#16) succeeded."),
        "{text}"
    );
    assert!(
        text.contains("because ControllerSelector succeeded. If ControllerSelector had failed, NavigateRecovery would have been running. Likewise for PlannerSelector, which also did as in every tick."),
        "{text}"
    );
    assert_eq!(
        text.matches("because PlannerSelector succeeded").count(),
        0,
        "{text}"
    );
}
