//! An MCAP chunk record, read from where it lies in the bag by whichever
//! thread reads it.

use std::borrow::Cow;

/// An MCAP chunk decompresses to at most this (rosbag2 writes chunks of
/// about 768 KiB): a chunk that claims more is refused before it is
/// decompressed.
pub const MCAP_CHUNK_MAX: u64 = 256 << 20;

/// Why a chunk record's bytes are not a chunk to read.
pub(super) enum Unread {
    /// Not a chunk record: the file cannot be read past it.
    Broken(String),
    /// A chunk that claims to decompress to this many bytes.
    TooBig(u64),
}

/// `len` bytes of `bag` from `at` into `buf`, which keeps its room from
/// one read to the next.
pub(super) fn read_at(
    bag: &std::fs::File,
    at: u64,
    len: usize,
    buf: &mut Vec<u8>,
) -> std::io::Result<()> {
    use std::os::unix::fs::FileExt;
    if buf.len() < len {
        buf.resize(len, 0);
    }
    bag.read_exact_at(&mut buf[..len], at)
}

/// A chunk record's header and records, as its bytes hold them.
pub(super) fn open(bytes: &[u8]) -> Result<(mcap::records::ChunkHeader, Cow<'_, [u8]>), Unread> {
    use mcap::records::Record;
    match mcap::parse_record(mcap::records::op::CHUNK, bytes) {
        Ok(Record::Chunk { header, .. }) if header.uncompressed_size > MCAP_CHUNK_MAX => {
            Err(Unread::TooBig(header.uncompressed_size))
        }
        Ok(Record::Chunk { header, data }) => Ok((header, data)),
        Ok(_) => Err(Unread::Broken("not a chunk".into())),
        Err(e) => Err(Unread::Broken(e.to_string())),
    }
}
