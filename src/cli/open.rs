//! `btx open`: Explore a tree and a run in the terminal: `btx open TREE [SESSION]` or `btx open SESSION`.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    #[arg(required = true, num_args = 1..=2, value_name = "TREE|SESSION")]
    pub files: Vec<PathBuf>,
    /// Show two trees or runs side by side (`btx open --diff A B`).
    #[arg(long, conflicts_with = "follow")]
    pub diff: bool,
    /// Keep reading a log (or session) that is still being written; the timeline grows.
    #[arg(long)]
    pub follow: bool,
    #[command(flatten)]
    pub reading: Reading,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    match args {
        Args {
            files,
            diff: true,
            reading,
            ..
        } => {
            if files.len() != 2 {
                fail!("--diff shows two inputs side by side: btx open --diff A B");
            }
            let mut app = btx::tui::open_diff(&files[0], &files[1], &reading.options())?;
            app.keymap = keymap(cli.keys.as_deref())?;
            btx::tui::run_with(app, cli.ascii)
                .map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
        }
        Args {
            files,
            diff: false,
            follow,
            reading,
        } => {
            let mut app = btx::tui::open(
                &files[0],
                files.get(1).map(PathBuf::as_path),
                &reading.options(),
            )?;
            if follow {
                let log = files.last().expect("one file at least");
                if app.session.is_none() {
                    fail!(
                        "--follow follows a log or a session as it grows, and {} is a tree",
                        log.display()
                    );
                }
                let mut f = btx::input::Follow::new(log);
                // The first reading is the one just opened.
                let _ = f.poll();
                app.follow = Some(f);
                // Start at the end: following means watching what comes in.
                app.update(btx::tui::Action::End);
            }
            app.keymap = keymap(cli.keys.as_deref())?;
            btx::tui::run_with(app, cli.ascii)
                .map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
        }
    }
    Ok(())
}
