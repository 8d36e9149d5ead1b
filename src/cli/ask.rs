//! `btx ask`: Ask questions about a node of a tree, or about a moment of a session.

use super::*;

#[derive(clap::Args)]
pub struct Args {
    /// A tree file, or a session (with --live: none, every word is a question).
    #[arg(value_name = "FILE")]
    pub file: Option<PathBuf>,
    /// Ask a robot running now (default 127.0.0.1:1667; BehaviorTree.CPP 4's Groot2 or 3's Groot 1 protocol) about the present moment: its nodes' statuses, read once; nothing is recorded, so a client that records is not disturbed.
    #[arg(long, value_name = "[HOST][:PORT]", num_args = 0..=1, default_missing_value = "", conflicts_with = "at")]
    pub live: Option<String>,
    /// A BehaviorTree.CPP 3 robot's publisher port (Groot 1's protocol; Nav2 Humble's groot_zmq_publisher_port), when it is not the one below the server's.
    #[arg(long, value_name = "PORT", requires = "live")]
    pub publisher_port: Option<u16>,
    #[command(flatten)]
    pub reading: Reading,
    /// The moment of a session: TICK (its end), TICK:STEP, last, end, or -N (-1: the last tick). Default: the end of the run.
    #[arg(long, value_name = "MOMENT", allow_hyphen_values = true)]
    pub at: Option<String>,
    /// The node: #uid, a description or ID, or a path like "go insert large gear/detect chuck/lift torso".
    /// Default for a session: the current node at the moment.
    #[arg(long, value_name = "PICK")]
    pub node: Option<String>,
    /// Questions, in your own words ("why did look at chuck fail?", "what happened at tick 10?", "did the recovery work?") or the paper's wording, "Can you X?", or q1 q2 q3 q4 q5 q5-goal anything-wrong wrong handled.
    #[arg(value_name = "QUESTION")]
    pub questions: Vec<String>,
    /// How much to say: brief (the restated question and the cause), normal, or full (every explanation, and what the run shows of each node it rests on).
    #[arg(long, value_enum, default_value = "normal")]
    pub detail: DetailArg,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

pub fn run(args: Args, cli: &Globals) -> Result<(), Failure> {
    let Args {
        file,
        live,
        publisher_port,
        reading,
        at,
        node,
        questions,
        detail,
        format,
    } = args;
    let detail = detail.into();
    if let Some(ep) = live {
        let (ep, words) = live_words(ep, file, questions);
        return live_ask(
            &ep,
            publisher_port,
            node.as_deref(),
            &words,
            (format, detail),
            cli.quiet,
        );
    }
    let Some(file) = file else {
        fail!("name a tree or a session to ask about (or --live to ask a running robot)");
    };
    if questions.is_empty() {
        fail!("ask at least one question, e.g. \"What are you doing?\" or q1");
    }
    let input = open_input(&file, &reading, cli.quiet)?;
    let tree = input.tree();
    let view = match input.session() {
        Some(s) => Some(moment_asked(s, at.as_deref(), &file)?),
        None if at.is_some() => fail!(
            "--at picks a moment of a run, and {} is a tree, not a session",
            btx::text::path(&file)
        ),
        None => None,
    };
    let uid = match &node {
        Some(p) => Some(node_asked(tree, p, format)?),
        None => None,
    };
    let cx = btx::ask::Context {
        tree,
        session: input.session(),
        tick: view.as_ref().map(|(_, t)| *t),
        at: view.map(|(a, _)| a),
        node: uid,
        detail,
        last: Default::default(),
    };
    print_replies(&cx, &questions, format)
}

/// `--live [HOST] Q…`: the robot's address, and the questions. A first word
/// that is a question (a shortcut, or words) is not a host: a host has a
/// port or a dot, or is one word.
fn live_words(
    ep: String,
    file: Option<std::path::PathBuf>,
    questions: Vec<String>,
) -> (String, Vec<String>) {
    let question = btx::explain::Question::parse(&ep).is_some()
        || ep.trim().contains(char::is_whitespace)
        || ep.trim_end().ends_with('?');
    let (ep, first) = if question && !ep.contains([':', '.']) {
        (String::new(), Some(ep))
    } else {
        (ep, None)
    };
    let words: Vec<String> = first
        .into_iter()
        .chain(file.map(|f| f.display().to_string()))
        .chain(questions)
        .collect();
    (ep, words)
}

/// The run at the moment `--at` names (default: its end).
fn moment_asked<'s>(
    s: &'s btx::session::Session,
    at: Option<&str>,
    file: &std::path::Path,
) -> Result<(btx::session::At<'s>, u32), Failure> {
    let m = match at {
        Some(a) => s.moment_at(a).map_err(Failure::Plain)?,
        None => Moment {
            tick: s.index.ticks().max(1),
            step: None,
        },
    };
    if s.index.ticks() == 0 {
        fail!("{}: the session recorded no tick", btx::text::path(file));
    }
    s.at(m).map(|a| (a, m.tick)).map_err(Failure::Plain)
}

/// The node `--node` names; where several answer to the name, the text
/// says which one is meant.
fn node_asked(tree: &btx::Tree, p: &str, format: Format) -> Result<btx::model::Uid, Failure> {
    let (uid, others) =
        btx::pick::pick_among(tree, p).map_err(|e| Failure::Plain(e.to_string()))?;
    if !others.is_empty() && matches!(format, Format::Text) {
        let also: Vec<String> = others.iter().map(|u| format!("#{u}")).collect();
        println!(
            "About #{uid} {} (\"{}\" also names {}):",
            btx::text::visible(&tree.display_path(uid)),
            btx::text::visible(p.trim()),
            btx::explain::han::and_list(&also)
        );
    }
    Ok(uid)
}

/// Asks each question in turn and prints the answers; exit status 1 when
/// one was not answered (not understood, no such node, a run question of
/// a tree), after printing them all.
fn print_replies(
    cx: &btx::ask::Context,
    questions: &[String],
    format: Format,
) -> Result<(), Failure> {
    let replies: Vec<btx::ask::Reply> = questions.iter().map(|q| btx::ask::ask(cx, q)).collect();
    match format {
        Format::Text => {
            for r in &replies {
                println!("{}", r.text());
            }
        }
        Format::Json => {
            let node = cx
                .node
                .or_else(|| cx.at.as_ref().and_then(|a| a.current()))
                .map(|u| serde_json::json!({"uid": u, "description": cx.tree.description(u)}));
            let j = serde_json::json!({
                "schema": "btx.answers/1",
                "moment": cx.at.as_ref().map(|a| a.moment().to_string()),
                "node": node,
                "answers": replies.iter().map(|r| r.json(cx.tree)).collect::<Vec<_>>(),
            });
            print!("{}", pretty(&j));
        }
    }
    let unanswered = replies.iter().filter(|r| !r.answered).count();
    if unanswered > 0 {
        fail!(
            "{unanswered} of {} question{} not answered",
            replies.len(),
            if replies.len() == 1 { " was" } else { "s were" }
        );
    }
    Ok(())
}

/// `--live`: the robot's tree (`T`) and its nodes' states now (`S`), as a
/// run recorded from this moment with no transition yet: every answer is
/// about the present, and what came before is unknown, and said so.
fn live_ask(
    ep: &str,
    publisher: Option<u16>,
    node: Option<&str>,
    words: &[String],
    (format, detail): (Format, btx::ask::Detail),
    quiet: bool,
) -> Result<(), Failure> {
    if words.is_empty() {
        fail!("ask at least one question, e.g. btx ask --live :1667 wrong");
    }
    let ep = btx::live::groot2::endpoint(ep);
    let s = btx::live::snapshot(&ep, publisher).map_err(|e| Failure::Plain(e.to_string()))?;
    warn_all(quiet, &s.warnings);
    let view = btx::session::At {
        index: &s.index,
        pos: 0,
    };
    let uid = match node {
        Some(p) => Some(pick_node(&s.tree, p)?),
        None => match view.current() {
            Some(u) => Some(u),
            None => fail!("{ep}: nothing is running on the robot now; pick a node with --node"),
        },
    };
    let cx = btx::ask::Context {
        tree: &s.tree,
        session: None,
        at: Some(view),
        tick: None,
        node: uid,
        detail,
        last: Default::default(),
    };
    print_replies(&cx, words, format)
}
