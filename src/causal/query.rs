//! Queries as a user writes them: `status(NODE)`, `executed(NODE)`,
//! `decision(NODE)` or a state variable `VAR` (`VAR^K` for copy K of the
//! tick), with foil values written as the values print.

use super::model::{Model, Val, VarId, VarKind};
use crate::model::Uid;
use crate::pick::pick;
use crate::run::domain::VarType;
use crate::run::Status;
use serde_json::Value;

/// A target as written, before it is found in a model.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    Status(Uid),
    Executed(Uid),
    Decision(Uid),
    /// A loop's attempts used before the tick.
    Attempts(Uid),
    State {
        var: usize,
        copy: Option<u32>,
    },
}

/// Parses a target against a model's tree and domain.
pub fn parse_target(model: &Model, s: &str) -> Result<Target, String> {
    let s = s.trim();
    if let Some((f, rest)) = s.split_once('(') {
        let inner = rest
            .strip_suffix(')')
            .ok_or_else(|| format!("\"{s}\": a target reads status(NODE), executed(NODE), decision(NODE) or a state variable"))?;
        let uid = pick(&model.tree, inner.trim()).map_err(|e| e.to_string())?;
        // `#N` is BehaviorTree.CPP's numbering; an attempt's copy is picked
        // by the name answers give it ("look at chuck (attempt 1)").
        if uid as usize > model.session_len() && inner.trim().starts_with('#') {
            return Err(format!(
                "there is no node {}: the tree has nodes #1 to #{}",
                inner.trim(),
                model.session_len()
            ));
        }
        return match f.trim().to_ascii_lowercase().as_str() {
            "status" | "return" | "r" => Ok(Target::Status(uid)),
            "executed" | "e" | "ran" => Ok(Target::Executed(uid)),
            "decision" | "d" => Ok(Target::Decision(uid)),
            "attempts" => Ok(Target::Attempts(uid)),
            other => Err(format!(
                "\"{other}(…)\" is not a target: use status(NODE), executed(NODE) or decision(NODE)"
            )),
        };
    }
    let (name, copy) = match s.split_once('^') {
        Some((n, k)) => (
            n,
            Some(
                k.parse::<u32>()
                    .map_err(|_| format!("\"{s}\": the copy after ^ must be a number"))?,
            ),
        ),
        None => (s, None),
    };
    if let Some(d) = &model.domain {
        if let Some(var) = d.var(name) {
            if let Some(k) = copy {
                let n = model.copies[var].len() as u32;
                if k >= n {
                    return Err(format!(
                        "{name} has copies 0 to {} in the model of this tick",
                        n - 1
                    ));
                }
            }
            return Ok(Target::State { var, copy });
        }
    }
    match pick(&model.tree, s) {
        Ok(uid) => Ok(Target::Status(uid)),
        Err(e) => {
            let vars = model
                .domain
                .as_ref()
                .map(|d| {
                    d.vars
                        .iter()
                        .map(|v| v.name.clone())
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .unwrap_or_default();
            Err(if vars.is_empty() {
                format!(
                    "{e}\n(the session has no domain, so it has no state variables to ask about)"
                )
            } else {
                format!("{e}\nstate variables: {vars}")
            })
        }
    }
}

/// At `step` of the tick, the node that stands for `u`'s call then: the
/// last call of `u` that had ended by that step (its first, if none had),
/// which is `u` itself for its last call in the tick and a copy of the
/// model's for an earlier attempt of a Retry or Repeat. A call the model
/// holds no copy of (a Nav2 RecoveryNode going back to its first child,
/// attempts folded into a count) is said, not replaced by another.
pub fn call_at(model: &Model, u: Uid, step: u32) -> Result<Uid, String> {
    let calls: Vec<_> = model.facts.call_log.iter().filter(|r| r.uid == u).collect();
    let last = model.facts.calls[u as usize - 1];
    let Some(first) = calls.first() else {
        return Ok(u);
    };
    let call = calls
        .iter()
        .filter(|r| r.transitions_after <= step)
        .map(|r| r.call)
        .max()
        .unwrap_or(first.call);
    // The session's node stands for the loop's last attempt; a call in an
    // earlier attempt is a copy's, even the node's last call of the tick.
    let copy = (model.session_len() as Uid + 1..=model.tree.len() as Uid).find(|&w| {
        model
            .copy_of(w)
            .is_some_and(|c| c.origin == u && c.call == call)
    });
    if let Some(w) = copy {
        return Ok(w);
    }
    (call >= last).then_some(u).ok_or_else(|| {
            format!(
                "at step {step} of tick {}, {} is in its call {call} of {last} in that tick, and btx's model of the tick holds only its last call there (a node called again in the tick by a Nav2 RecoveryNode, or an attempt past the {} the model copies); ask at the end of the tick, or at a step of its last call",
                model.facts.tick,
                model.tree.description(u),
                super::attempts::COPIES_MAX
            )
        })
}

/// The model variable of a target, at position `pos` of the run.
pub fn target_var(model: &Model, t: &Target, pos: u32) -> Result<VarId, String> {
    Ok(match *t {
        Target::Status(u) => model.r(u),
        Target::Executed(u) => model.e(u),
        Target::Decision(u) => model.d(u).ok_or_else(|| {
            format!(
                "{} takes no decisions in this model (only action leaves described by a domain do)",
                model.tree.description(u)
            )
        })?,
        Target::Attempts(u) => model.attempts_var(u).ok_or_else(|| {
            format!(
                "{} counts no attempts: only a RetryUntilSuccessful or a Repeat does",
                model.tree.description(u)
            )
        })?,
        Target::State { var, copy } => match copy {
            Some(k) => model.copies[var][k as usize],
            None => model
                .copy_at(var, pos)
                .ok_or("the variable has no copy in this model")?,
        },
    })
}

fn parse_bool(s: &str) -> Option<bool> {
    match s.trim().to_ascii_lowercase().as_str() {
        "true" | "yes" | "1" => Some(true),
        "false" | "no" | "0" => Some(false),
        _ => None,
    }
}

/// Parses a foil value for variable `v`.
pub fn parse_value(model: &Model, v: VarId, s: &str) -> Result<Val, String> {
    let bad = |what: &str| format!("\"{s}\" is not {what}");
    match model.vars[v].kind {
        VarKind::Executed(_) => parse_bool(s)
            .map(Val::Bool)
            .ok_or_else(|| bad("true or false")),
        VarKind::Status(_) => match s.trim().to_ascii_uppercase().as_str() {
            "INVALID" => Ok(Val::Status(Status::Idle)),
            x => Status::parse(x)
                .map(Val::Status)
                .ok_or_else(|| bad("a status (SUCCESS, FAILURE, RUNNING, IDLE)")),
        },
        VarKind::Attempts(_) => s
            .trim()
            .parse::<i64>()
            .map(|n| Val::Data(Value::from(n)))
            .map_err(|_| bad("a number of attempts")),
        VarKind::Decision(_) => {
            let t = s.trim();
            if matches!(
                t.to_ascii_lowercase().as_str(),
                "null" | "none" | "nothing" | "()"
            ) {
                return Ok(Val::Action(None));
            }
            let x = Val::Action(Some(t.to_string()));
            if model.vars[v].range.contains(&x) {
                Ok(x)
            } else {
                Err(format!(
                    "\"{t}\" is not one of {}'s actions: {}",
                    model.var_name(v),
                    model.vars[v]
                        .range
                        .iter()
                        .map(super::english::value_text)
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            }
        }
        VarKind::State { var, .. } => {
            let d = model.domain.as_ref().expect("a domain");
            let t = s.trim();
            let val = match &d.vars[var].ty {
                VarType::Bool => Value::Bool(parse_bool(t).ok_or_else(|| bad("true or false"))?),
                VarType::Int { .. } => {
                    Value::from(t.parse::<i64>().map_err(|_| bad("an integer"))?)
                }
                VarType::Float { .. } => {
                    let x = t.parse::<f64>().map_err(|_| bad("a number"))?;
                    return Ok(model.snap(v, &Val::Data(Value::from(x))));
                }
                VarType::Cat { .. } | VarType::Any => Value::from(t.to_string()),
            };
            let x = Val::Data(val);
            if !model.vars[v].range.is_empty() && !model.vars[v].range.contains(&x) {
                return Err(format!("{t} is outside the range of {}", d.vars[var].name));
            }
            Ok(x)
        }
    }
}
