//! The hard check: running a fixture tree with its plan gives exactly the
//! (tick, uid, previous status, status) sequence that BehaviorTree.CPP logged.

mod common;
use btx::run::plan::{Plan, PlanLeaves};
use btx::run::{Event, Executor, RunOptions, Status};
use common::*;

fn ours(tree: &str, plan: &str) -> Vec<(u32, u32, String, String)> {
    let t = load(&fixture(tree));
    let plan = Plan::load(&fixture(&format!("plans/{plan}.plan"))).unwrap();
    let leaves = PlanLeaves::new(plan, &t);
    let mut ex = Executor::new(&t, leaves, RunOptions::default());
    let mut out = Vec::new();
    for _ in 0..500 {
        let s = ex.tick_once().unwrap();
        for e in ex.take_events() {
            if let Event::Transition {
                tick,
                uid,
                prev,
                status,
                ..
            } = e
            {
                out.push((tick, uid, prev.to_string(), status.to_string()));
            }
        }
        if s != Status::Running {
            break;
        }
    }
    out
}

fn check(tree: &str, plan: &str, run: &str) {
    let want = logged(run);
    let got = ours(tree, plan);
    for (i, (w, g)) in want.iter().zip(&got).enumerate() {
        assert_eq!(w, g, "{run}: transition {i} differs");
    }
    assert_eq!(want.len(), got.len(), "{run}: number of transitions");
}

#[test]
fn taxi_nominal() {
    check("taxi-domain-tree.v4.xml", "taxi_nominal", "taxi_nominal");
    check("taxi-domain-tree.v3.xml", "taxi_nominal", "taxi_nominal_v3");
}

#[test]
fn kitting_nominal() {
    check("kitting-tree.v4.xml", "kitting_nominal", "kitting_nominal");
    check(
        "kitting-tree.v3.xml",
        "kitting_nominal",
        "kitting_nominal_v3",
    );
}

#[test]
fn kitting_lookat_fails_once() {
    check(
        "kitting-tree.v4.xml",
        "kitting_lookat_fails_once",
        "kitting_lookat_fails_once",
    );
    check(
        "kitting-tree.v3.xml",
        "kitting_lookat_fails_once",
        "kitting_lookat_fails_once_v3",
    );
}

#[test]
fn kitting_detect_chuck_always_fails() {
    check(
        "kitting-tree.v4.xml",
        "kitting_detect_chuck_always_fails",
        "kitting_detect_chuck_always_fails",
    );
    check(
        "kitting-tree.v3.xml",
        "kitting_detect_chuck_always_fails",
        "kitting_detect_chuck_always_fails_v3",
    );
}

#[test]
fn kitting_grasp_check_fails_first() {
    check(
        "kitting-tree.v4.xml",
        "kitting_grasp_check_fails_first",
        "kitting_grasp_check_fails_first",
    );
    check(
        "kitting-tree.v3.xml",
        "kitting_grasp_check_fails_first",
        "kitting_grasp_check_fails_first_v3",
    );
}

#[test]
fn shipped_kitting_tree_runs_like_the_recorded_one() {
    check(
        "../../trees/kitting.xml",
        "kitting_lookat_fails_once",
        "kitting_lookat_fails_once",
    );
}
