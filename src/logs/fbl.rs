//! BehaviorTree.CPP 3's FileLogger `.fbl`: a flatbuffer with the tree, then
//! 12-byte records (u32 seconds, u32 µs, u16 uid, prev and new status).
//! The tree is turned into the instantiated XML btx reads for `.btlog`.

use super::btlog::Record;
use crate::run::Status;
use crate::source::Located;
use std::path::Path;

/// A little flatbuffer reader: bounds-checked, so a broken file is an error.
struct Fb<'a> {
    b: &'a [u8],
    path: &'a Path,
    /// Where the flatbuffer starts in what the user has (4 in an `.fbl`).
    base: usize,
}

impl<'a> Fb<'a> {
    fn err(&self, at: usize, msg: &str) -> Located {
        Located::file(
            self.path,
            format!("byte offset {}: {msg}", at.saturating_add(self.base)),
        )
    }
    fn bytes<const N: usize>(&self, at: usize) -> Result<[u8; N], Located> {
        at.checked_add(N)
            .and_then(|end| self.b.get(at..end))
            .map(|b| b.try_into().expect("N bytes"))
            .ok_or_else(|| self.err(at, "the tree's flatbuffer ends early"))
    }
    fn u8(&self, at: usize) -> Result<u8, Located> {
        Ok(self.bytes::<1>(at)?[0])
    }
    fn u16(&self, at: usize) -> Result<u16, Located> {
        Ok(u16::from_le_bytes(self.bytes(at)?))
    }
    fn u32(&self, at: usize) -> Result<u32, Located> {
        Ok(u32::from_le_bytes(self.bytes(at)?))
    }
    /// The position of field `i` of the table at `t`, if present.
    fn field(&self, t: usize, i: usize) -> Result<Option<usize>, Located> {
        let vt = usize::try_from(t as i64 - i64::from(self.u32(t)? as i32))
            .map_err(|_| self.err(t, "a table's vtable lies before the flatbuffer"))?;
        let vt_len = self.u16(vt)? as usize;
        if 4 + 2 * i >= vt_len {
            return Ok(None);
        }
        let off = self.u16(vt + 4 + 2 * i)? as usize;
        Ok((off != 0).then_some(t + off))
    }
    fn indirect(&self, at: usize) -> Result<usize, Located> {
        Ok(at + self.u32(at)? as usize)
    }
    fn string(&self, t: usize, i: usize) -> Result<String, Located> {
        let Some(f) = self.field(t, i)? else {
            return Ok(String::new());
        };
        let s = self.indirect(f)?;
        let n = self.u32(s)? as usize;
        let bytes = self
            .b
            .get(s + 4..s + 4 + n)
            .ok_or_else(|| self.err(s, "a string runs past the end"))?;
        Ok(String::from_utf8_lossy(bytes).into_owned())
    }
    /// Element positions of a vector field (tables: followed; scalars: in place).
    fn vector(&self, t: usize, i: usize, elem: usize, tables: bool) -> Result<Vec<usize>, Located> {
        let Some(f) = self.field(t, i)? else {
            return Ok(Vec::new());
        };
        let v = self.indirect(f)?;
        let n = self.u32(v)? as usize;
        if n > self.b.len() {
            return Err(self.err(v, "a vector is longer than the file"));
        }
        (0..n)
            .map(|k| {
                let at = v + 4 + k * elem;
                if tables {
                    self.indirect(at)
                } else {
                    Ok(at)
                }
            })
            .collect()
    }
}

pub struct RawFbl {
    pub xml: String,
    pub records: Vec<(Record, Status)>,
    pub partial_tail: usize,
}

/// Whether the bytes look like an `.fbl`: a plausible flatbuffer length and
/// whole 12-byte records after it.
pub fn is_fbl(bytes: &[u8]) -> bool {
    if bytes.len() < 12 {
        return false;
    }
    let n = i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
    n > 8 && (n as usize) + 4 <= bytes.len() && {
        let root = u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]) as usize;
        root < n as usize
    }
}

/// Why bytes that should be an `.fbl` are not: what their first field,
/// the flatbuffer's length, says against the file.
pub fn not_fbl(bytes: &[u8]) -> String {
    if bytes.len() < 12 {
        return format!(
            "byte offset 0: not an .fbl: {} bytes, fewer than a length field and a tree need",
            bytes.len()
        );
    }
    let n = i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
    if n <= 8 || (n as usize) + 4 > bytes.len() {
        return format!(
            "byte offset 0: not an .fbl, or a corrupt one: its size field says the tree takes {n} bytes, \
             but the file has {} after the field",
            bytes.len() - 4
        );
    }
    "byte offset 4: not an .fbl, or a corrupt one: the tree's root offset lies outside the tree"
        .into()
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

pub fn parse(path: &Path, bytes: &[u8]) -> Result<RawFbl, Located> {
    if !is_fbl(bytes) {
        return Err(Located::file(path, not_fbl(bytes)));
    }
    let n = i32::from_le_bytes(bytes[..4].try_into().expect("4 bytes")) as usize;
    let xml = tree_xml(path, &bytes[4..4 + n], 4, ".fbl's tree")?;
    let mut records = Vec::new();
    let mut off = 4 + n;
    while off + 12 <= bytes.len() {
        let r: &[u8; 12] = bytes[off..off + 12].try_into().expect("12 bytes");
        records.push(
            record(r, off)
                .map_err(|m| Located::file(path, format!("byte offset {}: {m}", off + 10)))?,
        );
        off += 12;
    }
    Ok(RawFbl {
        xml,
        records,
        partial_tail: bytes.len() - off,
    })
}

/// One 12-byte transition record, as BehaviorTree.CPP 3 writes it to an
/// `.fbl` and publishes it (`PublisherZMQ`): the record and the status
/// before it.
pub fn record(r: &[u8; 12], offset: usize) -> Result<(Record, Status), String> {
    let sec = u32::from_le_bytes(r[0..4].try_into().expect("4")) as i64;
    let usec = u32::from_le_bytes(r[4..8].try_into().expect("4")) as i64;
    let uid = u16::from_le_bytes([r[8], r[9]]) as u32;
    let prev = Status::from_code(r[10]).filter(|s| *s != Status::Skipped);
    let status = Status::from_code(r[11]).filter(|s| *s != Status::Skipped);
    let (Some(prev), Some(status)) = (prev, status) else {
        return Err("a status byte is not 0 to 3".into());
    };
    Ok((
        Record {
            time_us: sec * 1_000_000 + usec,
            uid,
            status,
            offset,
        },
        prev,
    ))
}

/// BehaviorTree.CPP 3's tree flatbuffer (`Serialization::BehaviorTree`,
/// in an `.fbl` after its size, and the reply of a Groot 1 server) as the
/// instantiated XML btx reads; `base` is where it starts in what the user
/// has, for the byte offsets of errors, `what` names it.
pub fn tree_xml(path: &Path, tree: &[u8], base: usize, what: &str) -> Result<String, Located> {
    let n = tree.len();
    let fb = Fb {
        b: tree,
        path,
        base,
    };
    let root = fb.indirect(0)?;
    let root_uid = fb
        .field(root, 0)?
        .map(|f| fb.u16(f))
        .transpose()?
        .unwrap_or(1);
    let kinds = model_kinds(&fb, root)?;
    let nodes = tree_nodes(&fb, root)?;
    // The instantiated XML: one <BehaviorTree> per subtree instance.
    let mut trees: Vec<String> = Vec::new();
    let mut main = String::new();
    let mut seen = std::collections::HashSet::new();
    element(
        root_uid, &nodes, &kinds, &mut trees, &mut main, &mut seen, 0,
    )
    .map_err(|m| {
        Located::file(
            path,
            format!("byte offset {base}: the {what} (a flatbuffer of {n} bytes there): {m}"),
        )
    })?;
    let mut xml =
        format!("<root><BehaviorTree ID=\"MainTree\" _fullpath=\"\">{main}</BehaviorTree>");
    for t in trees {
        xml.push_str(&t);
    }
    xml.push_str("</root>");
    Ok(xml)
}

/// The node models: each registration name's type (NodeModel:
/// registration_name (0), type (1)).
fn model_kinds(fb: &Fb, root: usize) -> Result<std::collections::HashMap<String, u8>, Located> {
    let mut kinds = std::collections::HashMap::new();
    for m in fb.vector(root, 2, 4, true)? {
        let name = fb.string(m, 0)?;
        let ty = fb.field(m, 1)?.map(|f| fb.u8(f)).transpose()?.unwrap_or(0);
        kinds.insert(name, ty);
    }
    Ok(kinds)
}

/// A node of the flatbuffer's tree.
struct FbNode {
    children: Vec<u16>,
    name: String,
    reg: String,
    ports: Vec<(String, String)>,
}

/// The tree's nodes by uid (TreeNode: uid (0), children_uid (1), status
/// (2), instance_name (3), registration_name (4), port_remaps (5)).
fn tree_nodes(fb: &Fb, root: usize) -> Result<std::collections::HashMap<u16, FbNode>, Located> {
    let mut nodes = std::collections::HashMap::new();
    for t in fb.vector(root, 1, 4, true)? {
        let uid = fb.field(t, 0)?.map(|f| fb.u16(f)).transpose()?.unwrap_or(0);
        let children = fb
            .vector(t, 1, 2, false)?
            .into_iter()
            .map(|p| fb.u16(p))
            .collect::<Result<_, _>>()?;
        let mut ports = Vec::new();
        for p in fb.vector(t, 5, 4, true)? {
            ports.push((fb.string(p, 0)?, fb.string(p, 1)?));
        }
        nodes.insert(
            uid,
            FbNode {
                children,
                name: fb.string(t, 3)?,
                reg: fb.string(t, 4)?,
                ports,
            },
        );
    }
    Ok(nodes)
}

/// Node `u` as an XML element of `out`, a subtree's nodes as a
/// <BehaviorTree> of its own in `trees`.
fn element(
    u: u16,
    nodes: &std::collections::HashMap<u16, FbNode>,
    kinds: &std::collections::HashMap<String, u8>,
    trees: &mut Vec<String>,
    out: &mut String,
    seen: &mut std::collections::HashSet<u16>,
    depth: usize,
) -> Result<(), String> {
    let n = nodes
        .get(&u)
        .ok_or_else(|| format!("the tree names node {u}, which it does not describe"))?;
    // A node reached twice would be a cycle, or a copy that multiplies
    // at every level.
    if !seen.insert(u) {
        return Err(format!("node {u} is the child of more than one node"));
    }
    if depth > 10_000 {
        return Err("the tree is nested too deep".into());
    }
    let ports: String = n
        .ports
        .iter()
        .map(|(k, v)| format!(" {}=\"{}\"", esc(k), esc(v)))
        .collect();
    if n.reg == "SubTree" || n.reg == "SubTreePlus" || kinds.get(&n.reg) == Some(&5) {
        let path = format!("{u}/{}", n.name);
        out.push_str(&format!(
            "<{} ID=\"{}\" _fullpath=\"{}\" _uid=\"{u}\"{ports}/>",
            n.reg,
            esc(&n.name),
            esc(&path)
        ));
        let mut sub = String::new();
        for &c in &n.children {
            element(c, nodes, kinds, trees, &mut sub, seen, depth + 1)?;
        }
        trees.push(format!(
            "<BehaviorTree ID=\"{}\" _fullpath=\"{}\">{sub}</BehaviorTree>",
            esc(&n.name),
            esc(&path)
        ));
        return Ok(());
    }
    let explicit = match kinds.get(&n.reg) {
        _ if crate::model::builtins::lookup(&n.reg).is_some() => None,
        Some(1) => Some("Action"),
        Some(2) => Some("Condition"),
        Some(3) => Some("Control"),
        Some(4) => Some("Decorator"),
        _ => Some("Action"),
    };
    let open = match explicit {
        Some(tag) => format!("{tag} ID=\"{}\"", esc(&n.reg)),
        None => n.reg.clone(),
    };
    let close = explicit.unwrap_or(&n.reg).to_string();
    out.push_str(&format!(
        "<{open} name=\"{}\" _uid=\"{u}\"{ports}",
        esc(&n.name)
    ));
    if n.children.is_empty() {
        out.push_str("/>");
    } else {
        out.push('>');
        for &c in &n.children {
            element(c, nodes, kinds, trees, out, seen, depth + 1)?;
        }
        out.push_str(&format!("</{close}>"));
    }
    Ok(())
}
