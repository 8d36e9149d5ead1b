//! `btx import`: Convert a log (BehaviorTree.CPP .btlog, .db3 or .fbl, or a btcm log) into a btx session file.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    pub log: PathBuf,
    /// The tree file the robot ran: checked against the log's tree (a difference is an error) and kept in the session.
    #[arg(long, value_name = "FILE")]
    pub tree: Option<PathBuf>,
    #[command(flatten)]
    pub reading: Reading,
    #[arg(long, value_name = "SESSION")]
    pub out: PathBuf,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        log,
        tree,
        reading,
        out,
    } = args;
    let _claim = btx::session::OutputLock::take(&out, "btx import")?;
    let mut s = match btx::input::open(&log, &LoadOptions::default())? {
        Input::Session(s) => *s,
        Input::Tree { .. } => fail!("{} is a tree, not a log", log.display()),
    };
    warn_all(cli.quiet, &s.warnings);
    if let Some(t) = &tree {
        let file = match open_input(t, &reading, cli.quiet)? {
            Input::Tree { tree, .. } => tree,
            Input::Session(_) => {
                fail!("--tree takes a tree file, and {} is a run", t.display())
            }
        };
        let diff = btx::logs::tree_mismatch(&file, &s.tree, 8);
        if !diff.is_empty() {
            fail!(
                "{} is not a log of {}:\n  {}",
                log.display(),
                t.display(),
                diff.join("\n  ")
            );
        }
        s.header.tree.path = Some(t.display().to_string());
        s.header.tree.xml = btx::xml::to_v4_xml(&file);
        s.tree = file;
    }
    let path = btx::logs::write_session(&s, &out)?;
    eprintln!(
        "{}: {} ticks, {} transitions",
        path.display(),
        s.index.ticks(),
        s.index.transitions.len()
    );
    Ok(())
}
