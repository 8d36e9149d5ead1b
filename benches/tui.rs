//! The explorer at scale: one `update` + `view` into a TestBackend, on a
//! 10,000-node tree with a 1,000,000-transition session.

use btx::session::Session;
use btx::tui::{Action, App};
use criterion::{criterion_group, criterion_main, Criterion};
use ratatui::backend::TestBackend;
use ratatui::Terminal;

#[path = "support/generated.rs"]
mod generated;

fn frames(c: &mut Criterion) {
    let s = Session::load(&generated::big_session()).unwrap();
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
            term.draw(|f| app.draw(f)).unwrap();
        })
    });
    g.bench_function("tick back + draw", |b| {
        b.iter(|| {
            app.update(Action::TickBack);
            term.draw(|f| app.draw(f)).unwrap();
        })
    });
    g.bench_function("scroll down + draw", |b| {
        b.iter(|| {
            app.update(Action::Down);
            term.draw(|f| app.draw(f)).unwrap();
        })
    });
    g.bench_function("jump to the end + draw", |b| {
        b.iter(|| {
            app.update(Action::End);
            term.draw(|f| app.draw(f)).unwrap();
            app.update(Action::Start);
        })
    });
    g.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
