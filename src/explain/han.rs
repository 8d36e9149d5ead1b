//! Han et al.'s hierarchical questions Q1–Q5 (Algorithms 1–6), with the
//! paper's sentence templates.

use super::{Answer, Question, TreeQuestion};
use crate::frame::steps;
use crate::model::{Kind, Tree, Uid};
use crate::run::Status;
use crate::session::At;

/// Answers one of Q1–Q5 about the node `n` the robot is executing.
pub fn answer(tree: &Tree, n: Uid, q: TreeQuestion) -> Answer {
    let (text, nodes) = match q {
        TreeQuestion::Doing => q1(tree, n),
        TreeQuestion::Why => q2(tree, n),
        TreeQuestion::Subgoal => q3(tree, n),
        TreeQuestion::Goal => q4(tree),
        TreeQuestion::HowSubgoal => match subgoal(tree, n) {
            Some(g) => q5(tree, "subgoal", g),
            None => (NO_SUBGOAL.to_string(), vec![n]),
        },
        TreeQuestion::HowGoal => match goal(tree) {
            Some(g) => q5(tree, "goal", g),
            None => (NO_GOAL.to_string(), vec![Tree::ROOT]),
        },
    };
    Answer {
        question: Question::Tree(q),
        text,
        nodes,
        insertion: None,
    }
}

const NO_SUBGOAL: &str = "Sorry. I don't have a subgoal.";
const NO_GOAL: &str = "Sorry. I don't have a named goal.";

/// Algorithm 1.
fn q1(tree: &Tree, n: Uid) -> (String, Vec<Uid>) {
    (format!("I {}.", tree.spoken(n)), vec![n])
}

/// Q1 at a moment of a run: what is running then (every RUNNING leaf, as
/// under a Parallel), never a leaf that finished or was halted; once the
/// root's run has completed, in the past tense.
pub fn doing_at(tree: &Tree, run: &At) -> (String, Vec<Uid>) {
    let running = run.running_leaves(tree);
    if !running.is_empty() {
        let names: Vec<String> = running.iter().map(|&u| tree.spoken(u)).collect();
        return (format!("I {}.", and_list(&names)), running);
    }
    let last = run.current();
    let last_text = |verb: &str| match last {
        Some(l) => format!(
            " The last thing I {verb} was {}{}.",
            tree.spoken(l),
            match (run.halted(l), run.last_completed(l)) {
                (true, _) => ", which was halted",
                (_, Some(Status::Success)) => ", which succeeded",
                (_, Some(Status::Failure)) => ", which failed",
                _ => "",
            }
        ),
        None => String::new(),
    };
    let mut nodes: Vec<Uid> = Vec::new();
    let text = match run.root_outcome() {
        Some(s) => {
            nodes.push(Tree::ROOT);
            format!(
                "I have finished: {} {}.{}",
                tree.spoken(Tree::ROOT),
                match s {
                    Status::Success => "succeeded",
                    _ => "failed",
                },
                last_text("did")
            )
        }
        None if last.is_none() => "I have not started yet.".to_string(),
        None => format!("I am between actions at this moment.{}", last_text("did")),
    };
    nodes.extend(last);
    (text, nodes)
}

/// "a", "a and b", "a, b and c".
pub(super) fn and_list<S: AsRef<str>>(items: &[S]) -> String {
    let items: Vec<&str> = items.iter().map(AsRef::as_ref).collect();
    match items.as_slice() {
        [] => String::new(),
        [a] => a.to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Algorithm 2: the nearest non-decorator ancestor that has a name different
/// from the node's.
pub fn why_ancestor(tree: &Tree, n: Uid) -> Option<Uid> {
    // Han's rule compares the names as written.
    let d = tree.description(n);
    tree.ancestors(n)
        .find(|&p| !tree.is_decorator(p) && tree.has_name(p) && tree.description(p) != d)
}

fn q2(tree: &Tree, n: Uid) -> (String, Vec<Uid>) {
    match why_ancestor(tree, n) {
        Some(p) => (
            format!("I {} in order to {}.", tree.spoken(n), tree.spoken(p)),
            vec![n, p],
        ),
        None if n == Tree::ROOT => (
            format!("I {} because it is my goal.", tree.spoken(n)),
            vec![n],
        ),
        None => (
            format!(
                "Sorry. I don't know why I {}: no node above it has a name.",
                tree.spoken(n)
            ),
            vec![n],
        ),
    }
}

/// Algorithm 3: the nearest SubTree ancestor.
pub fn subgoal(tree: &Tree, n: Uid) -> Option<Uid> {
    tree.ancestors(n)
        .find(|&p| tree.node(p).kind == Kind::SubTree)
}

fn q3(tree: &Tree, n: Uid) -> (String, Vec<Uid>) {
    match subgoal(tree, n) {
        Some(p) => (format!("My subgoal is to {}.", tree.spoken(p)), vec![n, p]),
        None => (NO_SUBGOAL.to_string(), vec![n]),
    }
}

/// Algorithm 4's goal: the root, when it has a name.
pub fn goal(tree: &Tree) -> Option<Uid> {
    tree.has_name(Tree::ROOT).then_some(Tree::ROOT)
}

fn q4(tree: &Tree) -> (String, Vec<Uid>) {
    match goal(tree) {
        Some(g) => (format!("My goal is to {}.", tree.spoken(g)), vec![g]),
        None => (NO_GOAL.to_string(), vec![Tree::ROOT]),
    }
}

/// Algorithm 6 over Algorithm 5's steps.
fn q5(tree: &Tree, what: &str, g: Uid) -> (String, Vec<Uid>) {
    let s = steps(tree, g);
    let mut text = format!(
        "To achieve the {what} \"{}\", I need to do {} step{}.",
        tree.spoken(g),
        s.len(),
        if s.len() == 1 { "" } else { "s" }
    );
    for (i, &x) in s.iter().enumerate() {
        text.push_str(&format!(" {}. {}.", i + 1, tree.spoken(x)));
    }
    let mut nodes = vec![g];
    nodes.extend(s);
    (text, nodes)
}
