//! Printing that never holds btx up (`btx watch`): what is said goes to
//! threads that write it, one for standard output and one for standard
//! error, so that an output nobody reads (Ctrl-S, `btx watch | less` left
//! unread) blocks its own thread only. What waits for them is bounded:
//! past `WAITING_MAX` bytes, rows are left out of the printing, counted,
//! and said once the printing goes on; the session keeps them all. A
//! robots' status line, on a terminal, is kept in place at the foot of
//! standard error, out of the way of every other line.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{channel, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Bytes that may wait to be printed, on each output.
pub const WAITING_MAX: usize = 4 << 20;
/// At the end, how long btx waits for an output that takes nothing more.
pub const STALLED: Duration = Duration::from_secs(2);

/// Back to the start of the line, and the line cleared.
const CLEAR: &str = "\r\x1b[K";

/// The status line as the terminal is sent it: btx's own cursor codes
/// around the text, whose own control characters are escaped.
fn status_line(t: &str) -> String {
    format!("\r{}\x1b[K", btx::text::visible(t))
}

/// What goes to a lane: a text, or (standard error) the status line in
/// place, `None` to clear it.
enum Said {
    /// A text of so many rows.
    Text(String, usize),
    Status(Option<String>),
}

/// One output and the thread that writes to it.
struct Lane {
    tx: Option<Sender<Said>>,
    /// Bytes and rows sent and not printed yet.
    waiting: Arc<AtomicUsize>,
    rows: Arc<AtomicUsize>,
    thread: Option<JoinHandle<()>>,
}

impl Lane {
    /// `write` prints a text; `shown` is whether the status line is on
    /// the terminal (cleared before any other line).
    fn new(name: &str, write: fn(&str), shown: Arc<AtomicBool>) -> Lane {
        let (tx, rx) = channel::<Said>();
        let waiting = Arc::new(AtomicUsize::new(0));
        let rows = Arc::new(AtomicUsize::new(0));
        let (done, done_rows) = (Arc::clone(&waiting), Arc::clone(&rows));
        let thread = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                for said in rx {
                    if shown.swap(false, Ordering::Relaxed) {
                        super::err_raw(CLEAR);
                    }
                    match said {
                        Said::Text(t, n) => {
                            write(&t);
                            done.fetch_sub(t.len(), Ordering::Relaxed);
                            done_rows.fetch_sub(n, Ordering::Relaxed);
                        }
                        Said::Status(Some(t)) => {
                            super::err_raw(&status_line(&t));
                            shown.store(true, Ordering::Relaxed);
                        }
                        Said::Status(None) => {}
                    }
                }
            })
            .ok();
        Lane {
            tx: thread.as_ref().map(|_| tx),
            waiting,
            rows,
            thread,
        }
    }

    fn waiting(&self) -> usize {
        self.waiting.load(Ordering::Relaxed)
    }

    fn room(&self, len: usize) -> bool {
        self.waiting() + len <= WAITING_MAX
    }

    fn send(&self, said: Said) {
        let (len, rows) = match &said {
            Said::Text(t, n) => (t.len(), *n),
            Said::Status(_) => (0, 0),
        };
        self.waiting.fetch_add(len, Ordering::Relaxed);
        self.rows.fetch_add(rows, Ordering::Relaxed);
        if let Some(tx) = &self.tx {
            if tx.send(said).is_err() {
                self.waiting.fetch_sub(len, Ordering::Relaxed);
                self.rows.fetch_sub(rows, Ordering::Relaxed);
            }
        }
    }

    /// Closes the lane and waits for its thread while it makes progress;
    /// whether everything was printed. An output that takes nothing for
    /// `STALLED` is left: its thread ends with the process.
    fn close(&mut self) -> bool {
        drop(self.tx.take());
        let Some(t) = self.thread.take() else {
            return true;
        };
        let (mut left, mut moved) = (self.waiting(), Instant::now());
        while !t.is_finished() {
            std::thread::sleep(Duration::from_millis(10));
            let now = self.waiting();
            if now != left {
                (left, moved) = (now, Instant::now());
            } else if moved.elapsed() >= STALLED {
                return false;
            }
        }
        let _ = t.join();
        true
    }
}

pub struct Printer {
    out: Lane,
    err: Lane,
    /// Rows and messages left out since the printing last went on.
    rows_left: usize,
    lines_left: usize,
    /// Whether the rows left out are kept in a session.
    kept: bool,
}

impl Printer {
    pub fn new(kept: bool) -> Printer {
        let shown = Arc::new(AtomicBool::new(false));
        Printer {
            out: Lane::new("btx-stdout", super::out, Arc::clone(&shown)),
            err: Lane::new("btx-stderr", super::err_out, shown),
            rows_left: 0,
            lines_left: 0,
            kept,
        }
    }

    /// What was left out, said once the printing goes on.
    fn say_left_out(&mut self) {
        let (rows, lines) = (self.rows_left, self.lines_left);
        if rows + lines == 0 {
            return;
        }
        self.rows_left = 0;
        self.lines_left = 0;
        self.err
            .send(Said::Text(left_out(rows, lines, self.kept), 1));
    }

    /// Rows to standard output (`rows` of them, for the count said when
    /// they are left out).
    pub fn out(&mut self, text: String, rows: usize) {
        if text.is_empty() {
            return;
        }
        if !self.out.room(text.len()) {
            self.rows_left += rows;
            return;
        }
        self.say_left_out();
        self.out.send(Said::Text(text, rows));
    }

    /// A line to standard error (a newline is added).
    pub fn err(&mut self, line: impl Into<String>) {
        let mut text = line.into();
        text.push('\n');
        if !self.err.room(text.len()) {
            self.lines_left += 1;
            return;
        }
        if self.rows_left > 0 && self.out.waiting() == 0 {
            self.say_left_out();
        }
        self.err.send(Said::Text(text, 1));
    }

    /// The status line, in place, when nothing waits to be printed (it is
    /// news only when it can be seen at once).
    pub fn status(&mut self, line: Option<String>) {
        if self.err.waiting() == 0 && self.out.waiting() == 0 {
            self.err.send(Said::Status(line));
        }
    }

    /// Says what was left out and waits for the rest to be printed, as
    /// long as the outputs take it.
    pub fn finish(mut self) {
        let printed = self.out.close();
        if !printed {
            // What still waits is left out too.
            self.rows_left += self.out.rows.load(Ordering::Relaxed);
        }
        self.say_left_out();
        self.err.close();
    }
}

/// The line that says what was not printed.
fn left_out(rows: usize, lines: usize, kept: bool) -> String {
    let mut what = Vec::new();
    if rows > 0 {
        what.push(format!("{rows} rows"));
    }
    if lines > 0 {
        what.push(format!("{lines} messages"));
    }
    format!(
        "{} not printed while the output was not read; {}\n",
        what.join(" and "),
        if kept {
            "the session has every row (and every gap and note)"
        } else {
            "watch with --out to keep every row"
        }
    )
}

impl Drop for Printer {
    fn drop(&mut self) {
        self.out.close();
        self.err.close();
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_status_line_moves_the_cursor_and_escapes_what_it_says() {
        assert_eq!(
            super::status_line("tick 3 \x1b[2J"),
            "\rtick 3 \\x1b[2J\x1b[K"
        );
        assert_eq!(super::CLEAR, "\r\x1b[K");
    }
}
