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
    pub records: Vec<Record>,
    /// Bytes at the end that are not a whole record (a log still being written).
    pub partial_tail: usize,
}

fn at(path: &Path, offset: usize, msg: impl std::fmt::Display) -> Located {
    Located::file(path, format!("byte offset {offset}: {msg}"))
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
    let mut records = Vec::with_capacity((bytes.len() - 31 - n) / 9);
    let mut off = 31 + n;
    while off + 9 <= bytes.len() {
        let r = &bytes[off..off + 9];
        let mut dt = [0u8; 8];
        dt[..6].copy_from_slice(&r[..6]);
        let dt = u64::from_le_bytes(dt) as i64;
        let uid = u16::from_le_bytes([r[6], r[7]]) as u32;
        let status = Status::from_code(r[8]).ok_or_else(|| {
            at(
                path,
                off + 8,
                format!("status byte {} is not a status (0 to 4)", r[8]),
            )
        })?;
        records.push(Record {
            time_us: t0_us.saturating_add(dt),
            uid,
            status,
            offset: off,
        });
        off += 9;
    }
    Ok(RawLog {
        xml,
        t0_us,
        records,
        partial_tail: bytes.len() - off,
    })
}
