//! Counterfactual explanations: one query on the case study, one on the
//! largest random models, and the whole random target-recovery sweep
//! (btcm needs 110 s for its 1800 comparisons on this machine kind).

use btx::causal::{self, eval};
use btx::session::{Moment, Session};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::sync::Arc;

fn queries(c: &mut Criterion) {
    let s = Session::load(Path::new("sessions/case-study.jsonl")).unwrap();
    let d = causal::session_domain(&s, None).unwrap();
    let mut g = c.benchmark_group("why");
    g.bench_function(
        "case study: why was X_c false (depth 2, model built)",
        |b| {
            b.iter(|| {
                let w = causal::why(
                    &s,
                    d.clone().map(|d| Arc::clone(&d)),
                    "X_c",
                    &[],
                    Some(Moment::parse("1:5").unwrap()),
                    2,
                )
                .unwrap();
                black_box(w.answer.explanations.len())
            })
        },
    );
    g.finish();
}

fn sweeps(c: &mut Criterion) {
    let mut g = c.benchmark_group("target recovery");
    g.sample_size(10);
    g.bench_function("random domains, 1800 comparisons", |b| {
        b.iter(|| {
            let rows = eval::recovery_random(10, false).unwrap();
            assert_eq!(rows.len(), 1800);
            black_box(rows.len())
        })
    });
    g.finish();
}

criterion_group!(benches, queries, sweeps);
criterion_main!(benches);
