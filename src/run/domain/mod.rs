//! Domain files: Love et al.'s domain knowledge in TOML, with the functions
//! written in rhai (sandboxed). These are the functions the simulator runs
//! and the causal model re-evaluates: one source of truth for both.
//! The format is documented in docs/trees-and-runs.md ("Domain files").

use super::exec::{LeafCall, LeafOutcome, Leaves};
use super::status::Status;
use crate::model::{Tree, Uid};
use crate::run::blackboard::EntryId;
use crate::source::Located;
use rhai::{Dynamic, Engine, Scope, AST};
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod engine;
mod functions;
mod leaves;
mod parse;

pub use engine::{dynamic_to_json, json_to_dynamic};
use engine::{engine, offset_in, NEXT_DOMAIN};
pub use leaves::{DomainLeaves, Intervention};
pub use parse::GRID_MAX;

pub const FORMAT_VERSION: i64 = 1;

/// The range of a state variable.
#[derive(Debug, Clone, PartialEq)]
pub enum VarType {
    Bool,
    Int {
        min: i64,
        max: i64,
    },
    Cat {
        values: Vec<String>,
    },
    /// A float in `[min, max]`; the search tries `grid` evenly spaced values.
    Float {
        min: f64,
        max: f64,
        grid: usize,
    },
    /// Any value (a string, a seed); never intervened on.
    Any,
}

#[derive(Debug, Clone)]
pub struct Var {
    pub name: String,
    pub ty: VarType,
    pub initial: Value,
    pub parents: Vec<usize>,
    /// Structural function of a derived variable (an expression over its parents).
    pub function: Option<Script>,
    pub intervene: bool,
    pub internal: bool,
}

/// A compiled rhai script and where it stands in the domain file.
#[derive(Debug, Clone)]
pub struct Script {
    pub ast: AST,
    /// Byte offset of the script's first character in the domain file.
    pub start: usize,
    pub what: String,
    /// Every identifier-like word of the script's text, sorted.
    words: Vec<String>,
}

impl Script {
    /// The variables of `among` that the script names. A script reads a
    /// variable of its scope only by naming it (`eval` is disabled and
    /// functions do not see the caller's scope), so its result depends on
    /// these alone; a name in a string or a comment only adds to them.
    pub fn reads(&self, among: &[usize], vars: &[Var]) -> Vec<usize> {
        among
            .iter()
            .copied()
            .filter(|&i| self.words.binary_search(&vars[i].name).is_ok())
            .collect()
    }
}

/// Which of a leaf's three functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeafFn {
    Status = 0,
    Decide = 1,
    Effect = 2,
}

fn words_of(text: &str) -> Vec<String> {
    let mut w: Vec<String> = text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect();
    w.sort_unstable();
    w.dedup();
    w
}

#[derive(Debug, Clone)]
pub struct LeafDef {
    /// The leaf's path, name or ID (or `@default_action`/`@default_condition`).
    pub key: String,
    pub inputs: Vec<usize>,
    pub outputs: Vec<usize>,
    pub actions: Vec<String>,
    pub decide: Option<Script>,
    pub effect: Option<Script>,
    pub status: Script,
    /// The inputs each function reads (by `LeafFn`): its results are
    /// memoised on these alone, so a decision that reads many inputs does
    /// not make an effect that reads few miss.
    pub reads: [Vec<usize>; 3],
}

impl LeafDef {
    pub fn reads(&self, f: LeafFn) -> &[usize] {
        &self.reads[f as usize]
    }
}

/// A loaded domain.
pub struct Domain {
    pub path: PathBuf,
    pub text: String,
    pub name: String,
    /// Leaves after whose tick the run ends; with none, a run ends when the
    /// root completes, with some, the tree is ticked again until one runs.
    pub end_after: Vec<String>,
    /// Scripting enums the tree's scripts may name (`[enums]`).
    pub enums: Vec<(String, i64)>,
    pub vars: Vec<Var>,
    pub leaves: Vec<LeafDef>,
    index: HashMap<String, usize>,
    /// Derived variables in an order where parents come first.
    order: Vec<usize>,
    lib: AST,
    /// Tells this domain's engines apart (see `Domain::engine`).
    id: u64,
    /// Results of the functions by their inputs: the functions are
    /// deterministic, and a search or an evaluation asks the same ones many
    /// times over.
    memo: std::sync::Mutex<rustc_hash::FxHashMap<Vec<u8>, Memoed>>,
}

/// A memoised result.
#[derive(Debug, Clone)]
enum Memoed {
    Value(Value),
    Action(Option<String>),
    Status(Status),
    Effect(Vec<(usize, Value)>),
}

/// Appends an exact, cheap key of a text.
pub fn str_key(s: &str, out: &mut Vec<u8>) {
    out.push(4);
    out.extend_from_slice(&(s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// Appends an exact, cheap key of a value (no number formatting).
pub fn value_key(v: &Value, out: &mut Vec<u8>) {
    match v {
        Value::Null => out.push(0),
        Value::Bool(b) => out.extend_from_slice(&[1, u8::from(*b)]),
        Value::Number(n) => match n.as_i64() {
            Some(i) => {
                out.push(2);
                out.extend_from_slice(&i.to_le_bytes());
            }
            None => {
                out.push(3);
                out.extend_from_slice(&n.as_f64().unwrap_or(0.0).to_bits().to_le_bytes());
            }
        },
        Value::String(s) => str_key(s, out),
        other => {
            out.push(5);
            str_key(&other.to_string(), out);
        }
    }
}

/// A state: one value per variable, in `Domain::vars` order.
pub type State = Vec<Value>;

// ---- the file ----

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_function_reads_the_inputs_it_names() {
        let text = r#"
btx_domain = 1
name = "reads"
[state.A]
type = "bool"
[state.B]
type = "bool"
[state.AB]
type = "bool"
[leaf.L]
inputs = ["A", "B", "AB"]
outputs = ["A"]
actions = ["go"]
decide = 'if AB { "go" } else { () }'
effect = '#{ A: !A } // B is only in this comment'
status = "SUCCESS"
"#;
        let d = Domain::parse(Path::new("reads.toml"), text).unwrap();
        let l = &d.leaves[0];
        let names = |f: LeafFn| -> Vec<&str> {
            l.reads(f)
                .iter()
                .map(|&i| d.vars[i].name.as_str())
                .collect()
        };
        assert_eq!(names(LeafFn::Decide), ["AB"]);
        assert_eq!(names(LeafFn::Effect), ["A", "B"]);
        assert!(names(LeafFn::Status).is_empty());
        // Memoised on what it reads: a change of B alone does not change
        // the decision, and the decision is the one a fresh domain makes.
        let mut s = d.initial_state().unwrap();
        s[d.var("AB").unwrap()] = Value::Bool(true);
        let first = d.decide(0, &s).unwrap();
        s[d.var("B").unwrap()] = Value::Bool(true);
        assert_eq!(d.decide(0, &s).unwrap(), first);
        assert_eq!(first.as_deref(), Some("go"));
    }
}
