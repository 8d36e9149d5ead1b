//! `btx log`: List the status transitions of a session, like Groot's table.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub session: PathBuf,
    /// Only this node's transitions.
    #[arg(long, value_name = "PICK")]
    pub node: Option<String>,
    /// Leave out transitions to IDLE (resets and halts).
    #[arg(long)]
    pub no_idle: bool,
    /// Keep printing transitions as the log grows (until interrupted); with --format json, one object a line.
    #[arg(long)]
    pub follow: bool,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    match args {
        Args {
            session,
            node,
            no_idle,
            follow: true,
            format,
        } => {
            // A session being recorded is `SESSION.partial` until the run
            // ends and it is renamed: follow it to its final name, then stop.
            let finished = session
                .to_str()
                .and_then(|p| p.strip_suffix(".partial"))
                .map(std::path::PathBuf::from);
            let mut f = btx::input::Follow::new(&session);
            let mut printed = 0usize;
            let mut header = false;
            loop {
                let mut done = false;
                if let Some(fin) = finished.as_ref().filter(|_| !session.exists()) {
                    if !fin.exists() {
                        fail!(
                            "{}: the session being followed is gone, and {} is not there either",
                            session.display(),
                            fin.display()
                        );
                    }
                    f = btx::input::Follow::new(fin);
                    done = true;
                }
                match f.poll() {
                    Ok(Some(s)) => {
                        let only = match &node {
                            Some(p) => Some(pick_node(&s.tree, p)?),
                            None => None,
                        };
                        print_grown(&s, only, no_idle, format, &mut printed, &mut header);
                    }
                    Ok(None) => {}
                    // Caught mid-write: read again at the next poll.
                    Err(e) if printed > 0 => eprintln!("following: {e}"),
                    Err(e) => return Err(located(e)),
                }
                if done {
                    if let Some(fin) = &finished {
                        eprintln!("the run ended: the session is now {}", fin.display());
                    }
                    return Ok(());
                }
                std::thread::sleep(std::time::Duration::from_millis(250));
            }
        }
        Args {
            session,
            node,
            no_idle,
            follow: false,
            format,
        } => {
            let s = match btx::input::open(&session, &LoadOptions::default())? {
                Input::Session(s) => *s,
                Input::Tree { .. } => fail!(
                    "{} is a tree; btx log reads sessions and logs",
                    session.display()
                ),
            };
            warn_all(cli.quiet, &s.warnings);
            let only = match &node {
                Some(p) => Some(pick_node(&s.tree, p)?),
                None => None,
            };
            // Written as it is read: a log of millions of transitions is
            // never held whole, in text or in JSON.
            let mut w = SafeOut::new();
            let done = match format {
                Format::Json => btx::export::write_log_json(&mut w, &s, only, no_idle),
                Format::Text => {
                    use std::io::Write;
                    let mut r = w.write_all(btx::export::LOG_TEXT_HEADER.as_bytes());
                    btx::export::each_log_row(&s, only, no_idle, |row| {
                        if r.is_ok() {
                            r = w.write_all(btx::export::log_text_row(&s, &row).as_bytes());
                        }
                    });
                    for g in btx::export::trailing_gaps(&s) {
                        if r.is_ok() {
                            r = w.write_all(format!("  --- gap: {g} ---\n").as_bytes());
                        }
                    }
                    r
                }
            };
            w.finish(done);
        }
    }
    Ok(())
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

/// Prints the rows of a growing run past the `printed` first, the table's
/// header once (`btx log --follow`, `btx watch`).
pub(super) fn print_grown(
    s: &btx::session::Session,
    only: Option<btx::Uid>,
    no_idle: bool,
    format: Format,
    printed: &mut usize,
    header: &mut bool,
) {
    let rows = btx::export::log_rows(s, only, no_idle);
    let new = rows.get(*printed..).unwrap_or(&[]);
    let out = match format {
        Format::Json => btx::export::log_json_lines(s, new),
        Format::Text => {
            let t = btx::export::log_text(s, new);
            if *header {
                t.split_once('\n')
                    .map_or(String::new(), |x| x.1.to_string())
            } else {
                *header = true;
                t
            }
        }
    };
    print!("{out}");
    *printed = (*printed).max(rows.len());
}
