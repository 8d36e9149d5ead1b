//! A long `.btlog` in the explorer (#42 item 3): its first part is shown
//! at once while the whole is read on a thread; moving goes on in that
//! part, and anything that answers, searches or lists waits for the whole.

mod common;

use btx::input::{open_first, FIRST_RECORDS};
use btx::tui::keymap::Action;
use btx::xml::LoadOptions;
use std::time::Duration;

/// The recorded kitting run repeated into a log of about 2.3 times the
/// records shown first (248 records a copy), written to `dir`.
fn long_log(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("long.btlog");
    std::fs::write(&path, common::long_btlog(600)).unwrap();
    path
}

fn screen(app: &btx::tui::app::App) -> String {
    let buf = btx::tui::render(app, 160, 45);
    (0..45)
        .map(|y| (0..160).map(|x| buf[(x, y)].symbol()).collect::<String>() + "\n")
        .collect()
}

fn transitions(app: &btx::tui::app::App) -> usize {
    app.shared.session.as_ref().unwrap().index.transitions.len()
}

#[test]
fn the_first_part_is_numbered_as_the_whole_is() {
    let dir = tempfile::tempdir().unwrap();
    let path = long_log(dir.path());
    let opts = LoadOptions::default();
    let part = open_first(&path, &opts, FIRST_RECORDS).unwrap().unwrap();
    let whole = match btx::input::open(&path, &opts).unwrap() {
        btx::input::Input::Session(s) => s,
        _ => panic!("a run"),
    };
    assert_eq!(part.index.transitions.len(), FIRST_RECORDS);
    assert_eq!(whole.index.transitions.len(), 600 * 248);
    // Every tick the first part holds whole is the whole log's tick, moment
    // for moment: what the first frame shows stays true.
    let last = part.index.ticks();
    assert!(last > 100, "{last} ticks");
    let shown = part.index.tick_range(last).start as u32;
    for pos in 0..=shown {
        assert_eq!(part.index.moment(pos), whole.index.moment(pos), "at {pos}");
    }
    assert_eq!(part.tree.len(), whole.tree.len());
}

#[test]
fn a_short_log_a_tree_or_a_run_picked_is_read_whole_at_once() {
    let opts = LoadOptions::default();
    let short = common::fixture("logs/kitting_lookat_fails_once.btlog");
    assert!(open_first(&short, &opts, FIRST_RECORDS).unwrap().is_none());
    assert!(open_first(&short, &opts, 10).unwrap().is_some());
    let tree = common::fixture("kitting-tree.v4.xml");
    assert!(open_first(&tree, &opts, 10).unwrap().is_none());
    let missing = common::fixture("logs/no-such.btlog");
    assert!(open_first(&missing, &opts, 10).unwrap().is_none());
    let one_run = LoadOptions {
        run: Some(2),
        ..LoadOptions::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let path = long_log(dir.path());
    assert!(open_first(&path, &one_run, 10).unwrap().is_none());
}

#[test]
fn moving_goes_on_in_the_first_part_and_a_question_waits_for_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = long_log(dir.path());
    let mut app = btx::tui::open(&path, None, &LoadOptions::default()).unwrap();
    assert!(app.shared.reading.is_some());
    assert_eq!(transitions(&app), FIRST_RECORDS);
    let s = screen(&app);
    assert!(
        s.contains("transition 6 of 65536+  · reading the rest of the log"),
        "{s}"
    );
    app.update(Action::TickForward);
    app.update(Action::TickForward);
    assert!(app.shared.reading.is_some(), "moving does not wait");
    let pos = app.shared.pos;
    // The finder lists the whole run's nodes and moments: it waits.
    app.update(Action::Find);
    assert!(app.shared.reading.is_none());
    assert_eq!(transitions(&app), 600 * 248);
    assert_eq!(app.shared.pos, pos, "the moment stays where it was put");
    app.update(Action::Back);
    let s = screen(&app);
    assert!(s.contains("moment 3  ·  tick 3 of "), "{s}");
    assert!(!s.contains("reading the rest"), "{s}");
    assert!(!app.quit && app.failed.is_none());
}

#[test]
fn at_the_end_of_the_first_part_the_whole_comes_at_its_end() {
    let dir = tempfile::tempdir().unwrap();
    let path = long_log(dir.path());
    let mut app = btx::tui::open(&path, None, &LoadOptions::default()).unwrap();
    app.update(Action::End);
    assert_eq!(app.shared.pos as usize, FIRST_RECORDS);
    assert!(app.take_read(Duration::from_secs(60)));
    assert_eq!(app.shared.pos as usize, 600 * 248, "at the whole's end");
    let s = screen(&app);
    assert!(s.contains("transition 148800 of 148800"), "{s}");
}

#[test]
fn a_log_broken_past_the_first_part_stops_the_explorer_with_where() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = common::long_btlog(600);
    let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
    // Record 100,000's status byte (0 to 4 are statuses).
    let at = 31 + n + 9 * 100_000 + 8;
    bytes[at] = 9;
    let path = dir.path().join("broken.btlog");
    std::fs::write(&path, &bytes).unwrap();
    let mut app = btx::tui::open(&path, None, &LoadOptions::default()).unwrap();
    assert_eq!(transitions(&app), FIRST_RECORDS);
    app.update(Action::Why);
    assert!(app.quit);
    let e = app.failed.take().expect("the error").to_string();
    assert!(e.contains("broken.btlog"), "{e}");
    assert!(e.contains(&format!("byte offset {at}")), "{e}");
    assert!(e.contains("status byte 9 is not a status"), "{e}");
}
