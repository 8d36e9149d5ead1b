//! `btx run`: Run a tree tick by tick and record the run as a session.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A BehaviorTree.CPP XML file (v3 or v4).
    pub tree: PathBuf,
    #[command(flatten)]
    pub reading: Reading,
    /// Scripted leaf outcomes (`key = S, F, 2RS, 1RF`).
    #[arg(long, value_name = "FILE", group = "leaves", required_unless_present_any = ["domain", "world"])]
    pub plan: Option<PathBuf>,
    /// A domain file (state variables and leaf functions).
    #[arg(long, value_name = "FILE", group = "leaves")]
    pub domain: Option<PathBuf>,
    /// A built-in world.
    #[arg(long, value_enum, group = "leaves")]
    pub world: Option<World>,
    /// Start with a value set (repeatable): with --domain a state variable (UserMemory=0.0), with --plan a root blackboard entry (goal=3, @mode="fast").
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    #[arg(long, value_name = "N", default_value_t = 10_000)]
    pub max_ticks: u32,
    /// Simulated milliseconds between ticks (Timeout, Delay, Sleep).
    #[arg(long, value_name = "MS", default_value_t = 10)]
    pub tick_ms: u64,
    /// The Nav2 release whose control and decorator nodes to follow where their sources differ (RoundRobin): humble, jazzy or main.
    #[arg(long, value_name = "RELEASE", default_value = "main", value_parser = parse_release)]
    pub nav2: btx::model::nav2::Release,
    /// Ask "Can you X?" at the end of tick MOMENT; a yes inserts the subgoal and the run goes on with it.
    #[arg(long, num_args = 2, value_names = ["MOMENT", "QUESTION"])]
    pub ask_at: Option<Vec<String>>,
    /// The session file to write (never overwritten): JSON lines, or Parquet if it ends in .parquet.
    #[arg(long, value_name = "SESSION")]
    pub out: PathBuf,
}

fn parse_release(s: &str) -> Result<btx::model::nav2::Release, String> {
    btx::model::nav2::Release::parse(s)
        .ok_or_else(|| format!("\"{s}\" is not a Nav2 release btx knows: humble, jazzy or main"))
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        tree: path,
        reading,
        plan,
        domain,
        world,
        set,
        seed,
        max_ticks,
        tick_ms,
        nav2,
        ask_at,
        out,
    } = args;
    if let Some(t) = &reading.run_tree {
        fail!(
            "--tree {} is for reading a log with the tree its robot ran; btx run runs the tree file it is given ({})",
            btx::text::path(t),
            btx::text::path(&path)
        );
    }
    let _claim = btx::session::OutputLock::take(&out, "btx run")?;
    let text = btx::source::read_text(&path, btx::source::TEXT_SIZE_MAX, "the tree file")?;
    let loaded = btx::xml::load_str(&path, &text, &reading.options()?)?;
    warn_all(cli.quiet, &loaded.warnings);
    let tree = loaded.tree;
    let ask = ask_at.map(|v| asked_during(&v)).transpose()?;
    let req = |source: Source| RunRequest {
        tree: &tree,
        tree_file: Some((&path, &text)),
        source,
        seed: Some(seed),
        max_ticks,
        options: RunOptions { tick_ms, nav2 },
        ask: ask.clone(),
        out: &out,
    };
    let asked_at = ask.as_ref().map(|a| a.tick);
    if !set.is_empty() && domain.is_none() && plan.is_none() {
        fail!("--set starts a domain's state variable or a plan's blackboard entry, and a world has neither: it would change nothing");
    }
    match chosen_leaves(plan.as_deref(), domain.as_deref(), world, seed, &tree)? {
        Chosen::Plan(source, plan) => {
            let mut leaves = PlanLeaves::new(plan, &tree);
            for a in &set {
                leaves.seed(a).map_err(Failure::Plain)?;
            }
            warn_all(cli.quiet, &leaves.warnings);
            report_run(&tree, asked_at, record(req(source), leaves))
        }
        Chosen::Domain(source, d) => {
            let mut leaves = DomainLeaves::new(d, &tree)?;
            for a in &set {
                leaves.set(a).map_err(Failure::Plain)?;
            }
            report_run(&tree, asked_at, record(req(source), leaves))
        }
        Chosen::Taxi(source) => report_run(
            &tree,
            asked_at,
            record(req(source), TaxiLeaves::new(Grid::han())),
        ),
    }
}

/// Where a run's leaves come from, and the session's record of it.
enum Chosen {
    /// A plan file, or a kitting scenario's plan.
    Plan(Source, Plan),
    Domain(Source, std::sync::Arc<Domain>),
    Taxi(Source),
}

/// Loads the one source of leaves the command line names.
fn chosen_leaves(
    plan: Option<&std::path::Path>,
    domain: Option<&std::path::Path>,
    world: Option<World>,
    seed: u64,
    tree: &btx::model::Tree,
) -> Result<Chosen, Failure> {
    if let Some(p) = plan {
        let plan = Plan::load(p)?;
        return Ok(Chosen::Plan(
            source("plan", Some(p), Some(&plan.text), None),
            plan,
        ));
    }
    if let Some(p) = domain {
        let d = std::sync::Arc::new(Domain::load(p)?);
        let source = source("domain", Some(p), Some(&d.text), Some(d.name.clone()));
        return Ok(Chosen::Domain(source, d));
    }
    match world.expect("clap requires one source of leaves") {
        World::Taxi => {
            let unknown = TaxiLeaves::unknown_leaves(tree);
            if !unknown.is_empty() {
                fail!(
                    "the taxi world moves, picks up and drops off; it cannot run {}",
                    unknown.join(", ")
                );
            }
            Ok(Chosen::Taxi(source(
                "world",
                None,
                None,
                Some("taxi".into()),
            )))
        }
        World::Kitting => {
            let (name, plan) = kitting::scenario(seed).map_err(Failure::Plain)?;
            let name = format!("kitting: {name}");
            Ok(Chosen::Plan(
                source("world", None, Some(&plan.text), Some(name)),
                plan,
            ))
        }
    }
}

/// `--ask-at TICK "Can you X?"`: the question asked between ticks.
fn asked_during(v: &[String]) -> Result<btx::session::record::Asked, Failure> {
    let m = Moment::parse(&v[0]).map_err(Failure::Plain)?;
    if m.step.is_some() {
        fail!("--ask-at takes a whole tick: a run is asked between ticks");
    }
    match Question::parse(&v[1]) {
        Some(Question::CanYou(_)) => {}
        _ => fail!(
            "--ask-at asks \"Can you X?\"; other questions are asked of the session with btx ask"
        ),
    }
    Ok(btx::explain::insert::asked_during_run(m.tick, &v[1]))
}

/// Where a run's leaves came from, as the session's header says it.
fn source(
    kind: &str,
    path: Option<&std::path::Path>,
    text: Option<&str>,
    name: Option<String>,
) -> Source {
    Source {
        kind: kind.into(),
        path: path.map(|p| btx::text::path(p).to_string()),
        text: text.map(str::to_string),
        name,
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
                btx::text::path(&s.path),
                s.ticks,
                s.transitions,
                s.root,
                s.reason
            );
            Ok(())
        }
        Err(RecordError::Io(e)) => Err(e.into()),
        Err(RecordError::Script(e, s)) => {
            eprintln!("the run up to the error is in {}", btx::text::path(&s.path));
            Err(e.into())
        }
        Err(RecordError::Run(e, s)) => {
            let (file, line, col) = tree.location(e.uid);
            fail!(
                "{file}:{line}:{col}: {e}\nthe run up to here is in {}",
                btx::text::path(&s.path)
            );
        }
    }
}
