//! `btx log`: List the status transitions of a session, like Groot's table.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub session: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// Only this node's transitions.
    #[arg(long, value_name = "PICK")]
    pub node: Option<String>,
    /// Leave out transitions to IDLE (resets and halts).
    #[arg(long)]
    pub no_idle: bool,
    /// Keep printing transitions as the log grows (until interrupted); with --format json, one object a line.
    #[arg(long)]
    pub follow: bool,
    /// List the runs the log holds (a rosbag's goals, a .btlog's runs: each the root starting again after it completed), with their times and how each ended; --run N picks one.
    #[arg(long, conflicts_with_all = ["follow", "node"])]
    pub runs: bool,
    /// A time column first: the robot's clock at each transition, as the log recorded it (.btlog, .db3, .fbl, rosbags, runs kept by btx watch): `utc`, the time of day in UTC, `local`, in this machine's time zone (TZ), or `relative` (what `--time` alone gives), seconds since the run's first transition. JSON always has `time` and `time_us` (UTC) where they are known.
    #[arg(long, value_enum, value_name = "utc|local|relative", num_args = 0..=1, default_missing_value = "relative")]
    pub time: Option<TimeColumn>,
    /// Only the faults, each with what handles it and how that ended, as `btx watch` tells them as they happen.
    #[arg(long, conflicts_with_all = ["follow", "node", "no_idle", "runs"])]
    pub faults: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum TimeColumn {
    Utc,
    Local,
    Relative,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    if args.runs {
        return list_runs(&args, cli);
    }
    if args.faults {
        return list_faults(&args, cli);
    }
    if args.follow {
        follow(&args)
    } else {
        print(&args, cli)
    }
}

/// `--follow`: the log printed as it grows, until the run that writes it
/// ends.
fn follow(args: &Args) -> Result<(), Failure> {
    let session = &args.session;
    let opts = args.reading.options()?;
    // A session being recorded is `SESSION.partial` until the run
    // ends and it is renamed: follow it to its final name, then stop.
    let finished = session
        .to_str()
        .and_then(|p| p.strip_suffix(".partial"))
        .map(std::path::PathBuf::from);
    let mut f = btx::input::Follow::with(session, opts.clone());
    let mut grown = Grown::default();
    let started = std::time::Instant::now();
    let mut last = None;
    let mut last_error: Option<String> = None;
    loop {
        let mut done = false;
        if let Some(fin) = finished.as_ref().filter(|_| !session.exists()) {
            if !fin.exists() {
                fail!(
                    "{}: the session being followed is gone, and {} is not there either",
                    btx::text::path(session),
                    btx::text::path(fin)
                );
            }
            f = btx::input::Follow::with(fin, opts.clone());
            done = true;
        }
        let fresh = match f.poll() {
            Ok(Some(s)) => {
                last = Some(s);
                last_error = None;
                true
            }
            Ok(None) => false,
            // Caught mid-write: read again at the next poll; said
            // once, however many polls find it so.
            Err(e) if grown.printed() > 0 => {
                let said = e.to_string();
                if last_error.as_ref() != Some(&said) {
                    eprintln!("following: {said}");
                    last_error = Some(said);
                }
                false
            }
            Err(e) => return Err(located(e)),
        };
        // Rows held back (see `Grown`) are printed once the wait is
        // over, even if the log did not grow since.
        if let Some(s) = last.as_ref().filter(|_| fresh || grown.held()) {
            let only = match &args.node {
                Some(p) => Some(pick_node(&s.tree, p)?),
                None => None,
            };
            // As `btx watch`: the first rows wait at most 2 s.
            let settle = !done && started.elapsed().as_secs() < 2;
            grown.print(s, only, args.no_idle, args.format, settle);
        }
        if done {
            if let Some(fin) = &finished {
                eprintln!("the run ended: the session is now {}", btx::text::path(fin));
            }
            return Ok(());
        }
        std::thread::sleep(std::time::Duration::from_millis(250));
    }
}

/// The log printed once, written as it is read: a log of millions of
/// transitions is never held whole, in text or in JSON.
fn print(args: &Args, cli: &Globals) -> Result<(), Failure> {
    let session = &args.session;
    let opened = btx::input::open_to_print(session, &args.reading.options()?);
    let s: Box<dyn btx::export::Table> = match opened.map_err(located)? {
        Printable::Numbered(log) => log,
        Printable::Input(Input::Session(s)) => s,
        Printable::Input(Input::Tree { .. }) => fail!(
            "{} is a tree; btx log reads sessions and logs",
            btx::text::path(session)
        ),
    };
    warn_all(cli.quiet, s.warnings());
    let only = match &args.node {
        Some(p) => Some(pick_node(s.tree(), p)?),
        None => None,
    };
    let clock = clock_of(args.time, s.first_time_us(), session)?;
    let mut w = SafeOut::new();
    let done = match args.format {
        Format::Json => btx::export::write_log_json(&mut w, &*s, only, args.no_idle),
        Format::Text => write_text(&mut w, &*s, only, args.no_idle, clock),
    };
    w.finish(done);
    Ok(())
}

/// The log as Groot's table, a row a transition, with the clock's column
/// where one is asked for.
fn write_text(
    w: &mut SafeOut,
    s: &dyn btx::export::Table,
    only: Option<btx::model::Uid>,
    no_idle: bool,
    clock: Option<btx::export::Clock>,
) -> std::io::Result<()> {
    use std::io::Write;
    let head = clock.map_or(String::new(), |c| c.header());
    let mut r = w.write_all(format!("{head}{}", btx::export::LOG_TEXT_HEADER).as_bytes());
    let mut rows = btx::export::TextRows::new(s.tree());
    let mut text = String::new();
    s.each_row(only, no_idle, &mut |row| {
        if r.is_ok() {
            let cell = clock.map_or(String::new(), |c| c.cell(row.time_us));
            text.clear();
            rows.write(&mut text, &cell, &row);
            r = w.write_all(text.as_bytes());
        }
    });
    for g in s.trailing_gaps() {
        if r.is_ok() {
            r = w.write_all(format!("  --- gap: {g} ---\n").as_bytes());
        }
    }
    r
}

/// Standard output, buffered, through the sanitiser; a closed pipe ends
/// btx quietly (exit 0).
struct SafeOut(std::io::BufWriter<std::io::StdoutLock<'static>>);

impl SafeOut {
    fn new() -> SafeOut {
        SafeOut(std::io::BufWriter::with_capacity(
            1 << 16,
            std::io::stdout().lock(),
        ))
    }

    fn finish(mut self, r: std::io::Result<()>) {
        use std::io::Write;
        written(r.and_then(|()| self.0.flush()));
    }
}

impl std::io::Write for SafeOut {
    /// Each write is whole UTF-8 text (a row), so it is sanitised whole.
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match std::str::from_utf8(buf) {
            Ok(s) => self
                .0
                .write_all(btx::text::visible(s).as_bytes())
                .map(|()| buf.len()),
            Err(_) => self.0.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

/// A table printed as its run grows (`btx log --follow`, `btx watch`).
///
/// A log or a live run gives no tick for the ticks in which nothing
/// changed: they are counted from the time between ticks, measured over the
/// run so far. Early on that measure is poor, so the first rows wait for
/// `SETTLE_TICKS` ticks (while `settle` holds); and rows already printed
/// whose ticks come out otherwise later are said to have changed, never
/// silently.
#[derive(Default)]
struct Grown {
    header: bool,
    /// The tick of each row printed.
    ticks: Vec<u32>,
    /// The node and status of each row printed: a file that no longer
    /// starts with them was truncated or replaced.
    rows: Vec<(btx::Uid, btx::run::Status)>,
    /// The first rows are waiting for more ticks.
    held: bool,
}

/// Ticks a growing table waits for before its first rows.
const SETTLE_TICKS: usize = 8;

impl Grown {
    pub fn printed(&self) -> usize {
        self.ticks.len()
    }

    /// Whether rows wait to be printed though the run did not grow: print
    /// again once the wait is over.
    pub fn held(&self) -> bool {
        self.held
    }

    pub fn print(
        &mut self,
        s: &btx::session::Session,
        only: Option<btx::Uid>,
        no_idle: bool,
        format: Format,
        settle: bool,
    ) {
        // The rows printed are compared by node, status and tick on the
        // index, and only the new ones built and printed, a few thousand at
        // a time: following a run holds what `btx log` holds (its index),
        // not a row per transition.
        let (mut seen, mut replaced, mut renumbered) = (0usize, false, None);
        let mut ticks_seen = 0usize;
        let mut last_tick = None;
        for t in btx::export::log_transitions(s, only, no_idle) {
            if seen < self.rows.len() {
                replaced |= self.rows[seen] != (t.uid, t.status);
                if renumbered.is_none() && self.ticks[seen] != t.tick {
                    renumbered = Some((seen, t.tick));
                }
            }
            if last_tick != Some(t.tick) {
                ticks_seen += 1;
                last_tick = Some(t.tick);
            }
            seen += 1;
        }
        let changed = if replaced {
            Some("replaced by another run")
        } else if seen < self.rows.len() {
            Some("truncated or shrunk")
        } else {
            None
        };
        if let Some(why) = changed {
            eprintln!(
                "note: {} was {why}: its {} rows printed are not the start of what it holds now; following it again from its start",
                btx::text::path(&s.path),
                self.rows.len()
            );
            *self = Grown::default();
            renumbered = None;
        }
        if self.ticks.is_empty() && !self.header {
            self.held = settle && ticks_seen < SETTLE_TICKS;
            if self.held {
                return;
            }
        }
        if let Some((i, now)) = renumbered {
            eprintln!(
                "note: tick {} of the rows printed (from row {}) is tick {now} now, and so are those after it: ticks in which nothing changed are counted from the time between ticks, measured over more of the run; the session holds the new numbers",
                self.ticks[i],
                i + 1,
            );
            for (mine, t) in self
                .ticks
                .iter_mut()
                .zip(btx::export::log_transitions(s, only, no_idle))
            {
                *mine = t.tick;
            }
        }
        let printed = self.ticks.len();
        let mut chunk: Vec<btx::export::LogRow> = Vec::new();
        let mut k = 0;
        btx::export::each_log_row(s, only, no_idle, |r| {
            k += 1;
            if k <= printed {
                return;
            }
            chunk.push(r);
            if chunk.len() >= PRINT_CHUNK {
                self.print_rows(s, &std::mem::take(&mut chunk), format);
            }
        });
        self.print_rows(s, &chunk, format);
    }

    /// Prints rows after those printed, and keeps what is compared later.
    fn print_rows(
        &mut self,
        s: &btx::session::Session,
        new: &[btx::export::LogRow],
        format: Format,
    ) {
        if new.is_empty() {
            return;
        }
        let out = match format {
            Format::Json => btx::export::log_json_lines(s, new),
            Format::Text => {
                let t = btx::export::log_text(s, new);
                if self.header {
                    t.split_once('\n')
                        .map_or(String::new(), |x| x.1.to_string())
                } else {
                    self.header = true;
                    t
                }
            }
        };
        print!("{out}");
        self.ticks.extend(new.iter().map(|r| r.tick));
        self.rows.extend(new.iter().map(|r| (r.uid, r.status)));
    }
}

/// Rows a growing table prints at once.
const PRINT_CHUNK: usize = 4096;

/// `--runs`: one line (or JSON object) a run: its number, first and last
/// transition (UTC), ticks, transitions and how it ended.
fn list_runs(args: &Args, cli: &Globals) -> Result<(), Failure> {
    let mut w = SafeOut::new();
    btx::input::each_log_run(&args.session, &args.reading.options()?, |k, _, s| {
        use std::io::Write;
        if k == 1 {
            // Said once: the warnings every run shares. The header waits
            // for the first run, so that a log that cannot be read prints
            // its error alone.
            warn_all(cli.quiet, &s.warnings);
            if matches!(args.format, Format::Text) {
                let _ = w.write_all(
                    b" run  first transition (UTC)      last transition (UTC)       ticks  transitions  ended\n",
                );
            }
        }
        let t = s.index.transitions.len();
        let (first, last) = match s.span_us {
            Some((a, b)) => (btx::clock::utc(a), btx::clock::utc(b)),
            None => ("-".to_string(), "-".to_string()),
        };
        let ended = s.ending();
        let line = match args.format {
            Format::Text => format!(
                "{k:>4}  {first:<26}  {last:<26}  {:>5}  {t:>11}  {}\n",
                s.index.ticks(),
                btx::text::visible(&ended)
            ),
            Format::Json => format!(
                "{}\n",
                serde_json::json!({
                    "run": k,
                    "first": first,
                    "last": last,
                    "ticks": s.index.ticks(),
                    "transitions": t,
                    "root": s.end.as_ref().map(|e| e.1.as_str()),
                    "ended": ended,
                })
            ),
        };
        // A closed standard output stops the listing, quietly.
        let _ = w.write_all(line.as_bytes());
        Ok(())
    })?;
    Ok(())
}

/// `--time`'s column, for a run whose first transition was at `t0`.
fn clock_of(
    time: Option<TimeColumn>,
    t0: Option<i64>,
    session: &std::path::Path,
) -> Result<Option<btx::export::Clock>, Failure> {
    Ok(match (time, t0) {
        (None, _) => None,
        (Some(_), None) => fail!(
            "{}: no time is known for its transitions (a run btx simulated, a btcm log, a session written without them): --time shows the times a log or a watched robot gave",
            btx::text::path(session)
        ),
        (Some(TimeColumn::Utc), _) => Some(btx::export::Clock::Utc),
        (Some(TimeColumn::Local), Some(t0)) => Some(btx::export::Clock::Local(t0)),
        (Some(TimeColumn::Relative), Some(t0)) => Some(btx::export::Clock::Relative(t0)),
    })
}

/// `--faults`: the run's faults, as a watch would have told them.
fn list_faults(args: &Args, cli: &Globals) -> Result<(), Failure> {
    let s = match btx::input::open(&args.session, &args.reading.options()?).map_err(located)? {
        Input::Session(s) => *s,
        Input::Tree { .. } => fail!(
            "{} is a tree; btx log reads sessions and logs",
            btx::text::path(&args.session)
        ),
    };
    warn_all(cli.quiet, &s.warnings);
    let alerts = btx::explain::alerts::of_run(&s);
    let clock = clock_of(args.time, s.times_us.first().copied(), &args.session)?;
    let out = match args.format {
        Format::Text => alerts
            .iter()
            .map(|a| {
                let cell = clock.map_or(String::new(), |c| c.cell(a.time_us));
                format!("{cell}{}\n", a.text)
            })
            .collect::<String>(),
        Format::Json => {
            let v: Vec<serde_json::Value> = alerts
                .iter()
                .map(|a| btx::export::alert_json(&s.tree, a))
                .collect();
            serde_json::to_string_pretty(&serde_json::json!({
                "schema": "btx.faults/1",
                "session": btx::text::path(&s.path).to_string(),
                "events": v,
            }))
            .unwrap_or_default()
                + "\n"
        }
    };
    print!("{out}");
    Ok(())
}
