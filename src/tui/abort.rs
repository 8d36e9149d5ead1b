//! The terminal given back when btx aborts. A panic gives it back through
//! the panic hook; an abort (memory exhausted, a panic while panicking)
//! runs no hook and would leave the shell in the alternate screen, in raw
//! mode, with mouse reporting on. SIGABRT is caught to give it back first;
//! the process then dies of SIGABRT as it would have.

use std::sync::OnceLock;

/// The terminal's settings before the explorer changed them.
static SAVED: OnceLock<libc::termios> = OnceLock::new();

/// Mouse reporting off (every mode crossterm turns on), the cursor shown,
/// the alternate screen left.
const RESTORE: &[u8] =
    b"\x1b[?1000l\x1b[?1002l\x1b[?1003l\x1b[?1006l\x1b[?1015l\x1b[?25h\x1b[?1049l";

/// Saves the terminal's settings and catches SIGABRT; called before the
/// explorer takes the terminal (once a process).
pub fn guard() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // SAFETY: `termios` is plain data, filled by tcgetattr on success.
        let mut t: libc::termios = unsafe { std::mem::zeroed() };
        if unsafe { libc::tcgetattr(libc::STDIN_FILENO, &mut t) } == 0 {
            let _ = SAVED.set(t);
        }
        // SAFETY: the handler calls only tcsetattr and write, which are
        // async-signal-safe, and reads a value set before it was installed.
        let _ =
            unsafe { signal_hook::low_level::register(signal_hook::consts::SIGABRT, give_back) };
    });
}

fn give_back() {
    if let Some(t) = SAVED.get() {
        // SAFETY: async-signal-safe; `t` is a valid termios.
        unsafe { libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, t) };
    }
    // SAFETY: async-signal-safe; the bytes are a static slice.
    unsafe { libc::write(libc::STDOUT_FILENO, RESTORE.as_ptr().cast(), RESTORE.len()) };
}
