//! `btx open`: Explore a tree and a run in the terminal: `btx open TREE [SESSION]` or `btx open SESSION`.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    #[arg(required_unless_present = "live", num_args = 1..=2, value_name = "TREE|SESSION")]
    pub files: Vec<PathBuf>,
    /// Show two trees or runs side by side (`btx open --diff A B`).
    #[arg(long, conflicts_with = "follow")]
    pub diff: bool,
    /// Keep reading a log (or session) that is still being written; the timeline grows.
    #[arg(long)]
    pub follow: bool,
    /// Open robots that are running now: `[HOST][:PORT]` each (default 127.0.0.1:1667), a Groot2 server (BehaviorTree.CPP 4) or a Groot 1 server (BehaviorTree.CPP 3, Nav2 Humble). With several, `R` picks the one shown; all are watched.
    #[arg(long, value_name = "[HOST][:PORT]", num_args = 0.., conflicts_with_all = ["files", "diff", "follow"])]
    pub live: Option<Vec<String>>,
    /// With --live: keep the run as a session (`SESSION.partial` while it runs, SESSION when the explorer closes, as Parquet if it ends in .parquet); with several robots, a directory of one session a robot.
    #[arg(long, value_name = "SESSION|DIR", requires = "live")]
    pub out: Option<PathBuf>,
    /// A BehaviorTree.CPP 3 robot's publisher port (Groot 1's protocol; Nav2 Humble's groot_zmq_publisher_port), when it is not the one below the server's.
    #[arg(long, value_name = "PORT", requires = "live")]
    pub publisher_port: Option<u16>,
    #[command(flatten)]
    pub reading: Reading,
    #[command(flatten)]
    pub explorer: Explorer,
}

impl Args {
    /// `btx open FILES`, as `btx FILES` says it.
    pub fn of(files: Vec<PathBuf>) -> Args {
        Args {
            files,
            diff: false,
            follow: false,
            live: None,
            out: None,
            publisher_port: None,
            reading: Reading::default(),
            explorer: Explorer::default(),
        }
    }
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    if let Some(specs) = &args.live {
        return live(specs, args.publisher_port, args.out.as_deref(), cli);
    }
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
            let mut app = btx::tui::open_diff(&files[0], &files[1], &reading.options()?)?;
            app.keymap = keymap(cli.keys.as_deref())?;
            btx::tui::run_with(&mut app, cli.ascii)
                .map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
        }
        Args {
            files,
            diff: false,
            follow,
            reading,
            ..
        } => {
            let mut app = btx::tui::open(
                &files[0],
                files.get(1).map(PathBuf::as_path),
                &reading.options()?,
            )?;
            if follow {
                let log = files.last().expect("one file at least");
                if app.shared.session.is_none() {
                    fail!(
                        "--follow follows a log or a session as it grows, and {} is a tree",
                        btx::text::path(log)
                    );
                }
                // Following starts from the whole log as it is now.
                app.read_whole();
                let mut f = btx::input::Follow::new(log);
                // The first reading is the one just opened.
                let _ = f.poll();
                app.shared.follow = Some(f);
                // Start at the end: following means watching what comes in.
                app.update(btx::tui::Action::End);
            }
            app.shared.keymap = keymap(cli.keys.as_deref())?;
            btx::tui::run_with(&mut app, cli.ascii)
                .map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
            // A long log broken past the part shown first.
            if let Some(e) = app.failed.take() {
                return Err(e.into());
            }
        }
    }
    Ok(())
}

/// `btx open --live`: the explorer on robots running now, each watched
/// into its session, one shown at a time (`R` picks).
fn live(
    specs: &[String],
    publisher: Option<u16>,
    out: Option<&Path>,
    cli: &Globals,
) -> Result<(), Failure> {
    use btx::tui::choices::{Choices, RobotChoice};
    let robots = super::watch::Robots::new(specs, publisher, out, "btx open --live")?;
    let mut choices = Vec::new();
    for (ep, out) in robots.eps.iter().zip(robots.outs.clone()) {
        let (feed, unreachable) = match btx::live::Feed::start(ep, publisher, out) {
            Ok(f) => (Some(f), None),
            // One robot that cannot be reached does not stop the others.
            Err(e) if robots.eps.len() > 1 => (None, Some(e.to_string())),
            Err(e) => return Err(Failure::Plain(e.to_string())),
        };
        choices.push(RobotChoice {
            endpoint: ep.clone(),
            feed,
            unreachable,
        });
    }
    let Some(current) = choices.iter().position(|c| c.feed.is_some()) else {
        let why: Vec<String> = choices
            .iter()
            .filter_map(|c| c.unreachable.clone())
            .collect();
        fail!("no robot could be reached:\n  {}", why.join("\n  "));
    };
    let feed = choices[current].feed.take().expect("reachable");
    let first = feed.session()?;
    let ep = &robots.eps[current];
    let mut app = btx::tui::App::new(first.tree.clone(), Some(first), format!("live {ep}"));
    app.shared.live = Some(feed);
    if choices.len() > 1 {
        app.shared.choices = Some(Choices::Robots {
            robots: choices,
            current,
        });
    }
    app.shared.keymap = keymap(cli.keys.as_deref())?;
    btx::tui::run_with(&mut app, cli.ascii)
        .map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
    if !cli.quiet {
        for o in robots.outs.iter().flatten().filter(|o| o.exists()) {
            eprintln!("the run is in {}", btx::text::path(o));
        }
    }
    Ok(())
}
