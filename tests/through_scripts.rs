//! Complete where it claims to be (#32 item 4): a leaf whose writes reach
//! the target through a script or the blackboard (a `_skipIf` reading what
//! a leaf's `_onSuccess` wrote, a Switch whose variable a leaf sets) is
//! found by running the tree again, and where nothing can be run again
//! "No explanation" says what was not searched.

mod common;

use btx::causal::{session_domain, why};
use btx::run::plan::{Plan, PlanLeaves};
use btx::run::RunOptions;
use btx::session::record::simulate;
use btx::session::{Session, Source};
use btx::xml::{load_str, LoadOptions};
use std::path::Path;

fn run(xml: &str, as_log: bool) -> Session {
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(
        Path::new("p.plan"),
        "@default_action = S\n@default_condition = S\n",
    )
    .unwrap();
    let leaves = PlanLeaves::new(plan.clone(), &tree);
    let source = Source {
        kind: if as_log { "btlog" } else { "plan" }.into(),
        path: as_log.then(|| "t.btlog".into()),
        text: (!as_log).then_some(plan.text),
        name: None,
    };
    simulate(&tree, source, None, 5, RunOptions::default(), leaves).unwrap()
}

const SKIP_IF: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="T"><Sequence>
  <Script code="k := 0"/>
  <ForceSuccess><Action ID="A" name="setter" _onSuccess="k := 1"/></ForceSuccess>
  <Fallback><Action ID="B" name="guarded" _skipIf="k == 1"/><Action ID="C" name="other"/></Fallback>
</Sequence></BehaviorTree></root>"#;

const SWITCH: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="T"><Sequence>
  <Script code="mode := 1"/>
  <ForceSuccess><Action ID="A" name="setter" _onSuccess="mode := 2"/></ForceSuccess>
  <Switch2 variable="{mode}" case_1="1" case_2="2">
    <Action ID="B" name="first way"/><Action ID="C" name="second way"/><Action ID="D" name="no way"/>
  </Switch2>
</Sequence></BehaviorTree></root>"#;

#[test]
fn a_skip_if_that_reads_a_leaf_s_write_is_explained_by_that_leaf() {
    let s = run(SKIP_IF, false);
    let d = session_domain(&s, None).unwrap();
    let mut w = why(&s, d, "status(guarded)", &[], None, 2).unwrap();
    w.full = true;
    let text = w.text();
    assert!(
        text.contains("1. Guarded was skipped because setter succeeded. If setter had failed, guarded would have succeeded."),
        "{text}"
    );
    assert!(text.contains("Checked: running the tree again"), "{text}");
}

#[test]
fn a_switch_whose_variable_a_leaf_sets_is_explained_by_that_leaf() {
    let s = run(SWITCH, false);
    let d = session_domain(&s, None).unwrap();
    let w = why(&s, d, "status(first way)", &[], None, 2).unwrap();
    let text = w.text();
    assert!(
        text.contains("because setter succeeded. If setter had failed"),
        "{text}"
    );
    assert!(!text.contains("No explanation"), "{text}");
}

#[test]
fn a_log_says_what_it_could_not_search() {
    let s = run(SKIP_IF, true);
    let d = session_domain(&s, None).unwrap();
    let mut w = why(&s, d, "status(guarded)", &[], None, 2).unwrap();
    w.full = true;
    let text = w.text();
    assert!(text.contains("No explanation up to depth 2"), "{text}");
    assert!(
        text.contains(
            "Not searched by the model: guarded (#6) decides by the blackboard or a script"
        ),
        "{text}"
    );
    assert!(
        text.contains("Whether an explanation reaches the target that way is unknown."),
        "{text}"
    );
    assert_eq!(w.json()["held"][0], 6);
}

/// Issue #32's Nav2 example: why did the recovery run? FollowPath failed,
/// at a call the model of the tick does not hold (the RecoveryNode sends
/// the pipeline round again within the tick): found by running the tree
/// again, and said first.
#[test]
fn why_the_recovery_ran_is_that_follow_path_failed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gp.jsonl");
    common::run_nav2(
        "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",
        "nav2_followpath_fails_twice.plan",
        &out,
    );
    let s = Session::load(&out).unwrap();
    let d = session_domain(&s, None).unwrap();
    let at = btx::session::Moment {
        tick: 7,
        step: None,
    };
    let w = why(&s, d, "executed(RecoveryFallback)", &[], Some(at), 2).unwrap();
    let text = w.text();
    let second = text.lines().nth(1).unwrap_or("");
    assert_eq!(
        second,
        "• RecoveryFallback executed because FollowPath (#16) failed at 7:3. If it had succeeded then, RecoveryFallback would not have executed.",
        "{text}"
    );
}
