//! The explorer at scale: one `update` + `view` into a TestBackend, on a
//! 10,000-node tree with a 1,000,000-transition session.

use btx::run::plan::{Plan, PlanLeaves};
use btx::run::RunOptions;
use btx::session::record::{record, RunRequest};
use btx::session::{Session, Source};
use btx::tui::{Action, App};
use btx::xml::{load_str, LoadOptions};
use criterion::{criterion_group, criterion_main, Criterion};
use ratatui::backend::TestBackend;
use ratatui::Terminal;
use std::path::{Path, PathBuf};

#[path = "generated.rs"]
mod generated;

fn big_session() -> PathBuf {
    let dir = std::env::var("BTX_BENCH_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| std::env::temp_dir().join("btx-bench"));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.jsonl");
    if out.exists() {
        return out;
    }
    let xml = generated::generated_tree(10_000)
        .replace(
            "<BehaviorTree ID=\"Main\">",
            "<BehaviorTree ID=\"Main\"><Repeat num_cycles=\"-1\">",
        )
        .replacen(
            "</Sequence></BehaviorTree>",
            "</Sequence></Repeat></BehaviorTree>",
            1,
        );
    let tree = load_str(Path::new("deep.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(
        Path::new("b.plan"),
        "@default_action = 1RS\n@default_condition = S",
    )
    .unwrap();
    let req = RunRequest {
        tree: &tree,
        tree_file: None,
        source: Source {
            kind: "plan".into(),
            path: None,
            text: None,
            name: None,
        },
        seed: None,
        max_ticks: 250_000,
        options: RunOptions::default(),
        ask: None,
        out: &out,
    };
    record(req, PlanLeaves::new(plan, &tree)).unwrap();
    out
}

fn frames(c: &mut Criterion) {
    let s = Session::load(&big_session()).unwrap();
    eprintln!(
        "session: {} transitions on a {}-node tree",
        s.index.transitions.len(),
        s.tree.len()
    );
    let tree = s.tree.clone();
    let mut app = App::new(tree, Some(s), "bench".into());
    let mut term = Terminal::new(TestBackend::new(120, 40)).unwrap();
    let mut g = c.benchmark_group("frame on 10k nodes, 1M transitions");
    g.bench_function("step forward + draw", |b| {
        b.iter(|| {
            app.update(Action::StepForward);
            term.draw(|f| btx::tui::view::view(&app, f)).unwrap();
        })
    });
    g.bench_function("tick back + draw", |b| {
        b.iter(|| {
            app.update(Action::TickBack);
            term.draw(|f| btx::tui::view::view(&app, f)).unwrap();
        })
    });
    g.bench_function("scroll down + draw", |b| {
        b.iter(|| {
            app.update(Action::Down);
            term.draw(|f| btx::tui::view::view(&app, f)).unwrap();
        })
    });
    g.bench_function("jump to the end + draw", |b| {
        b.iter(|| {
            app.update(Action::End);
            term.draw(|f| btx::tui::view::view(&app, f)).unwrap();
            app.update(Action::Start);
        })
    });
    g.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
