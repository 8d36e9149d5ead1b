//! The explorer's screens, as TestBackend snapshots, and scripted key
//! sequences.

mod common;

use btx::tui::keymap::{Action, KEYMAP};
use btx::tui::{demo, render, scene, SCENES};

/// The explorer on a file of the project.
fn opened(file: &str) -> btx::tui::app::App {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    btx::tui::open(&root.join(file), None, &btx::xml::LoadOptions::default()).unwrap()
}

/// Serial recall, with the first why-question about RepeatOrEnd answered.
fn why_repeat_or_end() -> btx::tui::app::App {
    let mut app = opened("sessions/serial-recall.jsonl");
    app.shared.selected = (1..=app.shared.tree.len() as u32)
        .find(|&u| app.shared.tree.description(u) == "RepeatOrEnd")
        .unwrap();
    app.update(Action::Why);
    app.update(Action::Toggle);
    app
}

fn screen(app: &impl btx::tui::Screen, w: u16, h: u16) -> String {
    let buf = render(app, w, h);
    let mut s = String::new();
    for y in 0..h {
        for x in 0..w {
            s.push_str(buf[(x, y)].symbol());
        }
        s.push('\n');
    }
    s
}

#[test]
fn scenes() {
    for name in SCENES {
        let app = scene(name).unwrap();
        insta::assert_snapshot!(name, screen(&app, 110, 34));
    }
}

#[test]
fn the_smallest_screen_still_draws() {
    let app = scene("failure").unwrap();
    insta::assert_snapshot!("small", screen(&app, 80, 24));
}

#[test]
fn demo_f_a_what_went_wrong_shows_the_papers_sentence() {
    let mut app = demo();
    app.update(Action::NextFailure);
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "10");
    app.update(Action::Ask);
    let qs = app.shared.questions();
    let i = qs
        .iter()
        .position(|q| q.wording() == "What went wrong?")
        .unwrap();
    for _ in 0..i {
        app.update(Action::Down);
    }
    app.update(Action::Toggle);
    let a = app.shared.answer.as_ref().unwrap();
    assert_eq!(
        a.text,
        "I could not insert large gear because look at chuck failed."
    );
    let s = screen(&app, 110, 34);
    assert!(s.contains("I could not insert large gear because"), "{s}");
}

#[test]
fn stepping_moves_the_moment_both_ways() {
    let mut app = demo();
    let start = app.shared.pos;
    app.update(Action::StepForward);
    app.update(Action::StepForward);
    app.update(Action::StepBack);
    assert_eq!(app.shared.pos, start + 1);
    // Tick 2 has no transitions (the move runs on), so the step lands in tick 3.
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "3:1");
    app.update(Action::TickForward);
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "3");
    app.update(Action::End);
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "54");
    app.update(Action::PrevFailure);
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "10");
    app.update(Action::Start);
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "1");
    // The current node is selected and kept visible.
    assert_eq!(app.shared.selected, 6);
}

#[test]
fn finder_jumps_to_the_pick() {
    let mut app = demo();
    app.update(Action::Find);
    for c in "#27 retreat arm".chars() {
        app.type_char(c);
    }
    app.update(Action::Toggle);
    assert_eq!(app.shared.selected, 27);
    assert!(app.shared.row_of(27).is_some());
}

#[test]
fn framed_view_and_collapsing() {
    let mut app = demo();
    let full = app.shared.rows().len();
    app.update(Action::ToggleFramed);
    assert!(app.shared.rows().len() < full);
    app.update(Action::Start);
    app.shared.selected = 1;
    app.update(Action::Collapse);
    assert_eq!(app.shared.rows().len(), 1);
    app.update(Action::Expand);
    assert!(app.shared.rows().len() > 1);
}

#[test]
fn help_lists_every_binding_of_the_keymap_under_the_pane_that_takes_it() {
    let app = scene("help").unwrap();
    let s = screen(&app, 110, 120);
    for b in KEYMAP {
        assert!(
            s.contains(&b.keys.join(" ")),
            "help lacks the keys {:?}",
            b.keys
        );
    }
    // Each pane's keys under its heading, in its words or the keymap's.
    let parts = app.panes.help();
    for p in &parts {
        for (a, own) in p.anywhere.iter().chain(p.focused) {
            let words = match *own {
                "" => KEYMAP.iter().find(|b| b.action == *a).unwrap().help,
                w => w,
            };
            assert!(s.contains(words), "help lacks {words:?} ({})", p.name);
        }
    }
    let at = |h: &str| s.find(h).unwrap_or_else(|| panic!("no heading {h:?}"));
    assert!(at("│the explorer") < at("│tree ") && at("│tree ") < at("│timeline "));
    assert!(at("│answers ") < at("│timeline, when it has the focus"));
    assert!(at("Esc             clear the answer") < at("details, when it has the focus"));
}

#[test]
fn screenshots_are_svg() {
    let svg = btx::tui::svg::buffer_to_svg(&render(&demo(), 80, 24));
    assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert!(svg.trim_end().ends_with("</svg>"));
}

#[test]
fn a_keymap_file_overrides_the_table() {
    use btx::tui::keymap::Keymap;
    use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("keys.toml");
    std::fs::write(
        &p,
        "step_forward = [\"Z\", \"Right\"]\nexpand = [\"l\"]\nquit = [\"Q\"]\n",
    )
    .unwrap();
    let km = Keymap::with_file(&p).unwrap();
    let key = |c| KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE);
    assert_eq!(km.action_for(&key('Z')), Some(Action::StepForward));
    assert_eq!(km.action_for(&key('n')), None);
    assert_eq!(km.action_for(&key('Q')), Some(Action::Quit));
    assert!(km.hints().starts_with("Z step"), "{}", km.hints());
    let mut app = scene("help").unwrap();
    app.shared.keymap = km;
    let s = screen(&app, 110, 40);
    assert!(s.contains("Z Right"), "the help shows the keymap in force");
    std::fs::write(&p, "fly = [\"z\"]\n").unwrap();
    let e = Keymap::with_file(&p).unwrap_err().to_string();
    assert!(e.contains("keys.toml:1:7: \"fly\" is not an action"), "{e}");
    // Ctrl-c quits whatever the file says.
    let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
    assert_eq!(km_quit_elsewhere().action_for(&ctrl_c), Some(Action::Quit));
}

fn km_quit_elsewhere() -> btx::tui::keymap::Keymap {
    btx::tui::keymap::Keymap::parse(std::path::Path::new("k.toml"), "quit = [\"Q\"]\n").unwrap()
}

#[test]
fn a_keymap_that_clashes_or_locks_the_user_in_is_refused() {
    use btx::tui::keymap::Keymap;
    let err = |text: &str| {
        Keymap::parse(std::path::Path::new("k.toml"), text)
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        err("step_forward = [\"Right\"]\n"),
        "k.toml:1:16: \"Right\" is bound to both step_forward and expand (built in)"
    );
    assert_eq!(
        err("step_forward = [\"z\"]\nstep_back = [\"z\"]\n"),
        "k.toml:2:13: \"z\" is bound to both step_back and step_forward (in this file)"
    );
    assert_eq!(
        err("quit = []\n"),
        "k.toml:1:8: quit has no key: the keymap would leave no way out"
    );
    assert_eq!(
        err("why = [\"Ctrl-c\"]\n"),
        "k.toml:1:7: Ctrl-c is bound to why, and Ctrl-c always quits"
    );
    assert_eq!(
        err("why = [\"Rigth\"]\n"),
        "k.toml:1:7: \"Rigth\" is not a key"
    );
}

#[test]
fn why_dialog_answers_follows_up_and_shows_the_causal_model() {
    let mut app = opened("sessions/case-study.jsonl");
    // L1 (#4), at the end of the tick: why did it not execute?
    app.shared.selected = 4;
    app.update(Action::Why);
    let targets = match &app.overlay {
        Some(btx::tui::panes::overlays::Overlay::Why(w)) => w.targets.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(targets[0].1, "Why was L1 not ticked?");
    assert_eq!(targets[1].1, "Why did L1 not execute?");
    app.update(Action::Down);
    app.update(Action::Toggle);
    let w = app.shared.why.as_ref().unwrap();
    assert_eq!(
        w.why.sentences(),
        [
            "L1 did not execute because L0 failed. If L0 had succeeded, L1 would have executed.",
            "L1 did not execute because X_a was false. If X_a had been true, L1 would have executed."
        ]
    );
    // L0 is the first reason's node: it is highlighted in the tree.
    assert_eq!(app.shared.highlighted(), vec![3]);
    let s = screen(&app, 110, 34);
    assert!(
        s.contains("1. L1 did not execute because L0 failed."),
        "{s}"
    );
    // The causal model, the reason marked.
    app.update(Action::Graph);
    insta::assert_snapshot!("why", screen(&app, 110, 34));
    // Follow up on the first reason: why did L0 fail? (Tab brings the
    // focus to the answer; it stayed where the question was asked.)
    app.update(Action::NextPane);
    while app.focus != btx::tui::app::Pane::Ask {
        app.update(Action::NextPane);
    }
    app.update(Action::Toggle);
    let w = app.shared.why.as_ref().unwrap();
    assert_eq!(
        w.why.sentences(),
        ["L0 failed because X_a was false. If X_a had been true, L0 would have succeeded."]
    );
}

#[test]
fn x_asks_where_to_write_and_never_overwrites_unasked() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = opened("sessions/case-study.jsonl");
    app.shared.selected = 4;
    app.update(Action::Why);
    app.update(Action::Toggle);
    app.update(Action::ExportGraph);
    match &app.overlay {
        Some(Overlay::Export(e)) => {
            assert_eq!(e.input.text, "btx-model-tick-1.dot");
            assert!(!e.replace);
        }
        other => panic!("{other:?}"),
    }
    assert!(screen(&app, 110, 34).contains("btx-model-tick-1.dot▏"));
    let dir = tempfile::tempdir().unwrap();
    let to = dir.path().join("m.dot");
    std::fs::write(&to, "mine").unwrap();
    app.overlay = Some(Overlay::export(String::new()));
    for c in to.display().to_string().chars() {
        app.type_char(c);
    }
    // A file is there: the prompt asks, and Esc keeps it.
    app.update(Action::Toggle);
    assert!(matches!(&app.overlay, Some(Overlay::Export(e)) if e.replace));
    assert!(screen(&app, 110, 34).contains("a file is there: Enter replaces it"));
    app.update(Action::Back);
    assert_eq!(std::fs::read_to_string(&to).unwrap(), "mine");
    // Asked again and confirmed, it is replaced.
    app.overlay = Some(Overlay::export(to.display().to_string()));
    app.update(Action::Toggle);
    app.update(Action::Toggle);
    assert!(app.overlay.is_none());
    assert!(std::fs::read_to_string(&to)
        .unwrap()
        .contains("digraph model"));
    // A link planted there is never written through, confirmed or not.
    let target = dir.path().join("target");
    std::fs::write(&target, "keep").unwrap();
    let link = dir.path().join("link.dot");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    for replace in [false, true] {
        app.overlay = Some(Overlay::Export(btx::tui::panes::overlays::Export {
            input: btx::tui::text_input::TextInput::new(link.display().to_string()),
            replace,
        }));
        app.update(Action::Toggle);
        assert!(app
            .shared
            .message
            .as_deref()
            .unwrap()
            .contains("symbolic link"));
    }
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
}

fn diff_app(a: &str, b: &str) -> btx::tui::diff::DiffApp {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    std::env::set_current_dir(root).unwrap();
    btx::tui::open_diff(
        std::path::Path::new(a),
        std::path::Path::new(b),
        &Default::default(),
    )
    .unwrap()
}

#[test]
fn side_by_side_taxi_policies_colour_the_detour() {
    let mut app = diff_app("trees/taxi-expected.xml", "trees/taxi.xml");
    insta::assert_snapshot!("diff_taxi", screen(&app, 110, 34));
    // Fig. 14's colours: the detour's leaves dark blue, their parent blue-grey.
    let buf = render(&app, 110, 34);
    let row_of = |text: &str, from: u16| {
        (0..34u16)
            .find(|&y| {
                let line: String = (from..from + 55).map(|x| buf[(x, y)].symbol()).collect();
                line.contains(text)
            })
            .unwrap_or_else(|| panic!("no {text}"))
    };
    let y = row_of("move left #10", 55);
    let x = (55..110).find(|&x| buf[(x, y)].symbol() == "m").unwrap();
    assert_eq!(buf[(x, y)].bg, btx::tui::diff::DIVERGENT);
    let y = row_of("navigate to passenger #4", 55);
    let x = (55..110).find(|&x| buf[(x, y)].symbol() == "n").unwrap();
    assert_eq!(buf[(x, y)].bg, btx::tui::diff::PARENT);
    // The left side has a gap facing each inserted action.
    let left: String = (0..55).map(|x| buf[(x, y + 3)].symbol()).collect();
    assert!(left.trim_matches(['│', ' ']).is_empty(), "{left:?}");
    // d jumps from divergence to divergence, and wraps around.
    let mut seen = Vec::new();
    for _ in 0..5 {
        app.update(Action::NextDivergence);
        seen.push(app.shared.message.clone().unwrap());
    }
    assert!(
        seen[0].starts_with("divergence 1 of 4: go pick up passenger"),
        "{seen:?}"
    );
    assert_eq!(seen[4], seen[0]);
    app.update(Action::PrevDivergence);
    assert!(app
        .shared
        .message
        .as_deref()
        .unwrap()
        .starts_with("divergence 4 of 4"));
}

#[test]
fn side_by_side_runs_move_together_and_say_why_they_diverged() {
    let mut app = diff_app(
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
    );
    app.update(Action::TickForward);
    let (a, b) = (
        app.shared.a.moment().unwrap(),
        app.shared.b.moment().unwrap(),
    );
    assert_eq!((a.tick, b.tick), (2, 2));
    app.update(Action::NextDivergence);
    assert_eq!(app.shared.b.moment().unwrap().tick, 9);
    assert_eq!(app.shared.a.moment().unwrap().tick, 9);
    app.update(Action::Why);
    let text = app.shared.answer.clone().unwrap();
    assert!(
        text.starts_with("The runs part ways at transition 32 (moment 10:1): look at chuck (#18) became FAILURE in B and SUCCESS in A."),
        "{text}"
    );
    assert_eq!(app.shared.b.moment().unwrap().to_string(), "10:1");
    insta::assert_snapshot!("diff_runs_why", screen(&app, 110, 34));
    app.update(Action::Back);
    assert!(app.shared.answer.is_none());
}

#[test]
fn next_tick_goes_to_every_tick_empty_or_not() {
    let mut app = demo();
    app.update(Action::Start);
    let ticks = |app: &btx::tui::app::App| app.shared.shown_moment().unwrap().tick;
    assert_eq!(ticks(&app), 1);
    // Ticks in which nothing changed (a leaf kept RUNNING) are ticks too.
    let mut seen = vec![1];
    for _ in 0..30 {
        app.update(Action::TickForward);
        seen.push(ticks(&app));
    }
    assert_eq!(seen, (1..=31).collect::<Vec<u32>>());
    let s = screen(&app, 110, 34);
    assert!(s.contains("tick 31 of"), "{s}");
    for _ in 0..30 {
        app.update(Action::TickBack);
    }
    assert_eq!(ticks(&app), 1);
}

#[test]
fn the_status_bar_fits_and_always_says_how_to_quit() {
    use btx::tui::keymap::Keymap;
    let km = Keymap::default();
    for width in [30, 60, 80, 120, 250] {
        let h = km.hints_within(&[(Action::Down, "move")], width);
        assert!(h.chars().count() <= width.max(16), "{width}: {h}");
        // `?` last (#27 item 5).
        assert!(h.ends_with("q quit  ? help"), "{width}: {h}");
    }
    // At 80 columns the tree pane's bar keeps the two headline questions
    // and drops lesser hints first (#27 item 5: they were dropped first).
    let tree = [
        (Action::Down, "move"),
        (Action::Expand, "open"),
        (Action::Collapse, "close"),
    ];
    for width in [60, 78] {
        let h = km.hints_within(&tree, width);
        assert!(h.contains("a ask") && h.contains("w why"), "{width}: {h}");
    }
    assert!(km
        .hints_within(&[(Action::Down, "move")], 250)
        .starts_with("Down move  n step"));
}

#[test]
fn names_give_way_to_the_uid_with_an_ellipsis() {
    use btx::tui::view::fit;
    assert_eq!(fit("trial and error insert", 10), "trial and…");
    assert_eq!(fit("ask", 10), "ask");
    assert_eq!(fit("抓取螺丝钉", 5), "抓取…");
    assert_eq!(fit("abc", 0), "");
}

#[test]
fn the_help_scrolls_to_a_legend_of_every_sign() {
    let mut app = scene("help").unwrap();
    let top = screen(&app, 80, 24);
    assert!(top.contains("↓ more"), "{top}");
    assert!(!top.contains("a divergent leaf"), "{top}");
    app.update(Action::End);
    let end = screen(&app, 80, 24);
    for sign in [
        "halted: was RUNNING",
        "IDLE now, and its last completion was FAILURE",
        "a tick it ran: running, failed, succeeded, halted",
        "not ticked that tick (blank: not run yet)",
        "side-by-side diff: a divergent leaf, its parent",
    ] {
        assert!(end.contains(sign), "{sign}: {end}");
    }
    app.update(Action::Back);
    assert!(!screen(&app, 80, 24).contains("keys and signs"));
}

#[test]
fn the_selection_stays_while_stepping_and_answers_keep_their_node() {
    let mut app = demo();
    // Following at first: stepping selects the current node.
    app.update(Action::TickForward);
    let current = app.shared.at().unwrap().current().unwrap();
    assert_eq!(app.shared.selected, current);
    // The person selects a node: it stays while the run moves.
    app.update(Action::Up);
    let mine = app.shared.selected;
    assert_ne!(mine, current);
    for _ in 0..5 {
        app.update(Action::TickForward);
    }
    assert_eq!(app.shared.selected, mine);
    // `o` follows again.
    app.update(Action::Follow);
    assert_eq!(
        app.shared.selected,
        app.shared.at().unwrap().current().unwrap()
    );
    // f lands on the leaf that failed and selects it.
    app.update(Action::NextFailure);
    assert_eq!(app.shared.selected, 18, "look at chuck");
    // Q1 there, then the selection moves: the pane still names #18.
    app.update(Action::Ask);
    app.update(Action::Toggle);
    app.focus = btx::tui::app::Pane::Tree;
    app.update(Action::Up);
    assert_ne!(app.shared.selected, 18);
    let s = screen(&app, 110, 34);
    assert!(s.contains("about look at chuck #18 at moment 10"), "{s}");
}

#[test]
fn every_pane_scrolls_and_zooms() {
    use btx::tui::app::Pane;
    // A why-answer's causal model in the details pane: 177 variables.
    let mut app = why_repeat_or_end();
    app.update(Action::Graph);
    app.focus = Pane::Details;
    let before = screen(&app, 80, 24);
    app.update(Action::PageDown);
    let after = screen(&app, 80, 24);
    assert_ne!(before, after, "the model scrolls");
    app.update(Action::PageUp);
    assert_eq!(screen(&app, 80, 24), before);
    // Zoomed, the details pane takes the screen: more of the model shows.
    app.update(Action::Zoom);
    let zoomed = screen(&app, 80, 24);
    assert!(!zoomed.contains("timeline"), "{zoomed}");
    app.update(Action::Zoom);
    // The wheel over the ask pane scrolls it, the focus stays.
    app.wheel(Pane::Ask, true);
    assert_eq!(app.panes.answers.scrolled(&app.shared), 1);
    assert_eq!(app.focus, Pane::Details);
    // The timeline's list scrolls away from the moment and back on a step.
    app.focus = Pane::Timeline;
    let pos = app.shared.pos;
    app.update(Action::PageUp);
    assert_eq!(
        app.shared.pos, pos,
        "scrolling the list does not move the moment"
    );
    assert_eq!(app.panes.timeline.scrolled(&app.shared), -10);
    app.update(Action::StepBack);
    assert_eq!(app.panes.timeline.scrolled(&app.shared), 0);
}

#[test]
fn the_transition_list_filters_and_follows_the_moment() {
    use btx::tui::app::Pane;
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    app.update(Action::End);
    app.focus = Pane::Timeline;
    let list = |app: &btx::tui::app::App| {
        let s = screen(app, 110, 34);
        let top = s.lines().position(|l| l.contains(" timeline")).unwrap();
        s.lines()
            .skip(top + 4)
            .take(4)
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert!(list(&app).contains("→ IDLE"), "{}", list(&app));
    app.update(Action::HideResets);
    assert!(!list(&app).contains("→ IDLE"), "{}", list(&app));
    assert!(screen(&app, 110, 34).contains("· showing no resets"));
    // Only failures.
    for _ in 0..3 {
        app.update(Action::OnlyStatus);
    }
    let l = list(&app);
    assert_eq!(l.matches("→ FAILURE").count(), 4, "{l}");
    assert_eq!(l.matches(" → ").count(), 4, "{l}");
    app.update(Action::OnlyStatus);
    // A name, typed.
    app.update(Action::Find);
    for c in "RETREAT".chars() {
        app.type_char(c);
    }
    app.update(Action::Toggle);
    let l = list(&app);
    assert!(
        l.lines()
            .all(|x| x.contains("retreat arm") || x.trim_matches(['│', ' ']).is_empty()),
        "{l}"
    );
    // The selected subtree: go insert large gear's transitions only.
    app.panes.timeline.filter.text.clear();
    app.shared.selected = 13;
    app.update(Action::OnlyBelow);
    let s = screen(&app, 110, 34);
    assert!(s.contains("#13 and below"), "{s}");
}

#[test]
fn can_you_is_typed_with_completion_over_the_whole_tree() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::NextFailure);
    app.update(Action::Ask);
    let last = app.shared.questions().len() - 1;
    for _ in 0..last {
        app.update(Action::Down);
    }
    assert!(screen(&app, 110, 34).contains("Can you …? (type any subgoal or step)"));
    app.update(Action::Toggle);
    assert!(matches!(app.overlay, Some(Overlay::CanYou(_))));
    // Every subgoal and sequence of the tree, not only the current subgoal's.
    let all = app.shared.can_you_candidates("");
    assert!(all.contains(&"go place screw".to_string()), "{all:?}");
    for c in "pick scr".chars() {
        app.type_char(c);
    }
    let picked = app.shared.can_you_candidates("pick scr")[0].clone();
    assert!(picked.contains("pick screw"), "{picked}");
    assert!(screen(&app, 110, 34).contains("Can you pick scr▏?"));
    app.update(Action::Toggle);
    let a = app.shared.answer.as_ref().unwrap();
    assert_eq!(a.question.wording(), format!("Can you {picked}?"));
    // The same answer as the CLI's.
    let (ok, out, _) = common::btx(&[
        "ask",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--at",
        "10",
        "--node",
        &format!("#{}", app.shared.asked.as_ref().unwrap().0),
        &format!("Can you {picked}?"),
    ]);
    assert!(ok);
    assert_eq!(out.trim_end(), a.text.trim_end());
}

#[test]
fn the_causal_graph_is_a_graph_you_can_walk() {
    use btx::tui::app::Pane;
    let mut app = opened("sessions/case-study.jsonl");
    app.shared.selected = 4;
    app.update(Action::Why);
    app.update(Action::Down);
    app.update(Action::Toggle);
    app.update(Action::Graph);
    app.focus = Pane::Details;
    app.zoom = true;
    insta::assert_snapshot!("graph_80x24", screen(&app, 80, 24));
    app.zoom = false;
    insta::assert_snapshot!("graph_120x40", screen(&app, 120, 40));
    // Pick the first cause and centre on it: the view moves along the edge.
    app.update(Action::Expand);
    let picked = screen(&app, 120, 40);
    assert!(picked.contains("picked: "), "{picked}");
    app.update(Action::Toggle);
    let w = app.shared.why.as_ref().unwrap();
    let centre = w.centre.expect("centred on the cause");
    assert!(w.why.model.parents[w.why.query.targets[0]].contains(&centre));
    insta::assert_snapshot!("graph_recentred_120x40", screen(&app, 120, 40));
    // Esc: back to the variable asked about.
    app.update(Action::Back);
    assert_eq!(app.shared.why.as_ref().unwrap().centre, None);
}

#[test]
fn ascii_covers_every_sign_the_explorer_draws() {
    let mut buffers = Vec::new();
    for name in SCENES {
        buffers.push(render(&scene(name).unwrap(), 120, 40));
    }
    let mut app = opened("sessions/case-study.jsonl");
    app.shared.selected = 4;
    app.update(Action::Why);
    app.update(Action::Toggle);
    app.update(Action::Graph);
    buffers.push(render(&app, 120, 40));
    app.update(Action::ExportGraph);
    buffers.push(render(&app, 120, 40));
    app.update(Action::Back);
    app.update(Action::Help);
    app.update(Action::End);
    buffers.push(render(&app, 120, 40));
    buffers.push(render(
        &diff_app("trees/taxi-expected.xml", "trees/taxi.xml"),
        120,
        40,
    ));
    for buf in buffers {
        for cell in buf.content.iter() {
            let s = btx::tui::ascii_of(cell.symbol()).unwrap_or(cell.symbol());
            assert!(s.is_ascii(), "{:?} has no ASCII form", cell.symbol());
        }
    }
}

#[test]
fn a_key_that_cannot_act_says_why() {
    let mut tree = opened("trees/kitting.xml");
    for a in [
        Action::StepForward,
        Action::NextFailure,
        Action::Why,
        Action::Play,
    ] {
        tree.update(a);
        assert_eq!(
            tree.shared.message.as_deref(),
            Some("this is a tree, not a run: open a session or a robot's log to step through one"),
            "{a:?}"
        );
    }
    let mut app = demo();
    app.update(Action::End);
    app.update(Action::NextFailure);
    assert_eq!(
        app.shared.message.as_deref(),
        Some("no fault after tick 54")
    );
    assert!(screen(&app, 110, 34).contains("no fault after tick 54"));
    app.update(Action::Graph);
    assert_eq!(
        app.shared.message.as_deref(),
        Some("ask why first (w): the causal graph is the answer's")
    );
    app.update(Action::NextDivergence);
    assert_eq!(
        app.shared.message.as_deref(),
        Some("divergences are shown by btx open --diff A B")
    );
}

#[test]
fn running_nodes_are_picked_answers_are_kept_and_copied() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::NextFailure);
    // The nodes RUNNING at moment 10, in tree order; Enter selects one.
    let running = app.shared.running_nodes();
    assert_eq!(running.first(), Some(&1));
    app.update(Action::Running);
    assert!(matches!(app.overlay, Some(Overlay::Running(_))));
    assert!(screen(&app, 110, 34).contains("RUNNING now: Enter selects"));
    app.update(Action::End);
    let last = *running.last().unwrap();
    for _ in 1..running.len() {
        app.update(Action::Down);
    }
    app.update(Action::Toggle);
    assert_eq!(app.shared.selected, last);
    // Two answers: the first is kept under the second.
    app.update(Action::Ask);
    app.update(Action::Toggle);
    let first = app.shared.answer.as_ref().unwrap().text.clone();
    app.update(Action::Ask);
    app.update(Action::Down);
    app.update(Action::Toggle);
    assert_eq!(app.shared.history.len(), 1);
    assert!(
        app.shared.history[0].ends_with(&first),
        "{:?}",
        app.shared.history
    );
    assert!(app.shared.history[0].starts_with(&format!(
        "about {} #{last} at moment 10",
        app.shared.tree.description(last)
    )));
    // y queues the answer for the clipboard, as OSC 52.
    app.update(Action::Copy);
    let copied = app.shared.clipboard.clone().unwrap();
    assert!(copied.contains(&app.shared.answer.as_ref().unwrap().text));
    assert_eq!(btx::tui::osc52("hi"), "\u{1b}]52;c;aGk=\u{7}");
}

#[test]
fn home_and_end_reach_the_ends_of_a_pane_and_scrolling_stops_there() {
    use btx::tui::app::Pane;
    let mut app = why_repeat_or_end();
    app.focus = Pane::Details;
    let top = screen(&app, 80, 24);
    app.update(Action::End);
    let bottom = screen(&app, 80, 24);
    assert_ne!(top, bottom);
    // Past the end nothing moves, and one page up is one page up.
    app.update(Action::PageDown);
    assert_eq!(screen(&app, 80, 24), bottom);
    app.update(Action::PageUp);
    assert_ne!(screen(&app, 80, 24), bottom);
    app.update(Action::Start);
    assert_eq!(screen(&app, 80, 24), top);
}

/// Keys as the terminal sends them, through the explorer's event handler.
fn press(app: &mut btx::tui::app::App, keys: &str) {
    use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
    for c in keys.chars() {
        let code = match c {
            '\n' => KeyCode::Enter,
            c => KeyCode::Char(c),
        };
        let mods = if c.is_uppercase() {
            KeyModifiers::SHIFT
        } else {
            KeyModifiers::NONE
        };
        btx::tui::handle(app, Event::Key(KeyEvent::new(code, mods)), (110, 34));
    }
}

#[test]
fn a_question_typed_in_words_is_answered_as_btx_ask_answers_it() {
    let mut app = demo();
    app.update(Action::NextFailure);
    // `A`, then the words, typed as keys: letters are text, not actions
    // (`f` would jump to a failure, `a` open the questions).
    press(&mut app, "Awhy did look at chuck fail");
    let s = screen(&app, 110, 34);
    assert!(
        s.contains("ask about look at chuck: why did look at chuck fail▏"),
        "{s}"
    );
    assert!(s.contains("│why did look at chuck fail"), "{s}");
    press(&mut app, "\n");
    let r = app.shared.reply.as_ref().expect("an answer");
    assert_eq!(r.understood, "Why did look at chuck (#18) fail at 10:1?");
    let s = screen(&app, 110, 34);
    assert!(
        s.contains("Why did look at chuck (#18) fail at 10:1?"),
        "{s}"
    );
    // Word for word the CLI's answer, the sentence about the plan included.
    let (_, out, _) = common::btx(&[
        "ask",
        "sessions/kitting-lookat-fails-once.jsonl",
        "--at",
        "10",
        "why did look at chuck fail?",
    ]);
    assert_eq!(out.trim_end(), r.text().trim_end());
    assert!(
        r.text()
            .contains("Why it failed is not in the run: the plan scripted it"),
        "{}",
        r.text()
    );
}

#[test]
fn every_prompt_takes_typed_text() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::NextFailure);
    app.update(Action::Ask);
    for _ in 0..app.shared.questions().len() - 1 {
        app.update(Action::Down);
    }
    app.update(Action::Toggle);
    assert!(matches!(app.overlay, Some(Overlay::CanYou(_))));
    press(&mut app, "pick");
    assert!(screen(&app, 110, 34).contains("Can you pick▏?"));
    app.update(Action::Back);
    // The timeline's name filter.
    app.focus = btx::tui::app::Pane::Timeline;
    app.update(Action::Find);
    press(&mut app, "look");
    assert!(
        matches!(&app.overlay, Some(Overlay::Filter(f)) if f.input.text == "look"),
        "{:?}",
        app.overlay
    );
}

#[test]
fn plus_and_minus_say_more_or_less_of_a_why_answer() {
    // Why did the kitting task succeed? (ten explanations)
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    app.update(Action::End);
    app.shared.selected = 1;
    app.update(Action::Why);
    app.update(Action::Toggle);
    // The answer's keys are its pane's once Tab brings the focus there.
    assert_eq!(app.focus, btx::tui::app::Pane::Tree);
    app.focus = btx::tui::app::Pane::Ask;
    let all = app.shared.why.as_ref().unwrap().why.groups().len();
    assert!(all > 3, "{all}");
    assert_eq!(app.shared.why.as_ref().unwrap().why.shown, Some(3));
    let s = screen(&app, 200, 70);
    assert!(
        s.contains(&format!("… and {} more (+ shows more)", all - 3)),
        "{s}"
    );
    app.update(Action::Faster);
    assert_eq!(app.shared.why.as_ref().unwrap().why.shown, None);
    app.update(Action::Slower);
    app.update(Action::Slower);
    assert_eq!(app.shared.why.as_ref().unwrap().why.shown, Some(1));
}

#[test]
fn format_characters_never_make_a_name_read_as_another_on_screen() {
    // A zero-width space inside "ask" and a right-to-left override: shown
    // as escapes in the tree and the details (#26 item 7).
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("fmt.xml");
    std::fs::write(
        &tree,
        "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Sequence name=\"go\u{2066}home\u{2069}\"><AlwaysSuccess name=\"as\u{200b}k\"/><AlwaysSuccess name=\"\u{202e}evil\"/></Sequence></BehaviorTree></root>",
    )
    .unwrap();
    let app = btx::tui::open(&tree, None, &btx::xml::LoadOptions::default()).unwrap();
    let s = screen(&app, 100, 30);
    assert!(
        !s.contains('\u{200b}') && !s.contains('\u{202e}') && !s.contains('\u{2066}'),
        "{s}"
    );
    assert!(s.contains("as\\u{200b}k"), "{s}");
    assert!(s.contains("go\\u{2066}home\\u{2069}"), "{s}");
}

#[test]
fn a_rosbags_runs_are_picked_with_r() {
    // tests/fixtures/rosbag/two_goals: two goals of the real
    // BehaviorTree.CPP, written by PyPI rosbags (see tests/rosbag.rs).
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let tree = root.join("tests/fixtures/rosbag/navigator.xml");
    let opts = btx::xml::LoadOptions {
        run_tree: Some(tree),
        ..Default::default()
    };
    let mut app =
        btx::tui::open(&root.join("tests/fixtures/rosbag/two_goals"), None, &opts).unwrap();
    // The last run is shown first, as every command reads it.
    assert_eq!(app.shared.title, "two_goals · run 2 of 2");
    assert_eq!(
        app.shared.session.as_ref().unwrap().index.transitions.len(),
        14
    );
    app.update(Action::Pick);
    insta::assert_snapshot!("run_picker", screen(&app, 110, 20));
    app.update(Action::Up);
    app.update(Action::Toggle);
    assert_eq!(app.shared.title, "two_goals · run 1 of 2");
    assert_eq!(
        app.shared.session.as_ref().unwrap().index.transitions.len(),
        20
    );
    // The keys and the other run are kept: back to run 2.
    app.update(Action::Pick);
    app.update(Action::Down);
    app.update(Action::Toggle);
    assert_eq!(app.shared.title, "two_goals · run 2 of 2");
    // One run: R says why it cannot act.
    let mut one = opened("sessions/kitting-lookat-fails-once.jsonl");
    one.update(Action::Pick);
    assert!(
        one.shared
            .message
            .as_deref()
            .unwrap()
            .contains("one run here"),
        "{:?}",
        one.shared.message
    );
}

/// Nav2's navigator run with FollowPath failing twice: the session, its
/// file, and the directory that holds it (kept while it is read).
fn nav2_followpath_fails_twice() -> (btx::session::Session, std::path::PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("nav.jsonl");
    common::run_nav2(
        "navigate_to_pose_w_replanning_and_recovery.xml",
        "nav2_followpath_fails_twice.plan",
        &run,
    );
    let s = btx::session::Session::load(&run).unwrap();
    (s, run, dir)
}

#[test]
fn the_strip_shows_a_status_only_in_the_ticks_a_node_ran() {
    // Nav2's navigator with FollowPath failing twice: the strip said `F`
    // at ticks where FollowPath was IDLE all tick (#27 item 3).
    let (s, run, _dir) = nav2_followpath_fails_twice();
    // The action (a RecoveryNode is named FollowPath too).
    let follow = (1..=s.tree.len() as u32)
        .find(|&u| s.tree.description(u) == "FollowPath" && s.tree.node(u).children.is_empty())
        .unwrap();
    // What `btx log --node` says FollowPath did, tick by tick.
    let (ok, log, err) = common::btx(&[
        "log",
        run.to_str().unwrap(),
        "--node",
        &format!("#{follow}"),
    ]);
    assert!(ok, "{err}");
    let mut rows: std::collections::BTreeMap<u32, Vec<String>> = Default::default();
    for l in log.lines().skip(1) {
        let cols: Vec<&str> = l.split_whitespace().collect();
        let tick: u32 = cols[0].parse().unwrap();
        rows.entry(tick)
            .or_default()
            .push(cols[cols.len() - 1].to_string());
    }
    let mut expected = String::new();
    let mut ran = false;
    let mut running = false;
    for t in 1..=s.index.ticks() {
        let c = match rows.get(&t) {
            Some(st) => {
                ran = true;
                running = st.last().unwrap() == "RUNNING";
                if running {
                    'R'
                } else if let Some(done) =
                    st.iter().rev().find(|x| *x == "SUCCESS" || *x == "FAILURE")
                {
                    done.chars().next().unwrap()
                } else {
                    'H'
                }
            }
            None if running => 'R',
            None if ran => '.',
            None => ' ',
        };
        expected.push(c);
    }
    let strip: String = (1..=s.index.ticks())
        .map(|t| match s.index.tick_mark(follow, t) {
            btx::session::TickMark::Running => 'R',
            btx::session::TickMark::Done(st) => st.as_str().chars().next().unwrap(),
            btx::session::TickMark::Halted => 'H',
            btx::session::TickMark::NotTicked => '.',
            btx::session::TickMark::NotYet => ' ',
        })
        .collect();
    assert_eq!(strip, expected, "{log}");
    // Not run at tick 1; at tick 4 it failed and was started again in the
    // same tick, so it ended the tick RUNNING; at tick 6 it ended failed.
    assert_eq!(strip, " RRRRFRRRS");
    // On screen, in ASCII: the same marks.
    let mut app = btx::tui::App::new(s.tree.clone(), Some(s), "nav".into());
    app.shared.selected = follow;
    app.update(Action::End);
    let screen = screen(&app, 120, 40);
    assert!(screen.contains("⊘ halted · not ticked"), "{screen}");
}

#[test]
fn the_finder_ranks_a_nodes_own_name_above_letters_spread_over_its_path() {
    let app = opened("sessions/kitting-lookat-fails-once.jsonl");
    let found = app.shared.finder_results("chuck");
    let own = |u: u32| {
        let d = app.shared.tree.description(u).to_lowercase();
        let id = app.shared.tree.node(u).id.to_lowercase();
        d.contains("chuck") || id.contains("chuck")
    };
    let first_other = found.iter().position(|(u, _)| !own(*u));
    // Every node named for the chuck comes before any other.
    if let Some(k) = first_other {
        assert!(found[k..].iter().all(|(u, _)| !own(*u)), "{found:?}");
    }
    assert!(own(found[0].0));
    // "back to approach pose" matched by letters of its path's segments
    // comes after every node whose one path segment holds them.
    let back = (1..=app.shared.tree.len() as u32)
        .find(|&u| app.shared.tree.description(u) == "back to approach pose")
        .unwrap();
    let at = |u: u32| found.iter().position(|(x, _)| *x == u);
    if let (Some(b), Some(k)) = (at(back), first_other) {
        assert!(b >= k);
        let label = app.shared.finder_label(found[b].0);
        let idx = &found[b].1;
        // Its matched letters are where they are in the label.
        let chars: Vec<char> = label.chars().collect();
        let got: String = idx.iter().map(|&i| chars[i].to_ascii_lowercase()).collect();
        assert_eq!(got, "chuck");
    }
}

#[test]
fn every_prompt_edits_as_a_line_editor() {
    use btx::tui::panes::overlays::Overlay;
    use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
    let press = |app: &mut btx::tui::app::App, code: KeyCode, m: KeyModifiers| {
        btx::tui::handle(app, Event::Key(KeyEvent::new(code, m)), (120, 40))
    };
    let typed = |app: &mut btx::tui::app::App, s: &str| {
        for c in s.chars() {
            press(app, KeyCode::Char(c), KeyModifiers::NONE);
        }
    };
    let text = |app: &btx::tui::app::App| match app.prompt_text() {
        Some(t) => t.to_string(),
        None => panic!("no prompt: {:?}", app.overlay),
    };
    let none = KeyModifiers::NONE;
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    // The finder: typing, ←, Home, End, Backspace, Ctrl-w, Ctrl-u.
    app.update(Action::Find);
    typed(&mut app, "chuk");
    press(&mut app, KeyCode::Left, none);
    typed(&mut app, "c");
    assert_eq!(text(&app), "chuck");
    assert!(screen(&app, 120, 40).contains("find: chuc▏k"));
    press(&mut app, KeyCode::Home, none);
    typed(&mut app, "look ");
    press(&mut app, KeyCode::End, none);
    press(&mut app, KeyCode::Backspace, none);
    assert_eq!(text(&app), "look chuc");
    press(&mut app, KeyCode::Char('w'), KeyModifiers::CONTROL);
    assert_eq!(text(&app), "look ");
    press(&mut app, KeyCode::Char('u'), KeyModifiers::CONTROL);
    assert_eq!(text(&app), "");
    // A paste goes in whole, control characters left out.
    btx::tui::handle(&mut app, Event::Paste("pick\nscrew".into()), (120, 40));
    assert_eq!(text(&app), "pickscrew");
    press(&mut app, KeyCode::Esc, none);
    // "Can you …?" and the timeline's filter take text the same way.
    app.overlay = Some(Overlay::can_you());
    typed(&mut app, "pick");
    press(&mut app, KeyCode::Left, none);
    press(&mut app, KeyCode::Backspace, none);
    assert_eq!(text(&app), "pik");
    assert!(screen(&app, 120, 40).contains("Can you pi▏k?"));
    press(&mut app, KeyCode::Esc, none);
    app.update(Action::NextPane);
    app.update(Action::Find);
    assert!(
        matches!(app.overlay, Some(Overlay::Filter(_))),
        "{:?}",
        app.overlay
    );
    typed(&mut app, "look");
    assert_eq!(text(&app), "look");
}

#[test]
fn fixed_screens_at_80x24_and_120x40() {
    // #27 item 10: the strip of a node that failed and ran again, the
    // status bar's hints, a prompt's cursor, the details' path and run.
    let (s, _, _dir) = nav2_followpath_fails_twice();
    let mut app = btx::tui::App::new(s.tree.clone(), Some(s), "nav.jsonl".into());
    app.update(Action::End);
    app.shared.selected = 10;
    for (w, h) in [(80, 24), (120, 40)] {
        insta::assert_snapshot!(format!("nav2_strip_{w}x{h}"), screen(&app, w, h));
    }
    app.overlay = Some(btx::tui::panes::overlays::Overlay::CanYou(
        btx::tui::panes::overlays::CanYou {
            input: btx::tui::text_input::TextInput {
                text: "pick screw".into(),
                cursor: Some(4),
            },
            ..Default::default()
        },
    ));
    for (w, h) in [(80, 24), (120, 40)] {
        insta::assert_snapshot!(format!("can_you_cursor_{w}x{h}"), screen(&app, w, h));
    }
    // The finder: a match in a node's own name first (item 6).
    use ratatui::crossterm::event::Event;
    let mut app = opened("tests/fixtures/logs/kitting_lookat_fails_once.btlog");
    app.update(Action::Find);
    for c in "chuck".chars() {
        btx::tui::handle(&mut app, Event::Key(key_event(&c.to_string())), (120, 40));
    }
    for (w, h) in [(80, 24), (120, 40)] {
        insta::assert_snapshot!(format!("finder_chuck_{w}x{h}"), screen(&app, w, h));
    }
    // A key that cannot act says why (item 2): Right on a leaf.
    let mut app = opened("tests/fixtures/logs/kitting_lookat_fails_once.btlog");
    app.update(Action::NextFailure);
    for (w, h) in [(80, 24), (120, 40)] {
        btx::tui::handle(&mut app, Event::Key(key_event("Right")), (w, h));
        insta::assert_snapshot!(format!("a_leaf_says_why_{w}x{h}"), screen(&app, w, h));
    }
    // Two runs of one tree part ways once (item 4): ≠ where, · what follows.
    let mut d = diff_app(
        "tests/fixtures/logs/kitting_nominal.btlog",
        "tests/fixtures/logs/kitting_lookat_fails_once.btlog",
    );
    d.update(Action::NextDivergence);
    for (w, h) in [(80, 24), (120, 40)] {
        insta::assert_snapshot!(format!("diff_parting_{w}x{h}"), screen(&d, w, h));
    }
}

#[test]
fn at_80_columns_the_diff_cuts_names_with_an_ellipsis_and_keeps_each_uid() {
    let app = diff_app("trees/taxi-expected.xml", "trees/taxi.xml");
    let s = screen(&app, 80, 24);
    insta::assert_snapshot!("diff_taxi_80x24", s);
    // Every row of each tree pane ends its name with its whole `#uid`:
    // the uids shown are those of the tree, in order, none cut.
    let uids: Vec<u32> = s
        .lines()
        .filter_map(|l| {
            let left: String = l.chars().take(40).collect();
            let at = left.rfind(" #")?;
            left[at + 2..]
                .trim_end_matches(|c: char| !c.is_ascii_digit())
                .split(|c: char| !c.is_ascii_digit())
                .next()?
                .parse()
                .ok()
        })
        .collect();
    assert!(uids.len() > 5, "{s}");
    assert!(uids.windows(2).all(|w| w[1] == w[0] + 1), "{uids:?}\n{s}");
    assert!(s.contains('…'), "{s}");
}

#[test]
fn faster_and_slower_while_paused_say_the_speed() {
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    assert!(!app.shared.playing);
    app.update(Action::Faster);
    assert_eq!(
        app.shared.message.as_deref(),
        Some("play speed: a step every 100 ms (s plays)")
    );
    app.update(Action::Slower);
    assert_eq!(
        app.shared.message.as_deref(),
        Some("play speed: a step every 200 ms (s plays)")
    );
}

/// A key press as a terminal sends it, from its name in the keymap.
fn key_event(name: &str) -> ratatui::crossterm::event::KeyEvent {
    use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
    let (mods, base) = match name.strip_prefix("Ctrl-") {
        Some(b) => (KeyModifiers::CONTROL, b),
        None => (KeyModifiers::NONE, name),
    };
    let code = match base {
        "Up" => KeyCode::Up,
        "Down" => KeyCode::Down,
        "Left" => KeyCode::Left,
        "Right" => KeyCode::Right,
        "Enter" => KeyCode::Enter,
        "Tab" => KeyCode::Tab,
        "Esc" => KeyCode::Esc,
        "Home" => KeyCode::Home,
        "End" => KeyCode::End,
        "PageUp" => KeyCode::PageUp,
        "PageDown" => KeyCode::PageDown,
        "Backspace" => KeyCode::Backspace,
        "Space" => KeyCode::Char(' '),
        c => KeyCode::Char(c.chars().next().unwrap()),
    };
    let shift = matches!(code, KeyCode::Char(c) if c.is_ascii_uppercase());
    KeyEvent::new(
        code,
        if shift {
            mods | KeyModifiers::SHIFT
        } else {
            mods
        },
    )
}

#[test]
fn every_key_in_every_pane_and_mode_acts_or_says_why_not() {
    // #27 item 2: "a key that cannot act says why". Every key of the
    // keymap, pressed through the terminal's event path in each pane and
    // mode of a recorded run, changes the screen (what it did, or the
    // status bar saying why it could not); quitting quits.
    use btx::tui::app::Pane;
    use btx::tui::panes::overlays::Overlay;
    use ratatui::crossterm::event::Event;
    type Setup = fn(&mut btx::tui::app::App);
    let modes: [(&str, Setup); 11] = [
        ("tree", |_| {}),
        ("timeline", |a| a.focus = Pane::Timeline),
        ("details", |a| a.focus = Pane::Details),
        ("answer", |a| {
            a.update(Action::Ask);
            a.update(Action::Toggle);
            a.focus = Pane::Ask;
        }),
        ("help", |a| a.update(Action::Help)),
        ("finder", |a| a.update(Action::Find)),
        ("timeline filter", |a| {
            a.focus = Pane::Timeline;
            a.update(Action::Find);
        }),
        ("can you", |a| {
            a.overlay = Some(Overlay::CanYou(btx::tui::panes::overlays::CanYou {
                input: btx::tui::text_input::TextInput {
                    text: String::new(),
                    cursor: Some(0),
                },
                ..Default::default()
            }));
        }),
        ("questions", |a| a.update(Action::Ask)),
        ("playing", |a| a.update(Action::Play)),
        ("at the end", |a| a.update(Action::End)),
    ];
    let mut silent = Vec::new();
    for (mode, setup) in modes {
        for b in KEYMAP {
            for &k in b.keys {
                let mut app = opened("tests/fixtures/logs/kitting_lookat_fails_once.btlog");
                app.update(Action::NextFailure);
                setup(&mut app);
                app.shared.message = None;
                // Styles count: a list's selection is drawn reversed.
                let before = render(&app, 120, 40);
                btx::tui::handle(&mut app, Event::Key(key_event(k)), (120, 40));
                if app.quit {
                    assert_eq!(b.action, Action::Quit, "{mode}: {k} quit");
                    continue;
                }
                if render(&app, 120, 40) == before {
                    silent.push(format!("{mode}: {k} ({})", b.help));
                }
            }
        }
    }
    // The side-by-side diff of two runs: its own keys act, the others say
    // they are not in it.
    type DiffSetup = fn(&mut btx::tui::diff::DiffApp);
    let diff_modes: [(&str, DiffSetup); 3] = [
        ("diff", |_| {}),
        ("diff help", |d| d.update(Action::Help)),
        ("diff answer", |d| d.update(Action::Why)),
    ];
    for (mode, setup) in diff_modes {
        for b in KEYMAP {
            for &k in b.keys {
                let mut d = diff_app(
                    "tests/fixtures/logs/kitting_nominal.btlog",
                    "tests/fixtures/logs/kitting_lookat_fails_once.btlog",
                );
                setup(&mut d);
                d.shared.message = None;
                let before = render(&d, 120, 40);
                btx::tui::Screen::event(&mut d, Event::Key(key_event(k)), (120, 40));
                if d.quit {
                    assert_eq!(b.action, Action::Quit, "{mode}: {k} quit");
                    continue;
                }
                if render(&d, 120, 40) == before {
                    silent.push(format!("{mode}: {k} ({})", b.help));
                }
            }
        }
    }
    assert!(
        silent.is_empty(),
        "{} silent keys:\n{}",
        silent.len(),
        silent.join("\n")
    );
}

/// The fleet view on the shipped kitting sessions.
fn fleet_app() -> btx::tui::fleet::FleetApp {
    // Names as a person gives them, relative to the project.
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    let paths = common::kitting_fleet();
    let files = btx::fleet::files(&paths).unwrap();
    let opts = btx::xml::LoadOptions::default();
    let fleet = btx::fleet::Fleet::read(&files, &opts, None, None, &|| {});
    btx::tui::fleet::FleetApp::new(fleet, opts)
}

#[test]
fn the_fleet_view_shows_failures_as_bars_and_opens_a_run() {
    // #31 item 4: the fleet in the explorer; Enter on an action lists the
    // runs it failed in, Enter on a run opens it, and quitting the run
    // comes back to the fleet.
    use ratatui::crossterm::event::Event;
    let mut app = fleet_app();
    for (w, h) in [(80, 24), (120, 40)] {
        insta::assert_snapshot!(format!("fleet_{w}x{h}"), screen(&app, w, h));
    }
    // Look at chuck: the runs it failed in are the two that say so.
    let look = app
        .shared
        .nodes
        .iter()
        .position(|n| n.name == "look at chuck #18")
        .unwrap();
    app.shared.node = look;
    app.update(Action::Toggle);
    let names: Vec<&str> = app
        .shared
        .shown
        .iter()
        .map(|&i| app.shared.fleet.runs[i].name.as_str())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    assert!(names.iter().all(|n| n.contains("lookat")), "{names:?}");
    insta::assert_snapshot!("fleet_only_look_at_chuck", screen(&app, 120, 40));
    // Enter opens the run at its end; q there comes back here.
    btx::tui::Screen::event(&mut app, Event::Key(key_event("Enter")), (120, 40));
    let run = app.opened.as_ref().expect("the run opened");
    assert_eq!(
        run.shared.pos as usize,
        run.shared.session.as_ref().unwrap().index.transitions.len()
    );
    let shown = screen(&app, 120, 40);
    assert!(shown.contains("full tree"));
    // Its status bar says where q goes (it said "q quit").
    assert!(
        shown.contains("q back") && !shown.contains("q quit"),
        "{shown}"
    );
    btx::tui::Screen::event(&mut app, Event::Key(key_event("q")), (120, 40));
    assert!(app.opened.is_none() && !app.quit);
    // Esc lists every run again; a key the view has no use for says so.
    app.update(Action::Back);
    assert_eq!(app.shared.shown.len(), app.shared.fleet.runs.len());
    app.update(Action::Why);
    assert!(app
        .shared
        .message
        .as_deref()
        .unwrap()
        .contains("is not in the fleet view"));
    btx::tui::Screen::event(&mut app, Event::Key(key_event("q")), (120, 40));
    assert!(app.quit);
}

/// One ask prompt (#38 item 5): `a` and `A` open the same prompt; the
/// questions about the node are its completions, filtered as one types;
/// Space and q are typed, not actions; Enter asks what was typed as typed;
/// Tab takes the chosen completion into the text.
#[test]
fn one_ask_prompt_takes_typed_words_and_completions() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::NextFailure);
    press(&mut app, "a");
    assert!(matches!(app.overlay, Some(Overlay::Words(_))));
    let s = screen(&app, 110, 34);
    assert!(s.contains("What went wrong?"), "{s}");
    insta::assert_snapshot!("ask_prompt_80x24", screen(&app, 80, 24));
    // Typed with spaces and a q: nothing quits, nothing else acts.
    press(&mut app, "is it q ok");
    assert!(!app.quit);
    assert!(
        screen(&app, 110, 34).contains("is it q ok▏"),
        "{}",
        screen(&app, 110, 34)
    );
    // Filtered as one types: "went" keeps "What went wrong?".
    app.edit(btx::tui::text_input::Edit::ToStart);
    press(&mut app, "went");
    assert_eq!(
        btx::tui::panes::overlays::Words::completions(&app.shared, "went")
            .first()
            .map(String::as_str),
        Some("What went wrong?")
    );
    // Tab takes the completion into the text; Enter asks it.
    btx::tui::handle(
        &mut app,
        ratatui::crossterm::event::Event::Key(ratatui::crossterm::event::KeyEvent::new(
            ratatui::crossterm::event::KeyCode::Tab,
            ratatui::crossterm::event::KeyModifiers::NONE,
        )),
        (110, 34),
    );
    assert_eq!(app.prompt_text(), Some("What went wrong?"));
    press(&mut app, "\n");
    assert!(app.overlay.is_none());
    let a = app.shared.answer.as_ref().expect("the list's answer");
    assert!(
        a.text.contains("because look at chuck failed"),
        "{}",
        a.text
    );
    // Typed text is asked as typed, even where a completion is shown.
    press(&mut app, "Awhats wrong\n");
    let r = app.shared.reply.as_ref().expect("a reply");
    assert_eq!(r.understood, "What went wrong?");
}

/// A reading btx is not sure of says what it read in the answer pane and
/// offers the other readings as a list to pick from.
#[test]
fn an_unsure_reading_offers_the_other_readings_to_pick() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::NextFailure);
    press(&mut app, "alook at the chuck failed\n");
    let r = app.shared.reply.as_ref().expect("a reply");
    assert!(r.unsure(), "{:?}", r.confidence);
    assert!(matches!(app.overlay, Some(Overlay::Words(_))));
    let s = screen(&app, 110, 34);
    assert!(s.contains("When did look at chuck (#18) fail?"), "{s}");
    assert!(s.contains("I read this as"), "{s}");
    // Picking one asks it.
    app.update(Action::Down);
    press(&mut app, "\n");
    let r = app.shared.reply.as_ref().expect("a reply");
    assert!(
        r.understood
            .starts_with("How often did look at chuck (#18) fail"),
        "{}",
        r.understood
    );
    assert!(app.shared.did_you_mean.is_empty());
}

/// `f` goes by faults (#39 item 5): in the patrol, the e-stop check under
/// its Inverter answers no in every tick, as designed; the battery check
/// failing at tick 7, which fails the patrol, is the one fault.
#[test]
fn f_stops_at_faults_not_at_branches_taken() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let opts = btx::xml::LoadOptions {
        run_tree: Some(root.join("tests/fixtures/answers/patrol-battery.xml")),
        ..Default::default()
    };
    let mut app = btx::tui::open(
        &root.join("tests/fixtures/logs/patrol_battery_drops.btlog"),
        None,
        &opts,
    )
    .unwrap();
    app.update(Action::Start);
    app.update(Action::NextFailure);
    assert_eq!(
        app.shared.tree.description(app.shared.selected),
        "battery ok"
    );
    assert!(screen(&app, 110, 34).contains("tick 7 of 7"));
    app.update(Action::NextFailure);
    assert_eq!(app.shared.message.as_deref(), Some("no fault after tick 7"));
}

/// #40 item 2: `e` lists the run's faults as a watch told them, newest
/// first; Enter goes to the moment of one with its failed node selected.
#[test]
fn the_faults_are_listed_newest_first_and_enter_goes_to_one() {
    use btx::tui::panes::overlays::Overlay;
    let mut app = demo();
    app.update(Action::Faults);
    let Some(Overlay::Faults(btx::tui::panes::overlays::Faults { lines, .. })) = &app.overlay
    else {
        panic!("no faults list: {:?}", app.shared.message);
    };
    let texts: Vec<&str> = lines.iter().map(|l| l.0.as_str()).collect();
    assert_eq!(
        texts,
        [
            "run 1 ended at tick 54: SUCCESS",
            "26:20 recovered: RetryUntilSuccessful (#7) succeeded",
            "10:1 look at chuck failed; insert large gear failed; RetryUntilSuccessful (#7) tries again, attempt 2 of 3",
        ]
    );
    let shown = screen(&app, 110, 34);
    assert!(shown.contains("Faults, newest first"), "{shown}");
    assert!(
        shown.contains("10:1 look at chuck failed; insert large gear failed"),
        "{shown}"
    );
    app.update(Action::Down);
    app.update(Action::Down);
    app.update(Action::Toggle);
    assert!(app.overlay.is_none());
    assert_eq!(app.shared.at().unwrap().moment().to_string(), "10:1");
    assert_eq!(app.shared.selected, 18);
}

#[test]
fn a_question_longer_than_the_prompt_shows_where_it_is_typed() {
    // The prompt was drawn in its window's title and cut on the right, so
    // past the edge the user typed blind and was told "at the start of the
    // text" at each key.
    let mut app = demo();
    app.update(Action::NextFailure);
    let words =
        "why did look at chuck fail and not succeed before the robot went on to the next gear";
    press(&mut app, &format!("A{words}"));
    let s = screen(&app, 110, 34);
    assert!(s.contains("ask about look at chuck: …"), "{s}");
    assert!(s.contains("went on to the next gear▏ ┐"), "{s}");
    assert_eq!(app.shared.message, None);
    // Home shows its start again, the rest cut with a mark.
    use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
    let home = KeyEvent::new(KeyCode::Home, KeyModifiers::NONE);
    btx::tui::handle(&mut app, Event::Key(home), (110, 34));
    let s = screen(&app, 110, 34);
    assert!(
        s.contains("ask about look at chuck: ▏why did look at chuck fail"),
        "{s}"
    );
    assert!(!s.contains("next gear"), "{s}");
    assert_eq!(app.shared.message, None);
}

#[test]
fn a_paste_of_pages_into_the_prompt_is_cut_at_its_bound_and_said() {
    // 20 KB pasted into the question prompt pinned a core for over a
    // minute: completion ran at each key over the whole text (#41 item 8).
    use btx::tui::text_input::{Edit, PROMPT_MAX};
    let mut app = demo();
    app.update(Action::NextFailure);
    press(&mut app, "a");
    let pasted = "why did look at chuck fail ".repeat(800);
    btx::tui::handle(
        &mut app,
        ratatui::crossterm::event::Event::Paste(pasted),
        (110, 34),
    );
    let Some(text) = app.prompt_text() else {
        panic!("{:?}", app.overlay)
    };
    assert_eq!(text.chars().count(), PROMPT_MAX);
    assert!(
        app.shared.message.as_deref().is_some_and(
            |m| m.contains("at most 1000 characters: the 20600 past them were left out")
        ),
        "{:?}",
        app.shared.message
    );
    // Typed on, nothing more is taken, and the screen still draws.
    app.edit(Edit::Insert("x".into()));
    let Some(text) = app.prompt_text() else {
        panic!()
    };
    assert_eq!(text.chars().count(), PROMPT_MAX);
    assert!(screen(&app, 110, 34).contains("why did look at chuck fail"));
}

/// After an answer the focus is where the question was asked from, so the
/// keys that move in time still do; an answer about the moment left goes
/// to the history once, with its moment, and a typed question is said
/// once in it.
#[test]
fn an_answer_keeps_the_focus_and_the_history_keeps_each_answer_once_with_its_moment() {
    use btx::tui::app::Pane;
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    app.update(Action::NextFailure);
    let moment = app.shared.shown_moment().unwrap().to_string();
    app.focus = Pane::Timeline;
    app.shared.ask_words("why did look at chuck fail?");
    assert_eq!(app.focus, Pane::Timeline);
    let on_screen = app.shared.answer_text().unwrap();
    assert_eq!(
        on_screen
            .matches("Why did look at chuck (#18) fail")
            .count(),
        1,
        "{on_screen}"
    );
    app.shared.ask(&btx::explain::Question::Tree(
        btx::explain::TreeQuestion::Doing,
    ));
    app.update(Action::End);
    let end = app.shared.shown_moment().unwrap().to_string();
    assert_ne!(end, moment, "End moved in time");
    let h = &app.shared.history;
    assert_eq!(h.len(), 2, "{h:#?}");
    assert!(
        h[0].contains(&format!("at moment {moment}")) && h[0].contains("What are you doing?"),
        "{h:#?}"
    );
    assert!(h[1].contains(&format!("at moment {moment}")), "{h:#?}");
    assert_eq!(
        h[1].matches("Why did look at chuck (#18) fail").count(),
        1,
        "{h:#?}"
    );
    // Moving again adds nothing: the answer is in the history once.
    app.update(Action::Start);
    assert_eq!(app.shared.history.len(), 2);
}

/// The screen's rows as one text, each row's borders and padding off, so
/// that a wrapped sentence reads whole.
fn joined(s: &str) -> String {
    s.lines()
        .map(|l| {
            l.trim_matches(|c: char| c == ' ' || "│┃".contains(c))
                .trim()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// A why-question, a divergence and a causal variable longer than the
/// screen wraps; none is cut at the popup's or the status bar's edge.
#[test]
fn long_lines_wrap_in_popups_and_the_status_bar() {
    let mut app = opened("sessions/kitting-lookat-fails-once.jsonl");
    app.update(Action::NextFailure);
    app.update(Action::Why);
    let Some(btx::tui::panes::overlays::Overlay::Why(btx::tui::panes::overlays::WhyList {
        targets,
        ..
    })) = &app.overlay
    else {
        panic!("the why-questions: {:?}", app.overlay)
    };
    let questions: Vec<String> = targets.iter().map(|(_, q)| q.clone()).collect();
    assert!(
        questions.iter().any(|q| q.chars().count() > 70),
        "{questions:#?}"
    );
    let s = joined(&screen(&app, 80, 40));
    for q in &questions {
        assert!(
            s.contains(q.as_str()),
            "{q:?} cut:\n{}",
            screen(&app, 80, 40)
        );
    }
    let mut d = diff_app(
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
    );
    d.update(Action::NextDivergence);
    let said = d.shared.message.clone().unwrap();
    assert!(said.chars().count() > 80, "{said}");
    let s = screen(&d, 80, 30);
    assert!(joined(&s).ends_with(&said), "{said:?} cut:\n{s}");
}

#[test]
fn the_diffs_and_the_fleets_help_scroll_to_their_last_key_on_a_small_terminal() {
    let mut diff = diff_app(
        "sessions/kitting-nominal.jsonl",
        "sessions/kitting-lookat-fails-once.jsonl",
    );
    diff.update(Action::Help);
    let top = screen(&diff, 80, 16);
    assert!(top.contains("↓ more") && top.contains("the diff"), "{top}");
    assert!(!top.contains("end of the run"), "{top}");
    diff.update(Action::End);
    let end = screen(&diff, 80, 16);
    assert!(
        end.contains("end of the run") && !end.contains("↓ more"),
        "{end}"
    );
    // Up from the end scrolls at once (the end is where the last page shows).
    diff.update(Action::Up);
    assert!(screen(&diff, 80, 16).contains("↓ more"));

    let files = btx::fleet::files(&common::kitting_fleet()).unwrap();
    let opts = btx::xml::LoadOptions::default();
    let fleet = btx::fleet::Fleet::read(&files, &opts, None, None, &|| {});
    let mut app = btx::tui::fleet::FleetApp::new(fleet, opts);
    app.update(Action::Help);
    let top = screen(&app, 80, 24);
    assert!(
        top.contains("↓ more") && top.contains("the actions, or the runs"),
        "{top}"
    );
    app.update(Action::End);
    let end = screen(&app, 80, 24);
    assert!(
        end.contains("open the run in the explorer (q comes back)"),
        "{end}"
    );
    assert!(!end.contains("↓ more"), "{end}");
}
