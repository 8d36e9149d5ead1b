//! What each node does in the tick, as the model sees it: the statuses it
//! can return, its control flow, its scripts, and its loops.

use super::*;

pub(super) fn status_range(kind: Kind) -> Vec<Val> {
    let mut r = vec![Val::Status(Status::Success), Val::Status(Status::Failure)];
    if kind != Kind::Condition {
        r.insert(0, Val::Status(Status::Running));
    }
    r.push(Val::Status(Status::Idle));
    r
}

/// The statuses a built-in node can return, where they are fewer than
/// its kind allows: no explanation may suppose a Script failing, a
/// ForceSuccess failing or an AlwaysFailure succeeding. A node with
/// pre- or post-condition scripts may be made to return anything.
pub(super) fn returns(node: &crate::model::Node) -> Option<&'static [Status]> {
    use Status::{Failure, Running, Success};
    if !node.scripts.is_empty() {
        return None;
    }
    Some(match node.builtin? {
        Builtin::AlwaysSuccess
        | Builtin::Script
        | Builtin::SetBlackboard
        | Builtin::UnsetBlackboard => &[Success],
        Builtin::AlwaysFailure => &[Failure],
        Builtin::Sleep => &[Running, Success],
        Builtin::ForceSuccess => &[Running, Success],
        Builtin::ForceFailure => &[Running, Failure],
        Builtin::KeepRunningUntilFailure => &[Running, Failure],
        _ => return None,
    })
}

pub(super) fn state_range(ty: &VarType) -> Vec<Val> {
    match ty {
        VarType::Bool => vec![Val::Data(Value::Bool(true)), Val::Data(Value::Bool(false))],
        VarType::Int { min, max } => (*min..=*max)
            .take(10_000)
            .map(|i| Val::Data(Value::from(i)))
            .collect(),
        VarType::Cat { values } => values
            .iter()
            .map(|v| Val::Data(Value::from(v.clone())))
            .collect(),
        VarType::Float { min, max, grid } => {
            let n = (*grid).max(2);
            (0..n)
                .map(|i| {
                    let x = min + (max - min) * i as f64 / (n - 1) as f64;
                    Val::Data(Value::from((x * 1e10).round() / 1e10))
                })
                .collect()
        }
        VarType::Any => Vec::new(),
    }
}

pub(super) fn literal_int(tree: &Tree, uid: Uid, names: &[&str], default: i64) -> i64 {
    names
        .iter()
        .find_map(|name| literal_port(tree, uid, name).ok().flatten())
        .unwrap_or(default)
}

/// A port's integer as written in the tree: `Ok(None)` when absent,
/// `Err` when it is a blackboard entry or not a number (the model cannot
/// know its value).
pub(super) fn literal_port(tree: &Tree, uid: Uid, name: &str) -> Result<Option<i64>, ()> {
    match tree.node(uid).ports.iter().find(|p| p.name == name) {
        None => Ok(None),
        Some(p) => match &p.value {
            PortValue::Literal(s) => s.trim().parse().map(Some).map_err(|_| ()),
            _ => Err(()),
        },
    }
}

/// Nav2's RecoveryNode in the tick: a `Flow::Recovery` when it ticked each
/// child at most once and never went back from its recovery to its first
/// child; otherwise its choices are the recorded ones (`Flow::Gated`).
pub(super) fn recovery_flow(tree: &Tree, uid: Uid, facts: &TickFacts) -> Flow {
    let kids = &tree.node(uid).children;
    let f = &facts.flows[uid as usize - 1];
    let Ok(retries) = literal_port(tree, uid, "number_of_retries") else {
        return Flow::Gated;
    };
    if kids.len() != 2 || f.idx > 1 {
        return Flow::Gated;
    }
    let calls = |c: Uid| facts.calls[c as usize - 1];
    let looped = calls(kids[0]) > 1
        || calls(kids[1]) > 1
        || (f.idx == 1 && facts.ticked[kids[0] as usize - 1]);
    if looped {
        return Flow::Gated;
    }
    Flow::Recovery {
        start: f.idx,
        count: f.count,
        retries: retries.unwrap_or(1),
    }
}

pub(super) fn flow_of(tree: &Tree, uid: Uid, f: &crate::run::Flow) -> Flow {
    let n = tree.node(uid);
    let seq = |cont, asynch| Flow::Sequential {
        cont,
        start: f.idx,
        asynch,
    };
    if n.kind == Kind::SubTree {
        return Flow::Map(Mapping::Same);
    }
    match n.builtin {
        Some(Builtin::Sequence) => seq(Status::Success, false),
        // A child that starts and succeeds within a tick wakes the tree up
        // for the next (BehaviorTree.CPP 4), as in the Async composites.
        Some(Builtin::SequenceWithMemory) => {
            seq(Status::Success, tree.version == crate::model::Version::V4)
        }
        Some(Builtin::AsyncSequence) => seq(Status::Success, true),
        Some(Builtin::Fallback) => seq(Status::Failure, false),
        Some(Builtin::AsyncFallback) => seq(Status::Failure, true),
        Some(Builtin::ReactiveSequence) => Flow::Reactive {
            cont: Status::Success,
        },
        Some(Builtin::ReactiveFallback) => Flow::Reactive {
            cont: Status::Failure,
        },
        Some(Builtin::Parallel) => {
            let k = n.children.len() as i64;
            let v3 = tree.version == crate::model::Version::V3;
            let s = literal_int(
                tree,
                uid,
                &["success_count", "success_threshold"],
                if v3 { k } else { -1 },
            );
            let fl = literal_int(tree, uid, &["failure_count", "failure_threshold"], 1);
            let th = |t: i64| if t < 0 { (k + t + 1).max(0) } else { t };
            Flow::Parallel {
                need_s: th(s),
                need_f: th(fl),
                any_s: s < 0,
            }
        }
        Some(Builtin::ParallelAll) => {
            let k = n.children.len() as i64;
            let m = literal_int(tree, uid, &["max_failures"], 1);
            Flow::ParallelAll {
                threshold: if m < 0 { (k + m + 1).max(0) } else { m },
            }
        }
        Some(Builtin::IfThenElse) => Flow::Branch { start: f.idx },
        Some(Builtin::WhileDoElse) => Flow::Branch { start: 0 },
        Some(Builtin::Inverter) => Flow::Map(Mapping::Invert),
        Some(Builtin::ForceSuccess) => Flow::Map(Mapping::ForceSuccess),
        Some(Builtin::ForceFailure) => Flow::Map(Mapping::ForceFailure),
        Some(Builtin::KeepRunningUntilFailure) => Flow::Map(Mapping::KeepRunning),
        Some(Builtin::RetryUntilSuccessful | Builtin::Repeat) => Flow::Map(Mapping::Same),
        Some(Builtin::PipelineSequence) => Flow::Pipeline { last: f.idx },
        Some(Builtin::RoundRobin) if f.idx < n.children.len() => Flow::RoundRobin {
            start: f.idx,
            failed: f.failures.min(n.children.len()),
            wraps: f.wraps,
        },
        _ => Flow::Gated,
    }
}

/// A decorator the model gates (which child it ticks is the recorded
/// choice) whose status is then its ticked child's, as each source has it.
pub(super) fn passes_ticked_child(b: Option<Builtin>) -> bool {
    matches!(
        b,
        Some(
            Builtin::Timeout
                | Builtin::Delay
                | Builtin::RunOnce
                | Builtin::Precondition
                | Builtin::Switch(_)
                | Builtin::SkipUnlessUpdated
                | Builtin::WaitValueUpdate
                | Builtin::BlackboardCheckInt
                | Builtin::BlackboardCheckDouble
                | Builtin::BlackboardCheckString
                | Builtin::BlackboardCheckBool
                | Builtin::RateController
                | Builtin::DistanceController
                | Builtin::SpeedController
                | Builtin::GoalUpdatedController
                | Builtin::GoalUpdater
                | Builtin::SingleTrigger
        )
    )
}

/// The script attributes that can decide a node's status before it runs.
pub(super) const PRE_CONDITIONS: [&str; 4] = ["_skipIf", "_successIf", "_failureIf", "_while"];

/// The script attributes that write the blackboard after a node runs.
pub(super) const POST_CONDITIONS: [&str; 4] = ["_onSuccess", "_onFailure", "_post", "_onHalted"];

pub(super) fn has_script(n: &crate::model::Node, attrs: &[&str]) -> bool {
    n.scripts.iter().any(|(k, _)| attrs.contains(&k.as_str()))
}

/// A node whose status or choice of child a script or a blackboard entry
/// decides.
pub(super) fn reads_blackboard(n: &crate::model::Node) -> bool {
    has_script(n, &PRE_CONDITIONS)
        || matches!(
            n.builtin,
            Some(
                Builtin::ScriptCondition
                    | Builtin::Precondition
                    | Builtin::Switch(_)
                    | Builtin::BlackboardCheckInt
                    | Builtin::BlackboardCheckDouble
                    | Builtin::BlackboardCheckString
                    | Builtin::BlackboardCheckBool
                    | Builtin::WasEntryUpdated
                    | Builtin::SkipUnlessUpdated
                    | Builtin::WaitValueUpdate
                    | Builtin::DistanceController
                    | Builtin::SpeedController
                    | Builtin::GoalUpdatedController
                    | Builtin::PathLongerOnApproach
            )
        )
}

/// A node that writes the blackboard when it runs or completes.
pub(super) fn writes_blackboard(n: &crate::model::Node) -> bool {
    has_script(n, &POST_CONDITIONS)
        || matches!(
            n.builtin,
            Some(
                Builtin::Script
                    | Builtin::SetBlackboard
                    | Builtin::UnsetBlackboard
                    | Builtin::LoopInt
                    | Builtin::LoopDouble
                    | Builtin::LoopString
                    | Builtin::LoopBool
                    | Builtin::GoalUpdater
            )
        )
}

/// A gated decorator that ticks its child in the tick it starts from IDLE
/// (Timeout arms its timer, Nav2's controllers take their first reading),
/// so that the model follows it when a change starts it.
pub(super) fn starts_its_child(b: Option<Builtin>) -> bool {
    matches!(
        b,
        Some(
            Builtin::Timeout
                | Builtin::RateController
                | Builtin::DistanceController
                | Builtin::SpeedController
                | Builtin::GoalUpdater
        )
    )
}

/// A RetryUntilSuccessful's or Repeat's control flow.
pub(super) fn loop_of(tree: &Tree, uid: Uid) -> Option<Flow> {
    let k = crate::causal::attempts::loop_kind(tree, uid)?;
    Some(Flow::Map(Mapping::Loop {
        again: k.again,
        max: k.max,
    }))
}

pub(super) fn continues(s: Status, cont: Status) -> bool {
    s == cont || s == Status::Skipped
}
