//! A rosbag2 MCAP storage file: its channels, and its `behavior_tree_log`
//! messages read a chunk at a time.

use super::*;

/// An MCAP chunk decompresses to at most this (rosbag2 writes chunks of
/// about 768 KiB): a chunk that claims more is refused before it is
/// decompressed.
pub const MCAP_CHUNK_MAX: u64 = 256 << 20;

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
            Record::Chunk { header, data } if header.uncompressed_size <= MCAP_CHUNK_MAX => {
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
pub(super) fn read_mcap(
    file: &Path,
    m: &mut Matcher,
    want: Option<&str>,
) -> Result<(String, Option<String>), Located> {
    use mcap::records::Record;
    let mut st = McapLog {
        file,
        want,
        schemas: Default::default(),
        topics: Vec::new(),
        log: None,
        defs: None,
    };
    let mut ended = false;
    let (len, error) = mcap_records(file, |rec| {
        match rec {
            Record::Chunk { header, data } => {
                if header.uncompressed_size > MCAP_CHUNK_MAX {
                    return Err(Located::file(
                        file,
                        format!(
                            "an MCAP chunk claims {} bytes decompressed, more than the {} MiB btx reads in one chunk (rosbag2 writes chunks of about 768 KiB)",
                            header.uncompressed_size,
                            MCAP_CHUNK_MAX >> 20
                        ),
                    ));
                }
                let inner = mcap::read::ChunkReader::new(header, &data)
                    .map_err(|e| Located::file(file, format!("MCAP chunk: {e}")))?;
                for r in inner {
                    let r = r.map_err(|e| Located::file(file, format!("MCAP chunk: {e}")))?;
                    st.take(r, m)?;
                    if m.full() {
                        break;
                    }
                }
            }
            Record::DataEnd(_) | Record::Footer(_) => ended = true,
            r => st.take(r, m)?,
        }
        Ok(!m.full() && !ended)
    })?;
    if m.full() {
        return Ok((st.topic()?, None));
    }
    let cut = match error {
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

/// An MCAP file's records in order, as its specification describes for a
/// file with no summary, read a piece at a time (the bag is never held
/// whole: a chunk at most, with its records), chunks given whole to `take`
/// until it says stop. The file's length, and the error a cut file (a
/// recorder killed) ends in, if any.
pub(super) fn mcap_records(
    file: &Path,
    mut take: impl FnMut(mcap::records::Record<'_>) -> Result<bool, Located>,
) -> Result<(u64, Option<String>), Located> {
    use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
    use std::io::Read;
    let len = crate::source::check_input(file, crate::source::INPUT_SIZE_MAX, "the bag")?;
    let cannot = |e: std::io::Error| Located::file(file, format!("cannot read the bag: {e}"));
    let mut f = std::fs::File::open(file).map_err(cannot)?;
    let options = LinearReaderOptions::default()
        .with_skip_end_magic(true)
        .with_emit_chunks(true)
        // A chunk's compressed bytes: past what it may decompress to, and
        // a margin, a length is a broken file, not an allocation.
        .with_record_length_limit((MCAP_CHUNK_MAX + (1 << 20)) as usize);
    let mut reader = LinearReader::new_with_options(options);
    let mut read_any = false;
    while let Some(event) = reader.next_event() {
        match event {
            Ok(LinearReadEvent::ReadRequest(need)) => {
                let n = f.read(reader.insert(need.max(1 << 16))).map_err(cannot)?;
                reader.notify_read(n);
            }
            Ok(LinearReadEvent::Record { opcode, data }) => {
                let record = match mcap::parse_record(opcode, data) {
                    Ok(r) => r,
                    Err(e) => return Ok((len, Some(e.to_string()))),
                };
                read_any = true;
                if !take(record)? {
                    return Ok((len, None));
                }
            }
            Err(mcap::McapError::BadMagic) if !read_any => {
                return Err(Located::file(
                    file,
                    format!("not a readable MCAP file: {}", mcap::McapError::BadMagic),
                ))
            }
            Err(e) => return Ok((len, Some(e.to_string()))),
        }
    }
    Ok((len, None))
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
