//! The `btx` binary: parses the command line and dispatches it (`cli`).

mod cli;

use clap::Parser;
use std::process::ExitCode;

/// The stack btx runs on. The executor, the loaders and the explanations
/// recurse down the tree, and a tree may be `DEPTH_MAX` (25,000) levels deep;
/// the main thread's 8 MiB overflows before that (so does BehaviorTree.CPP's,
/// past about 13,900 levels), and running a 9,600-level chain was measured to
/// need 16 MiB; a 24,801-level chain loads, runs, is explained and graphed on
/// this stack. Only the pages used are committed.
const STACK_SIZE: usize = 256 << 20;

/// glibc's allocator, left to itself, hands a freed block of a few MiB
/// back to the kernel and takes fresh pages for the next: an explanation
/// checks each claim by re-running the tree, and on a chain of 4,000
/// SubTrees every re-run's tables were faulted in anew (150,000 page
/// faults, a third of `btx why`'s time; `btx fleet` and its export paid it
/// per run too). Kept up to these sizes, a freed block is reused.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn keep_freed_memory() {
    // SAFETY: mallopt only sets the allocator's tunables; it is called
    // before any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn keep_freed_memory() {}

fn main() -> ExitCode {
    keep_freed_memory();
    // Past `ulimit -f` a write raises SIGXFSZ, which kills silently; caught,
    // the write fails with EFBIG instead, and btx says which file and what
    // it kept.
    let _ = signal_hook::flag::register(
        signal_hook::consts::SIGXFSZ,
        std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false)),
    );
    let cli = cli::Cli::parse();
    let worker = std::thread::Builder::new()
        .name("btx".into())
        .stack_size(STACK_SIZE)
        .spawn(move || cli::main(cli));
    match worker.map(|w| w.join()) {
        Ok(Ok(code)) => code,
        // The panic hook has already restored the terminal and said why.
        Ok(Err(_)) => ExitCode::from(101),
        Err(e) => {
            eprintln!("error: cannot start btx's thread ({e}): is the address space limited below {} MiB?", STACK_SIZE >> 20);
            ExitCode::FAILURE
        }
    }
}
