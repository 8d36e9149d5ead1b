#![no_main]
//! The moment syntax (`TICK`, `TICK:STEP`), node picks (`#uid`, names,
//! paths), questions and why-targets, against a shipped session.

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use std::sync::OnceLock;

fn session() -> &'static btx::session::Session {
    static S: OnceLock<btx::session::Session> = OnceLock::new();
    S.get_or_init(|| {
        btx::session::Session::parse(
            Path::new("case-study.jsonl"),
            include_str!("../../sessions/case-study.jsonl"),
        )
        .expect("the shipped session reads")
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let s = session();
    if let Ok(m) = btx::session::Moment::parse(text) {
        let _ = s.at(m);
    }
    let _ = btx::pick::pick(&s.tree, text);
    let _ = btx::explain::Question::parse(text);
    let d = btx::causal::session_domain(s, None).ok().flatten();
    let _ = btx::causal::why(s, d, text, &[], None, 1);
});
