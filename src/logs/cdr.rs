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
        let mut r = Reader::open(bytes)?;
        let v = self.message(&self.top, &mut r, 0)?;
        r.finish()?;
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

/// A message whose one sequence of structs is what is read (Nav2's
/// `event_log`), laid out flat from its definition: every other field is
/// read past by its type, and the items' fields asked for (`paths`, such as
/// `timestamp.sec`) are read into slots, without a `Value` tree or a copy
/// of their text. Made only where every field but the sequence has a size
/// the definition fixes (primitives, strings, nested messages, small
/// arrays); else `Definitions::decode` reads it.
#[derive(Debug, Clone)]
pub struct Flat {
    head: Vec<Op>,
    items: Vec<Op>,
    seq: String,
    tail: Vec<Op>,
    kinds: Vec<SlotKind>,
}

/// One field a `Flat` reads, in the order it lies: an integer of a
/// size, or a string; with the slot it fills, if any.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    Int {
        size: usize,
        signed: bool,
        slot: Option<usize>,
    },
    Text {
        slot: Option<usize>,
    },
}

/// What the definition makes of a path asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlotKind {
    Absent,
    Int,
    Text,
    /// A nested message (its fields are paths of their own).
    Message,
    /// Anything else (a float, a bool, an array): not read into the slot.
    Other,
}

/// A slot of one item, as read: a text as where it lies in the message
/// (its closing NUL left out), so that one buffer of slots serves every
/// message and no text is copied or checked for UTF-8 until it is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    Absent,
    Int(i64),
    Text { start: usize, end: usize },
}

impl Slot {
    pub fn int(self) -> Option<i64> {
        match self {
            Slot::Int(i) => Some(i),
            _ => None,
        }
    }

    /// A text slot's bytes in `message` (the bytes it was read from); no
    /// bytes for any other slot.
    pub fn bytes(self, message: &[u8]) -> &[u8] {
        match self {
            Slot::Text { start, end } => &message[start..end],
            _ => &[],
        }
    }
}

impl Definitions {
    /// The top message laid out flat around its sequence field `seq`, with
    /// `paths` of each item read into slots; `None` where it cannot be.
    pub fn flat(&self, seq: &str, paths: &[&str]) -> Option<Flat> {
        let mut flat = Flat {
            head: Vec::new(),
            items: Vec::new(),
            seq: seq.to_string(),
            tail: Vec::new(),
            kinds: vec![SlotKind::Absent; paths.len()],
        };
        let mut seen = false;
        for f in self.types.get(&self.top)? {
            if f.name == seq && !seen {
                let (Shape::Sequence, Type::Message(item)) = (&f.shape, &f.ty) else {
                    return None;
                };
                seen = true;
                let mut ops = Vec::new();
                for g in self.types.get(item)? {
                    self.lay(g, "", paths, &mut flat.kinds, &mut ops, 0)?;
                }
                flat.items = ops;
            } else {
                let mut none = Vec::new();
                let ops = if seen { &mut flat.tail } else { &mut flat.head };
                self.lay(f, "", &[], &mut none, ops, 0)?;
            }
        }
        seen.then_some(flat)
    }

    /// One field's ops, its path's slot tagged (the first field of a path).
    fn lay(
        &self,
        f: &Field,
        prefix: &str,
        paths: &[&str],
        kinds: &mut [SlotKind],
        ops: &mut Vec<Op>,
        depth: usize,
    ) -> Option<()> {
        if depth > 32 {
            return None;
        }
        let path = if prefix.is_empty() {
            f.name.clone()
        } else {
            format!("{prefix}.{}", f.name)
        };
        let slot = paths
            .iter()
            .position(|p| *p == path)
            .filter(|&i| kinds[i] == SlotKind::Absent);
        let (kind, times) = match f.shape {
            Shape::One => (None, 1),
            Shape::Array(n) if n <= 64 => (Some(SlotKind::Other), n),
            _ => return None,
        };
        for _ in 0..times {
            let tag = |k: SlotKind, kinds: &mut [SlotKind]| {
                let k = kind.unwrap_or(k);
                if let Some(i) = slot {
                    kinds[i] = k;
                }
                slot.filter(|_| kind.is_none())
            };
            match &f.ty {
                Type::Int { size, signed } => ops.push(Op::Int {
                    size: *size,
                    signed: *signed,
                    slot: tag(SlotKind::Int, kinds),
                }),
                Type::Float(size) => {
                    tag(SlotKind::Other, kinds);
                    ops.push(Op::Int {
                        size: *size,
                        signed: false,
                        slot: None,
                    });
                }
                Type::Bool => {
                    tag(SlotKind::Other, kinds);
                    ops.push(Op::Int {
                        size: 1,
                        signed: false,
                        slot: None,
                    });
                }
                Type::Text => ops.push(Op::Text {
                    slot: tag(SlotKind::Text, kinds),
                }),
                Type::Message(name) => {
                    tag(SlotKind::Message, kinds);
                    for g in self.types.get(name)? {
                        self.lay(g, &path, paths, kinds, ops, depth + 1)?;
                    }
                }
            }
        }
        Some(())
    }
}

impl Flat {
    /// What each path asked for is in this definition.
    pub fn kinds(&self) -> &[SlotKind] {
        &self.kinds
    }

    /// The fields before the sequence, of each of its items, and after
    /// it: for a reader of one known layout to check it is that one.
    pub fn ops(&self) -> [&[Op]; 3] {
        [&self.head, &self.items, &self.tail]
    }

    /// One message's items into `out`, each `kinds().len()` slots in a
    /// row. Its errors are `Definitions::decode`'s, word for word.
    pub fn decode(&self, bytes: &[u8], out: &mut Vec<Slot>) -> Result<(), String> {
        out.clear();
        let mut r = Reader::open(bytes)?;
        let k = self.kinds.len();
        let mut none = [];
        run(&self.head, &mut r, &mut none)?;
        let n = r.int(4, false)? as usize;
        if n > r.body.len() - r.at {
            return Err(format!(
                "{}: a sequence of {n} elements in {} bytes",
                self.seq,
                r.body.len() - r.at
            ));
        }
        out.resize(n * k, Slot::Absent);
        for item in out.chunks_exact_mut(k.max(1)).take(n) {
            run(&self.items, &mut r, item)?;
        }
        run(&self.tail, &mut r, &mut none)?;
        r.finish()
    }
}

fn run(ops: &[Op], r: &mut Reader, slots: &mut [Slot]) -> Result<(), String> {
    for op in ops {
        match *op {
            Op::Int { size, signed, slot } => {
                let v = r.int(size, signed)?;
                if let Some(i) = slot {
                    slots[i] = Slot::Int(v);
                }
            }
            Op::Text { slot } => {
                let (start, end) = r.text_span()?;
                if let Some(i) = slot {
                    // Where the text lies in the message, header counted.
                    slots[i] = Slot::Text {
                        start: start + HEADER,
                        end: end + HEADER,
                    };
                }
            }
        }
    }
    Ok(())
}

/// The encapsulation header's bytes.
const HEADER: usize = 4;

/// The bytes after the encapsulation header; alignment counts from there.
struct Reader<'a> {
    body: &'a [u8],
    at: usize,
    little: bool,
}

impl<'a> Reader<'a> {
    /// A message's body, after its 4-byte encapsulation header.
    fn open(bytes: &'a [u8]) -> Result<Reader<'a>, String> {
        let little = match bytes.get(..2) {
            Some([0, 1]) | Some([0, 3]) => true,
            Some([0, 0]) | Some([0, 2]) => false,
            _ => return Err("not CDR (its encapsulation header is not 00 00/01 00 00)".into()),
        };
        Ok(Reader {
            body: &bytes[HEADER.min(bytes.len())..],
            at: 0,
            little,
        })
    }

    /// Every byte read, padding aside.
    fn finish(&self) -> Result<(), String> {
        match self.body.len() - self.at {
            left if left >= 4 => Err(format!(
                "{left} bytes left after the message: the definition does not describe it"
            )),
            _ => Ok(()),
        }
    }

    #[cold]
    fn short(&self, n: usize) -> String {
        format!(
            "the message ends at byte {} of {n} more it needs",
            self.body.len() + HEADER
        )
    }

    /// An integer of `size` bytes (1, 2, 4 or 8: the definition's
    /// primitives), each size read by code of its own.
    #[inline]
    fn int(&mut self, size: usize, signed: bool) -> Result<i64, String> {
        match size {
            1 => self.int_of::<1>(signed),
            2 => self.int_of::<2>(signed),
            4 => self.int_of::<4>(signed),
            _ => self.int_of::<8>(signed),
        }
    }

    #[inline(always)]
    fn int_of<const N: usize>(&mut self, signed: bool) -> Result<i64, String> {
        let start = (self.at + N - 1) & !(N - 1);
        let Some(b) = self.body.get(start..start + N) else {
            return Err(self.short(N));
        };
        self.at = start + N;
        let mut buf = [0u8; 8];
        let x = if self.little {
            buf[..N].copy_from_slice(b);
            u64::from_le_bytes(buf)
        } else {
            buf[8 - N..].copy_from_slice(b);
            u64::from_be_bytes(buf)
        };
        Ok(if signed && N < 8 {
            let shift = 64 - 8 * N as u32;
            ((x << shift) as i64) >> shift
        } else {
            x as i64
        })
    }

    fn text(&mut self) -> Result<String, String> {
        let (start, end) = self.text_span()?;
        Ok(String::from_utf8_lossy(&self.body[start..end]).into_owned())
    }

    /// Where the next string's text lies in the body, its closing NUL
    /// (which its length counts) left out.
    fn text_span(&mut self) -> Result<(usize, usize), String> {
        let n = self.int_of::<4>(false)? as usize;
        let start = self.at;
        let Some(end) = start.checked_add(n).filter(|&e| e <= self.body.len()) else {
            return Err(self.short(n));
        };
        self.at = end;
        Ok(match self.body[start..end].last() {
            Some(0) => (start, end - 1),
            _ => (start, end),
        })
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

    /// A slot as the tree of values says it.
    #[derive(Debug, PartialEq)]
    enum Seen {
        Absent,
        Int(i64),
        Text(String),
    }

    /// Every field a flat read gives, from the tree of values of the
    /// general read: the two must agree, errors included.
    fn flat_as_values(d: &Definitions, bytes: &[u8], paths: &[&str]) -> Result<Vec<Seen>, String> {
        let v = d.decode(bytes)?;
        let mut out = Vec::new();
        for c in v.get("event_log").unwrap().list().unwrap() {
            for p in paths {
                let mut at = Some(c);
                for part in p.split('.') {
                    at = at.and_then(|x| x.get(part));
                }
                out.push(match at {
                    Some(Value::Int(i)) => Seen::Int(*i),
                    Some(Value::Text(t)) => Seen::Text(t.clone()),
                    _ => Seen::Absent,
                });
            }
        }
        Ok(out)
    }

    #[test]
    fn a_flat_read_reads_what_the_tree_of_values_reads() {
        let paths = [
            "timestamp.sec",
            "timestamp.nanosec",
            "node_name",
            "uid",
            "previous_status",
            "current_status",
        ];
        let humble = LOG.replace("uint16 uid # since Jazzy\n", "");
        // A field before the sequence and one after it are read past.
        let around = LOG.replacen(
            "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n",
            "uint8 flag\nbuiltin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\nfloat64 after\nstring label\nbool[3] bits\n",
            1,
        );
        let jazzy = cdr(&[
            ("FollowPath", 12, "IDLE", "RUNNING"),
            ("Seq", 3, "RUNNING", "SUCCESS"),
        ]);
        for text in [LOG.to_string(), humble, around] {
            let d = Definitions::parse("nav2_msgs/msg/BehaviorTreeLog", &text).unwrap();
            let flat = d.flat("event_log", &paths).unwrap();
            let mut cases: Vec<Vec<u8>> = vec![
                jazzy.clone(),
                b"xy".to_vec(),
                b"\x00\x01\x00\x00\xff\xff".to_vec(),
            ];
            // Every cut of the message, and a byte more than it holds.
            cases.extend((0..jazzy.len()).map(|n| jazzy[..n].to_vec()));
            cases.push([jazzy.clone(), vec![0; 4]].concat());
            // One buffer for every message, as a bag is read.
            let mut slots = vec![Slot::Int(1); 3];
            for bytes in cases {
                let read = flat.decode(&bytes, &mut slots).map(|()| {
                    let seen = |s: &Slot| match *s {
                        Slot::Text { .. } => {
                            Seen::Text(String::from_utf8_lossy(s.bytes(&bytes)).into_owned())
                        }
                        Slot::Int(i) => Seen::Int(i),
                        Slot::Absent => Seen::Absent,
                    };
                    slots.iter().map(seen).collect::<Vec<_>>()
                });
                assert_eq!(read, flat_as_values(&d, &bytes, &paths), "{bytes:?}");
            }
        }
        assert_eq!(
            Definitions::parse("nav2_msgs/msg/BehaviorTreeLog", LOG)
                .unwrap()
                .flat("event_log", &paths)
                .unwrap()
                .kinds(),
            [
                SlotKind::Int,
                SlotKind::Int,
                SlotKind::Text,
                SlotKind::Int,
                SlotKind::Text,
                SlotKind::Text
            ]
        );
        // A sequence besides the log's is left to the tree of values.
        let more = LOG.replacen(
            "BehaviorTreeStatusChange[] event_log\n",
            "BehaviorTreeStatusChange[] event_log\nint32[] extra\n",
            1,
        );
        assert!(Definitions::parse("nav2_msgs/msg/BehaviorTreeLog", &more)
            .unwrap()
            .flat("event_log", &paths)
            .is_none());
    }
}
