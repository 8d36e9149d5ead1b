use super::*;
use crate::logs::btlog::Record;
use crate::session::{At, Before};

/// Root Sequence(1) > Retry(2) > Sequence "insert"(3) > A(4), B(5);
/// then C(6). Recording began while B ran in attempt 2, A having
/// failed in attempt 1 (reset since: IDLE after FAILURE).
const XML: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>
    <RetryUntilSuccessful num_attempts="3"><Sequence name="insert">
    <AlwaysFailure name="look"/><AlwaysSuccess name="grasp"/></Sequence></RetryUntilSuccessful>
    <AlwaysSuccess name="leave"/></Sequence></BehaviorTree></root>"#;

/// The states of `attached`'s robot when recording began.
fn states() -> Vec<Before> {
    vec![
        Before {
            uid: 1,
            status: Status::Running,
            done: None,
        },
        Before {
            uid: 2,
            status: Status::Running,
            done: None,
        },
        Before {
            uid: 3,
            status: Status::Running,
            done: None,
        },
        Before {
            uid: 4,
            status: Status::Idle,
            done: Some(Status::Failure),
        },
        Before {
            uid: 5,
            status: Status::Running,
            done: None,
        },
    ]
}

fn records(records: &[(u32, Status)]) -> Vec<Record> {
    records
        .iter()
        .enumerate()
        .map(|(i, &(uid, status))| Record {
            time_us: i as i64 * 1000,
            uid,
            status,
            offset: i,
        })
        .collect()
}

fn attached(recs: &[(u32, Status)]) -> crate::session::Session {
    crate::logs::open_live(
        crate::logs::Protocol::Groot2,
        std::path::Path::new("live"),
        XML,
        &records(recs),
        &[(0, states())],
    )
    .unwrap()
}

#[test]
fn after_a_gap_the_states_read_again_are_the_runs() {
    // Recorded from the start until the Retry's first attempt began;
    // then transitions were lost, and the states read again are those
    // of `attached` (A failed in attempt 1, B runs in attempt 2); then
    // B succeeds.
    let recs = records(&[
        (1, Status::Running),
        (2, Status::Running),
        (3, Status::Running),
        (4, Status::Running),
        (5, Status::Running),
        (5, Status::Success),
    ]);
    let s = crate::logs::open_live(
        crate::logs::Protocol::Groot2,
        std::path::Path::new("live"),
        XML,
        &recs,
        &[(4, states())],
    )
    .unwrap();
    let at = |pos| At {
        index: &s.index,
        pos,
    };
    assert_eq!(at(4).status(4), Status::Idle);
    assert_eq!(at(4).last_completed(4), Some(Status::Failure));
    assert_eq!(at(3).last_completed(4), None);
    let (text, nodes) = what_went_wrong(&s.tree, &at(4), 5);
    assert_eq!(
        text,
        "I cannot tell: I was already running RetryUntilSuccessful (#2) when btx read the statuses again after a gap (after transition 4), and look (#4) had last failed before that; whether that was in this run of it, the statuses btx read do not say."
    );
    assert_eq!(nodes, [2, 4]);
    // B's RUNNING the read already showed left what the records
    // followed (IDLE); its SUCCESS left RUNNING.
    let prev: Vec<_> = s.index.transitions[4..].iter().map(|t| t.prev).collect();
    assert_eq!(prev, [Status::Idle, Status::Running]);
    // Written and read back, the session keeps the read and its place.
    let dir = tempfile::tempdir().unwrap();
    let out = crate::logs::write_session(&s, &dir.path().join("s.jsonl")).unwrap();
    let back = crate::session::Session::load(&out).unwrap();
    assert_eq!(back.index.resyncs(), s.index.resyncs());
    assert_eq!(back.index.resyncs()[0].0, 4);
    assert_eq!(back.index.at(4).last_completed(4), Some(Status::Failure));
}

#[test]
fn a_failure_from_before_recording_is_named_with_what_is_unknown() {
    let s = attached(&[]);
    let at = At {
        index: &s.index,
        pos: 0,
    };
    assert_eq!(at.status(5), Status::Running);
    assert_eq!(at.current(), Some(5));
    assert_eq!(at.done_before(4), Some(Status::Failure));
    let (text, nodes) = what_went_wrong(&s.tree, &at, 5);
    assert_eq!(
        text,
        "I cannot tell: I was already running RetryUntilSuccessful (#2) when btx attached, and look (#4) had last failed before that; whether that was in this run of it, the statuses btx read do not say."
    );
    assert_eq!(nodes, [2, 4]);
    // Not "Yes.": the run does not say that anything went wrong.
    assert_eq!(anything_wrong(&s.tree, &at, 5).0, text);
}

#[test]
fn what_the_recording_shows_is_said_as_usual() {
    // B finishes, the insert sequence and the Retry succeed, C runs:
    // recorded transitions; the first one's `prev` is B's state then.
    let s = attached(&[
        (5, Status::Success),
        (3, Status::Success),
        (2, Status::Success),
        (6, Status::Running),
    ]);
    assert_eq!(s.index.transitions[0].prev, Status::Running);
    // The Retry has finished: above leave (#6) no Retry or Fallback
    // is active, and Algorithm 7 finds nothing now. Look's failure
    // before recording began is said, as the whole run recorded would
    // have said it, with what the session cannot say.
    let at = At {
        index: &s.index,
        pos: 4,
    };
    assert_eq!(
        what_went_wrong(&s.tree, &at, 6).0,
        "Nothing went wrong since recording began. Before recording began, look had last failed: how, and what handled it, is not in the session."
    );
    // Once look completes within the recording, the snapshot's failure
    // is no longer its last completion.
    let s = attached(&[(4, Status::Running), (4, Status::Success)]);
    let at = At {
        index: &s.index,
        pos: 2,
    };
    assert_eq!(at.done_before(4), None);
    assert_eq!(at.last_completed(4), Some(Status::Success));
}
