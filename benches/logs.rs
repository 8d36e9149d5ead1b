//! Opening a long log: a generated 1,000,000-record `.btlog` (the recorded
//! kitting run, repeated as a robot doing the task over and over), written
//! to `$TMPDIR/btx-bench/big.btlog` for `/usr/bin/time -v btx log` too.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::{Path, PathBuf};

const RECORDS: usize = 1_000_000;

/// The fixture's header, then its records again and again, each repetition
/// starting 10 ms after the last one ended.
fn big_btlog() -> PathBuf {
    let dir = std::env::temp_dir().join("btx-bench");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.btlog");
    if out.exists() {
        return out;
    }
    let src = std::fs::read("tests/fixtures/logs/kitting_nominal.btlog").unwrap();
    let n = i32::from_le_bytes(src[19..23].try_into().unwrap()) as usize;
    let (head, body) = src.split_at(31 + n);
    let recs: Vec<(u64, &[u8])> = body
        .chunks_exact(9)
        .map(|r| {
            let mut dt = [0u8; 8];
            dt[..6].copy_from_slice(&r[..6]);
            (u64::from_le_bytes(dt), &r[6..])
        })
        .collect();
    let span = recs.last().unwrap().0 + 10_000;
    let mut bytes = head.to_vec();
    bytes.reserve(RECORDS * 9);
    'outer: for rep in 0.. {
        for (dt, rest) in &recs {
            if (bytes.len() - head.len()) / 9 == RECORDS {
                break 'outer;
            }
            let t = dt + rep * span;
            bytes.extend_from_slice(&t.to_le_bytes()[..6]);
            bytes.extend_from_slice(rest);
        }
    }
    let tmp = out.with_extension("partial");
    std::fs::write(&tmp, &bytes).unwrap();
    std::fs::rename(&tmp, &out).unwrap();
    out
}

fn open(c: &mut Criterion) {
    let p = big_btlog();
    let bytes = std::fs::read(&p).unwrap();
    let mut g = c.benchmark_group("logs");
    g.sample_size(10);
    g.bench_function("open a 1,000,000-record .btlog (read, ticks, index)", |b| {
        b.iter(|| {
            let s = btx::logs::open_btlog(Path::new(&p), &bytes).unwrap();
            assert_eq!(s.index.transitions.len(), RECORDS);
            black_box(s.index.ticks())
        })
    });
    g.finish();
}

criterion_group!(benches, open);
criterion_main!(benches);
