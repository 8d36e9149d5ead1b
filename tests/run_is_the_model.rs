//! The run is the model (#39 items 1–4): a why about any call a run holds
//! is answered from the run's own leaf outcomes, run again through the
//! executor with one of them changed. Each claim is checked here against a
//! run of the tree with the plan changed so that the counterfactual holds.
//!
//! The run is issue #39's: Nav2 main's
//! `navigate_to_pose_w_replanning_and_recovery.xml` (copied from
//! navigation2 at a3a9704, see tests/fixtures/realworld/SOURCES) with
//! `FollowPath = 2RF, 2RF, 3RS`: the FollowPath action (#22) fails at 4:1,
//! its RecoveryNode (#21) clears the local costmap and tries it again, it
//! fails again at 7:1 and #21 fails at 7:4.

mod common;

use common::{btx, fixture};
use std::path::Path;

const NAV: &str = "realworld/nav2-a3a9704/navigate_to_pose_w_replanning_and_recovery.xml";
const MODELS: &str = "realworld/nav2-a3a9704/nav2_tree_nodes.xml";

/// Runs the navigator with `FollowPath = {follow}`: the session's path.
fn run(dir: &Path, name: &str, follow: &str) -> String {
    let plan = dir.join(format!("{name}.plan"));
    std::fs::write(
        &plan,
        format!("@default_action = 1RS\n@default_condition = S\nFollowPath = {follow}\n"),
    )
    .unwrap();
    let out = dir.join(format!("{name}.jsonl"));
    let (ok, _, err) = btx(&[
        "-q",
        "run",
        fixture(NAV).to_str().unwrap(),
        "--models",
        fixture(MODELS).to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    out.display().to_string()
}

/// The rows of `btx log RUN --node N` as (moment, prev, status).
fn rows(run: &str, node: &str) -> Vec<(String, String, String)> {
    let (ok, out, err) = btx(&["log", run, "--node", node]);
    assert!(ok, "{err}");
    out.lines()
        .skip(1)
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (
                format!("{}:{}", w[0], w[1]),
                w[4].to_string(),
                w[6].to_string(),
            )
        })
        .collect()
}

#[test]
fn a_recovery_node_s_failure_is_told_down_to_the_action_that_failed_again() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), "twice", "2RF, 2RF, 3RS");
    assert!(rows(&r, "#21").contains(&("7:4".into(), "IDLE".into(), "FAILURE".into())));
    let (ok, out, err) = btx(&["why", &r, "status(#21)", "--at", "7:4"]);
    assert!(ok, "{err}");
    assert_eq!(
        out,
        "Why did the FollowPath recovery node (#21) fail at 7:4?\n\
         1. The FollowPath recovery node (#21) failed at 7:4 because the FollowPath action (#22) failed again at 7:1, after it failed at 4:1 and its one retry (number_of_retries=1) was used. \
         Had it succeeded at 7:1, the FollowPath recovery node (#21) would have succeeded at 7:4; had it succeeded at 4:1, the FollowPath recovery node (#21) would have succeeded at 4:4.\n"
    );
    // The claims, run: the second call succeeding, then the first.
    let second = run(dir.path(), "second", "2RF, 2RS, 3RS");
    assert!(rows(&second, "#21").contains(&("7:4".into(), "IDLE".into(), "SUCCESS".into())));
    let first = run(dir.path(), "first", "2RS, 2RF, 3RS");
    assert!(rows(&first, "#21").contains(&("4:4".into(), "IDLE".into(), "SUCCESS".into())));
}

#[test]
fn a_call_within_a_tick_is_answered_not_refused() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), "twice", "2RF, 2RF, 3RS");
    let (ok, out, err) = btx(&["why", &r, "status(#22)", "--at", "7:1"]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("Why did the FollowPath action (#22) fail at 7:1?\nThe FollowPath action (#22) returned FAILURE itself at 7:1, after running from 5:6 (3 ticks): it is an action, so nothing in the tree decided it. It had failed once before, at 4:1. The FollowPath recovery node (#21) then failed, at 7:4;"),
        "{out}"
    );
    let (ok, json, err) = btx(&["why", &r, "status(#21)", "--at", "7:4", "--format", "json"]);
    assert!(ok, "{err}");
    let j: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        j["question"],
        "Why did the FollowPath recovery node (#21) fail at 7:4?"
    );
    let causes = j["by_calls"]["causes"].as_array().unwrap();
    assert_eq!(causes.len(), 2, "{json}");
    assert_eq!(causes[0]["leaf"], 22);
    assert_eq!(causes[0]["at"], "7:1");
    assert_eq!(causes[0]["instead"]["status"], "SUCCESS");
}

/// A cause comes before its effect: at 4:1 the model of tick 4 said the
/// action failed "because ClearLocalCostmap-Context was still running",
/// the clearing its failure set going at 4:5.
#[test]
fn no_cause_is_an_event_after_the_one_asked_about() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), "twice", "2RF, 2RF, 3RS");
    assert!(rows(&r, "#25").contains(&("4:5".into(), "IDLE".into(), "RUNNING".into())));
    let (ok, out, err) = btx(&["why", &r, "status(#22)", "--at", "4:1"]);
    assert!(ok, "{err}");
    assert!(!out.contains("because ClearLocalCostmap"), "{out}");
    assert!(
        out.contains("returned FAILURE itself at 4:1") && out.contains("tried it again at 5:6"),
        "{out}"
    );
}

/// Every step at which a node of a Nav2 navigator failed, asked about:
/// none refused, and every answer's causes come before the failure.
#[test]
fn every_failure_of_the_nav2_navigators_is_answered_at_its_step() {
    let dir = tempfile::tempdir().unwrap();
    let mut navigators: Vec<_> = std::fs::read_dir(fixture("realworld/nav2"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_str().unwrap();
            n.starts_with("nav") && !n.contains("tree_nodes") && !n.contains(".docs.")
        })
        .collect();
    navigators.push(fixture(NAV));
    navigators.sort();
    let (mut asked, mut refused, mut later) = (0, Vec::new(), Vec::new());
    for (i, nav) in navigators.iter().enumerate() {
        let out = dir.path().join(format!("{i}.jsonl"));
        let models = if nav.ends_with(NAV) {
            fixture(MODELS)
        } else {
            common::nav2_models_for(nav)
        };
        let (ok, _, err) = btx(&[
            "-q",
            "run",
            nav.to_str().unwrap(),
            "--models",
            models.to_str().unwrap(),
            "--plan",
            fixture("plans/nav2_followpath_fails_twice.plan")
                .to_str()
                .unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{}: {err}", nav.display());
        let out = out.to_str().unwrap();
        let (_, log, _) = btx(&["log", out, "--format", "json"]);
        let log: serde_json::Value = serde_json::from_str(&log).unwrap();
        let rows = log["transitions"].as_array().unwrap();
        for t in rows.iter().filter(|t| t["status"] == "FAILURE") {
            let at = format!("{}:{}", t["tick"], t["step"]);
            let target = format!("status(#{})", t["uid"]);
            asked += 1;
            let (ok, json, err) = btx(&["why", out, &target, "--at", &at, "--format", "json"]);
            if !ok {
                refused.push(format!("{}: {target} at {at}: {err}", nav.display()));
                continue;
            }
            let j: serde_json::Value = serde_json::from_str(&json).unwrap();
            for c in j["by_calls"]["causes"].as_array().into_iter().flatten() {
                let m = |s: &str| {
                    let (a, b) = s.split_once(':').unwrap();
                    (a.parse::<u32>().unwrap(), b.parse::<u32>().unwrap())
                };
                if m(c["at"].as_str().unwrap()) >= m(&at) {
                    later.push(format!("{target} at {at}: {}", c["text"]));
                }
            }
        }
    }
    eprintln!(
        "Nav2 navigators: {asked} failures asked about at their step; {} refused; {} causes after the failure",
        refused.len(),
        later.len()
    );
    assert!(asked >= 100, "{asked}");
    assert!(refused.is_empty(), "{refused:#?}");
    assert!(later.is_empty(), "{later:#?}");
}

/// Faults before branches (#39 item 5): at tick 7 "What went wrong?" named
/// the routine replanning check ("global updated goal succeeded and the
/// inverter above it turned that into a failure"), a branch taken by
/// design, not FollowPath's second failure.
#[test]
fn what_went_wrong_names_the_fault_not_a_branch_taken() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), "twice", "2RF, 2RF, 3RS");
    let (ok, out, err) = btx(&["ask", &r, "--at", "7", "What went wrong?"]);
    assert!(ok, "{err}");
    assert!(!out.contains("global updated goal"), "{out}");
    assert_eq!(
        out,
        "I could not run NavigateRecovery because I was unable to run FollowPath as FollowPath failed.\n"
    );
}

/// Asked in words at a step inside a node ticked twice in the tick, the
/// root cause comes first and is said once (it was said twice: the
/// record's chain, then the run's).
#[test]
fn asked_in_words_at_the_step_the_cause_is_said_once() {
    let dir = tempfile::tempdir().unwrap();
    let r = run(dir.path(), "twice", "2RF, 2RF, 3RS");
    let (ok, out, err) = btx(&[
        "ask",
        &r,
        "--at",
        "7:4",
        "why did the followpath recovery node fail?",
    ]);
    assert!(ok, "{err}");
    assert_eq!(out.matches(" because ").count(), 1, "{out}");
    assert!(
        out.lines().nth(1).unwrap_or("").starts_with(
            "1. The FollowPath recovery node (#21) failed at 7:4 because the FollowPath action (#22) failed again at 7:1"
        ),
        "{out}"
    );
}

/// The root cause is said of the state asked about: at the end of tick 7
/// NavigateWithReplanning (#2) runs again (it failed at 7:12 and started
/// over at 7:43), so why it keeps running is not answered with why it
/// failed; at 7:12 it is.
#[test]
fn the_root_cause_is_of_the_state_asked_about() {
    let dir = tempfile::tempdir().unwrap();
    let s = run(dir.path(), "nav", "2RF, 2RF, 3RS");
    let (ok, end, err) = btx(&["why", &s, "status(#2)", "--at", "7"]);
    assert!(ok, "{err}");
    assert!(
        end.starts_with("Why did NavigateWithReplanning keep running"),
        "{end}"
    );
    assert!(!end.contains("failed at 7:12 because"), "{end}");
    let (ok, at, err) = btx(&["why", &s, "status(#2)", "--at", "7:12", "--format", "json"]);
    assert!(ok, "{err}");
    let j: serde_json::Value = serde_json::from_str(&at).unwrap();
    assert_eq!(j["root_cause"]["leaf"], 22, "{j}");
}
