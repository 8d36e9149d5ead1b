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
use serde::Deserialize;
use serde_json::Value;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::Spanned;

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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileVar {
    #[serde(rename = "type")]
    ty: Spanned<String>,
    initial: Option<toml::Value>,
    min: Option<toml::Value>,
    max: Option<toml::Value>,
    values: Option<Vec<String>>,
    grid: Option<usize>,
    #[serde(default)]
    parents: Vec<Spanned<String>>,
    function: Option<Spanned<String>>,
    intervene: Option<bool>,
    internal: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileLeaf {
    #[serde(default)]
    inputs: Vec<Spanned<String>>,
    #[serde(default)]
    outputs: Vec<Spanned<String>>,
    #[serde(default)]
    actions: Vec<String>,
    decide: Option<Spanned<String>>,
    effect: Option<Spanned<String>>,
    status: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    btx_domain: Spanned<i64>,
    #[serde(default)]
    name: String,
    #[serde(default)]
    end_after: Vec<String>,
    /// Scripting enums, as the robot registers them
    /// (`registerScriptingEnum`): name → value.
    #[serde(default)]
    enums: BTreeMap<String, i64>,
    #[serde(default)]
    functions: Option<Spanned<String>>,
    #[serde(default)]
    state: BTreeMap<String, Spanned<FileVar>>,
    #[serde(default)]
    leaf: BTreeMap<String, Spanned<FileLeaf>>,
}

/// The seeded random helpers scripts may call: pure functions of a seed, so
/// that every function stays deterministic, as the causal search needs.
fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E3779B97F4A7C15);
    let mut z = x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
    z ^ (z >> 31)
}

fn unit(seed: i64) -> f64 {
    (splitmix(seed as u64) >> 11) as f64 / (1u64 << 53) as f64
}

static NEXT_DOMAIN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The most operations one script may run, counting those of the domain's
/// functions it calls.
const MAX_OPERATIONS: u64 = 1_000_000;

thread_local! {
    /// Operations of the script running on this thread, its functions' included.
    static OPERATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// An engine for compiling, per thread: building one costs more than many
/// evaluations, and sharing one across threads makes them fight over its
/// reference counts. Each thread's engine lives as long as the thread.
fn engine() -> &'static Engine {
    thread_local! {
        static ENGINE: &'static Engine = Box::leak(Box::new(new_engine()));
    }
    ENGINE.with(|e| *e)
}

/// rhai's standard functions, registered once for every engine.
fn standard() -> rhai::Shared<rhai::Module> {
    use rhai::packages::Package;
    static STD: std::sync::OnceLock<rhai::Shared<rhai::Module>> = std::sync::OnceLock::new();
    STD.get_or_init(|| rhai::packages::StandardPackage::new().as_shared_module())
        .clone()
}

/// Results of a `functions` function by its arguments' key.
type FnResults = rustc_hash::FxHashMap<Vec<u8>, Dynamic>;

/// A key of a function call's arguments, if they are all plain values.
fn args_key(args: &[&mut Dynamic], out: &mut Vec<u8>) -> bool {
    out.clear();
    for a in args {
        if let Ok(i) = a.as_int() {
            out.push(1);
            out.extend_from_slice(&i.to_le_bytes());
        } else if let Ok(f) = a.as_float() {
            out.push(2);
            out.extend_from_slice(&f.to_bits().to_le_bytes());
        } else if let Ok(b) = a.as_bool() {
            out.push(3 + b as u8);
        } else if a.is_unit() {
            out.push(5);
        } else if let Some(s) = a.read_lock::<rhai::ImmutableString>() {
            out.push(6);
            str_key(s.as_str(), out);
        } else {
            return false;
        }
    }
    true
}

fn new_engine() -> Engine {
    let mut e = Engine::new_raw();
    e.register_global_module(standard());
    e.set_optimization_level(rhai::OptimizationLevel::Full);
    // Counts every operation, those of the functions called through
    // `Domain::engine`'s wrappers too (each call starts its own count).
    e.on_progress(|_| {
        OPERATIONS.with(|c| {
            let n = c.get() + 1;
            c.set(n);
            (n > MAX_OPERATIONS + 1).then(|| Dynamic::from("Too many operations"))
        })
    });
    e.set_max_operations(MAX_OPERATIONS);
    e.set_max_call_levels(64);
    e.set_max_expr_depths(128, 64);
    e.set_max_string_size(1 << 20);
    e.set_max_array_size(100_000);
    e.set_max_map_size(100_000);
    e.on_print(|_| {});
    e.on_debug(|_, _, _| {});
    // A script must name each variable it reads (see `Script::reads`).
    e.disable_symbol("eval");
    e.register_fn("rand_seeded", unit);
    e.register_fn("rand_int_seeded", |seed: i64, lo: i64, hi: i64| {
        if hi <= lo {
            lo
        } else {
            lo + (splitmix(seed as u64) % ((hi - lo + 1) as u64)) as i64
        }
    });
    e.register_fn("normal_seeded", |seed: i64, mean: f64, sd: f64| {
        // Box–Muller on two draws from the seed.
        let u1 = unit(seed).max(f64::MIN_POSITIVE);
        let u2 = unit(seed ^ 0x5DEECE66D);
        mean + sd * (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    });
    e.register_fn("next_seed", |seed: i64| (splitmix(seed as u64) >> 1) as i64);
    e.register_fn("clamp", |x: f64, lo: f64, hi: f64| x.max(lo).min(hi));
    exact_comparisons(&mut e);
    e
}

/// Rhai compares floats within an epsilon (`1e-30 > 0.0` is false there);
/// a domain's rules compare as IEEE 754 does, as the robot's code would.
/// Registered operators are seen only with fast operators off.
fn exact_comparisons(e: &mut Engine) {
    e.set_fast_operators(false);
    macro_rules! ops {
        ($a:ty, $b:ty) => {
            e.register_fn("==", |x: $a, y: $b| x as f64 == y as f64);
            e.register_fn("!=", |x: $a, y: $b| x as f64 != y as f64);
            e.register_fn("<", |x: $a, y: $b| (x as f64) < (y as f64));
            e.register_fn("<=", |x: $a, y: $b| x as f64 <= y as f64);
            e.register_fn(">", |x: $a, y: $b| x as f64 > y as f64);
            e.register_fn(">=", |x: $a, y: $b| x as f64 >= y as f64);
        };
    }
    ops!(f64, f64);
    ops!(f64, i64);
    ops!(i64, f64);
}

/// Where a script's text starts, inside its TOML string.
fn script_start(text: &str, span: &std::ops::Range<usize>) -> usize {
    let raw = &text[span.start..span.end];
    let q = if raw.starts_with("\"\"\"") || raw.starts_with("'''") {
        3
    } else {
        1
    };
    let mut s = span.start + q;
    if q == 3 && text[s..].starts_with('\n') {
        s += 1;
    } else if q == 3 && text[s..].starts_with("\r\n") {
        s += 2;
    }
    s
}

/// The file offset of a (1-based) line and column inside a script.
fn offset_in(text: &str, start: usize, line: usize, col: usize) -> usize {
    let mut off = start;
    for _ in 1..line {
        match text[off..].find('\n') {
            Some(i) => off += i + 1,
            None => break,
        }
    }
    let line_text = text[off..].split('\n').next().unwrap_or("");
    off + line_text
        .char_indices()
        .nth(col.saturating_sub(1))
        .map_or(line_text.len(), |(i, _)| i)
}

impl Domain {
    pub fn load(path: &Path) -> Result<Domain, Located> {
        let text = crate::source::read_text(path, crate::source::TEXT_SIZE_MAX, "the domain")?;
        Domain::parse(path, &text)
    }

    fn err(&self, range: std::ops::Range<usize>, msg: impl Into<String>) -> Located {
        Located::at(&self.path, &self.text, range.start, range.end, msg)
    }

    pub fn parse(path: &Path, text: &str) -> Result<Domain, Located> {
        let file: File = toml::from_str(text).map_err(|e| {
            let r = e.span().unwrap_or(0..0);
            Located::at(
                path,
                text,
                r.start,
                r.end.max(r.start + 1),
                format!("not a btx domain file: {}", e.message().trim()),
            )
        })?;
        let mut d = Domain {
            path: path.to_path_buf(),
            text: text.to_string(),
            name: file.name.clone(),
            end_after: file.end_after.clone(),
            enums: file.enums.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            vars: Vec::new(),
            leaves: Vec::new(),
            index: HashMap::new(),
            order: Vec::new(),
            lib: AST::empty(),
            id: NEXT_DOMAIN.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            memo: Default::default(),
        };
        if *file.btx_domain.get_ref() != FORMAT_VERSION {
            return Err(d.err(
                file.btx_domain.span(),
                format!(
                    "btx_domain = {} is not a format this btx reads (it reads {FORMAT_VERSION})",
                    file.btx_domain.get_ref()
                ),
            ));
        }
        if let Some(f) = &file.functions {
            d.lib = d.compile(f, "functions")?.ast;
        }
        for name in file.state.keys() {
            let i = d.vars.len();
            d.index.insert(name.clone(), i);
            d.vars.push(Var {
                name: name.clone(),
                ty: VarType::Any,
                initial: Value::Null,
                parents: Vec::new(),
                function: None,
                intervene: true,
                internal: false,
            });
        }
        for (name, v) in &file.state {
            let i = d.index[name];
            let span = v.span();
            let v = v.get_ref();
            let num = |x: &Option<toml::Value>, what: &str| -> Result<Option<f64>, Located> {
                match x {
                    None => Ok(None),
                    Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
                    // A search tries values between min and max: an
                    // infinite bound has no values to try.
                    Some(toml::Value::Float(f)) if !f.is_finite() => Err(d.err(
                        span.clone(),
                        format!("{name}: {what} is {f}; a range's bounds are finite numbers (the search tries values between them)"),
                    )),
                    Some(toml::Value::Float(f)) => Ok(Some(*f)),
                    Some(_) => Err(d.err(span.clone(), format!("{name}: {what} must be a number"))),
                }
            };
            let (min, max) = (num(&v.min, "min")?, num(&v.max, "max")?);
            let ty = match v.ty.get_ref().as_str() {
                "bool" => VarType::Bool,
                "int" => match (min, max) {
                    (Some(a), Some(b)) if a <= b => VarType::Int {
                        min: a as i64,
                        max: b as i64,
                    },
                    _ => return Err(d.err(v.ty.span(), format!("{name}: an int needs min <= max"))),
                },
                "cat" => match &v.values {
                    Some(vals) if !vals.is_empty() => VarType::Cat {
                        values: vals.clone(),
                    },
                    _ => {
                        return Err(
                            d.err(v.ty.span(), format!("{name}: a cat needs values = [...]"))
                        )
                    }
                },
                "float" if v.grid.is_some_and(|g| g > GRID_MAX) => {
                    return Err(d.err(
                        v.ty.span(),
                        format!(
                            "{name}: grid {} is more values than the {GRID_MAX} a search tries",
                            v.grid.unwrap_or(0)
                        ),
                    ))
                }
                "float" => match (min, max) {
                    (Some(a), Some(b)) if a <= b => VarType::Float {
                        min: a,
                        max: b,
                        grid: v.grid.unwrap_or(11).max(2),
                    },
                    _ => {
                        return Err(d.err(v.ty.span(), format!("{name}: a float needs min <= max")))
                    }
                },
                "any" => VarType::Any,
                other => {
                    return Err(d.err(
                        v.ty.span(),
                        format!(
                            "{name}: type \"{other}\" is not one of bool, int, cat, float, any"
                        ),
                    ))
                }
            };
            let mut parents = Vec::new();
            for p in &v.parents {
                match d.index.get(p.get_ref()) {
                    Some(&j) => parents.push(j),
                    None => {
                        return Err(d.err(
                            p.span(),
                            format!("{name}: parent \"{}\" is not a state variable", p.get_ref()),
                        ))
                    }
                }
            }
            let function = match &v.function {
                Some(f) => Some(d.compile(f, &format!("function of {name}"))?),
                None if !parents.is_empty() => {
                    return Err(d.err(
                        span,
                        format!("{name} has parents but no function computing it from them"),
                    ))
                }
                None => None,
            };
            let initial = match &v.initial {
                Some(x) => {
                    let val = toml_to_json(x);
                    d.check_value(&ty, &val)
                        .map_err(|m| d.err(span.clone(), format!("{name}: initial value {m}")))?;
                    val
                }
                None if function.is_some() => Value::Null,
                None => default_of(&ty),
            };
            let var = &mut d.vars[i];
            var.ty = ty;
            var.initial = initial;
            var.parents = parents;
            var.function = function;
            var.intervene = v.intervene.unwrap_or(true) && var.ty != VarType::Any;
            var.internal = v.internal.unwrap_or(false);
        }
        d.order = d.topological().map_err(|cycle| {
            let first = file.state.get(&cycle[0]).map_or(0..0, |s| s.span());
            d.err(
                first,
                format!(
                    "the state's causal graph has a cycle: {}",
                    cycle.join(" → ")
                ),
            )
        })?;
        for (key, l) in &file.leaf {
            let span = l.span();
            let l = l.get_ref();
            let vars = |list: &[Spanned<String>], what: &str| -> Result<Vec<usize>, Located> {
                list.iter()
                    .map(|v| {
                        d.index.get(v.get_ref()).copied().ok_or_else(|| {
                            d.err(
                                v.span(),
                                format!(
                                    "leaf {key}: {what} \"{}\" is not a state variable",
                                    v.get_ref()
                                ),
                            )
                        })
                    })
                    .collect()
            };
            let inputs = vars(&l.inputs, "input")?;
            let outputs = vars(&l.outputs, "output")?;
            let decide = match &l.decide {
                Some(s) => Some(d.compile(s, &format!("decide of {key}"))?),
                None => None,
            };
            let effect = match &l.effect {
                Some(s) => Some(d.compile(s, &format!("effect of {key}"))?),
                None if !outputs.is_empty() => {
                    return Err(d.err(span, format!("leaf {key} has outputs but no effect")))
                }
                None => None,
            };
            let status = d.compile(&l.status, &format!("status of {key}"))?;
            let reads = |s: Option<&Script>| s.map_or(Vec::new(), |s| s.reads(&inputs, &d.vars));
            let reads = [
                reads(Some(&status)),
                reads(decide.as_ref()),
                reads(effect.as_ref()),
            ];
            d.leaves.push(LeafDef {
                key: key.clone(),
                inputs,
                outputs,
                actions: l.actions.clone(),
                decide,
                effect,
                status,
                reads,
            });
        }
        // A run that ends after a leaf no table describes would never end.
        if let Some(e) = d
            .end_after
            .iter()
            .find(|e| !d.leaves.iter().any(|l| &l.key == *e))
        {
            let at = text.find("end_after").unwrap_or(0);
            return Err(d
                .err(
                    at..at + "end_after".len(),
                    format!("end_after names \"{e}\", which no [leaf] table is"),
                )
                .with_help(format!(
                    "the leaf tables are: {}",
                    d.leaves
                        .iter()
                        .map(|l| l.key.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
        }
        Ok(d)
    }

    fn compile(&self, s: &Spanned<String>, what: &str) -> Result<Script, Located> {
        let start = script_start(&self.text, &s.span());
        let r = engine().compile(s.get_ref());
        match r {
            Ok(ast) => Ok(Script {
                ast,
                start,
                what: what.to_string(),
                words: words_of(s.get_ref()),
            }),
            Err(e) => {
                let p = e.position();
                let off = offset_in(
                    &self.text,
                    start,
                    p.line().unwrap_or(1),
                    p.position().unwrap_or(1),
                );
                Err(Located::at(
                    &self.path,
                    &self.text,
                    off,
                    off + 1,
                    format!("{what}: {}", e.err_type()),
                ))
            }
        }
    }

    fn topological(&self) -> Result<Vec<usize>, Vec<String>> {
        // 0 = unseen, 1 = on the stack, 2 = done
        let mut mark = vec![0u8; self.vars.len()];
        let mut order = Vec::new();
        fn visit(
            d: &Domain,
            i: usize,
            mark: &mut [u8],
            order: &mut Vec<usize>,
            path: &mut Vec<usize>,
        ) -> Result<(), Vec<String>> {
            match mark[i] {
                2 => return Ok(()),
                1 => {
                    let from = path.iter().position(|&p| p == i).unwrap_or(0);
                    let mut c: Vec<String> = path[from..]
                        .iter()
                        .map(|&p| d.vars[p].name.clone())
                        .collect();
                    c.push(d.vars[i].name.clone());
                    return Err(c);
                }
                _ => {}
            }
            mark[i] = 1;
            path.push(i);
            for &p in &d.vars[i].parents {
                visit(d, p, mark, order, path)?;
            }
            path.pop();
            mark[i] = 2;
            order.push(i);
            Ok(())
        }
        for i in 0..self.vars.len() {
            visit(self, i, &mut mark, &mut order, &mut Vec::new())?;
        }
        Ok(order
            .into_iter()
            .filter(|&i| self.vars[i].function.is_some())
            .collect())
    }

    fn check_value(&self, ty: &VarType, v: &Value) -> Result<(), String> {
        let ok = match ty {
            VarType::Bool => v.is_boolean(),
            VarType::Int { min, max } => v.as_i64().is_some_and(|x| (*min..=*max).contains(&x)),
            VarType::Cat { values } => v.as_str().is_some_and(|s| values.iter().any(|x| x == s)),
            VarType::Float { min, max, .. } => v
                .as_f64()
                .is_some_and(|x| x >= *min - 1e-9 && x <= *max + 1e-9),
            VarType::Any => true,
        };
        if ok {
            return Ok(());
        }
        let range = match ty {
            VarType::Bool => "true or false".to_string(),
            VarType::Int { min, max } => format!("an integer from {min} to {max}"),
            VarType::Cat { values } => format!("one of {}", values.join(", ")),
            VarType::Float { min, max, .. } => format!("a number from {min:?} to {max:?}"),
            VarType::Any => "any value".to_string(),
        };
        Err(format!("{v} is outside its range: {range}"))
    }

    pub fn var(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    /// The initial state: declared values, then derived ones computed.
    pub fn initial_state(&self) -> Result<State, Located> {
        let mut s: State = self.vars.iter().map(|v| v.initial.clone()).collect();
        for &i in &self.order.clone() {
            if self.vars[i].initial.is_null() {
                s[i] = self.derive(i, &s)?;
            }
        }
        Ok(s)
    }

    fn scope_for(&self, vars: impl Iterator<Item = usize>, state: &State) -> Scope<'static> {
        // Scripts run millions of times in a search: the status names are
        // made once per thread (cloning one shares it), and a variable's
        // name goes into the scope without a copy of the String.
        thread_local! {
            static STATUS_NAMES: [Dynamic; 3] =
                ["SUCCESS", "FAILURE", "RUNNING"].map(Dynamic::from);
        }
        let mut scope = Scope::new();
        STATUS_NAMES.with(|names| {
            for (n, v) in ["SUCCESS", "FAILURE", "RUNNING"].iter().zip(names) {
                scope.push_constant_dynamic(*n, v.clone());
            }
        });
        for i in vars {
            scope.push_dynamic(self.vars[i].name.as_str(), json_to_dynamic(&state[i]));
        }
        scope
    }

    /// This domain's engine on this thread: its functions are registered
    /// as native ones that remember their results (they are pure: a
    /// function sees only its arguments), so a script calling
    /// `confusion(m, c)` with arguments seen before does not run it again.
    /// A thread keeps the engines of the few domains it used last.
    fn engine(&self) -> std::rc::Rc<Engine> {
        thread_local! {
            static ENGINES: std::cell::RefCell<Vec<(u64, std::rc::Rc<Engine>)>> =
                const { std::cell::RefCell::new(Vec::new()) };
        }
        ENGINES.with(|c| {
            let mut c = c.borrow_mut();
            if let Some(i) = c.iter().position(|(id, _)| *id == self.id) {
                c[..=i].rotate_right(1);
            } else {
                c.insert(0, (self.id, std::rc::Rc::new(self.new_engine())));
                c.truncate(8);
            }
            std::rc::Rc::clone(&c[0].1)
        })
    }

    fn new_engine(&self) -> Engine {
        let mut e = new_engine();
        let lib = std::sync::Arc::new(self.lib.clone_functions_only());
        for f in self.lib.iter_functions() {
            let name = f.name.to_string();
            let types = vec![std::any::TypeId::of::<Dynamic>(); f.params.len()];
            let lib = std::sync::Arc::clone(&lib);
            // Each wrapper has its own results; rhai's `sync` feature wants
            // them behind a lock although one thread owns the engine.
            let memo: std::sync::Mutex<(FnResults, Vec<u8>)> = Default::default();
            e.register_raw_fn(name.clone(), types, move |ctx, args| {
                let mut guard = memo.lock().unwrap_or_else(|e| e.into_inner());
                let (seen, key) = &mut *guard;
                let plain = args_key(args, key);
                if plain {
                    if let Some(v) = seen.get(&key[..]) {
                        return Ok(v.clone());
                    }
                }
                let key = plain.then(|| key.clone());
                drop(guard);
                // Cloned, not taken: rhai may pass a variable itself.
                let args: Vec<Dynamic> = args.iter().map(|a| (**a).clone()).collect();
                let v: Dynamic = ctx.engine().call_fn_with_options(
                    rhai::CallFnOptions::new().eval_ast(false),
                    &mut Scope::new(),
                    &lib,
                    &name,
                    args,
                )?;
                if let Some(key) = key {
                    let mut guard = memo.lock().unwrap_or_else(|e| e.into_inner());
                    if guard.0.len() >= 1 << 16 {
                        guard.0.clear();
                    }
                    guard.0.insert(key, v.clone());
                }
                Ok(v)
            });
        }
        e
    }

    fn eval(&self, script: &Script, scope: &mut Scope) -> Result<Dynamic, Located> {
        OPERATIONS.with(|c| c.set(0));
        self.engine()
            .eval_ast_with_scope::<Dynamic>(scope, &script.ast)
            .map_err(|e| {
                let p = e.position();
                let off = offset_in(
                    &self.text,
                    script.start,
                    p.line().unwrap_or(1),
                    p.position().unwrap_or(1),
                );
                let msg = match e.unwrap_inner() {
                    rhai::EvalAltResult::ErrorTerminated(..) => format!(
                        "Too many operations (more than {MAX_OPERATIONS}, the functions it calls included)"
                    ),
                    _ => e.to_string(),
                };
                let msg = msg.split(" (line ").next().unwrap_or(&msg).to_string();
                Located::at(
                    &self.path,
                    &self.text,
                    off,
                    off + 1,
                    format!("{}: {msg}", script.what),
                )
            })
    }

    /// A derived variable's structural function, on a state.
    fn key(
        &self,
        tag: u8,
        index: usize,
        vars: &[usize],
        state: &State,
        action: Option<&Option<String>>,
    ) -> Vec<u8> {
        let mut k = Vec::with_capacity(16 + 9 * vars.len());
        k.push(tag);
        k.extend_from_slice(&(index as u32).to_le_bytes());
        for &x in vars {
            value_key(&state[x], &mut k);
        }
        match action {
            Some(Some(a)) => str_key(a, &mut k),
            Some(None) => k.push(0),
            None => {}
        }
        k
    }

    fn memoised(
        &self,
        key: Vec<u8>,
        f: impl FnOnce() -> Result<Memoed, Located>,
    ) -> Result<Memoed, Located> {
        if let Some(x) = self
            .memo
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            return Ok(x.clone());
        }
        let x = f()?;
        let mut m = self.memo.lock().unwrap_or_else(|e| e.into_inner());
        if m.len() >= 1 << 20 {
            m.clear();
        }
        m.insert(key, x.clone());
        Ok(x)
    }

    pub fn derive(&self, var: usize, state: &State) -> Result<Value, Located> {
        let key = self.key(0, var, &self.vars[var].parents, state, None);
        match self.memoised(key, || self.derive_now(var, state).map(Memoed::Value))? {
            Memoed::Value(v) => Ok(v),
            other => unreachable!("{other:?}"),
        }
    }

    fn derive_now(&self, var: usize, state: &State) -> Result<Value, Located> {
        let v = &self.vars[var];
        let f = v
            .function
            .as_ref()
            .expect("derived variables have functions");
        let mut scope = self.scope_for(v.parents.iter().copied(), state);
        let out = dynamic_to_json(self.eval(f, &mut scope)?);
        let out = self.conform(&v.ty, out);
        self.check_value(&v.ty, &out)
            .map_err(|m| self.at_script(f, format!("{} returned {m}", f.what)))?;
        Ok(out)
    }

    fn at_script(&self, s: &Script, msg: String) -> Located {
        Located::at(&self.path, &self.text, s.start, s.start + 1, msg)
    }

    /// Ints where a float is expected, rounded floats on the way back.
    fn conform(&self, ty: &VarType, v: Value) -> Value {
        match (ty, &v) {
            (VarType::Float { .. }, Value::Number(n)) => Value::from(n.as_f64().unwrap_or(0.0)),
            _ => v,
        }
    }

    /// The leaf's decision (d_i): an action name, or `None` for the null action.
    pub fn decide(&self, leaf: usize, state: &State) -> Result<Option<String>, Located> {
        let key = self.key(
            1,
            leaf,
            self.leaves[leaf].reads(LeafFn::Decide),
            state,
            None,
        );
        match self.memoised(key, || self.decide_now(leaf, state).map(Memoed::Action))? {
            Memoed::Action(a) => Ok(a),
            other => unreachable!("{other:?}"),
        }
    }

    fn decide_now(&self, leaf: usize, state: &State) -> Result<Option<String>, Located> {
        let l = &self.leaves[leaf];
        let Some(script) = &l.decide else {
            return Ok(None);
        };
        let mut scope = self.scope_for(l.inputs.iter().copied(), state);
        let r = self.eval(script, &mut scope)?;
        if r.is_unit() {
            return Ok(None);
        }
        let a = r.into_string().map_err(|t| {
            self.at_script(
                script,
                format!("{} returned a {t}, not an action name", script.what),
            )
        })?;
        if !l.actions.is_empty() && !l.actions.contains(&a) {
            return Err(self.at_script(
                script,
                format!(
                    "{} chose \"{a}\", which is not in actions {:?}",
                    script.what, l.actions
                ),
            ));
        }
        Ok(Some(a))
    }

    fn action_scope(&self, leaf: usize, state: &State, action: &Option<String>) -> Scope<'static> {
        let l = &self.leaves[leaf];
        let mut scope = self.scope_for(l.inputs.iter().copied(), state);
        scope.push(
            "action",
            action.clone().map_or(Dynamic::UNIT, Dynamic::from),
        );
        scope
    }

    /// The leaf's return status (r_i) for a state and a decision.
    pub fn status(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Status, Located> {
        let reads = self.leaves[leaf].reads(LeafFn::Status);
        let key = self.key(2, leaf, reads, state, Some(action));
        match self.memoised(key, || {
            self.status_now(leaf, state, action).map(Memoed::Status)
        })? {
            Memoed::Status(s) => Ok(s),
            other => unreachable!("{other:?}"),
        }
    }

    fn status_now(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Status, Located> {
        let l = &self.leaves[leaf];
        let mut scope = self.action_scope(leaf, state, action);
        let r = self.eval(&l.status, &mut scope)?;
        let s = r.clone().into_string().ok().and_then(|s| Status::parse(&s));
        match s {
            Some(s @ (Status::Success | Status::Failure | Status::Running)) => Ok(s),
            _ => Err(self.at_script(
                &l.status,
                format!(
                    "{} returned {r}, not SUCCESS, FAILURE or RUNNING",
                    l.status.what
                ),
            )),
        }
    }

    /// The leaf's direct effect (p_i): new values of its outputs.
    pub fn effect(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Vec<(usize, Value)>, Located> {
        let reads = self.leaves[leaf].reads(LeafFn::Effect);
        let key = self.key(3, leaf, reads, state, Some(action));
        match self.memoised(key, || {
            self.effect_now(leaf, state, action).map(Memoed::Effect)
        })? {
            Memoed::Effect(e) => Ok(e),
            other => unreachable!("{other:?}"),
        }
    }

    fn effect_now(
        &self,
        leaf: usize,
        state: &State,
        action: &Option<String>,
    ) -> Result<Vec<(usize, Value)>, Located> {
        let l = &self.leaves[leaf];
        let Some(script) = &l.effect else {
            return Ok(Vec::new());
        };
        let mut scope = self.action_scope(leaf, state, action);
        let r = self.eval(script, &mut scope)?;
        if r.is_unit() {
            return Ok(Vec::new());
        }
        let map = r.try_cast::<rhai::Map>().ok_or_else(|| {
            self.at_script(
                script,
                format!("{} must return a map #{{ var: value }} or ()", script.what),
            )
        })?;
        let mut out = Vec::new();
        for (k, v) in map {
            let Some(i) = self.var(k.as_str()).filter(|i| l.outputs.contains(i)) else {
                return Err(self.at_script(
                    script,
                    format!(
                        "{} sets \"{k}\", which is not one of its outputs",
                        script.what
                    ),
                ));
            };
            let v = self.conform(&self.vars[i].ty, dynamic_to_json(v));
            self.check_value(&self.vars[i].ty, &v).map_err(|m| {
                self.at_script(script, format!("{} sets {k} to a value {m}", script.what))
            })?;
            out.push((i, v));
        }
        Ok(out)
    }

    /// Recomputes derived variables after `changed` changed, parents first,
    /// leaving alone the ones the leaf set itself.
    pub fn propagate(
        &self,
        state: &mut State,
        changed: &[usize],
        set_by_leaf: &[usize],
    ) -> Result<Vec<usize>, Located> {
        let mut dirty = vec![false; self.vars.len()];
        for &c in changed {
            dirty[c] = true;
        }
        let mut updated = Vec::new();
        for &i in &self.order {
            if set_by_leaf.contains(&i) || !self.vars[i].parents.iter().any(|&p| dirty[p]) {
                continue;
            }
            let v = self.derive(i, state)?;
            if v != state[i] {
                state[i] = v;
                dirty[i] = true;
                updated.push(i);
            }
        }
        Ok(updated)
    }

    /// Which leaf definition drives a tree leaf (path, name, ID, default).
    pub fn leaf_for(&self, tree: &Tree, uid: Uid) -> Option<usize> {
        super::leaf_keys(tree, uid)
            .iter()
            .find_map(|k| self.leaves.iter().position(|l| l.key == *k))
    }
}

/// The most values a float variable's grid may have.
pub const GRID_MAX: usize = 10_000;

fn default_of(ty: &VarType) -> Value {
    match ty {
        VarType::Bool => Value::Bool(false),
        VarType::Int { min, .. } => Value::from(*min),
        VarType::Cat { values } => Value::from(values[0].clone()),
        VarType::Float { min, .. } => Value::from(*min),
        VarType::Any => Value::from(""),
    }
}

fn toml_to_json(v: &toml::Value) -> Value {
    match v {
        toml::Value::String(s) => Value::from(s.clone()),
        toml::Value::Integer(i) => Value::from(*i),
        // JSON has no NaN: `initial = nan` is kept as a run keeps it.
        toml::Value::Float(f) if !f.is_finite() => super::script::number(*f),
        toml::Value::Float(f) => Value::from(*f),
        toml::Value::Boolean(b) => Value::Bool(*b),
        other => Value::from(other.to_string()),
    }
}

pub fn json_to_dynamic(v: &Value) -> Dynamic {
    match v {
        Value::Bool(b) => Dynamic::from(*b),
        Value::Number(n) => match n.as_i64() {
            Some(i) => Dynamic::from(i),
            None => Dynamic::from(n.as_f64().unwrap_or(0.0)),
        },
        Value::String(s) => Dynamic::from(s.clone()),
        Value::Null => Dynamic::UNIT,
        other => Dynamic::from(other.to_string()),
    }
}

pub fn dynamic_to_json(d: Dynamic) -> Value {
    if let Ok(b) = d.as_bool() {
        return Value::Bool(b);
    }
    if let Ok(i) = d.as_int() {
        return Value::from(i);
    }
    if let Ok(f) = d.as_float() {
        if !f.is_finite() {
            return super::script::number(f);
        }
        return Value::from(f);
    }
    if d.is_unit() {
        return Value::Null;
    }
    if d.is_string() {
        if let Ok(s) = d.into_string() {
            return Value::String(s);
        }
        return Value::Null;
    }
    Value::from(d.to_string())
}

/// Leaves driven by a domain. The state lives in the root blackboard, one
/// entry per variable, so `{@X_a}` ports read and write it.
pub struct DomainLeaves {
    pub domain: Arc<Domain>,
    pub state: State,
    assigned: HashMap<Uid, usize>,
    /// The first error met; the leaf then fails and the run stops.
    pub error: Option<Located>,
    /// A leaf of `end_after` ran.
    ended: bool,
    /// Interventions of a counterfactual re-run.
    pub intervene: Intervention,
}

/// What a counterfactual re-run changes within one tick: a leaf's decision
/// at one of its calls (Love's d_i), or a state variable's value right
/// after a leaf's first call (a temporal copy the leaf leaves behind).
#[derive(Debug, Clone, Default)]
pub struct Intervention {
    pub tick: u32,
    /// (leaf, which call within the tick from 1, the action it takes).
    pub actions: Vec<(Uid, u32, Option<String>)>,
    /// (place, variable, value): set before the first call of a leaf at
    /// or past that place in the tree's pre-order (a temporal copy is
    /// there whether or not the leaves around it run).
    pub sets: Vec<(usize, usize, Value)>,
    /// Each node's place in the tree's pre-order, by uid − 1.
    pub order: Vec<usize>,
    /// A variable to read once the first leaf at or past a place in the
    /// pre-order is called (or at the tick's end): (variable, place).
    pub watch: Option<(usize, Option<usize>)>,
    /// What the watched variable was then.
    pub seen: Option<Value>,
    calls: HashMap<Uid, u32>,
    applied: Vec<bool>,
}

impl DomainLeaves {
    /// Every leaf of the tree must be described (or covered by a default).
    pub fn new(domain: Arc<Domain>, tree: &Tree) -> Result<DomainLeaves, Located> {
        let mut assigned = HashMap::new();
        let mut missing = Vec::new();
        for n in &tree.nodes {
            if n.kind.is_leaf() && n.builtin.is_none() {
                match domain.leaf_for(tree, n.uid) {
                    Some(l) => {
                        assigned.insert(n.uid, l);
                    }
                    None => missing.push(format!("{} #{}", tree.description(n.uid), n.uid)),
                }
            }
        }
        if !missing.is_empty() {
            return Err(Located::file(&domain.path, format!("no [leaf] for {}", missing.join(", ")))
                .with_help("add [leaf.\"NAME\"] tables, or [leaf.\"@default_action\"] / [leaf.\"@default_condition\"]"));
        }
        let state = domain.initial_state()?;
        Ok(DomainLeaves {
            domain,
            state,
            assigned,
            error: None,
            ended: false,
            intervene: Intervention::default(),
        })
    }

    /// Starts the run with `NAME=VALUE` for a variable without a function
    /// (a top-level one, or one only leaves write), then recomputes what
    /// derives from it. VALUE is JSON (`0.0`, `true`, `"a"`) or a bare word.
    pub fn set(&mut self, assignment: &str) -> Result<(), String> {
        let (name, raw) = assignment
            .split_once('=')
            .ok_or_else(|| format!("--set {assignment}: write NAME=VALUE"))?;
        let (name, raw) = (name.trim(), raw.trim());
        let d = &self.domain;
        let k = d.var(name).ok_or_else(|| {
            let names: Vec<&str> = d.vars.iter().map(|v| v.name.as_str()).collect();
            format!(
                "--set {name}: the domain has no such variable; it has {}",
                names.join(", ")
            )
        })?;
        if d.vars[k].function.is_some() {
            return Err(format!(
                "--set {name}: it is computed from {} by the domain's function; set one of those instead",
                d.vars[k]
                    .parents
                    .iter()
                    .map(|&p| d.vars[p].name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let v: Value = serde_json::from_str(raw).unwrap_or_else(|_| Value::from(raw));
        d.check_value(&d.vars[k].ty, &v)
            .map_err(|e| format!("--set {name}: {e}"))?;
        self.state[k] = v;
        d.propagate(&mut self.state, &[k], &[])
            .map_err(|e| format!("--set {name}: {e}"))?;
        Ok(())
    }

    /// Notes the watched variable's value now.
    fn watch_now(&mut self) {
        if let Some((x, _)) = self.intervene.watch {
            self.intervene.seen = Some(self.state[x].clone());
        }
    }

    /// Sets a state variable as an intervention does (what derives from it
    /// is recomputed, what it derives from is not): the variables changed.
    pub fn apply(&mut self, var: usize, v: Value) -> Result<Vec<usize>, Located> {
        self.state[var] = v;
        let d = Arc::clone(&self.domain);
        let mut changed = vec![var];
        changed.extend(d.propagate(&mut self.state, &[var], &[var])?);
        Ok(changed)
    }

    /// The state as root-blackboard entries.
    pub fn entries(&self) -> Vec<(EntryId, Value)> {
        self.domain
            .vars
            .iter()
            .zip(&self.state)
            .map(|(v, x)| {
                (
                    EntryId {
                        scope: 0,
                        key: v.name.clone(),
                    },
                    x.clone(),
                )
            })
            .collect()
    }

    fn step(&mut self, call: &mut LeafCall) -> Result<LeafOutcome, Located> {
        let leaf = match self.assigned.get(&call.uid) {
            Some(&l) => l,
            None => {
                let l = self.domain.leaf_for(call.tree, call.uid).ok_or_else(|| {
                    Located::file(
                        &self.domain.path,
                        format!(
                            "no [leaf] for {} #{}",
                            call.tree.description(call.uid),
                            call.uid
                        ),
                    )
                })?;
                self.assigned.insert(call.uid, l);
                l
            }
        };
        let d = Arc::clone(&self.domain);
        if d.end_after.contains(&d.leaves[leaf].key) {
            self.ended = true;
        }
        let call_no = if call.tick == self.intervene.tick {
            let c = self.intervene.calls.entry(call.uid).or_insert(0);
            *c += 1;
            *c
        } else {
            0
        };
        let forced = self
            .intervene
            .actions
            .iter()
            .find(|(u, k, _)| *u == call.uid && *k == call_no)
            .map(|(_, _, a)| a.clone());
        let mut derived_early = Vec::new();
        if call_no > 0 {
            let iv = &mut self.intervene;
            iv.applied.resize(iv.sets.len(), false);
            let here = iv.order.get(call.uid as usize - 1).copied().unwrap_or(0);
            let boundary = match iv.watch {
                Some((_, Some(b))) if iv.seen.is_none() && here >= b => Some(b),
                _ => None,
            };
            // Copies set at or before the watched place first, then the
            // watched value, then the rest.
            let mut due: Vec<usize> = (0..iv.sets.len())
                .filter(|&i| !iv.applied[i] && iv.sets[i].0 <= here)
                .collect();
            due.sort_by_key(|&i| boundary.is_some_and(|b| iv.sets[i].0 > b));
            let mut watched = false;
            for i in due {
                let (place, x, v) = self.intervene.sets[i].clone();
                if !watched && boundary.is_some_and(|b| place > b) {
                    self.watch_now();
                    watched = true;
                }
                self.intervene.applied[i] = true;
                derived_early.extend(self.apply(x, v)?);
            }
            if !watched && boundary.is_some() {
                self.watch_now();
            }
        }
        let action = match forced {
            Some(a) => a,
            None => d.decide(leaf, &self.state)?,
        };
        let status = d.status(leaf, &self.state, &action)?;
        let effect = d.effect(leaf, &self.state, &action)?;
        let mut changed = Vec::new();
        for (i, v) in effect {
            if self.state[i] != v {
                self.state[i] = v;
                changed.push(i);
            }
        }
        let derived = d.propagate(&mut self.state, &changed, &d.leaves[leaf].outputs)?;
        for i in derived_early.into_iter().chain(changed).chain(derived) {
            call.write_entry(
                EntryId {
                    scope: 0,
                    key: d.vars[i].name.clone(),
                },
                self.state[i].clone(),
            );
        }
        let decision = if d.leaves[leaf].decide.is_some() {
            Some(action.unwrap_or_else(|| "null".into()))
        } else {
            None
        };
        Ok(LeafOutcome { status, decision })
    }
}

impl Leaves for DomainLeaves {
    fn enums(&self) -> &[(String, i64)] {
        &self.domain.enums
    }

    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        self.entries()
    }

    fn take_error(&mut self) -> Option<Located> {
        self.error.take()
    }

    fn run_over(&mut self, root: Status) -> bool {
        if self.domain.end_after.is_empty() {
            root != Status::Running
        } else {
            self.ended
        }
    }

    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        match self.step(call) {
            Ok(o) => o,
            Err(e) => {
                if self.error.is_none() {
                    self.error = Some(e);
                }
                LeafOutcome {
                    status: Status::Failure,
                    decision: None,
                }
            }
        }
    }
}

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
