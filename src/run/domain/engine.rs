//! The rhai engine the domain's scripts run in: sandboxed (a bound on
//! operations, no I/O), deterministic (seeded random helpers), and
//! memoised per function and arguments.

use super::*;

/// The seeded random helpers scripts may call: pure functions of a seed, so
/// that every function stays deterministic, as the causal search needs.
pub(super) fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E3779B97F4A7C15);
    let mut z = x;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
    z ^ (z >> 31)
}

pub(super) fn unit(seed: i64) -> f64 {
    (splitmix(seed as u64) >> 11) as f64 / (1u64 << 53) as f64
}

pub(super) static NEXT_DOMAIN: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// The most operations one script may run, counting those of the domain's
/// functions it calls.
pub(super) const MAX_OPERATIONS: u64 = 1_000_000;

thread_local! {
    /// Operations of the script running on this thread, its functions' included.
    static OPERATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// An engine for compiling, per thread: building one costs more than many
/// evaluations, and sharing one across threads makes them fight over its
/// reference counts. Each thread's engine lives as long as the thread.
pub(super) fn engine() -> &'static Engine {
    thread_local! {
        static ENGINE: &'static Engine = Box::leak(Box::new(new_engine()));
    }
    ENGINE.with(|e| *e)
}

/// rhai's standard functions, registered once for every engine.
pub(super) fn standard() -> rhai::Shared<rhai::Module> {
    use rhai::packages::Package;
    static STD: std::sync::OnceLock<rhai::Shared<rhai::Module>> = std::sync::OnceLock::new();
    STD.get_or_init(|| rhai::packages::StandardPackage::new().as_shared_module())
        .clone()
}

/// Results of a `functions` function by its arguments' key.
type FnResults = rustc_hash::FxHashMap<Vec<u8>, Dynamic>;

/// A key of a function call's arguments, if they are all plain values.
pub(super) fn args_key(args: &[&mut Dynamic], out: &mut Vec<u8>) -> bool {
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

pub(super) fn new_engine() -> Engine {
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
pub(super) fn exact_comparisons(e: &mut Engine) {
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

impl Domain {
    pub(super) fn scope_for(
        &self,
        vars: impl Iterator<Item = usize>,
        state: &State,
    ) -> Scope<'static> {
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
    pub(super) fn engine(&self) -> std::rc::Rc<Engine> {
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

    pub(super) fn new_engine(&self) -> Engine {
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

    pub(super) fn eval(&self, script: &Script, scope: &mut Scope) -> Result<Dynamic, Located> {
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
    pub(super) fn key(
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

    pub(super) fn memoised(
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

    pub(super) fn at_script(&self, s: &Script, msg: String) -> Located {
        Located::at(&self.path, &self.text, s.start, s.start + 1, msg)
    }

    /// Ints where a float is expected, rounded floats on the way back.
    pub(super) fn conform(&self, ty: &VarType, v: Value) -> Value {
        match (ty, &v) {
            (VarType::Float { .. }, Value::Number(n)) => Value::from(n.as_f64().unwrap_or(0.0)),
            _ => v,
        }
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
            return crate::run::script::number(f);
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

/// The file offset of a (1-based) line and column inside a script.
pub(super) fn offset_in(text: &str, start: usize, line: usize, col: usize) -> usize {
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
