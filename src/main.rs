//! The `btx` command line: a thin shell over the library.

use btx::explain::{self, Question};
use btx::frame::Framed;
use btx::input::{open, Input};
use btx::run::domain::{Domain, DomainLeaves};
use btx::run::plan::{Plan, PlanLeaves};
use btx::run::world::kitting;
use btx::run::world::taxi::{self, Costs, Grid, TaxiLeaves};
use btx::run::RunOptions;
use btx::session::record::{record, RecordError, RunRequest};
use btx::session::{Moment, Session, Source};
use btx::xml::LoadOptions;
use btx::{export, pick, Version};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "btx",
    version,
    about = "Explain behaviour-tree runs: BehaviorTree.CPP trees and their runs, framed and questioned"
)]
struct Cli {
    /// Do not print warnings.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// The explorer's keymap file (default: $XDG_CONFIG_HOME/btx/keys.toml or ~/.config/btx/keys.toml, if it exists).
    #[arg(long, global = true, value_name = "FILE")]
    keys: Option<PathBuf>,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, ValueEnum)]
enum TreeFormat {
    Text,
    Json,
    Dot,
    Xml,
    Mermaid,
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Text,
    Json,
}

#[derive(Clone, Copy, ValueEnum)]
enum EvalWhat {
    Recovery,
    Truth,
}

#[derive(Clone, Copy, ValueEnum)]
enum EvalDomain {
    Random,
    SerialRecall,
}

#[derive(Clone, Copy, ValueEnum)]
enum GraphFormat {
    Dot,
    Json,
    Mermaid,
}

#[derive(Clone, Copy, ValueEnum)]
enum CostModel {
    Optimal,
    Expected,
}

#[derive(Clone, Copy, ValueEnum)]
enum World {
    Taxi,
    Kitting,
}

#[derive(clap::Args, Default)]
struct Reading {
    /// Run this <BehaviorTree> instead of the file's main tree.
    #[arg(long, value_name = "ID")]
    main_tree: Option<String>,
    /// Read the file by BehaviorTree.CPP 3 or 4 rules (default: its BTCPP_format).
    #[arg(long, value_name = "3|4", value_parser = ["3", "4"])]
    btcpp: Option<String>,
}

impl Reading {
    fn options(&self) -> LoadOptions {
        LoadOptions {
            version: self
                .btcpp
                .as_deref()
                .map(|v| if v == "3" { Version::V3 } else { Version::V4 }),
            main_tree: self.main_tree.clone(),
            embedded: false,
        }
    }
}

#[derive(Subcommand)]
enum Command {
    /// Print a tree (of a tree file or a session): the full tree, or the framed tree.
    Tree {
        /// A BehaviorTree.CPP XML file (v3 or v4), or a session.
        file: PathBuf,
        #[command(flatten)]
        reading: Reading,
        /// Show the framed tree and the semantic sets {goal, subgoals, steps, actions}.
        #[arg(long)]
        framed: bool,
        #[arg(long, value_enum, default_value = "text")]
        format: TreeFormat,
    },
    /// Ask questions about a node of a tree, or about a moment of a session.
    Ask {
        /// A tree file, or a session.
        file: PathBuf,
        #[command(flatten)]
        reading: Reading,
        /// The moment of a session: TICK (its end), TICK:STEP, last, end, or -N (-1: the last tick). Default: the end of the run.
        #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
        at: Option<String>,
        /// The node: #uid, a description or ID, or a path like "go insert large gear/detect chuck/lift torso".
        /// Default for a session: the current node at the moment.
        #[arg(long, value_name = "PICK")]
        node: Option<String>,
        /// Questions: the paper's wording, "Can you X?", or q1 q2 q3 q4 q5-subgoal q5-goal anything-wrong wrong handled.
        #[arg(required = true, value_name = "QUESTION")]
        questions: Vec<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Run a tree tick by tick and record the run as a session.
    Run {
        /// A BehaviorTree.CPP XML file (v3 or v4).
        tree: PathBuf,
        #[command(flatten)]
        reading: Reading,
        /// Scripted leaf outcomes (`key = S, F, 2RS, 1RF`).
        #[arg(long, value_name = "FILE", group = "leaves", required_unless_present_any = ["domain", "world"])]
        plan: Option<PathBuf>,
        /// A domain file (state variables and leaf functions).
        #[arg(long, value_name = "FILE", group = "leaves")]
        domain: Option<PathBuf>,
        /// A built-in world.
        #[arg(long, value_enum, group = "leaves")]
        world: Option<World>,
        /// With --domain: start with a state variable set (repeatable), e.g. UserMemory=0.0.
        #[arg(long = "set", value_name = "NAME=VALUE", requires = "domain")]
        set: Vec<String>,
        #[arg(long, default_value_t = 0)]
        seed: u64,
        #[arg(long, value_name = "N", default_value_t = 10_000)]
        max_ticks: u32,
        /// Simulated milliseconds between ticks (Timeout, Delay, Sleep).
        #[arg(long, value_name = "MS", default_value_t = 10)]
        tick_ms: u64,
        /// Ask "Can you X?" at the end of tick MOMENT; a yes inserts the subgoal and the run goes on with it.
        #[arg(long, num_args = 2, value_names = ["MOMENT", "QUESTION"])]
        ask_at: Option<Vec<String>>,
        /// The session file to write (never overwritten).
        #[arg(long, value_name = "SESSION")]
        out: PathBuf,
    },
    /// Convert a log (BehaviorTree.CPP .btlog, .db3 or .fbl, or a btcm log) into a btx session file.
    Import {
        log: PathBuf,
        /// The tree file the robot ran: checked against the log's tree (a difference is an error) and kept in the session.
        #[arg(long, value_name = "FILE")]
        tree: Option<PathBuf>,
        #[command(flatten)]
        reading: Reading,
        #[arg(long, value_name = "SESSION")]
        out: PathBuf,
    },
    /// Show a built-in world: the taxi grid, its optimal policy and the tree generated from it.
    World {
        #[arg(value_enum)]
        world: World,
        /// Whose costs: the optimal driver's (a toll costs 3 moves) or a person's expectation (1 move).
        #[arg(long, value_enum, default_value = "optimal")]
        costs: CostModel,
        /// Print the behaviour tree generated from the policy, as BehaviorTree.CPP 4 XML.
        #[arg(long)]
        tree: bool,
    },
    /// Explore a tree and a run in the terminal: `btx open TREE [SESSION]` or `btx open SESSION`.
    Open {
        #[arg(required = true, num_args = 1..=2, value_name = "TREE|SESSION")]
        files: Vec<PathBuf>,
        /// Show two trees or runs side by side (`btx open --diff A B`).
        #[arg(long, conflicts_with = "follow")]
        diff: bool,
        /// Keep reading a log (or session) that is still being written; the timeline grows.
        #[arg(long)]
        follow: bool,
        #[command(flatten)]
        reading: Reading,
    },
    /// Render a scripted scene of the explorer's demo to an SVG or PNG file.
    Screenshot {
        /// failure, framed, answer, finder or help.
        #[arg(long, value_name = "SCENE")]
        demo: String,
        #[arg(long, value_name = "FILE.svg|FILE.png")]
        out: PathBuf,
        /// Columns, 20 to 1000.
        #[arg(long, default_value_t = 110, value_parser = clap::value_parser!(u16).range(20..=1000))]
        width: u16,
        /// Rows, 5 to 500.
        #[arg(long, default_value_t = 34, value_parser = clap::value_parser!(u16).range(5..=500))]
        height: u16,
    },
    /// Why did something happen and not something else? A counterfactual search
    /// over the explanation model of the tick (Love et al.).
    Why {
        /// A session (or a log btx reads as one).
        session: PathBuf,
        /// status(NODE), executed(NODE), decision(NODE) or a state variable VAR (VAR^K: its copy K in the tick).
        target: String,
        /// A value the target did not have (repeatable). Default: every other value.
        #[arg(long = "not", value_name = "VALUE")]
        not: Vec<String>,
        /// The moment: TICK (its end), TICK:STEP, last, end, or -N (-1: the last tick). Default: the end of the run.
        #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
        at: Option<String>,
        /// The largest number of variables changed together.
        #[arg(long, value_name = "N", default_value_t = 2)]
        max_depth: usize,
        /// A domain file instead of the one the session recorded.
        #[arg(long, value_name = "FILE")]
        domain: Option<PathBuf>,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Evaluations: `btx eval recovery random` (Love et al.'s Table 2).
    Eval {
        #[arg(value_enum)]
        what: EvalWhat,
        #[arg(value_enum)]
        domain: EvalDomain,
        /// Seeds per configuration (random: the paper uses 10; serial recall: 50), at most 10,000.
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=10_000))]
        seeds: Option<u64>,
        /// Random trees with reactive and memory composites, Parallel, IfThenElse, decorators and RUNNING leaves.
        #[arg(long)]
        extended: bool,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// Print the explanation model (causal graph) of a tick of a session.
    Graph {
        session: PathBuf,
        /// The moment: TICK, TICK:STEP, last, end, or -N (-1: the last tick). Default: the last tick.
        #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
        at: Option<String>,
        /// A domain file instead of the one the session recorded.
        #[arg(long, value_name = "FILE")]
        domain: Option<PathBuf>,
        #[arg(long, value_enum, default_value = "dot")]
        format: GraphFormat,
    },
    /// Compare two trees or runs subgoal by subgoal (Han et al.'s expected vs
    /// actual policy), or one reference with several runs.
    Diff {
        /// A then B (trees, sessions or logs); or a reference and several runs.
        #[arg(required = true, num_args = 2.., value_name = "A B | REF RUN...")]
        files: Vec<PathBuf>,
        #[command(flatten)]
        reading: Reading,
        /// For two runs of one tree: where they first part ways, and why B did not do what A did.
        #[arg(long)]
        why: bool,
        /// With --why: the largest number of variables changed together.
        #[arg(long, value_name = "N", default_value_t = 2)]
        max_depth: usize,
        /// With --why: a domain file instead of the one B recorded.
        #[arg(long, value_name = "FILE")]
        domain: Option<PathBuf>,
        /// Exit with status 1 when the inputs diverge (like diff(1)).
        #[arg(long)]
        exit_code: bool,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
    /// List the status transitions of a session, like Groot's table.
    Log {
        session: PathBuf,
        /// Only this node's transitions.
        #[arg(long, value_name = "PICK")]
        node: Option<String>,
        /// Leave out transitions to IDLE (resets and halts).
        #[arg(long)]
        no_idle: bool,
        /// Keep printing transitions as the log grows (until interrupted); with --format json, one object a line.
        #[arg(long)]
        follow: bool,
        #[arg(long, value_enum, default_value = "text")]
        format: Format,
    },
}

/// What went wrong: located input errors are drawn by miette with the
/// offending line; the others are one plain message (lists stay unwrapped).
enum Failure {
    Located(miette::Report),
    Plain(String),
    /// Not an error: an exit status the command reports (`diff --exit-code`).
    Exit(u8),
}

impl From<btx::Located> for Failure {
    fn from(mut e: btx::Located) -> Self {
        use btx::text::{same_length, visible};
        e.location = visible(&e.location).into_owned();
        e.message = visible(&e.message).into_owned();
        e.label = visible(&e.label).into_owned();
        e.help = e.help.map(|h| visible(&h).into_owned());
        // The offending line is shown only when it is of a readable length
        // (a minified file's one line is not, and miette cannot draw a
        // column past 65,535); control characters in it become `?`, byte
        // for byte, so that the span still points where it did.
        if let (Some(src), Some(span)) = (&e.source_code, e.span) {
            let text = src.inner();
            let at = span.offset().min(text.len());
            let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
            let end = text[at..].find('\n').map_or(text.len(), |i| at + i);
            if end - start > LINE_SHOWN_MAX {
                e.source_code = None;
                e.span = None;
            } else if let std::borrow::Cow::Owned(clean) = same_length(text) {
                e.source_code = Some(miette::NamedSource::new(src.name(), clean));
            }
        }
        Failure::Located(miette::Report::new(e))
    }
}

/// The longest line an error shows with its source (bytes).
const LINE_SHOWN_MAX: usize = 2000;

// Everything btx prints goes through one sanitiser (data never drives the
// terminal), and a closed pipe (`btx log … | head`) ends btx quietly, as
// ripgrep does.
macro_rules! print {
    ($($t:tt)*) => { out(&format!($($t)*)) };
}
macro_rules! println {
    () => { out("\n") };
    ($($t:tt)*) => { out(&format!("{}\n", format_args!($($t)*))) };
}
macro_rules! eprintln {
    ($($t:tt)*) => { err_out(&format!("{}\n", format_args!($($t)*))) };
}

fn out(s: &str) {
    use std::io::Write;
    let s = btx::text::visible(s);
    let mut o = std::io::stdout().lock();
    written(o.write_all(s.as_bytes()).and_then(|()| o.flush()));
}

/// The end of a write to standard output: a closed pipe ends btx quietly
/// (exit 0), any other failure with a message (exit 1).
fn written(r: std::io::Result<()>) {
    if let Err(e) = r {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        err_out(&format!("error: cannot write the output: {e}\n"));
        std::process::exit(1);
    }
}

fn err_out(s: &str) {
    use std::io::Write;
    let _ = std::io::stderr().write_all(btx::text::visible(s).as_bytes());
}

macro_rules! fail {
    ($($t:tt)*) => { return Err(Failure::Plain(format!($($t)*))) };
}

fn warn_all(quiet: bool, warnings: &[btx::Warning]) {
    if !quiet {
        for w in warnings {
            eprintln!("{w}");
        }
    }
}

fn open_input(file: &Path, reading: &Reading, quiet: bool) -> Result<Input, Failure> {
    let input = open(file, &reading.options())?;
    warn_all(quiet, input.warnings());
    Ok(input)
}

/// An error without a position reads best as one plain message.
fn located(e: btx::Located) -> Failure {
    if e.source_code.is_none() {
        Failure::Plain(e.to_string())
    } else {
        Failure::from(e)
    }
}

fn session_of<'a>(input: &'a Input, file: &Path) -> Result<&'a Session, Failure> {
    match input.session() {
        Some(s) if s.index.ticks() > 0 => Ok(s),
        Some(_) => fail!("{}: the session recorded no tick", file.display()),
        None => fail!(
            "{} is a tree; a why-question is about a run: give a session (btx run … --out SESSION) or a log",
            file.display()
        ),
    }
}

fn pick_node(tree: &btx::Tree, pick: &str) -> Result<btx::Uid, Failure> {
    pick::pick(tree, pick).map_err(|e| Failure::Plain(e.to_string()))
}

fn run(cli: Cli) -> Result<(), Failure> {
    let Some(command) = cli.command else {
        let mut app = btx::tui::demo();
        app.keymap = keymap(cli.keys.as_deref())?;
        return btx::tui::run(app).map_err(|e| Failure::Plain(format!("the terminal: {e}")));
    };
    match command {
        Command::Open {
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
            btx::tui::run(app).map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
        }
        Command::Open {
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
            btx::tui::run(app).map_err(|e| Failure::Plain(format!("the terminal: {e}")))?;
        }
        Command::Screenshot {
            demo,
            out,
            width,
            height,
        } => {
            let app = btx::tui::scene(&demo).map_err(Failure::Plain)?;
            let buf = btx::tui::render(&app, width, height);
            match out.extension().and_then(|e| e.to_str()) {
                Some("svg") => std::fs::write(&out, btx::tui::svg::buffer_to_svg(&buf))
                    .map_err(|e| Failure::Plain(format!("{}: {e}", out.display())))?,
                Some("png") => {
                    let png = btx::tui::svg::svg_to_png(&btx::tui::svg::buffer_to_svg(&buf))
                        .map_err(Failure::Plain)?;
                    std::fs::write(&out, png)
                        .map_err(|e| Failure::Plain(format!("{}: {e}", out.display())))?
                }
                _ => fail!("{}: a screenshot is a .svg or a .png file", out.display()),
            }
        }
        Command::Tree {
            file,
            reading,
            framed,
            format,
        } => {
            let input = open_input(&file, &reading, cli.quiet)?;
            let tree = input.tree();
            let out = match (framed, format) {
                (false, TreeFormat::Text) => {
                    export::write_tree_text(tree, &mut |l| print!("{l}"));
                    return Ok(());
                }
                (false, TreeFormat::Json) => pretty(&export::tree_json(tree)),
                (false, TreeFormat::Dot) => export::tree_dot(tree),
                (false, TreeFormat::Mermaid) => export::tree_mermaid(tree),
                (true, TreeFormat::Xml) => fail!(
                    "the framed tree is a view, not a runnable tree: drop --framed to write XML"
                ),
                (false, TreeFormat::Xml) => btx::xml::to_v4_xml(tree),
                (true, f) => {
                    let fr = Framed::new(tree);
                    match f {
                        TreeFormat::Json => pretty(&export::framed_json(tree, &fr)),
                        TreeFormat::Dot => export::framed_dot(tree, &fr),
                        TreeFormat::Mermaid => export::framed_mermaid(tree, &fr),
                        _ => export::framed_text(tree, &fr),
                    }
                }
            };
            print!("{out}");
        }
        Command::Why {
            session,
            target,
            not,
            at,
            max_depth,
            domain,
            format,
        } => {
            let input = open_input(&session, &Reading::default(), cli.quiet)?;
            let s = session_of(&input, &session)?;
            let at = at
                .as_deref()
                .map(|a| Moment::parse_within(a, s.index.ticks()))
                .transpose()
                .map_err(Failure::Plain)?;
            let d = btx::causal::session_domain(s, domain.as_deref()).map_err(located)?;
            let w = btx::causal::why(s, d, &target, &not, at, max_depth).map_err(located)?;
            match format {
                Format::Text => print!("{}", w.text()),
                Format::Json => print!("{}", pretty(&w.json())),
            }
        }
        Command::Eval {
            what: EvalWhat::Truth,
            domain,
            seeds,
            extended,
            format,
        } => {
            if !matches!(domain, EvalDomain::Random) {
                fail!("btx eval truth runs on random domains: btx eval truth random");
            }
            let started = std::time::Instant::now();
            let t = btx::causal::truth::truth_random(seeds.unwrap_or(2), extended)
                .map_err(Failure::Plain)?;
            let secs = started.elapsed().as_secs_f64();
            match format {
                Format::Text => {
                    print!("{}", t.text());
                    println!("in {secs:.2} s");
                }
                Format::Json => print!(
                    "{}",
                    pretty(&serde_json::json!({"tally": t, "seconds": secs}))
                ),
            }
        }
        Command::Eval {
            what: EvalWhat::Recovery,
            domain,
            seeds,
            extended,
            format,
        } => {
            let started = std::time::Instant::now();
            let (rows, table) = match domain {
                EvalDomain::Random => {
                    let rows = btx::causal::eval::recovery_random(seeds.unwrap_or(10), extended)
                        .map_err(Failure::Plain)?;
                    let t = btx::causal::eval::table2(&rows);
                    (rows, t)
                }
                EvalDomain::SerialRecall => {
                    let rows = btx::causal::eval::recovery_serial_recall(seeds.unwrap_or(50))
                        .map_err(Failure::Plain)?;
                    let t = btx::causal::eval::table3(&rows);
                    (rows, t)
                }
            };
            let secs = started.elapsed().as_secs_f64();
            match format {
                Format::Text => {
                    print!("{table}");
                    println!(
                        "{} comparisons in {secs:.2} s ({} threads)",
                        rows.len(),
                        rayon::current_num_threads()
                    );
                }
                Format::Json => print!(
                    "{}",
                    pretty(&serde_json::json!({"rows": rows, "seconds": secs}))
                ),
            }
        }
        Command::Graph {
            session,
            at,
            domain,
            format,
        } => {
            let input = open_input(&session, &Reading::default(), cli.quiet)?;
            let s = session_of(&input, &session)?;
            let tick = match at.as_deref() {
                Some(a) => {
                    let m = Moment::parse_within(a, s.index.ticks()).map_err(Failure::Plain)?;
                    s.index.position(m).map_err(Failure::Plain)?;
                    m.tick
                }
                None => s.index.ticks(),
            };
            let d = btx::causal::session_domain(s, domain.as_deref()).map_err(located)?;
            let m = btx::causal::model_at(s, d, tick).map_err(located)?;
            match format {
                GraphFormat::Dot => print!("{}", btx::causal::graph::dot(&m)),
                GraphFormat::Json => print!("{}", pretty(&btx::causal::graph::json(&m))),
                GraphFormat::Mermaid => print!("{}", btx::causal::graph::mermaid(&m)),
            }
        }
        Command::Ask {
            file,
            reading,
            at,
            node,
            questions,
            format,
        } => {
            let input = open_input(&file, &reading, cli.quiet)?;
            let mut qs = Vec::new();
            for q in &questions {
                match Question::parse(q) {
                    Some(q) => qs.push(q),
                    None => {
                        let known: Vec<String> = Question::fixed()
                            .iter()
                            .map(|q| format!("\"{}\" ({})", q.wording(), q.short()))
                            .collect();
                        fail!(
                            "unknown question \"{q}\"; ask one of: {}, or \"Can you X?\"",
                            known.join(", ")
                        );
                    }
                }
            }
            let tree = input.tree();
            let view = match input.session() {
                Some(s) => {
                    let m = match &at {
                        Some(a) => {
                            Moment::parse_within(a, s.index.ticks()).map_err(Failure::Plain)?
                        }
                        None => Moment {
                            tick: s.index.ticks().max(1),
                            step: None,
                        },
                    };
                    if s.index.ticks() == 0 {
                        fail!("{}: the session recorded no tick", file.display());
                    }
                    Some(s.at(m).map_err(Failure::Plain)?)
                }
                None => {
                    if at.is_some() {
                        fail!(
                            "--at picks a moment of a run, and {} is a tree, not a session",
                            file.display()
                        );
                    }
                    None
                }
            };
            let uid = match (&node, &view) {
                (Some(p), _) => pick_node(tree, p)?,
                (None, Some(v)) => match v.current() {
                    Some(u) => u,
                    None => fail!(
                        "nothing has been ticked yet at moment {}; pick a node with --node",
                        v.moment()
                    ),
                },
                (None, None) => {
                    fail!("pick the node to ask about with --node (a tree has no current node)")
                }
            };
            let mut answers = Vec::new();
            for q in &qs {
                answers.push(explain::answer(tree, view.as_ref(), uid, q).map_err(Failure::Plain)?);
            }
            match format {
                Format::Text => {
                    for a in &answers {
                        println!("{}", a.text);
                    }
                }
                Format::Json => {
                    let moment = view.map(|v| v.moment().to_string());
                    print!(
                        "{}",
                        pretty(&export::answers_json(
                            tree,
                            uid,
                            moment.as_deref(),
                            &answers
                        ))
                    )
                }
            }
        }
        Command::Run {
            tree: path,
            reading,
            plan,
            domain,
            world,
            set,
            seed,
            max_ticks,
            tick_ms,
            ask_at,
            out,
        } => {
            let text = btx::source::read_text(&path, btx::source::TEXT_SIZE_MAX, "the tree file")?;
            let loaded = btx::xml::load_str(&path, &text, &reading.options())?;
            warn_all(cli.quiet, &loaded.warnings);
            let tree = loaded.tree;
            let ask = match ask_at {
                Some(v) => {
                    let m = Moment::parse(&v[0]).map_err(Failure::Plain)?;
                    if m.step.is_some() {
                        fail!("--ask-at takes a whole tick: a run is asked between ticks");
                    }
                    match Question::parse(&v[1]) {
                        Some(Question::CanYou(_)) => {}
                        _ => fail!("--ask-at asks \"Can you X?\"; other questions are asked of the session with btx ask"),
                    }
                    Some((m.tick, v[1].clone()))
                }
                None => None,
            };
            let req = |source: Source| RunRequest {
                tree: &tree,
                tree_file: Some((&path, &text)),
                source,
                seed: Some(seed),
                max_ticks,
                options: RunOptions { tick_ms },
                ask: ask.clone(),
                out: &out,
            };
            if !set.is_empty() && domain.is_none() {
                fail!("--set starts a domain's state variable, and this run has no --domain: with a plan or a world it would change nothing");
            }
            if let Some(p) = &plan {
                let plan = Plan::load(p)?;
                let source = Source {
                    kind: "plan".into(),
                    path: Some(p.display().to_string()),
                    text: Some(plan.text.clone()),
                    name: None,
                };
                let leaves = PlanLeaves::new(plan, &tree);
                warn_all(cli.quiet, &leaves.warnings);
                report_run(
                    &tree,
                    ask.as_ref().map(|(t, _)| *t),
                    record(req(source), leaves),
                )?;
            } else if let Some(p) = &domain {
                let d = std::sync::Arc::new(Domain::load(p)?);
                let source = Source {
                    kind: "domain".into(),
                    path: Some(p.display().to_string()),
                    text: Some(d.text.clone()),
                    name: Some(d.name.clone()),
                };
                let mut leaves = DomainLeaves::new(d, &tree)?;
                for a in &set {
                    leaves.set(a).map_err(Failure::Plain)?;
                }
                report_run(
                    &tree,
                    ask.as_ref().map(|(t, _)| *t),
                    record(req(source), leaves),
                )?;
            } else {
                match world.expect("clap requires one source of leaves") {
                    World::Taxi => {
                        let unknown = TaxiLeaves::unknown_leaves(&tree);
                        if !unknown.is_empty() {
                            fail!(
                                "the taxi world moves, picks up and drops off; it cannot run {}",
                                unknown.join(", ")
                            );
                        }
                        let source = Source {
                            kind: "world".into(),
                            path: None,
                            text: None,
                            name: Some("taxi".into()),
                        };
                        report_run(
                            &tree,
                            ask.as_ref().map(|(t, _)| *t),
                            record(req(source), TaxiLeaves::new(Grid::han())),
                        )?;
                    }
                    World::Kitting => {
                        let (name, plan) = kitting::scenario(seed).map_err(Failure::Plain)?;
                        let source = Source {
                            kind: "world".into(),
                            path: None,
                            text: Some(plan.text.clone()),
                            name: Some(format!("kitting: {name}")),
                        };
                        let leaves = PlanLeaves::new(plan, &tree);
                        warn_all(cli.quiet, &leaves.warnings);
                        report_run(
                            &tree,
                            ask.as_ref().map(|(t, _)| *t),
                            record(req(source), leaves),
                        )?;
                    }
                }
            }
        }
        Command::Import {
            log,
            tree,
            reading,
            out,
        } => {
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
        }
        Command::World { world, costs, tree } => match world {
            World::Kitting => {
                for (i, (name, _)) in kitting::SCENARIOS.iter().enumerate() {
                    println!("--seed {i}: {name}");
                }
            }
            World::Taxi => {
                let g = Grid::han();
                let c = match costs {
                    CostModel::Optimal => Costs::OPTIMAL,
                    CostModel::Expected => Costs::EXPECTED,
                };
                let actions = g.rollout(&g.solve(c));
                if tree {
                    print!("{}", taxi::policy_tree_xml(&actions));
                } else {
                    print!("{}", taxi_text(&g, c, &actions));
                }
            }
        },
        Command::Diff {
            files,
            reading,
            why,
            max_depth,
            domain,
            exit_code,
            format,
        } => {
            let inputs = files
                .iter()
                .map(|f| open_input(f, &reading, cli.quiet))
                .collect::<Result<Vec<_>, _>>()?;
            let sides: Vec<btx::diff::Side> = files
                .iter()
                .zip(&inputs)
                .map(|(f, i)| {
                    let name = f.display().to_string();
                    match i.session() {
                        Some(s) => btx::diff::Side::session(name, s),
                        None => btx::diff::Side::tree(name, i.tree()),
                    }
                })
                .collect();
            let diverges = if sides.len() > 2 {
                if why {
                    fail!("--why compares two runs; give A and B only");
                }
                let f = btx::diff::fleet::Fleet::new(&sides[0], &sides[1..]);
                match format {
                    Format::Text => print!("{}", f.text()),
                    Format::Json => print!("{}", pretty(&f.json())),
                }
                f.diffs.iter().any(|d| !d.is_empty())
            } else {
                let d = btx::diff::Diff::new(&sides[0], &sides[1]);
                let diverged = if why {
                    let (Some(a), Some(b)) = (inputs[0].session(), inputs[1].session()) else {
                        fail!("--why asks why two runs diverged: give two sessions or logs");
                    };
                    if !btx::diff::same_shape(&a.tree, &b.tree) {
                        fail!(
                            "--why compares two runs of one tree, and {} and {} ran different trees",
                            files[0].display(),
                            files[1].display()
                        );
                    }
                    let dom = btx::causal::session_domain(b, domain.as_deref()).map_err(located)?;
                    Some(
                        btx::causal::compare::why_diverged(a, b, dom, max_depth)
                            .map_err(located)?,
                    )
                } else {
                    None
                };
                use btx::causal::compare::Diverged;
                match format {
                    Format::Text => {
                        print!("{}", d.text());
                        match &diverged {
                            Some(None) => println!("\n{}", Diverged::SAME),
                            Some(Some(x)) => {
                                print!("\n{}", x.text(inputs[1].tree(), "Why, in B: "))
                            }
                            None => {}
                        }
                    }
                    Format::Json => {
                        let mut v = d.json();
                        if let Some(x) = &diverged {
                            v["why"] = match x {
                                None => serde_json::Value::Null,
                                Some(x) => serde_json::json!({
                                    "transition": x.difference.index + 1,
                                    "moment": x.difference.moment.to_string(),
                                    "text": x.difference.text(inputs[1].tree(), "A", "B"),
                                    "answer": x.why.as_ref().map(|w| w.json()),
                                }),
                            };
                        }
                        print!("{}", pretty(&v));
                    }
                }
                !d.is_empty() || matches!(diverged, Some(Some(_)))
            };
            if exit_code && diverges {
                return Err(Failure::Exit(1));
            }
        }
        Command::Log {
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
                        let rows = btx::export::log_rows(&s, only, no_idle);
                        let new = rows.get(printed..).unwrap_or(&[]);
                        let out = match format {
                            Format::Json => btx::export::log_json_lines(&s, new),
                            Format::Text => {
                                let t = btx::export::log_text(&s, new);
                                if header {
                                    t.split_once('\n')
                                        .map_or(String::new(), |x| x.1.to_string())
                                } else {
                                    header = true;
                                    t
                                }
                            }
                        };
                        print!("{out}");
                        printed = printed.max(rows.len());
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
        Command::Log {
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

fn taxi_text(g: &Grid, c: Costs, actions: &[taxi::Action]) -> String {
    let mut out = String::new();
    for y in (1..=g.height).rev() {
        out.push_str(&format!("row {y} "));
        for x in 1..=g.width {
            let cell = if (x, y) == g.passenger {
                'P'
            } else if g.tolls.contains(&(x, y)) {
                'T'
            } else if (x, y) == g.start {
                'S'
            } else {
                '.'
            };
            let wall = x > 1 && g.walls.contains(&((x - 1, y), (x, y)));
            out.push_str(if wall { " | " } else { "   " });
            out.push(cell);
        }
        out.push('\n');
    }
    out.push_str("      ");
    for x in 1..=g.width {
        out.push_str(&format!("   {x}"));
    }
    out.push_str(&format!(
        "\ncosts: a move {}, a toll {}\npolicy: ",
        c.step, c.toll
    ));
    out.push_str(
        &actions
            .iter()
            .map(|a| a.name())
            .collect::<Vec<_>>()
            .join(", "),
    );
    out.push('\n');
    out
}

/// The keymap: the given file, else the user's config file if there is one.
fn keymap(path: Option<&Path>) -> Result<btx::tui::keymap::Keymap, Failure> {
    let default = std::env::var_os("XDG_CONFIG_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config")))
        .map(|d| d.join("btx/keys.toml"))
        .filter(|p| p.exists());
    match path.map(Path::to_path_buf).or(default) {
        Some(p) => Ok(btx::tui::keymap::Keymap::with_file(&p)?),
        None => Ok(btx::tui::keymap::Keymap::default()),
    }
}

fn report_run(
    tree: &btx::Tree,
    asked_at: Option<u32>,
    r: Result<btx::session::record::RunSummary, RecordError>,
) -> Result<(), Failure> {
    match r {
        Ok(s) => {
            if let Some(a) = &s.answer {
                println!("{a}");
            } else if let Some(t) = asked_at {
                eprintln!(
                    "warning: the run ended at tick {}, before tick {t} where --ask-at was to ask; nothing was asked",
                    s.ticks
                );
            }
            eprintln!(
                "{}: {} ticks, {} transitions, root {} ({})",
                s.path.display(),
                s.ticks,
                s.transitions,
                s.root,
                s.reason
            );
            Ok(())
        }
        Err(RecordError::Io(e)) => Err(e.into()),
        Err(RecordError::Script(e, s)) => {
            eprintln!("the run up to the error is in {}", s.path.display());
            Err(e.into())
        }
        Err(RecordError::Run(e, s)) => {
            let (file, line, col) = tree.location(e.uid);
            fail!(
                "{file}:{line}:{col}: {e}\nthe run up to here is in {}",
                s.path.display()
            );
        }
    }
}

fn pretty(v: &serde_json::Value) -> String {
    let mut s = serde_json::to_string_pretty(v).expect("JSON values serialise");
    s.push('\n');
    s
}

/// The stack btx runs on. The executor, the loaders and the explanations
/// recurse down the tree, and a tree may be `DEPTH_MAX` (10,000) levels deep;
/// the main thread's 8 MiB overflows before that, and running a 9,600-level
/// chain was measured to need 16 MiB. Only the pages used are committed.
const STACK_SIZE: usize = 256 << 20;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let worker = std::thread::Builder::new()
        .name("btx".into())
        .stack_size(STACK_SIZE)
        .spawn(move || finish(run(cli)));
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

fn finish(result: Result<(), Failure>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Located(report)) => {
            // Its text was made safe when it was built; miette may colour it.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "{report:?}");
            ExitCode::FAILURE
        }
        Err(Failure::Plain(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
        Err(Failure::Exit(code)) => ExitCode::from(code),
    }
}
