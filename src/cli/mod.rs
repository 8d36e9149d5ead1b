//! The `btx` command line, a thin shell over the library: what each command
//! takes (clap), how it prints (every text output through the sanitiser),
//! and one module a command.

use btx::explain::Question;
use btx::frame::Framed;
use btx::input::{open, Input, Printable};
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
    about = "Explain behaviour-tree runs: BehaviorTree.CPP trees and their runs, framed and questioned",
    long_about = "Explain behaviour-tree runs: BehaviorTree.CPP trees and their runs, framed and questioned.\n\n`btx FILE` opens a tree, a session or a log in the explorer (as `btx open FILE`); `btx` alone opens the explorer's demo."
)]
pub struct Cli {
    /// Do not print warnings.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// A tree, a session or a log to open in the explorer (`btx open TREE [SESSION]`); none: the demo.
    #[arg(value_name = "FILE", num_args = 0..=2)]
    files: Vec<PathBuf>,
    #[command(flatten)]
    explorer: Explorer,
    #[command(subcommand)]
    command: Option<Command>,
}

/// The explorer's options: what `btx`, `btx FILE`, `btx open` and
/// `btx fleet --open` take, and no other command.
#[derive(clap::Args, Default, Clone)]
pub struct Explorer {
    /// The explorer's keymap file (default: $XDG_CONFIG_HOME/btx/keys.toml or ~/.config/btx/keys.toml, if it exists).
    #[arg(long, value_name = "FILE")]
    keys: Option<PathBuf>,
    /// The explorer draws only ASCII: no box drawing, arrows or symbols (names stay as they are).
    #[arg(long)]
    ascii: bool,
}

impl Explorer {
    /// These options, with those given before the command (`btx --ascii open`) where these are unset.
    fn or(self, before: &Explorer) -> Explorer {
        Explorer {
            keys: self.keys.or_else(|| before.keys.clone()),
            ascii: self.ascii || before.ascii,
        }
    }
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
    /// A models file (<TreeNodesModel>, e.g. Nav2's nav2_tree_nodes.xml): node kinds and port directions. Repeatable.
    #[arg(long, value_name = "FILE")]
    models: Vec<PathBuf>,
    /// More tree files, or directories of them (*.xml): their <BehaviorTree>s are registered for SubTrees to call, as registerBehaviorTreeFromFile does. Repeatable.
    #[arg(long, value_name = "FILE|DIR", num_args = 1..)]
    with: Vec<PathBuf>,
    /// For a log: the tree file the robot ran, used instead of the tree the log embeds (which BehaviorTree.CPP writes back without _autoremap and its models), after checking that the two match node for node.
    #[arg(long = "tree", id = "run_tree", value_name = "FILE")]
    run_tree: Option<PathBuf>,
    /// For a log of several runs (a rosbag's goals, a .btlog whose tree was started again): the run to read, from 1 (default: a bag's last run; a .btlog whole). `btx log LOG --runs` lists them.
    #[arg(long = "run", id = "run_number", value_name = "N")]
    run: Option<usize>,
    /// For a rosbag that holds several behavior_tree_log topics (one robot's each): the topic to read, e.g. /robot1/behavior_tree_log.
    #[arg(long, value_name = "TOPIC")]
    topic: Option<String>,
}

impl Reading {
    fn options(&self) -> Result<LoadOptions, Failure> {
        let mut with = Vec::new();
        for w in &self.with {
            if w.is_dir() {
                let mut files: Vec<PathBuf> = std::fs::read_dir(w)
                    .map_err(|e| Failure::Plain(format!("{}: {e}", btx::text::path(w))))?
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|x| x == "xml") && p.is_file())
                    .collect();
                files.sort();
                with.extend(files);
            } else {
                with.push(w.clone());
            }
        }
        Ok(LoadOptions {
            version: self
                .btcpp
                .as_deref()
                .map(|v| if v == "3" { Version::V3 } else { Version::V4 }),
            main_tree: self.main_tree.clone(),
            embedded: false,
            models: self.models.clone(),
            with,
            run_tree: self.run_tree.clone(),
            run: self.run,
            topic: self.topic.clone(),
        })
    }
}

#[derive(Subcommand)]
enum Command {
    /// Print a tree (of a tree file or a session): the full tree, or the framed tree.
    Tree(tree::Args),
    /// Ask questions about a node of a tree, or about a moment of a session.
    Ask(ask::Args),
    /// Run a tree tick by tick and record the run as a session.
    Run(run::Args),
    /// Convert a log (BehaviorTree.CPP .btlog, .db3 or .fbl, a rosbag, or a btcm log) into a btx session file, or a session from JSON lines to Parquet and back.
    Import(import::Args),
    /// Show a built-in world: the taxi grid, its optimal policy and the tree generated from it.
    World(world::Args),
    /// Explore a tree and a run in the terminal: `btx open TREE [SESSION]` or `btx open SESSION`.
    Open(open::Args),
    /// Render a scripted scene of the explorer's demo to an SVG or PNG file.
    Screenshot(screenshot::Args),
    /// Why did something happen and not something else? A counterfactual search
    /// over the explanation model of the tick (Love et al.).
    Why(why::Args),
    /// Evaluations: `btx eval recovery random` (Love et al.'s Table 2).
    Eval(eval::Args),
    /// Print the explanation model (causal graph) of a tick of a session.
    Graph(graph::Args),
    /// Compare two trees or runs subgoal by subgoal (Han et al.'s expected vs
    /// actual policy), or one reference with several runs.
    Diff(diff::Args),
    /// A fleet's runs at once: per node, the runs it failed in, what recovered it and how long it kept RUNNING; per run, how it ended and what went wrong; the failures grouped by cause.
    Fleet(fleet::Args),
    /// List the status transitions of a session, like Groot's table.
    Log(log::Args),
    /// Serve a recorded run (session or log) over the Groot2 protocol, as a robot that is running now, for Groot2, btview or btx watch.
    Serve(serve::Args),
    /// Watch running robots (BehaviorTree.CPP 4 over Groot2, BehaviorTree.CPP 3 and Nav2 Humble over Groot 1): tell each fault as it happens, what handles it and whether that worked (or every transition, with --transitions), and keep each run as a session.
    Watch(watch::Args),
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
        // A file's name that holds a line break cannot start a line.
        e.location = visible(&btx::text::one_line(&e.location)).into_owned();
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
            } else {
                let name = visible(&btx::text::one_line(src.name())).into_owned();
                let clean = same_length(text).into_owned();
                e.source_code = Some(miette::NamedSource::new(name, clean));
            }
        }
        Failure::Located(miette::Report::new(e))
    }
}

/// The longest line an error shows with its source (bytes): an error quotes
/// at most a line's first few hundred bytes, and names file:line:column.
const LINE_SHOWN_MAX: usize = 400;

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

/// Set by a command that records (`btx watch`): a closed standard output
/// then no longer ends btx, which finishes its recording (`stdout_closed`).
static RECORDING: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether standard output was closed while recording.
fn stdout_closed() -> bool {
    STDOUT_CLOSED.load(std::sync::atomic::Ordering::Relaxed)
}

/// The end of a write to standard output: a closed pipe ends btx quietly
/// (exit 0), unless it records, any other failure with a message (exit 1).
fn written(r: std::io::Result<()>) {
    if let Err(e) = r {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            if RECORDING.load(std::sync::atomic::Ordering::Relaxed) {
                STDOUT_CLOSED.store(true, std::sync::atomic::Ordering::Relaxed);
                return;
            }
            std::process::exit(0);
        }
        err_out(&format!("error: cannot write the output: {e}\n"));
        std::process::exit(1);
    }
}

fn err_out(s: &str) {
    err_raw(&btx::text::visible(s));
}

/// Standard error as given: btx's own cursor codes, around text escaped
/// by `err_out`'s rule.
fn err_raw(s: &str) {
    use std::io::Write;
    let _ = std::io::stderr().write_all(s.as_bytes());
}

macro_rules! fail {
    ($($t:tt)*) => { return Err(Failure::Plain(format!($($t)*))) };
}

/// A number of seconds an option takes: finite, 0 or more (clap refuses
/// the rest with this message, naming the option).
pub fn seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err(format!(
            "\"{s}\" is not a number of seconds: give 0 or more, e.g. 2.5"
        )),
    }
}

/// A factor an option takes: finite and more than 0.
pub fn positive(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("\"{s}\" is not a positive number, e.g. 2 or 0.5")),
    }
}

/// `--detail`: how much an answer says.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum DetailArg {
    Brief,
    Normal,
    Full,
}

impl From<DetailArg> for btx::ask::Detail {
    fn from(d: DetailArg) -> Self {
        match d {
            DetailArg::Brief => btx::ask::Detail::Brief,
            DetailArg::Normal => btx::ask::Detail::Normal,
            DetailArg::Full => btx::ask::Detail::Full,
        }
    }
}

/// The options every command takes.
pub struct Globals {
    pub quiet: bool,
    pub keys: Option<PathBuf>,
    pub ascii: bool,
}

// One module a command, as ripgrep and cargo keep them; declared after the
// printing macros so that they use them.
mod ask;
mod diff;
mod eval;
mod fleet;
mod graph;
mod import;
mod log;
mod open;
mod printer;
mod run;
mod screenshot;
mod serve;
mod tree;
mod watch;
mod why;
mod world;

fn warn_all(quiet: bool, warnings: &[btx::Warning]) {
    if !quiet {
        for w in warnings {
            eprintln!("{w}");
        }
    }
}

fn open_input(file: &Path, reading: &Reading, quiet: bool) -> Result<Input, Failure> {
    let input = open(file, &reading.options()?).map_err(located)?;
    warn_all(quiet, input.warnings());
    Ok(input)
}

/// An input's error, drawn by miette (with the offending line, where it
/// has one).
fn located(e: btx::Located) -> Failure {
    Failure::from(e)
}

fn session_of<'a>(input: &'a Input, file: &Path) -> Result<&'a Session, Failure> {
    match input.session() {
        Some(s) if s.index.ticks() > 0 => Ok(s),
        Some(_) => fail!("{}: the session recorded no tick", btx::text::path(file)),
        None => fail!(
            "{} is a tree; a why-question is about a run: give a session (btx run … --out SESSION) or a log",
            btx::text::path(file)
        ),
    }
}

fn pick_node(tree: &btx::Tree, pick: &str) -> Result<btx::Uid, Failure> {
    pick::pick(tree, pick).map_err(|e| Failure::Plain(e.to_string()))
}

/// Runs a command line: the demo with none, else its command's module.
fn dispatch(cli: Cli) -> Result<(), Failure> {
    let with = |e: &Explorer| Globals {
        quiet: cli.quiet,
        keys: e.keys.clone(),
        ascii: e.ascii,
    };
    let globals = with(&cli.explorer);
    let Some(command) = cli.command else {
        if !cli.files.is_empty() {
            return open::run(open::Args::of(cli.files), &globals);
        }
        let mut app = btx::tui::demo();
        app.shared.keymap = keymap(globals.keys.as_deref())?;
        return btx::tui::run_with(&mut app, globals.ascii)
            .map_err(|e| Failure::Plain(format!("the terminal: {e}")));
    };
    let before = cli.explorer;
    match command {
        Command::Open(mut a) => {
            a.explorer = std::mem::take(&mut a.explorer).or(&before);
            let globals = with(&a.explorer);
            open::run(a, &globals)
        }
        Command::Fleet(mut a) => {
            a.explorer = std::mem::take(&mut a.explorer).or(&before);
            let globals = with(&a.explorer);
            fleet::run(a, &globals)
        }
        Command::Tree(a) => tree::run(a, &globals),
        Command::Ask(a) => ask::run(a, &globals),
        Command::Run(a) => run::run(a, &globals),
        Command::Import(a) => import::run(a, &globals),
        Command::World(a) => world::run(a),
        Command::Screenshot(a) => screenshot::run(a),
        Command::Why(a) => why::run(a, &globals),
        Command::Eval(a) => eval::run(a),
        Command::Graph(a) => graph::run(a, &globals),
        Command::Diff(a) => diff::run(a, &globals),
        Command::Log(a) => log::run(a, &globals),
        Command::Watch(a) => watch::run(a, &globals),
        Command::Serve(a) => serve::run(a, &globals),
    }
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

fn pretty(v: &serde_json::Value) -> String {
    let mut s = serde_json::to_string_pretty(v).expect("JSON values serialise");
    s.push('\n');
    s
}

/// The exit status of a command, its error printed (sanitised).
fn finish(result: Result<(), Failure>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Located(report)) => {
            // Its text was made safe when it was built; miette may colour it.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "{}", format!("{report:?}").trim_end());
            ExitCode::FAILURE
        }
        Err(Failure::Plain(msg)) => {
            // In the style of every other error (miette's), made safe here.
            use std::io::Write;
            let report = miette::Report::msg(btx::text::visible(&msg).into_owned());
            let _ = writeln!(std::io::stderr(), "{}", format!("{report:?}").trim_end());
            ExitCode::FAILURE
        }
        Err(Failure::Exit(code)) => ExitCode::from(code),
    }
}

/// Runs a parsed command line to its exit status.
pub fn main(cli: Cli) -> ExitCode {
    // Errors unwrapped: a list of nodes or files keeps a line an item (the
    // terminal wraps what is longer).
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(miette::MietteHandlerOpts::new().wrap_lines(false).build())
    }));
    finish(dispatch(cli))
}
