//! ROS 2 messages as a rosbag keeps them: CDR bytes (XCDR1, as rmw writes
//! them), read by the `.msg` definition the bag carries, so that a field
//! added in a later release (Nav2's `uid` since Jazzy) is read where the
//! definition puts it, never guessed.

use std::collections::HashMap;

/// A decoded value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Int(i64),
    Float(f64),
    Bool(bool),
    Text(String),
    List(Vec<Value>),
    Struct(Vec<(String, Value)>),
}

impl Value {
    /// A field of a message.
    pub fn get(&self, name: &str) -> Option<&Value> {
        match self {
            Value::Struct(fields) => fields.iter().find(|(n, _)| n == name).map(|(_, v)| v),
            _ => None,
        }
    }

    pub fn int(&self) -> Option<i64> {
        match self {
            Value::Int(i) => Some(*i),
            _ => None,
        }
    }

    pub fn text(&self) -> Option<&str> {
        match self {
            Value::Text(s) => Some(s),
            _ => None,
        }
    }

    pub fn list(&self) -> Option<&[Value]> {
        match self {
            Value::List(v) => Some(v),
            _ => None,
        }
    }
}

/// A field's type.
#[derive(Debug, Clone, PartialEq)]
enum Type {
    /// A primitive of this many bytes: signed, float, bool.
    Int {
        size: usize,
        signed: bool,
    },
    Float(usize),
    Bool,
    Text,
    Message(String),
}

#[derive(Debug, Clone, PartialEq)]
enum Shape {
    One,
    /// A sequence, its length first.
    Sequence,
    /// A fixed-size array.
    Array(usize),
}

#[derive(Debug, Clone, PartialEq)]
struct Field {
    name: String,
    ty: Type,
    shape: Shape,
}

/// Message definitions: the top type's and those it uses, by full name
/// (`pkg/Type`).
#[derive(Debug, Clone, Default)]
pub struct Definitions {
    top: String,
    types: HashMap<String, Vec<Field>>,
}

/// `pkg/msg/Type` and `pkg/Type` are one name.
fn full_name(name: &str, package: &str) -> String {
    let parts: Vec<&str> = name.split('/').filter(|p| *p != "msg").collect();
    match parts.as_slice() {
        [ty] => format!("{package}/{ty}"),
        [pkg, .., ty] => format!("{pkg}/{ty}"),
        [] => String::new(),
    }
}

fn primitive(name: &str) -> Option<Type> {
    let int = |size, signed| Some(Type::Int { size, signed });
    match name {
        "bool" => Some(Type::Bool),
        "byte" | "uint8" | "char" => int(1, false),
        "int8" => int(1, true),
        "int16" => int(2, true),
        "uint16" => int(2, false),
        "int32" => int(4, true),
        "uint32" => int(4, false),
        "int64" => int(8, true),
        "uint64" => int(8, false),
        "float32" => Some(Type::Float(4)),
        "float64" => Some(Type::Float(8)),
        "string" => Some(Type::Text),
        _ if name.starts_with("string<=") => Some(Type::Text),
        _ => None,
    }
}

impl Definitions {
    /// Reads `text` (the `ros2msg` encoding: the type's fields, then each
    /// type it uses after a line of `=` and a `MSG: pkg/Type` line) as the
    /// definition of `top` (`pkg/msg/Type`).
    pub fn parse(top: &str, text: &str) -> Result<Definitions, String> {
        let top_name = full_name(top, "");
        let package = top_name.split('/').next().unwrap_or("").to_string();
        let mut defs = Definitions {
            top: top_name.clone(),
            types: HashMap::new(),
        };
        let (mut current, mut pkg, mut fields) = (top_name, package, Vec::new());
        for line in text.lines() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.starts_with("====") {
                continue;
            }
            if let Some(name) = line.strip_prefix("MSG:") {
                defs.types
                    .insert(std::mem::take(&mut current), std::mem::take(&mut fields));
                current = full_name(name.trim(), "");
                pkg = current.split('/').next().unwrap_or("").to_string();
                continue;
            }
            let mut words = line.split_whitespace();
            let (Some(ty), Some(name)) = (words.next(), words.next()) else {
                continue;
            };
            // Constants (`uint8 IDLE=0`) are not fields.
            if name.contains('=') || words.next().is_some_and(|w| w.starts_with('=')) {
                continue;
            }
            let (base, shape) = match ty.split_once('[') {
                Some((b, rest)) => {
                    let inside = rest.trim_end_matches(']');
                    if inside.is_empty() || inside.starts_with("<=") {
                        (b, Shape::Sequence)
                    } else {
                        let n = inside.parse().map_err(|_| {
                            format!("the field \"{line}\": an array size that is not a number")
                        })?;
                        (b, Shape::Array(n))
                    }
                }
                None => (ty, Shape::One),
            };
            let ty = match primitive(base) {
                Some(t) => t,
                None if base == "time" || base == "duration" => {
                    Type::Message("builtin_interfaces/Time".into())
                }
                None => Type::Message(full_name(base, &pkg)),
            };
            fields.push(Field {
                name: name.to_string(),
                ty,
                shape,
            });
        }
        defs.types.insert(current, fields);
        defs.types
            .entry("builtin_interfaces/Time".into())
            .or_insert_with(|| {
                vec![
                    Field {
                        name: "sec".into(),
                        ty: Type::Int {
                            size: 4,
                            signed: true,
                        },
                        shape: Shape::One,
                    },
                    Field {
                        name: "nanosec".into(),
                        ty: Type::Int {
                            size: 4,
                            signed: false,
                        },
                        shape: Shape::One,
                    },
                ]
            });
        Ok(defs)
    }

    /// Decodes one message: the 4-byte encapsulation header, then the top
    /// type's fields; every byte must be read (padding aside).
    pub fn decode(&self, bytes: &[u8]) -> Result<Value, String> {
        let little = match bytes.get(..2) {
            Some([0, 1]) | Some([0, 3]) => true,
            Some([0, 0]) | Some([0, 2]) => false,
            _ => return Err("not CDR (its encapsulation header is not 00 00/01 00 00)".into()),
        };
        let mut r = Reader {
            body: &bytes[4.min(bytes.len())..],
            at: 0,
            little,
        };
        let v = self.message(&self.top, &mut r, 0)?;
        if r.body.len() - r.at >= 4 {
            return Err(format!(
                "{} bytes left after the message: the definition does not describe it",
                r.body.len() - r.at
            ));
        }
        Ok(v)
    }

    fn message(&self, name: &str, r: &mut Reader, depth: usize) -> Result<Value, String> {
        if depth > 32 {
            return Err("message types nest more than 32 deep".into());
        }
        let fields = self
            .types
            .get(name)
            .ok_or_else(|| format!("the definition names {name} but does not define it"))?;
        let mut out = Vec::with_capacity(fields.len());
        for f in fields {
            let v = match f.shape {
                Shape::One => self.one(&f.ty, r, depth)?,
                Shape::Sequence => {
                    let n = r.int(4, false)? as usize;
                    // Each element takes a byte at least: a count past the
                    // bytes left is a broken message, not an allocation.
                    if n > r.body.len() - r.at {
                        return Err(format!(
                            "{}: a sequence of {n} elements in {} bytes",
                            f.name,
                            r.body.len() - r.at
                        ));
                    }
                    let mut items = Vec::with_capacity(n);
                    for _ in 0..n {
                        items.push(self.one(&f.ty, r, depth)?);
                    }
                    Value::List(items)
                }
                Shape::Array(n) => {
                    let mut items = Vec::with_capacity(n.min(1 << 16));
                    for _ in 0..n {
                        items.push(self.one(&f.ty, r, depth)?);
                    }
                    Value::List(items)
                }
            };
            out.push((f.name.clone(), v));
        }
        Ok(Value::Struct(out))
    }

    fn one(&self, ty: &Type, r: &mut Reader, depth: usize) -> Result<Value, String> {
        Ok(match ty {
            Type::Int { size, signed } => Value::Int(r.int(*size, *signed)?),
            Type::Float(size) => {
                let raw = r.int(*size, false)? as u64;
                Value::Float(if *size == 4 {
                    f64::from(f32::from_bits(raw as u32))
                } else {
                    f64::from_bits(raw)
                })
            }
            Type::Bool => Value::Bool(r.int(1, false)? != 0),
            Type::Text => Value::Text(r.text()?),
            Type::Message(name) => self.message(name, r, depth + 1)?,
        })
    }
}

/// The bytes after the encapsulation header; alignment counts from there.
struct Reader<'a> {
    body: &'a [u8],
    at: usize,
    little: bool,
}

impl Reader<'_> {
    fn take(&mut self, n: usize, align: usize) -> Result<&[u8], String> {
        let start = self.at.div_ceil(align) * align;
        let end = start
            .checked_add(n)
            .filter(|&e| e <= self.body.len())
            .ok_or_else(|| {
                format!(
                    "the message ends at byte {} of {n} more it needs",
                    self.body.len() + 4
                )
            })?;
        self.at = end;
        Ok(&self.body[start..end])
    }

    fn int(&mut self, size: usize, signed: bool) -> Result<i64, String> {
        let little = self.little;
        let b = self.take(size, size)?;
        let mut x: u64 = 0;
        for i in 0..size {
            let byte = if little { b[size - 1 - i] } else { b[i] };
            x = (x << 8) | u64::from(byte);
        }
        Ok(if signed && size < 8 {
            let shift = 64 - 8 * size as u32;
            ((x << shift) as i64) >> shift
        } else {
            x as i64
        })
    }

    fn text(&mut self) -> Result<String, String> {
        let n = self.int(4, false)? as usize;
        let b = self.take(n, 1)?;
        // The length counts the closing NUL.
        let b = b.strip_suffix(&[0]).unwrap_or(b);
        Ok(String::from_utf8_lossy(b).into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LOG: &str = "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n================================================================================\nMSG: nav2_msgs/BehaviorTreeStatusChange\nbuiltin_interfaces/Time timestamp\nstring node_name\nuint16 uid # since Jazzy\nstring previous_status  # IDLE, RUNNING, SUCCESS or FAILURE\nstring current_status\n================================================================================\nMSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";

    /// A message as rmw writes it, by hand.
    fn cdr(changes: &[(&str, u16, &str, &str)]) -> Vec<u8> {
        let mut b = vec![0, 1, 0, 0];
        let pad = |b: &mut Vec<u8>, a: usize| {
            while !(b.len() - 4).is_multiple_of(a) {
                b.push(0);
            }
        };
        let text = |b: &mut Vec<u8>, s: &str| {
            pad(b, 4);
            b.extend_from_slice(&(s.len() as u32 + 1).to_le_bytes());
            b.extend_from_slice(s.as_bytes());
            b.push(0);
        };
        b.extend_from_slice(&7i32.to_le_bytes());
        b.extend_from_slice(&9u32.to_le_bytes());
        b.extend_from_slice(&(changes.len() as u32).to_le_bytes());
        for (name, uid, prev, now) in changes {
            pad(&mut b, 4);
            b.extend_from_slice(&100i32.to_le_bytes());
            b.extend_from_slice(&5000u32.to_le_bytes());
            text(&mut b, name);
            pad(&mut b, 2);
            b.extend_from_slice(&uid.to_le_bytes());
            text(&mut b, prev);
            text(&mut b, now);
        }
        b
    }

    #[test]
    fn a_behavior_tree_log_is_read_by_its_definition() {
        let d = Definitions::parse("nav2_msgs/msg/BehaviorTreeLog", LOG).unwrap();
        let v = d
            .decode(&cdr(&[
                ("FollowPath", 12, "IDLE", "RUNNING"),
                ("Seq", 3, "RUNNING", "SUCCESS"),
            ]))
            .unwrap();
        let log = v.get("event_log").unwrap().list().unwrap();
        assert_eq!(log.len(), 2);
        assert_eq!(log[0].get("node_name").unwrap().text(), Some("FollowPath"));
        assert_eq!(log[0].get("uid").unwrap().int(), Some(12));
        assert_eq!(
            log[1].get("current_status").unwrap().text(),
            Some("SUCCESS")
        );
        let t = log[0].get("timestamp").unwrap();
        assert_eq!(t.get("nanosec").unwrap().int(), Some(5000));
    }

    #[test]
    fn a_definition_that_does_not_fit_the_bytes_is_said() {
        // Humble's definition (no uid) over Jazzy's bytes reads other
        // strings (the caller checks them: `rosbag::definitions`).
        let humble = LOG.replace("uint16 uid # since Jazzy\n", "");
        let d = Definitions::parse("nav2_msgs/msg/BehaviorTreeLog", &humble).unwrap();
        let v = d.decode(&cdr(&[("FollowPath", 12, "IDLE", "RUNNING")]));
        let prev = v.ok().and_then(|v| {
            let first = &v.get("event_log")?.list()?[0];
            first.get("previous_status")?.text().map(str::to_string)
        });
        assert_ne!(prev.as_deref(), Some("IDLE"));
        assert!(d.decode(b"\x00\x01\x00\x00\xff\xff").is_err());
        assert!(d.decode(b"xy").is_err());
        // A sequence count past the bytes is refused before it allocates.
        let mut b = vec![0, 1, 0, 0];
        b.extend_from_slice(&[0; 8]);
        b.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(d
            .decode(&b)
            .unwrap_err()
            .contains("a sequence of 4294967295"));
    }
}
