//! Han et al. 2021 §7.1.1 and §7.2: the paper's answers, exactly, on the
//! released trees (v3), their v4 conversion and the trees btx ships.

mod common;
use btx::explain::{han, TreeQuestion};
use common::*;

fn ask(tree: &btx::Tree, pick: &str, q: TreeQuestion) -> String {
    han::answer(tree, uid_of(tree, pick), q).text
}

const KITTING: [&str; 3] = ["kitting-tree.v3.xml", "kitting-tree.v4.xml", "@kitting.xml"];
const TAXI: [&str; 3] = [
    "taxi-domain-tree.v3.xml",
    "taxi-domain-tree.v4.xml",
    "@taxi.xml",
];

fn open(name: &str) -> btx::Tree {
    match name.strip_prefix('@') {
        Some(n) => load(&shipped(n)),
        None => load(&fixture(name)),
    }
}

#[test]
fn move_to_see_chuck() {
    for f in KITTING {
        let t = open(f);
        let n = "go insert large gear/move to see chuck";
        assert_eq!(
            ask(&t, n, TreeQuestion::Doing),
            "I move to see chuck.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Why),
            "I move to see chuck in order to go insert large gear.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Subgoal),
            "My subgoal is to go insert large gear.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Goal),
            "My goal is to build a gearbox kit.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::HowSubgoal),
            "To achieve the subgoal \"go insert large gear\", I need to do 3 steps. 1. move to see chuck. 2. detect chuck. 3. insert large gear.",
            "{f}"
        );
    }
}

#[test]
fn how_do_you_achieve_your_goal_on_the_v3_file_and_ours() {
    for f in ["kitting-tree.v3.xml", "@kitting.xml"] {
        let t = open(f);
        assert_eq!(
            ask(&t, "#6", TreeQuestion::HowGoal),
            "To achieve the goal \"build a gearbox kit\", I need to do 3 steps. 1. go insert large gear. 2. go pick screw. 3. go place screw.",
            "{f}"
        );
    }
    // The v4 conversion gives the second subtree its own name, which BT.CPP 3 ignored.
    assert_eq!(
        ask(&open("kitting-tree.v4.xml"), "#6", TreeQuestion::HowGoal),
        "To achieve the goal \"build a gearbox kit\", I need to do 3 steps. 1. go insert large gear. 2. go pick first screw. 3. go place first screw."
    );
}

#[test]
fn look_at_chuck_roughly_and_scan_scene() {
    for f in KITTING {
        let t = open(f);
        let n = "go insert large gear/look at chuck roughly";
        assert_eq!(
            ask(&t, n, TreeQuestion::Doing),
            "I look at chuck roughly.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Why),
            "I look at chuck roughly in order to detect chuck.",
            "{f}"
        );
        let s = "go insert large gear/scan scene for collision avoidance";
        assert_eq!(
            ask(&t, s, TreeQuestion::Doing),
            "I scan scene for collision avoidance.",
            "{f}"
        );
        assert_eq!(
            ask(&t, s, TreeQuestion::Why),
            "I scan scene for collision avoidance in order to insert large gear.",
            "{f}"
        );
        assert_eq!(
            ask(&t, s, TreeQuestion::Subgoal),
            "My subgoal is to go insert large gear.",
            "{f}"
        );
    }
}

#[test]
fn taxi_move_right() {
    for f in TAXI {
        let t = open(f);
        let n = "#5"; // the first move right
        assert_eq!(ask(&t, n, TreeQuestion::Doing), "I move right.", "{f}");
        assert_eq!(
            ask(&t, n, TreeQuestion::Why),
            "I move right in order to navigate to passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Subgoal),
            "My subgoal is to go pick up passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Goal),
            "My goal is to go deliver passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::HowSubgoal),
            "To achieve the subgoal \"go pick up passenger\", I need to do 2 steps. 1. navigate to passenger. 2. pick up passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::HowGoal),
            "To achieve the goal \"go deliver passenger\", I need to do 2 steps. 1. go pick up passenger. 2. go drop off passenger.",
            "{f}"
        );
    }
}

#[test]
fn taxi_drop_off() {
    for f in TAXI {
        let t = open(f);
        let n = "drop off passenger";
        assert_eq!(
            ask(&t, n, TreeQuestion::Doing),
            "I drop off passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Why),
            "I drop off passenger in order to go drop off passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Subgoal),
            "My subgoal is to go drop off passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::Goal),
            "My goal is to go deliver passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::HowSubgoal),
            "To achieve the subgoal \"go drop off passenger\", I need to do 2 steps. 1. navigate to destination. 2. drop off passenger.",
            "{f}"
        );
        assert_eq!(
            ask(&t, n, TreeQuestion::HowGoal),
            "To achieve the goal \"go deliver passenger\", I need to do 2 steps. 1. go pick up passenger. 2. go drop off passenger.",
            "{f}"
        );
    }
}

#[test]
fn the_goal_has_no_subgoal() {
    let t = open("@kitting.xml");
    assert_eq!(
        ask(&t, "#1", TreeQuestion::Subgoal),
        "Sorry. I don't have a subgoal."
    );
    assert_eq!(
        ask(&t, "#1", TreeQuestion::HowSubgoal),
        "Sorry. I don't have a subgoal."
    );
    assert_eq!(
        ask(&t, "#1", TreeQuestion::Why),
        "I build a gearbox kit because it is my goal."
    );
}

#[test]
fn an_unnamed_goal_is_said_to_be_missing() {
    let t = btx::xml::load_str(
        std::path::Path::new("mem.xml"),
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><Action ID="go"/></Sequence></BehaviorTree></root>"#,
        &Default::default(),
    )
    .unwrap()
    .tree;
    assert_eq!(
        ask(&t, "go", TreeQuestion::Goal),
        "Sorry. I don't have a named goal."
    );
    assert_eq!(
        ask(&t, "go", TreeQuestion::HowGoal),
        "Sorry. I don't have a named goal."
    );
    assert_eq!(
        ask(&t, "go", TreeQuestion::Why),
        "Sorry. I don't know why I go: no node above it has a name."
    );
}

#[test]
fn one_step_is_singular() {
    let t = open("kitting-tree.v4.xml");
    assert_eq!(
        ask(&t, "#33", TreeQuestion::HowSubgoal),
        "To achieve the subgoal \"go pick first screw\", I need to do 1 step. 1. go pick screw."
    );
}

#[test]
fn answers_name_the_nodes_they_used() {
    let t = open("@kitting.xml");
    let a = han::answer(&t, 11, TreeQuestion::Why);
    assert_eq!(a.nodes, vec![11, 9]);
    let a = han::answer(&t, 11, TreeQuestion::HowSubgoal);
    assert_eq!(a.nodes, vec![2, 6, 9, 13]);
}
