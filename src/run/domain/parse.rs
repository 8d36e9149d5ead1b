//! Reading a domain file: the TOML checked table by table, its scripts
//! compiled, each error at the file's line and column.

use super::*;
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

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

impl Domain {
    pub fn load(path: &Path) -> Result<Domain, Located> {
        let text = crate::source::read_text(path, crate::source::TEXT_SIZE_MAX, "the domain")?;
        Domain::parse(path, &text)
    }

    pub(super) fn err(&self, range: std::ops::Range<usize>, msg: impl Into<String>) -> Located {
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
            d.define_var(name, v)?;
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
            let leaf = d.leaf_def(key, l)?;
            d.leaves.push(leaf);
        }
        d.check_end_after()?;
        Ok(d)
    }

    /// A state variable's table, once every name is declared: its type and
    /// range, its parents, the function computing it and its initial value.
    fn define_var(&mut self, name: &str, v: &Spanned<FileVar>) -> Result<(), Located> {
        let d = &*self;
        let i = d.index[name];
        let span = v.span();
        let v = v.get_ref();
        let ty = d.var_type(name, v, &span)?;
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
        let var = &mut self.vars[i];
        var.ty = ty;
        var.initial = initial;
        var.parents = parents;
        var.function = function;
        var.intervene = v.intervene.unwrap_or(true) && var.ty != VarType::Any;
        var.internal = v.internal.unwrap_or(false);
        Ok(())
    }

    /// A state variable's type, with its range or values checked.
    fn var_type(
        &self,
        name: &str,
        v: &FileVar,
        span: &std::ops::Range<usize>,
    ) -> Result<VarType, Located> {
        let d = self;
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
                _ => return Err(d.err(v.ty.span(), format!("{name}: a cat needs values = [...]"))),
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
                _ => return Err(d.err(v.ty.span(), format!("{name}: a float needs min <= max"))),
            },
            "any" => VarType::Any,
            other => {
                return Err(d.err(
                    v.ty.span(),
                    format!("{name}: type \"{other}\" is not one of bool, int, cat, float, any"),
                ))
            }
        };
        Ok(ty)
    }

    /// A leaf's table: the variables it reads and writes, its scripts
    /// compiled, and which inputs each script reads.
    fn leaf_def(&self, key: &str, l: &Spanned<FileLeaf>) -> Result<LeafDef, Located> {
        let d = self;
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
        Ok(LeafDef {
            key: key.to_string(),
            inputs,
            outputs,
            actions: l.actions.clone(),
            decide,
            effect,
            status,
            reads,
        })
    }

    /// A run that ends after a leaf no table describes would never end.
    fn check_end_after(&self) -> Result<(), Located> {
        let d = self;
        if let Some(e) = d
            .end_after
            .iter()
            .find(|e| !d.leaves.iter().any(|l| &l.key == *e))
        {
            let at = d.text.find("end_after").unwrap_or(0);
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
        Ok(())
    }

    pub(super) fn compile(&self, s: &Spanned<String>, what: &str) -> Result<Script, Located> {
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

    pub(super) fn topological(&self) -> Result<Vec<usize>, Vec<String>> {
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

    pub(super) fn check_value(&self, ty: &VarType, v: &Value) -> Result<(), String> {
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
}

/// Where a script's text starts, inside its TOML string.
pub(super) fn script_start(text: &str, span: &std::ops::Range<usize>) -> usize {
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

/// The most values a float variable's grid may have.
pub const GRID_MAX: usize = 10_000;

pub(super) fn default_of(ty: &VarType) -> Value {
    match ty {
        VarType::Bool => Value::Bool(false),
        VarType::Int { min, .. } => Value::from(*min),
        VarType::Cat { values } => Value::from(values[0].clone()),
        VarType::Float { min, .. } => Value::from(*min),
        VarType::Any => Value::from(""),
    }
}

pub(super) fn toml_to_json(v: &toml::Value) -> Value {
    match v {
        toml::Value::String(s) => Value::from(s.clone()),
        toml::Value::Integer(i) => Value::from(*i),
        // JSON has no NaN: `initial = nan` is kept as a run keeps it.
        toml::Value::Float(f) if !f.is_finite() => crate::run::script::number(*f),
        toml::Value::Float(f) => Value::from(*f),
        toml::Value::Boolean(b) => Value::Bool(*b),
        other => Value::from(other.to_string()),
    }
}
