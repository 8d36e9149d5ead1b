//! Built-in worlds: the taxi domain solved by value iteration, and the kitting
//! scenarios.

mod common;
use btx::run::blackboard::EntryId;
use btx::run::plan::PlanLeaves;
use btx::run::world::kitting;
use btx::run::world::taxi::{policy_tree_xml, Action, Costs, Grid, TaxiLeaves};
use btx::run::{Leaves, RunOptions};
use btx::session::record::{record, RunRequest};
use btx::session::{Moment, Session, Source};
use btx::xml::{load_str, LoadOptions};
use common::*;
use serde_json::Value;
use std::path::Path;

fn leaf_ids(t: &btx::Tree) -> Vec<String> {
    t.leaves_below(btx::Tree::ROOT)
        .map(|u| t.node(u).id.clone())
        .collect()
}

fn run<L: Leaves>(tree: &btx::Tree, leaves: L) -> Session {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.jsonl");
    let req = RunRequest {
        tree,
        tree_file: None,
        source: Source {
            kind: "world".into(),
            path: None,
            text: None,
            name: None,
        },
        seed: Some(0),
        max_ticks: 100,
        options: RunOptions::default(),
        ask: None,
        out: &out,
    };
    record(req, leaves).unwrap_or_else(|e| panic!("{e:?}"));
    Session::load(&out).unwrap()
}

#[test]
fn the_generated_policy_tree_is_the_shipped_taxi_tree() {
    let g = Grid::han();
    let xml = policy_tree_xml(&g.rollout(&g.solve(Costs::OPTIMAL)));
    let generated = load_str(Path::new("generated.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let shipped = load(&shipped("taxi.xml"));
    assert_eq!(leaf_ids(&generated), leaf_ids(&shipped));
    assert_eq!(
        btx::export::tree_text(&generated),
        btx::export::tree_text(&shipped)
    );
    // And the released tree's v3 spelling of the same actions.
    let released: Vec<String> = leaf_ids(&load(&fixture("taxi-domain-tree.v3.xml")))
        .iter()
        .map(|s| s.replace(' ', "_"))
        .collect();
    let ours = leaf_ids(&shipped);
    assert_eq!(released, ours);
}

#[test]
fn the_taxi_world_delivers_without_tolls_and_the_expected_policy_pays_two() {
    let tree = load(&shipped("taxi.xml"));
    let s = run(&tree, TaxiLeaves::new(Grid::han()));
    let end = s
        .at(Moment {
            tick: s.index.ticks(),
            step: None,
        })
        .unwrap();
    let get = |k: &str| {
        end.entry(&EntryId {
            scope: 0,
            key: k.into(),
        })
        .cloned()
    };
    assert_eq!(get("passenger"), Some(Value::from("delivered")));
    assert_eq!(get("tolls paid"), Some(Value::from(0)));
    assert_eq!(
        (get("taxi column"), get("taxi row")),
        (Some(Value::from(1)), Some(Value::from(1)))
    );
    // It ticks like the recorded taxi run (one tick of RUNNING per action).
    let logged = std::fs::read_to_string(fixture("runs/taxi_nominal.txt")).unwrap();
    let ours: Vec<String> = s
        .index
        .transitions
        .iter()
        .map(|t| format!("{} {} {} {}", t.tick, t.uid, t.prev, t.status))
        .collect();
    let theirs: Vec<&str> = logged.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(ours, theirs);

    let expected = load(&shipped("taxi-expected.xml"));
    let s = run(&expected, TaxiLeaves::new(Grid::han()));
    let end = s
        .at(Moment {
            tick: s.index.ticks(),
            step: None,
        })
        .unwrap();
    assert_eq!(
        end.entry(&EntryId {
            scope: 0,
            key: "tolls paid".into()
        }),
        Some(&Value::from(2))
    );
    assert_eq!(
        end.entry(&EntryId {
            scope: 0,
            key: "passenger".into()
        }),
        Some(&Value::from("delivered"))
    );
}

#[test]
fn a_move_into_a_wall_fails() {
    let xml = r#"<root BTCPP_format="4"><BehaviorTree><Sequence name="go"><move_up name="move up"/><move_right name="move right"/><move_right name="move right"/></Sequence></BehaviorTree></root>"#;
    let tree = load_str(Path::new("w.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let s = run(&tree, TaxiLeaves::new(Grid::han()));
    // From (1,1): up to (1,2), right to (2,2), then the wall.
    let last = s
        .index
        .transitions
        .iter()
        .rev()
        .find(|t| t.uid == 4 && t.status.is_completed())
        .unwrap();
    assert_eq!(last.status, btx::run::Status::Failure);
    assert_eq!(
        Action::of_leaf("move right", "move_right"),
        Some(Action::MoveRight)
    );
}

#[test]
fn kitting_world_seeds_are_the_scenarios() {
    let tree = load(&shipped("kitting.xml"));
    let (name, plan) = kitting::scenario(1).unwrap();
    assert_eq!(name, "lookat-fails-once");
    let s = run(&tree, PlanLeaves::new(plan, &tree));
    let shipped = Session::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/kitting-lookat-fails-once.jsonl"),
    )
    .unwrap();
    assert_eq!(s.index.transitions, shipped.index.transitions);
    assert!(kitting::scenario(6).unwrap_err().contains("seeds 0 to 5"));
}
