//! A rosbag2 SQLite storage file (`.db3`): its topics, where a file cut
//! short ends, and its `behavior_tree_log` messages in order.

use super::*;

/// Every topic of a `.db3` and its type.
pub(super) fn db3_topics(file: &Path) -> Result<Vec<(String, String)>, Located> {
    let sql = |e: rusqlite::Error| Located::file(file, format!("table topics: {e}"));
    let (conn, _copy) = crate::logs::db3::open_read_only(file)?;
    let mut st = conn
        .prepare("SELECT name, type FROM topics ORDER BY id")
        .map_err(sql)?;
    let rows = st
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .map_err(sql)?;
    rows.collect::<Result<_, _>>().map_err(sql)
}

/// Said of a `.db3` shorter than its header says (a copy or a disk that
/// ran out): read in the order written, up to its first page lost.
pub(super) fn db3_cut(m: &Matcher, len: u64, whole: u64) -> String {
    match m.records.last() {
        Some(r) => format!(
            "the bag's database ends at byte {len} of the {whole} its header says, after the change at {}: the file was cut short; read up to there",
            &crate::clock::utc(r.time_us)[11..]
        ),
        None => format!(
            "the bag's database ends at byte {len} of the {whole} its header says, before any message of Nav2's log: the file was cut short"
        ),
    }
}

/// The bytes of `.db3` messages given to the pool at a time.
const PIECE_BYTES: usize = 1 << 20;

/// The bag's log topic, and where it is cut short if it is.
pub(super) fn read_db3(
    file: &Path,
    m: &mut Matcher,
    want: Option<&str>,
) -> Result<(String, Option<String>), Located> {
    let fail = |m: String| Located::file(file, m);
    let cut = crate::logs::db3::cut_short(file);
    let note = cut.map_or(String::new(), |c| c.note());
    let sql = |what: &str, e: rusqlite::Error| fail(format!("{what}: {e}{note}"));
    let (conn, _copy) = crate::logs::db3::open_read_only(file)?;
    let topics: Vec<(i64, String, String)> = {
        let mut st = conn
            .prepare("SELECT id, name, type FROM topics")
            .map_err(|e| sql("table topics", e))?;
        let rows = st
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
            .map_err(|e| sql("table topics", e))?;
        rows.collect::<Result<_, _>>()
            .map_err(|e| sql("table topics", e))?
    };
    let topic = log_topic(
        file,
        topics.iter().map(|(_, n, t)| (n.as_str(), t.as_str())),
        want,
    )?;
    let id = topics.iter().find(|t| t.1 == topic).map_or(0, |t| t.0);
    // From Iron on, the bag keeps each type's definition.
    let definition: Option<String> = conn
        .query_row(
            "SELECT encoded_message_definition FROM message_definitions WHERE topic_type = ?1",
            [LOG_TYPE],
            |r| r.get(0),
        )
        .ok();
    // A file cut short has lost pages of the time index too: its rows are
    // read in the order the recorder wrote them, up to the cut.
    let order = if cut.is_some() { "id" } else { "timestamp, id" };
    let mut st = conn
        .prepare(&format!(
            "SELECT data FROM messages WHERE topic_id = ?1 ORDER BY {order}"
        ))
        .map_err(|e| sql("table messages", e))?;
    let said = |m: &Matcher, e: Option<rusqlite::Error>| match cut {
        Some(c) => db3_cut(m, c.len, c.whole),
        None => cut_short(m, &e.map_or(String::new(), |e| e.to_string())),
    };
    let mut rows = st.query([id]).map_err(|e| sql("table messages", e))?;
    let mut defs = None;
    let stop = messages(
        &mut rows,
        &mut defs,
        (&topic, definition.as_deref()),
        m,
        file,
    )?;
    match stop {
        None if defs.is_none() && cut.is_some() => return Err(fail(said(m, None))),
        None => {}
        // A page past the last one read is damaged: the rows before it
        // are the run so far.
        Some(e) if m.messages > 0 => return Ok((topic, Some(said(m, Some(e))))),
        Some(_) if defs.is_none() && cut.is_some() => return Err(fail(said(m, None))),
        Some(e) => return Err(sql("table messages", e)),
    }
    if defs.is_none() {
        // A definition that cannot be read is said even over no message.
        m.definitions(file, &topic, definition.as_deref(), None)?;
    }
    Ok((topic, cut.map(|_| said(m, None))))
}

/// The log's messages, row by row, to `m`: on this thread until they are
/// known plain, then on every core, a run of them a piece, joined in
/// order; the definition, the topic's and the bag's, read by the first
/// message. What stopped the rows early, if anything did.
fn messages(
    rows: &mut rusqlite::Rows,
    defs: &mut Option<LogDefs>,
    (topic, definition): (&str, Option<&str>),
    m: &mut Matcher,
    file: &Path,
) -> Result<Option<rusqlite::Error>, Located> {
    // Messages read on every core once they are known plain, a run of
    // them a piece, joined in order.
    let mut pool: Option<pool::Pool> = None;
    let mut piece = (Vec::new(), Vec::new());
    let join =
        |piece: pool::Piece, read: Option<pool::Read>, defs: &LogDefs, m: &mut Matcher| match (
            read, piece,
        ) {
            _ if m.full() => Ok(()),
            (Some(read), _) => {
                m.join(read);
                Ok(())
            }
            (None, pool::Piece::Messages(bytes, ends)) => {
                let mut from = 0;
                for end in ends {
                    m.message(defs, &bytes[from..end])?;
                    if m.full() {
                        break;
                    }
                    from = end;
                }
                Ok(())
            }
            (None, pool::Piece::Chunk(..)) => Ok(()),
        };
    let stop = loop {
        // Each row's blob read where SQLite holds it, not copied (but
        // into a piece for the pool).
        let row = rows.next().and_then(|r| match r {
            Some(r) => r.get_ref(0).map(Some),
            None => Ok(None),
        });
        let data = match row {
            Ok(Some(v)) => v.as_blob().unwrap_or_default(),
            Ok(None) => break None,
            Err(e) => break Some(e),
        };
        if defs.is_none() {
            *defs = Some(m.definitions(file, topic, definition, Some(data))?);
        }
        let Some(d) = &*defs else { continue };
        if pool.is_none() {
            pool = m.layout(d, 0).and_then(|l| pool::Pool::start(l, file));
        }
        let Some(p) = &mut pool else {
            m.message(d, data)?;
            if m.full() {
                break None;
            }
            continue;
        };
        piece.0.extend_from_slice(data);
        piece.1.push(piece.0.len());
        if piece.0.len() >= PIECE_BYTES {
            let given =
                pool::Piece::Messages(std::mem::take(&mut piece.0), std::mem::take(&mut piece.1));
            p.give(given, &mut |p, r| join(p, r, d, m))?;
            if m.full() {
                break None;
            }
        }
    };
    if let (Some(mut p), Some(d)) = (pool.take(), &*defs) {
        if !piece.1.is_empty() {
            p.give(pool::Piece::Messages(piece.0, piece.1), &mut |p, r| {
                join(p, r, d, m)
            })?;
        }
        p.finish(&mut |p, r| join(p, r, d, m))?;
    }
    Ok(stop)
}
