//! Faults said as they happen (#40): what `btx watch` spends on each
//! transition to tell faults from branches, find what handles them and see
//! the handling end. The recorded kitting run whose look at chuck fails
//! once (248 transitions, one fault, one recovery, one run's end), fed
//! 4,000 times over (992,000 transitions, 4,000 of each line): the cost a
//! transition, against the time of reading the same transitions' fields
//! only (the floor).

use btx::explain::alerts::{Alerts, Row};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;

const RUNS: usize = 4_000;

fn alerts(c: &mut Criterion) {
    let input = btx::input::open(
        Path::new("tests/fixtures/logs/kitting_lookat_fails_once.btlog"),
        &Default::default(),
    )
    .unwrap();
    let s = input.session().unwrap();
    let rows: Vec<Row> = btx::explain::alerts::rows(&s.index, &s.times_us).collect();
    let ticks = s.index.ticks();
    let mut g = c.benchmark_group("alerts");
    g.sample_size(10);
    g.throughput(criterion::Throughput::Elements((rows.len() * RUNS) as u64));
    g.bench_function("992,000 transitions read for faults", |b| {
        b.iter(|| {
            let mut a = Alerts::new(s.tree.clone());
            let mut said = 0;
            for k in 0..RUNS as u32 {
                for r in &rows {
                    let r = Row {
                        tick: r.tick + k * ticks,
                        ..*r
                    };
                    said += a.push(r).len();
                }
            }
            assert_eq!(said, 3 * RUNS);
            black_box(said)
        })
    });
    g.bench_function("992,000 transitions' fields read (the floor)", |b| {
        b.iter(|| {
            let mut sum = 0u64;
            for k in 0..RUNS as u32 {
                for r in &rows {
                    sum += u64::from(r.tick + k * ticks) ^ u64::from(r.uid) ^ r.status as u64;
                }
            }
            black_box(sum)
        })
    });
    g.finish();
}

criterion_group!(benches, alerts);
criterion_main!(benches);
