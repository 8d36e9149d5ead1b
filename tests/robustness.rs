//! Bad input never panics: mutated trees, sessions, plans, domain files and
//! logs are loaded or refused with an error that names the file and where
//! in it (line and column, or byte offset), nothing else.

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

/// The error names the file, and a line:column or a byte offset in it.
fn located(e: &btx::Located, file: &str) -> Result<(), TestCaseError> {
    // A tree embedded in a log or session is named after it, with the
    // line and column in the embedded XML.
    let at = e.location.strip_prefix(file).unwrap_or("");
    let at = at.strip_prefix(" (embedded tree)").unwrap_or(at);
    let line_col = at.starts_with(':')
        && at[1..]
            .split(':')
            .take(2)
            .all(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
    prop_assert!(e.location.starts_with(file), "{e}");
    prop_assert!(
        line_col || e.message.contains("byte offset"),
        "no place in the file: {e}"
    );
    Ok(())
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
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn trees(e in edits(), v3 in any::<bool>()) {
        let text = mutate(&root(if v3 { "tests/fixtures/kitting-tree.v3.xml" } else { "trees/kitting.xml" }), &e);
        match load_str(Path::new("m.xml"), &text, &LoadOptions::default()) {
            Ok(l) => {
                let _ = btx::xml::to_v4_xml(&l.tree);
                let _ = btx::frame::Framed::new(&l.tree);
            }
            Err(e) => located(&e, "m.xml")?,
        }
    }

    #[test]
    fn sessions(e in edits()) {
        let text = mutate(&root("sessions/kitting-lookat-fails-once.jsonl"), &e);
        match Session::parse(Path::new("m.jsonl"), &text) {
            Ok(s) => {
                for t in 1..=s.index.ticks() {
                    let at = s.at(btx::session::Moment { tick: t, step: None }).unwrap();
                    let _ = at.current();
                }
            }
            // The tree embedded in the session names itself after it.
            Err(e) => located(&e, "m.jsonl")?,
        }
    }

    #[test]
    fn plans_and_domains(e in edits()) {
        if let Err(e) = Plan::parse(Path::new("m.plan"), &mutate(&root("trees/plans/kitting-lookat-fails-once.plan"), &e)) {
            located(&e, "m.plan")?;
        }
        if let Err(e) = Domain::parse(Path::new("m.toml"), &mutate(&root("trees/case-study.domain.toml"), &e)) {
            located(&e, "m.toml")?;
        }
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
        if let Err(e) = btx::logs::open_btlog(p, &bytes) {
            located(&e, "m.log")?;
        }
        if let Err(e) = btx::logs::open_fbl(p, &bytes) {
            located(&e, "m.log")?;
        }
    }

    #[test]
    fn arbitrary_text(s in "\\PC{0,200}") {
        if let Err(e) = load_str(Path::new("a.xml"), &s, &LoadOptions::default()) {
            located(&e, "a.xml")?;
        }
        if let Err(e) = Session::parse(Path::new("a.jsonl"), &s) {
            located(&e, "a.jsonl")?;
        }
        if let Err(e) = Plan::parse(Path::new("a.plan"), &s) {
            located(&e, "a.plan")?;
        }
        if let Err(e) = Domain::parse(Path::new("a.toml"), &s) {
            located(&e, "a.toml")?;
        }
    }
}
