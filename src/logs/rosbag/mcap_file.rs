//! A rosbag2 MCAP storage file: its channels, and its `behavior_tree_log`
//! messages read a chunk at a time.

use super::*;
use std::sync::Arc;

pub(super) fn is_mcap(file: &Path) -> bool {
    std::fs::File::open(file)
        .and_then(|mut f| {
            let mut h = [0u8; 8];
            std::io::Read::read_exact(&mut f, &mut h).map(|()| h)
        })
        .is_ok_and(|h| h == MCAP_MAGIC)
}

/// Every topic of an MCAP and its type: from its summary, or else from
/// its channels in order (as far as the file is whole).
pub(super) fn mcap_topics(file: &Path) -> Result<Vec<(String, String)>, Located> {
    use mcap::records::Record;
    let bytes = crate::source::read_input(file, crate::source::INPUT_SIZE_MAX, "the bag")?;
    let name_of = |schema: Option<&std::sync::Arc<mcap::Schema>>| {
        schema.map_or(String::new(), |s| s.name.clone())
    };
    if let Ok(Some(summary)) = mcap::Summary::read(&bytes) {
        if !summary.channels.is_empty() {
            let mut ch: Vec<_> = summary.channels.values().collect();
            ch.sort_by_key(|c| c.id);
            return Ok(ch
                .into_iter()
                .map(|c| (c.topic.clone(), name_of(c.schema.as_ref())))
                .collect());
        }
    }
    let reader = mcap::read::LinearReader::new_with_options(
        &bytes,
        mcap::read::Options::IgnoreEndMagic.into(),
    )
    .map_err(|e| Located::file(file, format!("not a readable MCAP file: {e}")))?;
    let mut schemas = std::collections::HashMap::new();
    let mut topics = Vec::new();
    let mut take = |r: Record| match r {
        Record::Schema { header, .. } => {
            schemas.insert(header.id, header.name);
        }
        Record::Channel(c) => {
            let ty = schemas.get(&c.schema_id).cloned().unwrap_or_default();
            topics.push((c.topic, ty));
        }
        _ => {}
    };
    for rec in reader {
        // Past a cut, the topics before it are the bag's (`read` says the cut).
        let Ok(rec) = rec else { break };
        match rec {
            Record::Chunk { header, data } if header.uncompressed_size <= chunk::MCAP_CHUNK_MAX => {
                let Ok(inner) = mcap::read::ChunkReader::new(header, &data) else {
                    break;
                };
                for r in inner.map_while(Result::ok) {
                    take(r);
                }
            }
            Record::DataEnd(_) | Record::Footer(_) => break,
            r => take(r),
        }
    }
    Ok(topics)
}

/// An MCAP file read in order, record by record, as its specification
/// describes for a file with no summary: a file cut short (a recorder
/// killed) is read up to its last whole record, and what follows is said.
/// Once the log's messages are known plain, its chunks are read on every
/// core (`pool`), joined in the file's order.
pub(super) fn read_mcap(
    file: &Path,
    m: &mut Matcher,
    want: Option<&str>,
) -> Result<(String, Option<String>), Located> {
    let mut st = McapLog {
        file,
        want,
        schemas: Default::default(),
        topics: Vec::new(),
        log: None,
        defs: None,
        cut: None,
    };
    let mut reading = Reading {
        pool: None,
        ended: false,
    };
    let (len, error) = mcap_records(file, |rec, bag| reading.record(rec, bag, &mut st, m))?;
    reading.finish(&mut st, m)?;
    let ended = reading.ended;
    if m.full() {
        return Ok((st.topic()?, None));
    }
    let cut = match st.cut.take().or(error) {
        Some(e) => Some(cut_short(m, &e)),
        None if !ended => Some(cut_short(m, "")),
        None => None,
    };
    // Where: the file's end, a byte offset the user can check.
    let cut = cut.map(|c| format!("byte offset {len}: {c}"));
    if let (Some(c), 0) = (&cut, m.messages) {
        // Nothing whole to read: the cut is what there is to say.
        return Err(Located::file(file, c.clone()));
    }
    Ok((st.topic()?, cut))
}

/// Where reading an MCAP is: its chunks given to the pool, if one is
/// started; its end reached.
struct Reading {
    pool: Option<pool::Pool>,
    ended: bool,
}

impl Reading {
    /// One record, in the file's order; whether to read on.
    fn record(
        &mut self,
        rec: McapRecord,
        bag: &Arc<std::fs::File>,
        st: &mut McapLog,
        m: &mut Matcher,
    ) -> Result<bool, Located> {
        use mcap::records::Record;
        match rec {
            McapRecord::Chunk { at, len } => {
                if self.pool.is_none() {
                    // Once the log's messages are known plain.
                    let layout = st.defs.as_ref().zip(st.log.as_ref());
                    self.pool = layout
                        .and_then(|(d, l)| m.layout(d, l.id))
                        .and_then(|l| pool::Pool::start(l, st.file));
                }
                match &mut self.pool {
                    Some(p) => p.give(pool::Piece::Chunk(bag.clone(), at, len), &mut |p, r| {
                        join(p, r, st, m)
                    })?,
                    None => chunk(bag, at, len, st, m)?,
                }
            }
            // Indexes, statistics, attachments: nothing of the log.
            McapRecord::Other(
                Record::MessageIndex(_)
                | Record::ChunkIndex(_)
                | Record::Statistics(_)
                | Record::Attachment { .. }
                | Record::AttachmentIndex(_)
                | Record::Metadata(_)
                | Record::MetadataIndex(_)
                | Record::SummaryOffset(_),
            ) => {}
            McapRecord::Other(r) => {
                // In the bag's order: every chunk before it first.
                self.finish(st, m)?;
                match r {
                    _ if st.cut.is_some() => {}
                    Record::DataEnd(_) | Record::Footer(_) => self.ended = true,
                    r => st.take(r, m)?,
                }
            }
        }
        Ok(!m.full() && !self.ended && st.cut.is_none())
    }

    /// Every chunk given out joined.
    fn finish(&mut self, st: &mut McapLog, m: &mut Matcher) -> Result<(), Located> {
        match self.pool.take() {
            Some(mut p) => p.finish(&mut |p, r| join(p, r, st, m)),
            None => Ok(()),
        }
    }
}

/// A chunk back from the pool: its records, or, where a worker could not
/// read it, the chunk read here.
fn join(
    piece: pool::Piece,
    read: Option<pool::Read>,
    st: &mut McapLog,
    m: &mut Matcher,
) -> Result<(), Located> {
    match (read, piece) {
        _ if m.full() || st.cut.is_some() => Ok(()),
        (Some(read), _) => {
            m.join(read);
            Ok(())
        }
        (None, pool::Piece::Chunk(bag, at, len)) => chunk(&bag, at, len, st, m),
        (None, pool::Piece::Messages(..)) => Ok(()),
    }
}

/// A chunk's records, read in order on this thread. A chunk that is not
/// one is where the file stops being readable (`McapLog::cut`).
fn chunk(
    bag: &std::fs::File,
    at: u64,
    len: usize,
    st: &mut McapLog,
    m: &mut Matcher,
) -> Result<(), Located> {
    let file = st.file;
    let mut bytes = Vec::new();
    chunk::read_at(bag, at, len, &mut bytes)
        .map_err(|e| Located::file(file, format!("cannot read the bag: {e}")))?;
    let (header, data) = match chunk::open(&bytes[..len]) {
        Ok(c) => c,
        Err(chunk::Unread::Broken(why)) => {
            st.cut = Some(why);
            return Ok(());
        }
        Err(chunk::Unread::TooBig(size)) => {
            return Err(Located::file(
                file,
                format!(
                    "an MCAP chunk claims {size} bytes decompressed, more than the {} MiB btx reads in one chunk (rosbag2 writes chunks of about 768 KiB)",
                    chunk::MCAP_CHUNK_MAX >> 20
                ),
            ))
        }
    };
    let inner = mcap::read::ChunkReader::new(header, &data)
        .map_err(|e| Located::file(file, format!("MCAP chunk: {e}")))?;
    for r in inner {
        let r = r.map_err(|e| Located::file(file, format!("MCAP chunk: {e}")))?;
        st.take(r, m)?;
        if m.full() {
            break;
        }
    }
    Ok(())
}

/// A record of an MCAP as its file holds it: a chunk by where its bytes
/// lie, so that any thread can read it, any other read.
pub(super) enum McapRecord<'a> {
    Chunk { at: u64, len: usize },
    Other(mcap::records::Record<'a>),
}

/// An MCAP file's records in order, as its specification describes for a
/// file with no summary: an opcode, a length, that many bytes. The bag is
/// never held whole: a chunk is given as where it lies, any other record
/// read. Given to `take` until it says stop. The file's length, and why a
/// cut file (a recorder killed) stops where it does, if it does.
pub(super) fn mcap_records(
    file: &Path,
    mut take: impl FnMut(McapRecord<'_>, &Arc<std::fs::File>) -> Result<bool, Located>,
) -> Result<(u64, Option<String>), Located> {
    use std::io::{Read, Seek, SeekFrom};
    let len = crate::source::check_input(file, crate::source::INPUT_SIZE_MAX, "the bag")?;
    let cannot = |e: std::io::Error| Located::file(file, format!("cannot read the bag: {e}"));
    let bag = Arc::new(std::fs::File::open(file).map_err(cannot)?);
    let mut f = std::io::BufReader::with_capacity(1 << 16, &*bag);
    let mut magic = [0u8; 8];
    if f.read_exact(&mut magic).is_err() || magic != *MCAP_MAGIC {
        return Err(Located::file(
            file,
            format!("not a readable MCAP file: {}", mcap::McapError::BadMagic),
        ));
    }
    // A chunk's compressed bytes: past what it may decompress to, and a
    // margin, a length is a broken file, not an allocation.
    let limit = chunk::MCAP_CHUNK_MAX + (1 << 20);
    let mut at = 8u64;
    let mut bytes = Vec::new();
    loop {
        // A record's opcode and length, then its bytes: a file that ends
        // inside one was cut there.
        let mut head = [0u8; 9];
        if len - at < 9 {
            return Ok((len, None));
        }
        f.read_exact(&mut head).map_err(cannot)?;
        let n = u64::from_le_bytes(head[1..].try_into().expect("8 bytes"));
        if n > limit {
            return Ok((
                len,
                Some(format!("record length {n} exceeds limit {limit}")),
            ));
        }
        if len - at - 9 < n {
            return Ok((len, None));
        }
        let body = at + 9;
        at = body + n;
        let go = if head[0] == mcap::records::op::CHUNK {
            f.seek(SeekFrom::Start(at)).map_err(cannot)?;
            take(
                McapRecord::Chunk {
                    at: body,
                    len: n as usize,
                },
                &bag,
            )?
        } else {
            bytes.resize(n as usize, 0);
            f.read_exact(&mut bytes).map_err(cannot)?;
            match mcap::parse_record(head[0], &bytes) {
                Ok(r) => take(McapRecord::Other(r), &bag)?,
                Err(e) => return Ok((len, Some(e.to_string()))),
            }
        };
        if !go {
            return Ok((len, None));
        }
    }
}

/// What an MCAP's records said so far: schemas, channels, the log's.
pub(super) struct McapLog<'a> {
    pub(super) file: &'a Path,
    pub(super) want: Option<&'a str>,
    /// By id: name, encoding, text.
    pub(super) schemas: std::collections::HashMap<u16, (String, String, Vec<u8>)>,
    /// Every topic and its type, in the order they came.
    pub(super) topics: Vec<(String, String)>,
    /// The log's channel, and its definitions once its first message came.
    pub(super) log: Option<LogChannel>,
    pub(super) defs: Option<LogDefs>,
    /// Why the file cannot be read past a chunk, where one is not one.
    pub(super) cut: Option<String>,
}

pub(super) struct LogChannel {
    pub(super) id: u16,
    pub(super) topic: String,
    /// Its schema's text, where the bag carries one.
    pub(super) text: Option<String>,
}

impl McapLog<'_> {
    fn take(&mut self, r: mcap::records::Record, m: &mut Matcher) -> Result<(), Located> {
        use mcap::records::Record;
        match r {
            Record::Schema { header, data } => {
                self.schemas
                    .insert(header.id, (header.name, header.encoding, data.into_owned()));
            }
            Record::Channel(c) => {
                let ty = self
                    .schemas
                    .get(&c.schema_id)
                    .map_or(String::new(), |s| s.0.clone());
                if self.topics.iter().any(|(n, _)| *n == c.topic) {
                    return Ok(());
                }
                self.topics.push((c.topic.clone(), ty.clone()));
                if !is_log(&c.topic, &ty) {
                    return Ok(());
                }
                let chosen = match self.want {
                    Some(w) => w == c.topic,
                    None if self.log.is_none() => true,
                    None => {
                        let logs: Vec<&str> = self
                            .topics
                            .iter()
                            .filter(|(n, t)| is_log(n, t))
                            .map(|(n, _)| n.as_str())
                            .collect();
                        return Err(several(self.file, &logs));
                    }
                };
                if chosen {
                    let text = self
                        .schemas
                        .get(&c.schema_id)
                        .filter(|s| s.1 == "ros2msg")
                        .map(|s| String::from_utf8_lossy(&s.2).into_owned());
                    self.log = Some(LogChannel {
                        id: c.id,
                        topic: c.topic,
                        text,
                    });
                }
            }
            Record::Message { header, data } => {
                let Some(log) = &self.log else {
                    return Ok(());
                };
                if header.channel_id != log.id {
                    return Ok(());
                }
                if self.defs.is_none() {
                    let defs =
                        m.definitions(self.file, &log.topic, log.text.as_deref(), Some(&data))?;
                    self.defs = Some(defs);
                }
                if let Some(d) = &self.defs {
                    m.message(d, &data)?;
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// The log's topic, or why there is none.
    fn topic(&self) -> Result<String, Located> {
        match &self.log {
            Some(l) => Ok(l.topic.clone()),
            None => log_topic(
                self.file,
                self.topics.iter().map(|(n, t)| (n.as_str(), t.as_str())),
                self.want,
            ),
        }
    }
}
