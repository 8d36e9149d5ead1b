//! The `btx` command line: a thin shell over the library.

use btx::explain::{han, Question};
use btx::frame::Framed;
use btx::xml::{load_file, LoadOptions, Loaded};
use btx::{export, pick, Version};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "btx",
    version,
    about = "Explain behaviour-tree runs: BehaviorTree.CPP trees, framed and questioned"
)]
struct Cli {
    /// Do not print warnings.
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum TreeFormat {
    Text,
    Json,
    Dot,
    Xml,
}

#[derive(Clone, Copy, ValueEnum)]
enum AnswerFormat {
    Text,
    Json,
}

#[derive(clap::Args)]
struct TreeSource {
    /// A BehaviorTree.CPP XML file (v3 or v4).
    file: PathBuf,
    /// Run this <BehaviorTree> instead of the file's main tree.
    #[arg(long, value_name = "ID")]
    main_tree: Option<String>,
    /// Read the file by BehaviorTree.CPP 3 or 4 rules (default: its BTCPP_format).
    #[arg(long, value_name = "3|4", value_parser = ["3", "4"])]
    btcpp: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Print a tree: the full tree, or the framed tree (--framed).
    Tree {
        #[command(flatten)]
        source: TreeSource,
        /// Show the framed tree and the semantic sets {goal, subgoals, steps, actions}.
        #[arg(long)]
        framed: bool,
        #[arg(long, value_enum, default_value = "text")]
        format: TreeFormat,
    },
    /// Ask Han et al.'s questions about a node.
    Ask {
        #[command(flatten)]
        source: TreeSource,
        /// The node: #uid, a description or ID, or a path like "go insert large gear/detect chuck/lift torso".
        #[arg(long, value_name = "PICK")]
        node: String,
        /// Questions: the paper's wording or q1, q2, q3, q4, q5-subgoal, q5-goal.
        #[arg(required = true, value_name = "QUESTION")]
        questions: Vec<String>,
        #[arg(long, value_enum, default_value = "text")]
        format: AnswerFormat,
    },
}

fn load(source: &TreeSource, quiet: bool) -> Result<Loaded, Failure> {
    let opts = LoadOptions {
        version: source
            .btcpp
            .as_deref()
            .map(|v| if v == "3" { Version::V3 } else { Version::V4 }),
        main_tree: source.main_tree.clone(),
    };
    let loaded = load_file(&source.file, &opts)?;
    if !quiet {
        for w in &loaded.warnings {
            eprintln!("{w}");
        }
    }
    Ok(loaded)
}

/// What went wrong: located input errors are drawn by miette with the
/// offending line; the others are one plain message (lists stay unwrapped).
enum Failure {
    Located(miette::Report),
    Plain(String),
}

impl From<miette::Report> for Failure {
    fn from(r: miette::Report) -> Self {
        Failure::Located(r)
    }
}

impl From<btx::Located> for Failure {
    fn from(e: btx::Located) -> Self {
        Failure::Located(miette::Report::new(e))
    }
}

macro_rules! fail {
    ($($t:tt)*) => { return Err(Failure::Plain(format!($($t)*))) };
}

fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Tree {
            source,
            framed,
            format,
        } => {
            let tree = load(&source, cli.quiet)?.tree;
            let out = match (framed, format) {
                (false, TreeFormat::Text) => export::tree_text(&tree),
                (false, TreeFormat::Json) => pretty(&export::tree_json(&tree)),
                (false, TreeFormat::Dot) => export::tree_dot(&tree),
                (_, TreeFormat::Xml) => {
                    if framed {
                        fail!("the framed tree is a view, not a runnable tree: drop --framed to write XML");
                    }
                    btx::xml::to_v4_xml(&tree)
                }
                (true, f) => {
                    let fr = Framed::new(&tree);
                    match f {
                        TreeFormat::Json => pretty(&export::framed_json(&tree, &fr)),
                        TreeFormat::Dot => export::framed_dot(&tree, &fr),
                        _ => export::framed_text(&tree, &fr),
                    }
                }
            };
            print!("{out}");
        }
        Command::Ask {
            source,
            node,
            questions,
            format,
        } => {
            let tree = load(&source, cli.quiet)?.tree;
            let mut qs = Vec::new();
            for q in &questions {
                match Question::parse(q) {
                    Some(q) => qs.push(q),
                    None => {
                        let known: Vec<String> = Question::ALL
                            .iter()
                            .map(|q| format!("\"{}\" ({})", q.wording(), q.short()))
                            .collect();
                        fail!("unknown question \"{q}\"; ask one of: {}", known.join(", "));
                    }
                }
            }
            let uid = match pick::pick(&tree, &node) {
                Ok(uid) => uid,
                Err(e) => return Err(Failure::Plain(e.to_string())),
            };
            let answers: Vec<_> = qs.into_iter().map(|q| han::answer(&tree, uid, q)).collect();
            match format {
                AnswerFormat::Text => {
                    for a in &answers {
                        println!("{}", a.text);
                    }
                }
                AnswerFormat::Json => {
                    print!("{}", pretty(&export::answers_json(&tree, uid, &answers)))
                }
            }
        }
    }
    Ok(())
}

fn pretty(v: &serde_json::Value) -> String {
    let mut s = serde_json::to_string_pretty(v).expect("JSON values serialise");
    s.push('\n');
    s
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Located(report)) => {
            eprintln!("{report:?}");
            ExitCode::FAILURE
        }
        Err(Failure::Plain(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::FAILURE
        }
    }
}
