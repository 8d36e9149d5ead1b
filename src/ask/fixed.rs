//! Han's questions, the failure questions and "Can you X?", asked in the
//! user's words: answered by `explain` about the node picked or running.

use super::context::Context;
use super::Reply;
use crate::explain::{Question, TreeQuestion};

pub fn answer(cx: &Context, q: &Question, r: &mut Reply) -> Result<(), String> {
    // "Can you X?" inserts a subgoal into a run that goes on: once the
    // root has completed, there is none to insert it into.
    if let (Question::CanYou(_), Some(at)) = (q, cx.at.as_ref()) {
        let root = cx.tree.root().uid;
        if let (Some((p, s)), false) = (
            at.last_completion(root)
                .filter(|_| at.root_outcome().is_some()),
            at.status(root) == crate::run::Status::Running,
        ) {
            r.about = Some(root);
            r.understood = q.wording();
            let end = format!(
                "{} {} at {}",
                cx.tree.spoken(root),
                s.as_str(),
                super::say::step_moment(at.index, p)
            );
            let ended =
                format!("the run had ended by then ({end}), so there is no subgoal to add it to.");
            let later = "Ask while the robot runs, or of the tree.";
            r.answer = match (q, has_it(cx, at, q)) {
                (_, Some(has)) => format!("No, not now: {ended} {has} {later}"),
                (Question::CanYou(x), None) => format!(
                    "No: no behaviour of the tree is called \"{x}\" (and the run had ended by then: {end})."
                ),
                _ => format!("No: {ended} {later}"),
            };
            return Ok(());
        }
    }
    let uid = asked_of(cx, q)?;
    let a = crate::explain::answer(cx.tree, cx.at.as_ref(), uid, q)?;
    r.about = Some(uid);
    r.understood = q.wording();
    r.answer = a.text;
    // Nav2 calls a node again within its tick: why it runs again (the
    // failure and the retry the run shows) is the root cause, told before
    // the paper's answer of what it runs for.
    if let (Question::Tree(TreeQuestion::Why), Some(at)) = (q, cx.at.as_ref()) {
        let again = (at.status(uid) == crate::run::Status::Running)
            .then(|| at.index.call_start(uid, at.pos + 1))
            .flatten()
            .and_then(|p| {
                super::why::called_again(cx, at, uid, p).or_else(|| {
                    // "Why is it being run again?": a start in a later tick.
                    r.question
                        .to_lowercase()
                        .contains("again")
                        .then(|| super::why::restarted(cx, at, uid, p))
                        .flatten()
                })
            });
        if let Some(again) = again {
            r.answer = format!("{again}\n{}", r.answer);
        }
    }
    r.nodes = a.nodes;
    r.insertion = a.insertion;
    Ok(())
}

/// "Can you look around?" asked once the run has ended: the tree has it,
/// where it does, and what it last did in the run; not a bare "No".
fn has_it(cx: &Context, at: &crate::session::At, q: &Question) -> Option<String> {
    let Question::CanYou(x) = q else {
        return None;
    };
    let &u = crate::explain::insert::named_in_tree(cx.tree, x).first()?;
    let did = match at.last_completion(u) {
        Some((p, s)) => format!(
            "it last ended {} at {}",
            s.as_str(),
            super::say::step_moment(at.index, p)
        ),
        None if at.index.changes_of(u).is_empty() => "it did not run in this run".into(),
        None => "it ran in this run".into(),
    };
    Some(format!(
        "The tree has it: {} (#{u}), {did}.",
        crate::causal::english::capitalised(&cx.tree.spoken(u))
    ))
}

/// The node a question of Han's or of the run is asked of, where the
/// question names none.
fn asked_of(cx: &Context, q: &Question) -> Result<crate::model::Uid, String> {
    Ok(match (cx.node, cx.at.as_ref()) {
        (Some(u), _) => u,
        // Han's current node (the leaf ticked last) where it still runs.
        // Where an action has finished beside a leaf still running ("look
        // around" done, "walk" on under a Parallel), Han's questions are of
        // that leaf, so that "why are you doing this?" is of what "what are
        // you doing?" says; a condition ticked last is what is checked now,
        // and what went wrong stays of the leaf that finished. Before any
        // action is ticked, the deepest node running (the paper's questions
        // are then about it), else the root.
        (None, Some(at)) => {
            let running = |u: crate::model::Uid| at.status(u) == crate::run::Status::Running;
            match at.current() {
                Some(c)
                    if !running(c)
                        && matches!(q, Question::Tree(_))
                        && cx.tree.node(c).kind == crate::model::Kind::Action =>
                {
                    at.running_leaves(cx.tree).first().copied().unwrap_or(c)
                }
                Some(c) => c,
                None => (1..=cx.tree.len() as crate::model::Uid)
                    .rev()
                    .find(|&u| running(u))
                    .unwrap_or(cx.tree.root().uid),
            }
        }
        (None, None) => {
            return Err(
                "pick the node to ask about with --node (a tree has no current node)".into(),
            )
        }
    })
}
