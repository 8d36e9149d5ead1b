//! BehaviorTree.CPP 4's scripting language, as far as trees use it: the
//! `Script`, `ScriptCondition` and `Precondition` nodes and the `_skipIf`,
//! `_failureIf`, `_successIf`, `_while`, `_onSuccess`, `_onFailure`,
//! `_onHalted` and `_post` attributes. Variables are blackboard entries.

use serde_json::Value;

/// Where variables live: the node's blackboard.
pub trait Env {
    fn get(&self, name: &str) -> Option<Value>;
    fn set(&mut self, name: &str, v: Value);
    /// Whether the entry exists with no value yet: BehaviorTree.CPP
    /// creates the entry of every `{key}` port when it builds the tree, so
    /// `key = …` may assign it.
    fn declared(&self, _name: &str) -> bool {
        false
    }
    /// A scripting enum's value (registerScriptingEnum): BehaviorTree.CPP
    /// looks a name up there before the blackboard.
    fn enum_value(&self, _name: &str) -> Option<Value> {
        None
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64, bool),
    Str(String),
    Id(String),
    Op(&'static str),
}

const OPS: [&str; 27] = [
    ":=", "+=", "-=", "*=", "/=", "==", "!=", "<=", ">=", "&&", "||", "..", "=", "<", ">", "+",
    "-", "*", "/", "!", "(", ")", "?", ":", ";", "&", "|",
];

fn lex(src: &str) -> Result<Vec<Tok>, String> {
    let mut out = Vec::new();
    let chars: Vec<char> = src.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '.') {
                if chars[i] == '.' && chars.get(i + 1) == Some(&'.') {
                    break;
                }
                i += 1;
            }
            let s: String = chars[start..i].iter().collect();
            let v = if let Some(h) = s.strip_prefix("0x") {
                i64::from_str_radix(h, 16)
                    .map(|x| (x as f64, true))
                    .map_err(|_| format!("\"{s}\" is not a number"))?
            } else if let Ok(x) = s.parse::<i64>() {
                (x as f64, true)
            } else {
                (
                    s.parse::<f64>()
                        .map_err(|_| format!("\"{s}\" is not a number"))?,
                    false,
                )
            };
            out.push(Tok::Num(v.0, v.1));
        } else if c == '\'' || c == '"' {
            let end = chars[i + 1..]
                .iter()
                .position(|&d| d == c)
                .ok_or("a string is not closed")?;
            out.push(Tok::Str(chars[i + 1..i + 1 + end].iter().collect()));
            i += end + 2;
        } else if c.is_alphabetic() || c == '_' || c == '@' {
            let start = i;
            i += 1;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push(Tok::Id(chars[start..i].iter().collect()));
        } else {
            let rest: String = chars[i..chars.len().min(i + 2)].iter().collect();
            let op = OPS
                .iter()
                .find(|o| rest.starts_with(**o))
                .ok_or_else(|| format!("unexpected \"{c}\""))?;
            out.push(Tok::Op(op));
            i += op.chars().count();
        }
    }
    Ok(out)
}

struct P<'a, E: Env> {
    toks: Vec<Tok>,
    pos: usize,
    env: &'a mut E,
    /// How deep the expression being read nests (parentheses, unary
    /// operators): bounded, so that no script overflows the stack.
    depth: usize,
}

/// The longest string a script may make (bytes): `x := x .. x` run over
/// and over doubles a string each time.
pub const STRING_MAX: usize = 1 << 20;

fn joined(a: &str, b: &str) -> Result<String, String> {
    if a.len() + b.len() > STRING_MAX {
        return Err(format!(
            "the string would be {} bytes long, more than the {STRING_MAX} a script may make",
            a.len() + b.len()
        ));
    }
    Ok(format!("{a}{b}"))
}

/// The deepest an expression may nest.
pub const SCRIPT_NESTING_MAX: usize = 200;

fn truthy(v: &Value) -> bool {
    match v {
        Value::Bool(b) => *b,
        Value::Number(n) => n.as_f64().is_some_and(|x| x != 0.0),
        Value::String(s) => !s.is_empty() && s != "false" && s != "0",
        Value::Null => false,
        _ => true,
    }
}

fn num(v: &Value) -> Result<f64, String> {
    match v {
        Value::Number(n) => Ok(n.as_f64().unwrap_or(0.0)),
        Value::Bool(b) => Ok(f64::from(u8::from(*b))),
        Value::String(s) => s
            .trim()
            .parse()
            .map_err(|_| format!("\"{s}\" is not a number")),
        other => Err(format!("{other} is not a number")),
    }
}

/// A number as the blackboard keeps it. JSON has no infinity or NaN: they
/// are kept as BehaviorTree.CPP prints them (`inf`, `-inf`, `nan`), strings
/// that read back as the same numbers, so a session holds every value a
/// run can make.
pub fn number(x: f64) -> Value {
    if !x.is_finite() {
        return Value::from(if x.is_nan() {
            "nan".to_string()
        } else if x > 0.0 {
            "inf".to_string()
        } else {
            "-inf".to_string()
        });
    }
    if x.fract() == 0.0 && x.abs() < 9e15 {
        Value::from(x as i64)
    } else {
        Value::from(x)
    }
}

fn equal(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::String(x), Value::String(y)) => x == y,
        (Value::String(_), _) | (_, Value::String(_)) => match (num(a), num(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => a.to_string().trim_matches('"') == b.to_string().trim_matches('"'),
        },
        _ => num(a).ok() == num(b).ok(),
    }
}

impl<E: Env> P<'_, E> {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos)
    }

    fn eat(&mut self, op: &str) -> bool {
        if self.peek()
            == Some(&Tok::Op(
                OPS.iter().find(|o| **o == op).copied().unwrap_or("\0"),
            ))
        {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn statements(&mut self) -> Result<Value, String> {
        let mut last = Value::Null;
        while self.peek().is_some() {
            if self.eat(";") {
                continue;
            }
            last = self.statement()?;
            if self.peek().is_some() && !self.eat(";") {
                return Err(format!(
                    "expected \";\" before {:?}",
                    self.peek().expect("some")
                ));
            }
        }
        Ok(last)
    }

    fn statement(&mut self) -> Result<Value, String> {
        if let (Some(Tok::Id(name)), Some(Tok::Op(op))) = (
            self.toks.get(self.pos).cloned(),
            self.toks.get(self.pos + 1).cloned(),
        ) {
            if matches!(op, ":=" | "=" | "+=" | "-=" | "*=" | "/=") {
                self.pos += 2;
                let rhs = self.expr()?;
                let v = match op {
                    ":=" | "=" => rhs,
                    _ => {
                        let old = self
                            .env
                            .get(&name)
                            .ok_or_else(|| format!("\"{name}\" is not on the blackboard"))?;
                        match op {
                            "+=" if old.is_string() || rhs.is_string() => Value::from(joined(
                                old.as_str().unwrap_or(""),
                                &rhs.as_str().map_or(rhs.to_string(), str::to_string),
                            )?),
                            "+=" => number(num(&old)? + num(&rhs)?),
                            "-=" => number(num(&old)? - num(&rhs)?),
                            "*=" => number(num(&old)? * num(&rhs)?),
                            _ => number(num(&old)? / num(&rhs)?),
                        }
                    }
                };
                if op == "=" && self.env.get(&name).is_none() && !self.env.declared(&name) {
                    return Err(format!(
                        "\"{name}\" is not on the blackboard (create it with :=)"
                    ));
                }
                self.env.set(&name, v.clone());
                return Ok(v);
            }
        }
        self.expr()
    }

    fn expr(&mut self) -> Result<Value, String> {
        let c = self.or()?;
        if self.eat("?") {
            let a = self.expr()?;
            if !self.eat(":") {
                return Err("expected \":\" in a ?: expression".into());
            }
            let b = self.expr()?;
            return Ok(if truthy(&c) { a } else { b });
        }
        Ok(c)
    }

    fn or(&mut self) -> Result<Value, String> {
        let mut l = self.and()?;
        while self.eat("||") {
            let r = self.and()?;
            l = Value::Bool(truthy(&l) || truthy(&r));
        }
        Ok(l)
    }

    fn and(&mut self) -> Result<Value, String> {
        let mut l = self.cmp()?;
        while self.eat("&&") {
            let r = self.cmp()?;
            l = Value::Bool(truthy(&l) && truthy(&r));
        }
        Ok(l)
    }

    fn cmp(&mut self) -> Result<Value, String> {
        let l = self.concat()?;
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat(op) {
                let r = self.concat()?;
                return Ok(Value::Bool(match op {
                    "==" => equal(&l, &r),
                    "!=" => !equal(&l, &r),
                    "<" => num(&l)? < num(&r)?,
                    ">" => num(&l)? > num(&r)?,
                    "<=" => num(&l)? <= num(&r)?,
                    _ => num(&l)? >= num(&r)?,
                }));
            }
        }
        Ok(l)
    }

    fn concat(&mut self) -> Result<Value, String> {
        let mut l = self.sum()?;
        while self.eat("..") {
            let r = self.sum()?;
            let s = |v: &Value| v.as_str().map_or(v.to_string(), str::to_string);
            l = Value::from(joined(&s(&l), &s(&r))?);
        }
        Ok(l)
    }

    fn sum(&mut self) -> Result<Value, String> {
        let mut l = self.product()?;
        loop {
            if self.eat("+") {
                let r = self.product()?;
                // BehaviorTree.CPP 4 joins two strings with `+`
                // (ExprBinaryArithmetic); a string that reads as a number
                // (a port's text) stays a number, as btx reads it.
                l = match (&l, &r) {
                    (Value::String(a), Value::String(b))
                        if num(&l).is_err() || num(&r).is_err() =>
                    {
                        Value::from(joined(a, b)?)
                    }
                    _ => number(num(&l)? + num(&r)?),
                };
            } else if self.eat("-") {
                let r = self.product()?;
                l = number(num(&l)? - num(&r)?);
            } else {
                return Ok(l);
            }
        }
    }

    fn product(&mut self) -> Result<Value, String> {
        let mut l = self.unary()?;
        loop {
            if self.eat("*") {
                let r = self.unary()?;
                l = number(num(&l)? * num(&r)?);
            } else if self.eat("/") {
                let r = self.unary()?;
                let d = num(&r)?;
                if d == 0.0 {
                    return Err("division by zero".into());
                }
                l = number(num(&l)? / d);
            } else {
                return Ok(l);
            }
        }
    }

    fn unary(&mut self) -> Result<Value, String> {
        if self.depth >= SCRIPT_NESTING_MAX {
            return Err(format!(
                "the expression nests deeper than {SCRIPT_NESTING_MAX} levels"
            ));
        }
        self.depth += 1;
        let v = self.unary_inner();
        self.depth -= 1;
        v
    }

    fn unary_inner(&mut self) -> Result<Value, String> {
        if self.eat("!") {
            let v = self.unary()?;
            return Ok(Value::Bool(!truthy(&v)));
        }
        if self.eat("-") {
            let v = self.unary()?;
            return Ok(number(-num(&v)?));
        }
        self.atom()
    }

    fn atom(&mut self) -> Result<Value, String> {
        let t = self.peek().cloned().ok_or("the script ends too early")?;
        self.pos += 1;
        match t {
            Tok::Num(x, _) => Ok(number(x)),
            Tok::Str(s) => Ok(Value::from(s)),
            Tok::Id(id) if id == "true" => Ok(Value::Bool(true)),
            Tok::Id(id) if id == "false" => Ok(Value::Bool(false)),
            // BehaviorTree.CPP also reads enums the robot's code registers
            // (registerScriptingEnum), which no tree file declares.
            Tok::Id(id) => self.env.enum_value(&id).or_else(|| self.env.get(&id)).ok_or_else(|| {
                format!(
                    "\"{id}\" is not on the blackboard, nor an enum btx knows (BehaviorTree.CPP takes enums the robot registers with registerScriptingEnum): declare it in the plan (@enum {id} = VALUE) or the domain ([enums] {id} = VALUE), or give it with --set {id}=VALUE"
                )
            }),
            Tok::Op("(") => {
                let v = self.expr()?;
                if !self.eat(")") {
                    return Err("expected \")\"".into());
                }
                Ok(v)
            }
            Tok::Op(o) => Err(format!("unexpected \"{o}\"")),
        }
    }
}

/// Runs a script; returns the value of its last statement.
pub fn run(src: &str, env: &mut impl Env) -> Result<Value, String> {
    let toks = lex(src)?;
    P {
        toks,
        pos: 0,
        env,
        depth: 0,
    }
    .statements()
}

/// Runs a script as a condition.
pub fn test(src: &str, env: &mut impl Env) -> Result<bool, String> {
    run(src, env).map(|v| truthy(&v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[derive(Default)]
    struct M(HashMap<String, Value>);
    impl Env for M {
        fn get(&self, n: &str) -> Option<Value> {
            self.0.get(n).cloned()
        }
        fn set(&mut self, n: &str, v: Value) {
            self.0.insert(n.to_string(), v);
        }
    }

    #[test]
    fn scripts_assign_and_compare() {
        let mut m = M::default();
        run("a := 3; b := a * 2 + 1; msg := 'n=' .. b", &mut m).unwrap();
        assert_eq!(m.get("b"), Some(Value::from(7)));
        assert_eq!(m.get("msg"), Some(Value::from("n=7")));
        assert!(test("b > 6 && a == 3", &mut m).unwrap());
        assert!(!test("!(b > 6) || a != 3", &mut m).unwrap());
        run("a += 2; c := a >= 5 ? 'big' : 'small'", &mut m).unwrap();
        assert_eq!(m.get("c"), Some(Value::from("big")));
        assert!(test("c == 'big'", &mut m).unwrap());
        assert_eq!(
            run("x = 1", &mut m).unwrap_err(),
            "\"x\" is not on the blackboard (create it with :=)"
        );
        assert!(run("a := (1", &mut m).is_err());
        assert!(run("a := 1 / 0", &mut m).is_err());
        assert!(run("a := 1 $ 2", &mut m).is_err());
    }
}
