//! BehaviorTree.CPP 4's FileLogger2 `.btlog`: the magic, a version byte,
//! the instantiated tree's XML, t0, then 9-byte records (48-bit µs since
//! t0, 16-bit uid, status byte).

use crate::run::Status;
use crate::source::Located;
use std::path::Path;

pub const MAGIC: &[u8] = b"BTCPP4-FileLogger2";

/// One record of a log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Record {
    /// Microseconds since the epoch.
    pub time_us: i64,
    pub uid: u32,
    pub status: Status,
    /// Byte offset of the record in the file.
    pub offset: usize,
}

#[derive(Debug, Clone)]
pub struct RawLog {
    pub xml: String,
    pub t0_us: i64,
    /// The records, as columns: a `Record` a transition held 24 bytes where
    /// these hold 12, and a record's offset is `first + 9 × its index`.
    pub records: Columns,
    /// The first record's byte offset.
    pub first: usize,
    /// Bytes at the end that are not a whole record (a log still being written).
    pub partial_tail: usize,
}

/// A log's records as columns: each one's uid and status in 4 bytes
/// (`pack`), and its time (µs since the epoch).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Columns {
    pub moves: Vec<u32>,
    pub times: Vec<i64>,
}

/// Uids below this pack with a status in 4 bytes (BehaviorTree.CPP's are
/// 16-bit).
pub const PACKED_UID_MAX: u32 = (1 << 29) - 1;

/// A uid (at most `PACKED_UID_MAX`) and a status in 4 bytes.
pub fn pack(uid: u32, status: Status) -> u32 {
    debug_assert!(uid <= PACKED_UID_MAX);
    uid | u32::from(status.code()) << 29
}

pub fn unpack(m: u32) -> (u32, Status) {
    let status = Status::from_code((m >> 29) as u8).expect("a status packed by number");
    (m & PACKED_UID_MAX, status)
}

impl Columns {
    /// Records as columns; their uids must pack (checked by the caller).
    pub fn of(records: &[Record]) -> Columns {
        Columns {
            moves: records.iter().map(|r| pack(r.uid, r.status)).collect(),
            times: records.iter().map(|r| r.time_us).collect(),
        }
    }

    pub fn len(&self) -> usize {
        self.moves.len()
    }

    pub fn is_empty(&self) -> bool {
        self.moves.is_empty()
    }

    pub fn view(&self) -> Packed<'_> {
        Packed {
            moves: &self.moves,
            times: &self.times,
        }
    }
}

/// Columns borrowed, or a part of them.
#[derive(Debug, Clone, Copy)]
pub struct Packed<'a> {
    pub moves: &'a [u32],
    pub times: &'a [i64],
}

impl<'a> Packed<'a> {
    pub fn len(&self) -> usize {
        self.moves.len()
    }

    pub fn is_empty(&self) -> bool {
        self.moves.is_empty()
    }

    pub fn key(&self, i: usize) -> Option<(u32, Status)> {
        self.moves.get(i).map(|&m| unpack(m))
    }

    pub fn part(&self, r: std::ops::Range<usize>) -> Packed<'a> {
        Packed {
            moves: &self.moves[r.clone()],
            times: &self.times[r],
        }
    }
}

fn at(path: &Path, offset: usize, msg: impl std::fmt::Display) -> Located {
    Located::file(path, format!("byte offset {offset}: {msg}"))
}

/// How many bytes of a `.btlog` come before its first record, from its
/// first 23 (the magic, the version and the XML's length): None where
/// they are no `.btlog`'s.
pub fn records_start(head: &[u8]) -> Option<usize> {
    if !head.starts_with(MAGIC) {
        return None;
    }
    let n = i32::from_le_bytes(head.get(19..23)?.try_into().ok()?);
    usize::try_from(n).ok().map(|n| 31 + n)
}

/// A `.btlog`, or the start of one cut inside its magic.
pub fn is_btlog(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC) || (bytes.len() >= 6 && MAGIC.starts_with(bytes))
}

pub fn parse(path: &Path, bytes: &[u8]) -> Result<RawLog, Located> {
    if bytes.len() < MAGIC.len() && MAGIC.starts_with(bytes) {
        return Err(at(
            path,
            bytes.len(),
            "the file ends inside the .btlog's magic (BTCPP4-FileLogger2): a log cut short",
        ));
    }
    if !bytes.starts_with(MAGIC) {
        return Err(at(
            path,
            0,
            "not a .btlog: it does not start with BTCPP4-FileLogger2",
        ));
    }
    let v = *bytes
        .get(18)
        .ok_or_else(|| at(path, 18, "the file ends before the version byte"))?;
    if v != 1 {
        return Err(at(
            path,
            18,
            format!("FileLogger2 protocol {v} is not one btx reads (it reads 1)"),
        ));
    }
    let len_bytes = bytes
        .get(19..23)
        .ok_or_else(|| at(path, 19, "the file ends inside the XML length"))?;
    let n = i32::from_le_bytes(len_bytes.try_into().expect("4 bytes"));
    if n < 0 || 23 + n as usize > bytes.len() {
        return Err(at(
            path,
            19,
            format!(
                "the XML length {n} runs past the end of the file ({} bytes)",
                bytes.len()
            ),
        ));
    }
    let n = n as usize;
    let xml = std::str::from_utf8(&bytes[23..23 + n])
        .map_err(|e| at(path, 23 + e.valid_up_to(), "the embedded XML is not UTF-8"))?
        .to_string();
    let t0_bytes = bytes
        .get(23 + n..31 + n)
        .ok_or_else(|| at(path, 23 + n, "the file ends inside t0"))?;
    let t0_us = i64::from_le_bytes(t0_bytes.try_into().expect("8 bytes"));
    let first = 31 + n;
    let whole = (bytes.len() - first) / 9;
    let mut records = Columns {
        moves: crate::pages::with_capacity(whole),
        times: crate::pages::with_capacity(whole),
    };
    for (k, r) in bytes[first..first + 9 * whole].chunks_exact(9).enumerate() {
        let mut dt = [0u8; 8];
        dt[..6].copy_from_slice(&r[..6]);
        let dt = u64::from_le_bytes(dt) as i64;
        let uid = u16::from_le_bytes([r[6], r[7]]) as u32;
        let status = Status::from_code(r[8]).ok_or_else(|| {
            at(
                path,
                first + 9 * k + 8,
                format!("status byte {} is not a status (0 to 4)", r[8]),
            )
        })?;
        records.moves.push(pack(uid, status));
        records.times.push(t0_us.saturating_add(dt));
    }
    Ok(RawLog {
        xml,
        t0_us,
        records,
        first,
        partial_tail: bytes.len() - first - 9 * whole,
    })
}

/// A `.btlog`'s records again and again, each time later.
#[cfg(test)]
pub(crate) fn repeated(bytes: &[u8], times: usize) -> Vec<u8> {
    let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
    let (head, body) = bytes.split_at(31 + n);
    let span = u64::from_le_bytes(
        [&body[body.len() - 9..body.len() - 3], &[0, 0][..]]
            .concat()
            .try_into()
            .unwrap(),
    ) + 100_000;
    let mut out = head.to_vec();
    for k in 0..times as u64 {
        for r in body.chunks_exact(9) {
            let dt = u64::from_le_bytes([&r[..6], &[0, 0][..]].concat().try_into().unwrap());
            out.extend_from_slice(&(dt + k * span).to_le_bytes()[..6]);
            out.extend_from_slice(&r[6..]);
        }
    }
    out
}

/// Every recorded `.btlog` of the fixtures, in order.
#[cfg(test)]
pub(crate) fn fixture_logs() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/logs");
    let mut logs: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "btlog"))
        .collect();
    logs.sort();
    assert!(logs.len() >= 8, "{logs:?}");
    logs
}
