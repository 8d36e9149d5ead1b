use super::*;
use crate::run::Status;

fn rec(time_us: i64) -> Record {
    Record {
        time_us,
        uid: 1,
        status: Status::Running,
        offset: 0,
    }
}

/// A fixture log's tree and records.
fn fixture_log(name: &str) -> (Tree, Vec<Record>) {
    let bytes = std::fs::read(format!(
        "{}/tests/fixtures/logs/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let path = std::path::Path::new("log.btlog");
    let raw = crate::logs::btlog::parse(path, &bytes).unwrap();
    let tree = crate::xml::load_str(
        path,
        &raw.xml,
        &crate::xml::LoadOptions {
            embedded: true,
            ..Default::default()
        },
    )
    .unwrap()
    .tree;
    let records = (raw.records.moves.iter().zip(&raw.records.times))
        .enumerate()
        .map(|(i, (&m, &time_us))| {
            let (uid, status) = crate::logs::btlog::unpack(m);
            Record {
                time_us,
                uid,
                status,
                offset: raw.first + 9 * i,
            }
        })
        .collect();
    (tree, records)
}

/// Records as the numbering reads them.
fn cols(recs: &[Record]) -> crate::logs::btlog::Columns {
    crate::logs::btlog::Columns::of(recs)
}

/// The fixture runs of the kitting tree one after the other, `times`
/// over, each later than the last.
fn kitting_runs(times: usize) -> (Tree, Vec<Record>) {
    let names = [
        "kitting_nominal.btlog",
        "kitting_lookat_fails_once.btlog",
        "kitting_grasp_check_fails_first.btlog",
        "kitting_detect_chuck_always_fails.btlog",
    ];
    let (tree, _) = fixture_log(names[0]);
    let mut out: Vec<Record> = Vec::new();
    for k in 0..times {
        let (_, recs) = fixture_log(names[k % names.len()]);
        let base = out.last().map_or(0, |r| r.time_us + 100_000);
        out.extend(recs.iter().map(|r| Record {
            time_us: base + r.time_us - recs[0].time_us,
            ..*r
        }));
    }
    (tree, out)
}

#[test]
fn a_long_log_replayed_in_pieces_is_numbered_as_in_one() {
    let (tree, recs) = kitting_runs(1200);
    assert!(recs.len() > PARALLEL_MIN);
    let cut = cuts(&tree, cols(&recs).view(), 3);
    assert_eq!(cut.len(), 4, "three pieces");
    let whole = by_structure_whole(&tree, cols(&recs).view()).unwrap();
    assert_eq!(
        by_structure_in(&tree, cols(&recs).view(), 3).unwrap(),
        whole
    );
    assert_eq!(
        by_structure_in(&tree, cols(&recs).view(), 2).unwrap(),
        whole
    );
}

#[test]
fn the_pause_between_two_runs_is_no_ticks() {
    // Runs 100 ms apart, ticks about 5 ms apart: the tree was reset
    // between them, not ticked, so run 2 starts at the next tick.
    let (tree, recs) = kitting_runs(2);
    let t = reconstruct(&tree, cols(&recs).view());
    let second = recs
        .iter()
        .enumerate()
        .skip(1)
        .find(|(_, r)| r.uid == Tree::ROOT && r.status == Status::Running)
        .map(|(i, _)| i)
        .unwrap();
    assert_eq!(t.numbers[second], t.numbers[second - 1] + 1);
    // Numbered as the records arrive, the same.
    let mut stream = Stream::new(&tree);
    let mut got = stream.push(&recs);
    got.extend(stream.finish());
    let numbers: Vec<u32> = got.iter().map(|x| x.1).collect();
    assert_eq!(numbers, t.numbers);
}

#[test]
fn runs_done_again_are_numbered_as_their_first_without_replaying_them() {
    let (tree, recs) = kitting_runs(41);
    let whole = by_structure_whole(&tree, cols(&recs).view()).unwrap();
    assert_eq!(
        by_distinct_runs(&tree, cols(&recs).view(), 1).unwrap(),
        whole
    );
    assert_eq!(
        by_distinct_runs(&tree, cols(&recs).view(), 3).unwrap(),
        whole
    );
    // A log cut inside its last run: that run is one of its own.
    let cut = &recs[..recs.len() - 7];
    let whole = by_structure_whole(&tree, cols(cut).view()).unwrap();
    assert_eq!(by_distinct_runs(&tree, cols(cut).view(), 2).unwrap(), whole);
    // No run done twice: nothing to spare, the log is replayed as it is.
    let (tree, once) = kitting_runs(4);
    assert_eq!(by_distinct_runs(&tree, cols(&once).view(), 2), None);
}

#[test]
fn a_piece_that_needs_the_state_before_it_is_replayed_with_it() {
    // Nav2's RoundRobin keeps the child it is at when the root
    // completes: a piece replayed from a fresh tree would start at the
    // first child. The log says the second, the piece cannot follow,
    // and the log is replayed in one piece, numbered right.
    let tree = crate::xml::load_str(
        std::path::Path::new("rr.xml"),
        r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
             <RoundRobin><AlwaysSuccess/><AlwaysSuccess/><AlwaysSuccess/></RoundRobin>
           </BehaviorTree></root>"#,
        &crate::xml::LoadOptions::default(),
    )
    .unwrap()
    .tree;
    let plan = crate::run::plan::Plan::parse(std::path::Path::new("p.plan"), "").unwrap();
    let leaves = crate::run::plan::PlanLeaves::new(plan, &tree);
    let mut ex = Executor::new(&tree, leaves, RunOptions::default());
    let (mut recs, mut truth) = (Vec::new(), Vec::new());
    while recs.len() <= PARALLEL_MIN {
        ex.tick_once().unwrap();
        for e in ex.take_events() {
            if let crate::run::Event::Transition {
                tick, uid, status, ..
            } = e
            {
                recs.push(Record {
                    time_us: tick as i64 * 1000,
                    uid,
                    status,
                    offset: 0,
                });
                truth.push(tick);
            }
        }
    }
    let cut = cuts(&tree, cols(&recs).view(), 2);
    assert_eq!(cut.len(), 3);
    let second = &recs[cut[1]..];
    assert!(
        by_structure_whole(&tree, cols(second).view()).is_err(),
        "the second piece cannot be replayed alone"
    );
    assert_eq!(
        by_structure_in(&tree, cols(&recs).view(), 2).unwrap(),
        truth
    );
}

#[test]
fn a_log_cut_inside_a_tick_keeps_its_structural_ticks() {
    let (tree, records) = fixture_log("kitting_lookat_fails_once.btlog");
    let full = reconstruct(&tree, cols(&records).view());
    assert_eq!((full.fell_back, full.capped), (None, None));
    for cut in [1, 5, 40, 100, records.len() - 1] {
        let part = reconstruct(&tree, cols(&records[..cut]).view());
        assert_eq!(part.fell_back, None, "cut at {cut}");
        assert_eq!(part.numbers[..], full.numbers[..cut], "cut at {cut}");
    }
}

#[test]
fn a_short_run_that_goes_quiet_is_numbered_without_waiting_for_its_end() {
    let (tree, records) = fixture_log("kitting_nominal.btlog");
    let whole = reconstruct(&tree, cols(&records).view());
    // The first 5 ticks, then nothing: they wait for the period...
    let five = whole.numbers.iter().take_while(|&&n| n <= 5).count();
    let mut s = Stream::new(&tree);
    assert!(s.push(&records[..five]).is_empty());
    // ...until the robot goes quiet: every whole tick is numbered then,
    // as the whole log numbers it.
    let got = s.settle();
    let numbers: Vec<u32> = got.iter().map(|x| x.1).collect();
    assert!(!numbers.is_empty() && numbers.len() <= five);
    assert_eq!(numbers[..], whole.numbers[..numbers.len()]);
    assert!(s.settle().is_empty(), "nothing is numbered twice");
    let rest: Vec<(Record, u32)> = s
        .push(&records[five..])
        .into_iter()
        .chain(s.finish())
        .collect();
    assert_eq!(
        numbers.len() + rest.len(),
        records.len(),
        "every record, once"
    );
}

#[test]
fn records_numbered_as_they_arrive_get_the_numbers_of_the_whole_log() {
    for log in [
        "kitting_lookat_fails_once.btlog",
        "kitting_nominal.btlog",
        "kitting_detect_chuck_always_fails.btlog",
    ] {
        let (tree, records) = fixture_log(log);
        let whole = reconstruct(&tree, cols(&records).view());
        for chunk in [1, 2, 7, 64, records.len()] {
            let mut s = Stream::new(&tree);
            let mut got = Vec::new();
            for c in records.chunks(chunk) {
                got.extend(s.push(c));
            }
            got.extend(s.finish());
            let numbers: Vec<u32> = got.iter().map(|x| x.1).collect();
            let order: Vec<usize> = got.iter().map(|x| x.0.offset).collect();
            let want: Vec<usize> = records.iter().map(|r| r.offset).collect();
            assert_eq!(
                order, want,
                "{log} in chunks of {chunk}: every record, in order"
            );
            assert_eq!(numbers, whole.numbers, "{log} in chunks of {chunk}");
            assert_eq!(s.fell_back, whole.fell_back, "{log} in chunks of {chunk}");
        }
    }
}

/// A tree of one leaf, for numbering by timing.
fn one_leaf() -> Tree {
    crate::xml::load_str(
        std::path::Path::new("t.xml"),
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>"#,
        &Default::default(),
    )
    .unwrap()
    .tree
}

#[test]
fn after_a_gap_ticks_go_by_timing_and_every_record_is_kept() {
    let recs: Vec<Record> = [0, 10_000, 10_100, 20_000, 30_000]
        .into_iter()
        .map(rec)
        .collect();
    let tree = one_leaf();
    let mut s = Stream::new(&tree);
    let mut got = s.gap();
    got.extend(s.push(&recs));
    got.extend(s.finish());
    assert_eq!(got.len(), recs.len());
    let numbers: Vec<u32> = got.iter().map(|x| x.1).collect();
    assert_eq!(numbers, by_timing(&cols(&recs).times));
}

#[test]
fn by_timing_the_last_tick_is_numbered_once_the_robot_goes_quiet() {
    // Attached to a robot that was running: ticks go by timing. Its
    // last tick, the run's end, is whole once the robot is quiet.
    let recs: Vec<Record> = [0, 10_000, 10_100].into_iter().map(rec).collect();
    let tree = one_leaf();
    let mut s = Stream::new(&tree);
    let mut got = s.gap();
    got.extend(s.push(&recs));
    assert!(got.len() < 3, "the last tick waits for what follows");
    got.extend(s.settle());
    assert_eq!(got.iter().map(|x| x.1).collect::<Vec<_>>(), [1, 2, 2]);
    // What comes after the quiet is a later tick.
    got.extend(s.push(&[rec(50_000)]));
    got.extend(s.finish());
    assert_eq!(got.len(), 4);
    assert!(got[3].1 > 2);
}

#[test]
fn a_corrupt_timestamp_cannot_overflow_the_tick_numbers() {
    let recs: Vec<Record> = [0, 10_000, 20_000, i64::MAX / 4, i64::MAX / 2, 0]
        .into_iter()
        .map(rec)
        .collect();
    let c = cols(&recs);
    let (ticks, capped) = with_empty_ticks(c.view(), by_timing(&c.times));
    assert_eq!(&ticks[..3], [1, 2, 3]);
    assert_eq!(ticks[3], 3 + 1_000_000);
    assert!(ticks.iter().all(|&t| t <= u32::MAX / 2));
    assert_eq!(capped, None);
}

#[test]
fn empty_ticks_stop_being_counted_past_the_limit() {
    // Ticks every 10 ms, then gaps of a million periods each: the first
    // ten fill the budget, later ones count for one tick.
    let mut times: Vec<i64> = (0..20).map(|i| i * 10_000).collect();
    let mut t = *times.last().unwrap();
    for _ in 0..15 {
        t += 10_000 * 1_000_000;
        times.push(t);
    }
    let recs: Vec<Record> = times.into_iter().map(rec).collect();
    let c = cols(&recs);
    let (ticks, capped) = with_empty_ticks(c.view(), by_timing(&c.times));
    assert_eq!(capped, Some(30));
    let last = *ticks.last().unwrap();
    assert_eq!(last, 35 + EMPTY_TICKS_MAX);
    assert_eq!(ticks[30] - ticks[29], 1 + 10);
    assert_eq!(ticks[31] - ticks[30], 1);
}

#[test]
fn a_tick_that_never_ends_is_closed_at_its_bound() {
    // A flooding robot: transitions with one timestamp, no tick's end.
    let tree = crate::xml::load_str(
        std::path::Path::new("flood.xml"),
        "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><AlwaysSuccess/></BehaviorTree></root>",
        &Default::default(),
    )
    .unwrap()
    .tree;
    let mut s = Stream::new(&tree);
    let mut given = 0;
    let batch: Vec<Record> = (0..100_000)
        .map(|i| Record {
            time_us: 5,
            uid: 1,
            status: if i % 2 == 0 {
                Status::Running
            } else {
                Status::Success
            },
            offset: i,
        })
        .collect();
    for _ in 0..30 {
        given += s.push(&batch).len();
    }
    assert!(s.overlong.is_some());
    assert!(
        3_000_000 - given <= TICK_RECORDS_MAX + batch.len(),
        "{given}"
    );
    given += s.finish().len();
    assert_eq!(given, 3_000_000);
}
