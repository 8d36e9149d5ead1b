//! Counterfactual explanations: one query on the case study and one on the
//! serial-recall model, and the whole target-recovery sweeps (btcm needs
//! 110 s for its 1800 random comparisons and 680 s for the 200
//! serial-recall ones on this machine kind).

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
    let s = Session::load(Path::new("sessions/serial-recall.jsonl")).unwrap();
    let d = causal::session_domain(&s, None).unwrap();
    g.bench_function(
        "serial recall: why did RepeatOrEnd end the sequence (tick 2)",
        |b| {
            b.iter(|| {
                let w = causal::why(
                    &s,
                    d.clone(),
                    "decision(RepeatOrEnd)",
                    &[],
                    Some(Moment::parse("2").unwrap()),
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
    g.bench_function("serial recall, 200 comparisons", |b| {
        b.iter(|| {
            let rows = eval::recovery_serial_recall(50).unwrap();
            assert_eq!(rows.len(), 200);
            black_box(rows.len())
        })
    });
    g.finish();
}

criterion_group!(benches, queries, sweeps);
criterion_main!(benches);
