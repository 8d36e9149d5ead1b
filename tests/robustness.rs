//! Bad input never panics: mutated trees, sessions, plans and domain files
//! are loaded or refused with an error, nothing else.

use btx::run::domain::Domain;
use btx::run::plan::Plan;
use btx::session::Session;
use btx::xml::{load_str, LoadOptions};
use proptest::prelude::*;
use std::path::Path;

fn root(p: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(p)).unwrap()
}

/// `text` with a few bytes deleted, replaced or inserted (on char boundaries).
fn mutate(text: &str, edits: &[(usize, u8, char)]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for &(at, op, c) in edits {
        if chars.is_empty() {
            break;
        }
        let i = at % chars.len();
        match op % 3 {
            0 => {
                chars.remove(i);
            }
            1 => chars[i] = c,
            _ => chars.insert(i, c),
        }
    }
    chars.into_iter().collect()
}

fn edits() -> impl Strategy<Value = Vec<(usize, u8, char)>> {
    prop::collection::vec(
        (
            any::<usize>(),
            any::<u8>(),
            prop::sample::select(vec![
                '<', '>', '/', '"', '=', '{', '}', '\n', 'a', ' ', '#', ':', '@', '\0', 'é',
            ]),
        ),
        1..6,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn trees(e in edits(), v3 in any::<bool>()) {
        let text = mutate(&root(if v3 { "tests/fixtures/kitting-tree.v3.xml" } else { "trees/kitting.xml" }), &e);
        if let Ok(l) = load_str(Path::new("m.xml"), &text, &LoadOptions::default()) {
            let _ = btx::xml::to_v4_xml(&l.tree);
            let _ = btx::frame::Framed::new(&l.tree);
        }
    }

    #[test]
    fn sessions(e in edits()) {
        let text = mutate(&root("sessions/kitting-lookat-fails-once.jsonl"), &e);
        if let Ok(s) = Session::parse(Path::new("m.jsonl"), &text) {
            for t in 1..=s.index.ticks() {
                let at = s.at(btx::session::Moment { tick: t, step: None }).unwrap();
                let _ = at.current();
            }
        }
    }

    #[test]
    fn plans_and_domains(e in edits()) {
        let _ = Plan::parse(Path::new("m.plan"), &mutate(&root("trees/plans/kitting-lookat-fails-once.plan"), &e));
        let _ = Domain::parse(Path::new("m.toml"), &mutate(&root("trees/case-study.domain.toml"), &e));
    }

    #[test]
    fn logs(edits in prop::collection::vec((any::<usize>(), any::<u8>()), 1..8), fbl in any::<bool>(), cut in any::<u16>()) {
        let name = if fbl { "tests/fixtures/logs/kitting_lookat_fails_once_v3.fbl" } else { "tests/fixtures/logs/kitting_lookat_fails_once.btlog" };
        let mut bytes = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join(name)).unwrap();
        for (at, b) in edits {
            let i = at % bytes.len();
            bytes[i] = b;
        }
        let keep = bytes.len() - (cut as usize % bytes.len());
        bytes.truncate(keep);
        let p = Path::new("m.log");
        let _ = btx::logs::open_btlog(p, &bytes);
        let _ = btx::logs::open_fbl(p, &bytes);
    }

    #[test]
    fn arbitrary_text(s in "\\PC{0,200}") {
        let _ = load_str(Path::new("a.xml"), &s, &LoadOptions::default());
        let _ = Session::parse(Path::new("a.jsonl"), &s);
        let _ = Plan::parse(Path::new("a.plan"), &s);
        let _ = Domain::parse(Path::new("a.toml"), &s);
    }
}
