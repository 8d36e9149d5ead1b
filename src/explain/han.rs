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
        TreeQuestion::HowSubgoal => match answered_subgoal(tree, n) {
            Some(g) => q5(tree, "subgoal", g, &tree.spoken(g)),
            None => (NO_SUBGOAL.to_string(), vec![n]),
        },
        TreeQuestion::HowGoal => match goal_words(tree) {
            Some(w) => q5(tree, "goal", Tree::ROOT, &w.name),
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
    (format!("I {}.", tree.deed(n)), vec![n])
}

/// Q1 at a moment of a run: what is running then (every RUNNING leaf, as
/// under a Parallel), never a leaf that finished or was halted; once the
/// root's run has completed, in the past tense.
pub fn doing_at(tree: &Tree, run: &At) -> (String, Vec<Uid>) {
    let running = run.running_leaves(tree);
    if !running.is_empty() {
        let names: Vec<String> = running.iter().map(|&u| tree.deed(u)).collect();
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
        // The root ticked, none of its actions yet (the first steps of a
        // run): started, not "not started".
        None if last.is_none() && run.status(Tree::ROOT) == Status::Running => {
            nodes.push(Tree::ROOT);
            format!(
                "I have just started: {} is running, and no action has started yet.",
                tree.spoken(Tree::ROOT)
            )
        }
        None if last.is_none() => "I have not started yet.".to_string(),
        None => format!("I am between actions at this moment.{}", last_text("did")),
    };
    nodes.extend(last);
    (text, nodes)
}

/// "a", "a and b", "a, b and c".
pub fn and_list<S: AsRef<str>>(items: &[S]) -> String {
    let items: Vec<&str> = items.iter().map(AsRef::as_ref).collect();
    match items.as_slice() {
        [] => String::new(),
        [a] => a.to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Algorithm 2: the nearest ancestor that has a name different from the
/// node's. Beyond the paper, whose decorators have no names, a decorator
/// someone named (`<ForceFailure name="reset arm">`) counts.
pub fn why_ancestor(tree: &Tree, n: Uid) -> Option<Uid> {
    // Han's rule compares the names as written.
    let d = tree.description(n);
    tree.ancestors(n)
        .find(|&p| tree.has_name(p) && tree.description(p) != d)
}

fn q2(tree: &Tree, n: Uid) -> (String, Vec<Uid>) {
    match why_ancestor(tree, n) {
        Some(p) => (
            format!("I {} in order to {}.", tree.deed(n), tree.deed(p)),
            vec![n, p],
        ),
        None if n == Tree::ROOT => (
            format!("I {} because it is my goal.", tree.deed(n)),
            vec![n],
        ),
        // An unnamed root: the goal is the tree's ID (`goal_words`).
        None => match goal_words(tree) {
            Some(w) => (
                format!("I {} in order to {}.", tree.deed(n), w.deed),
                vec![n, Tree::ROOT],
            ),
            None => (
                format!(
                    "Sorry. I don't know why I {}: no node above it has a name.",
                    tree.deed(n)
                ),
                vec![n],
            ),
        },
    }
}

/// The goal's name and deed: the root's, or with an unnamed root the main
/// `<BehaviorTree>`'s ID as words (`NavigateToPose` → "navigate to pose"),
/// unless that ID names nothing (`MainTree`, one or two letters).
pub struct GoalWords {
    pub name: String,
    pub deed: String,
}

pub fn goal_words(tree: &Tree) -> Option<GoalWords> {
    if let Some(g) = goal(tree) {
        return Some(GoalWords {
            name: tree.spoken(g),
            deed: tree.deed(g),
        });
    }
    let id = &tree.main_tree;
    let plain: String = id
        .chars()
        .filter(|c| c.is_alphanumeric())
        .collect::<String>()
        .to_lowercase();
    let generic = plain.len() <= 2
        || [
            "maintree",
            "main",
            "behaviortree",
            "tree",
            "untitled",
            "root",
            "defaulttree",
            "mainbt",
        ]
        .contains(&plain.as_str());
    if generic {
        return None;
    }
    let name = crate::model::words(id);
    let name = if name == *id && !name.contains(' ') {
        name.to_lowercase()
    } else {
        name
    };
    Some(GoalWords {
        deed: crate::model::as_deed(&name),
        name,
    })
}

/// Algorithm 3: the nearest SubTree ancestor.
pub fn subgoal(tree: &Tree, n: Uid) -> Option<Uid> {
    tree.ancestors(n)
        .find(|&p| tree.node(p).kind == Kind::SubTree)
}

/// The subgoal Q3 and Q5 answer with: Algorithm 3's; beyond the paper, in
/// a tree with no SubTree at all (most of Nav2's), the goal's step or named
/// recovery that contains the node: such trees name their sub-objectives
/// as composites, not SubTrees.
pub fn answered_subgoal(tree: &Tree, n: Uid) -> Option<Uid> {
    if let Some(g) = subgoal(tree, n) {
        return Some(g);
    }
    if tree.nodes.iter().any(|x| x.kind == Kind::SubTree) {
        return None;
    }
    let mut parts = steps(tree, Tree::ROOT);
    parts.extend(
        crate::frame::recoveries(tree, Tree::ROOT)
            .into_iter()
            .flat_map(|(_, rs)| rs),
    );
    parts
        .into_iter()
        .find(|&p| p != n && tree.is_ancestor(p, n))
}

fn q3(tree: &Tree, n: Uid) -> (String, Vec<Uid>) {
    match answered_subgoal(tree, n) {
        Some(p) => (format!("My subgoal is to {}.", tree.deed(p)), vec![n, p]),
        None => (NO_SUBGOAL.to_string(), vec![n]),
    }
}

/// Algorithm 4's goal: the root, when it has a name.
pub fn goal(tree: &Tree) -> Option<Uid> {
    tree.has_name(Tree::ROOT).then_some(Tree::ROOT)
}

fn q4(tree: &Tree) -> (String, Vec<Uid>) {
    match goal_words(tree) {
        Some(w) => (format!("My goal is to {}.", w.deed), vec![Tree::ROOT]),
        None => (NO_GOAL.to_string(), vec![Tree::ROOT]),
    }
}

/// Algorithm 6 over Algorithm 5's steps; beyond the paper, then what the
/// named recoveries do ("If navigate with replanning fails, I recover by
/// running the recovery fallback.").
fn q5(tree: &Tree, what: &str, g: Uid, name: &str) -> (String, Vec<Uid>) {
    let mut s = steps(tree, g);
    // No named step (beyond the paper, whose trees always have some): its
    // actions are what it does.
    let unit = if s.is_empty() {
        s = tree.leaves_below(g).filter(|&l| l != g).collect();
        "action"
    } else {
        "step"
    };
    let mut text = if s.is_empty() {
        format!(
            "To achieve the {what} \"{name}\", I have nothing to do: it has no steps or actions."
        )
    } else {
        format!(
            "To achieve the {what} \"{name}\", I need to do {} {unit}{}.",
            s.len(),
            if s.len() == 1 { "" } else { "s" }
        )
    };
    for (i, &x) in s.iter().enumerate() {
        text.push_str(&format!(" {}. {}.", i + 1, tree.deed(x)));
    }
    let mut nodes = vec![g];
    nodes.extend(&s);
    for (fails, rs) in crate::frame::recoveries(tree, g) {
        // What fails: the branch by its name, else the steps in it.
        let branch = if tree.has_name(fails) {
            tree.spoken(fails)
        } else {
            let inner: Vec<String> = steps(tree, fails).iter().map(|&x| tree.spoken(x)).collect();
            if inner.is_empty() {
                // An unnamed built-in by its v4 name, so that a v3 file and
                // its conversion read alike (v3's RetryUntilSuccesful).
                crate::model::words(tree.type_name(fails))
            } else {
                and_list(&inner)
            }
        };
        let by: Vec<String> = rs
            .iter()
            .map(|&r| crate::model::gerund(&tree.deed(r)))
            .collect();
        text.push_str(&format!(
            " If {branch} fails, I recover by {}.",
            by.join(", then ")
        ));
        nodes.extend(rs);
    }
    (text, nodes)
}
