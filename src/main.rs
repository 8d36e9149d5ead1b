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

fn main() -> ExitCode {
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
