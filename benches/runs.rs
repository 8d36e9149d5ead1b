//! Running trees and reading sessions: executor ticks per second on a
//! 10,000-node tree; loading a 1,000,000-transition session; moving to a
//! random moment of it.

use btx::run::plan::{Plan, PlanLeaves};
use btx::run::{Executor, RunOptions, Status};
use btx::session::{Moment, Session};
use btx::xml::{load_str, LoadOptions};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use std::hint::black_box;
use std::path::Path;

#[path = "support/generated.rs"]
mod generated;

fn plan(text: &str) -> Plan {
    Plan::parse(Path::new("bench.plan"), text).unwrap()
}

fn executor(c: &mut Criterion) {
    // Every leaf succeeds at once: each tick runs the whole tree and resets it.
    let xml = generated::flat_tree(99, 100);
    let tree = load_str(Path::new("flat.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    eprintln!("flat tree: {} nodes", tree.len());
    let mut g = c.benchmark_group("executor, 10k-node tree");
    g.bench_function("one tick through every node", |b| {
        b.iter_batched(
            || {
                Executor::new(
                    &tree,
                    PlanLeaves::new(plan("@default_action = S"), &tree),
                    RunOptions::default(),
                )
            },
            |mut ex| {
                let s = ex.tick_once().unwrap();
                assert_eq!(s, Status::Success);
                ex.take_events().len()
            },
            BatchSize::SmallInput,
        )
    });
    // Realistic: one leaf runs for a tick at a time, in a deep kitting-like tree.
    let xml = generated::generated_tree(10_000);
    let deep = load_str(Path::new("deep.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    g.bench_function("100 ticks, one RUNNING leaf at a time", |b| {
        b.iter_batched(
            || {
                Executor::new(
                    &deep,
                    PlanLeaves::new(plan("@default_action = 1RS\n@default_condition = S"), &deep),
                    RunOptions::default(),
                )
            },
            |mut ex| {
                for _ in 0..100 {
                    ex.tick_once().unwrap();
                }
                ex.take_events().len()
            },
            BatchSize::SmallInput,
        )
    });
    g.finish();
}

fn sessions(c: &mut Criterion) {
    let path = generated::big_session();
    let s = Session::load(&path).unwrap();
    eprintln!(
        "session: {} transitions, {} ticks, {} bytes",
        s.index.transitions.len(),
        s.index.ticks(),
        std::fs::metadata(&path).unwrap().len()
    );
    let mut g = c.benchmark_group("1M-transition session");
    g.sample_size(10);
    g.bench_function("load", |b| {
        b.iter(|| {
            Session::load(black_box(&path))
                .unwrap()
                .index
                .transitions
                .len()
        })
    });
    let ticks = s.index.ticks();
    let mut x: u64 = 12345;
    g.bench_function(
        "move to a random moment (position, current node, 100 statuses)",
        |b| {
            b.iter(|| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let m = Moment {
                    tick: 1 + (x >> 33) as u32 % ticks,
                    step: None,
                };
                let at = s.index.at(s.index.position(m).unwrap());
                let cur = at.current().unwrap_or(1);
                let mut k = 0u32;
                for u in cur..cur + 100 {
                    if let Some(_n) = s.tree.get(u) {
                        k += at.status(u) as u32;
                    }
                }
                k
            })
        },
    );
    g.finish();
}

/// #31 item 1: `btx run` on a deep chain of SubTrees within 2× of loading
/// it (a scope's path rebuilt level by level made it cubic: 11.6 s).
fn deep_chain(c: &mut Criterion) {
    let xml = generated::subtree_chain(3_332);
    let load = || {
        load_str(Path::new("chain.xml"), &xml, &LoadOptions::default())
            .unwrap()
            .tree
    };
    let mut g = c.benchmark_group("a chain of 3,332 SubTrees");
    g.sample_size(10);
    g.bench_function("load", |b| b.iter(|| load().len()));
    g.bench_function("load, then run one tick", |b| {
        b.iter(|| {
            let t = load();
            let mut ex = Executor::new(&t, PlanLeaves::new(plan(""), &t), RunOptions::default());
            ex.tick_once().unwrap();
            ex.take_events().len()
        })
    });
    g.finish();
}

criterion_group!(benches, executor, sessions, deep_chain);
criterion_main!(benches);
