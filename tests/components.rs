//! Every key of every component of the explorer, pressed in isolation
//! (#43 item 1): each pane and window is given the shared state of the
//! demo run at its first fault, takes each action of the keymap with and
//! without the focus, and draws after it. What the router relies on is
//! checked here: a key a pane ignores changes nothing, the panes' keys
//! that act wherever the focus is are each one pane's, and a window takes
//! every key and closes on Esc. The fleet view's and the side-by-side
//! diff's components are pressed the same way over what they share.

mod common;

use btx::tui::diff::panes::{DiffHelp, Summary, Timelines, Trees};
use btx::tui::diff::DiffShared;
use btx::tui::fleet::panes::{Failures, FleetHelp, RunDetail, Runs, Spells};
use btx::tui::fleet::FleetShared;
use btx::tui::keymap::{Action, Keymap, KEYMAP};
use btx::tui::panes::answers::Answers;
use btx::tui::panes::details::Details;
use btx::tui::panes::overlays::Overlay;
use btx::tui::panes::timeline::Timeline;
use btx::tui::panes::tree::TreePane;
use btx::tui::panes::{Component, Handled, Hints};
use btx::tui::shared::Shared;

/// The demo run at its first fault (look at chuck, #18, selected).
fn shared() -> Shared {
    let mut app = btx::tui::demo();
    app.update(Action::NextFailure);
    assert_eq!(app.shared.selected, 18);
    app.shared
}

/// The demo at its first fault, then after `keys` pressed in the explorer:
/// the states in which the panes' keys mean something.
fn shared_after(keys: &[Action], focus: Option<btx::tui::app::Pane>) -> Shared {
    let mut app = btx::tui::demo();
    app.update(Action::NextFailure);
    if let Some(p) = focus {
        app.focus = p;
    }
    for &k in keys {
        app.update(k);
    }
    app.shared
}

/// The states the help is held against: at a fault; with a question
/// answered; with a why-answer; its causal graph; the graph centred on a
/// neighbour.
const STATES: usize = 5;

fn state(i: usize) -> Shared {
    use btx::tui::app::Pane;
    use Action::*;
    match i {
        0 => shared_after(&[], None),
        1 => shared_after(&[Ask, Toggle], None),
        2 => shared_after(&[Why, Toggle], None),
        3 => shared_after(&[Why, Toggle, Graph], None),
        _ => shared_after(&[Why, Toggle, Graph, Expand, Toggle], Some(Pane::Details)),
    }
}

fn panes() -> Vec<(&'static str, Box<dyn Component>)> {
    vec![
        ("tree", Box::new(TreePane)),
        ("timeline", Box::new(Timeline::default())),
        ("details", Box::new(Details::default())),
        ("answers", Box::new(Answers::default())),
    ]
}

fn windows(sh: &mut Shared, dir: &std::path::Path) -> Vec<(&'static str, Overlay)> {
    let targets = sh.why_targets();
    assert!(!targets.is_empty());
    let faults = sh.fault_lines();
    assert!(!faults.is_empty());
    let path = dir.join("model.dot").display().to_string();
    vec![
        ("help", Overlay::help(btx::tui::demo().panes.help())),
        ("finder", Overlay::finder()),
        ("why", Overlay::why(targets)),
        ("running", Overlay::running()),
        ("faults", Overlay::faults(faults)),
        ("pick", Overlay::pick(0)),
        ("words", Overlay::words()),
        ("can you", Overlay::can_you()),
        ("filter", Overlay::filter("look")),
        ("export", Overlay::export(path)),
    ]
}

/// Every action bound in the keymap, once each.
fn actions() -> Vec<Action> {
    let mut all: Vec<Action> = Vec::new();
    for b in KEYMAP {
        if !all.contains(&b.action) {
            all.push(b.action);
        }
    }
    assert!(all.len() > 30, "{all:?}");
    all
}

/// What a key could change in the shared state.
fn fingerprint(sh: &Shared) -> String {
    format!(
        "{} {:?} {} {} {:?} {} {:?} {} {} {} {} {} {} {:?}",
        sh.pos,
        sh.at_tick,
        sh.selected,
        sh.rows().len(),
        sh.framed_view,
        sh.follow_node,
        sh.message,
        sh.answer.is_some(),
        sh.why.is_some(),
        sh.reply.is_some(),
        sh.history.len(),
        sh.playing,
        sh.play_ms,
        sh.clipboard,
    )
}

/// Draws a component at two sizes (a terminal and a sliver of one).
fn draws(c: &dyn Component, sh: &Shared, focused: bool) {
    for (w, h) in [(80, 24), (24, 6)] {
        let mut t =
            ratatui::Terminal::new(ratatui::backend::TestBackend::new(w, h)).expect("a backend");
        t.draw(|f| c.draw(sh, f, f.area(), focused))
            .expect("drawing into memory");
    }
}

#[test]
fn every_key_of_every_pane_with_and_without_the_focus() {
    for (name, _) in panes() {
        for focused in [true, false] {
            for a in actions() {
                let mut sh = shared();
                let mut pane = panes().into_iter().find(|p| p.0 == name).unwrap().1;
                let before = fingerprint(&sh);
                let h = pane.key(a, &mut sh, focused);
                if h == Handled::Ignored {
                    assert_eq!(
                        fingerprint(&sh),
                        before,
                        "{name} ignored {a:?} (focused: {focused}) yet changed the state"
                    );
                }
                if !focused && name == "details" {
                    // Its keys (the graph's, scrolling) are its own.
                    assert_eq!(h, Handled::Ignored, "details took {a:?} unfocused");
                }
                draws(pane.as_ref(), &sh, focused);
            }
        }
    }
}

#[test]
fn the_keys_that_act_wherever_the_focus_is_are_each_one_panes() {
    // The app hands a key to the focused pane, then to each other pane: it
    // is right only if no two panes take the same key unfocused.
    for a in actions() {
        let takers: Vec<&str> = panes()
            .into_iter()
            .filter_map(|(name, mut p)| {
                let mut sh = shared();
                (p.key(a, &mut sh, false) != Handled::Ignored).then_some(name)
            })
            .collect();
        assert!(takers.len() <= 1, "{a:?} is taken by {takers:?}");
    }
}

#[test]
fn every_window_takes_every_key_and_esc_closes_it() {
    let dir = tempfile::tempdir().unwrap();
    let names: Vec<&str> = windows(&mut shared(), dir.path())
        .into_iter()
        .map(|w| w.0)
        .collect();
    for name in names {
        for a in actions() {
            let mut sh = shared();
            let mut w = windows(&mut sh, dir.path())
                .into_iter()
                .find(|w| w.0 == name)
                .unwrap()
                .1;
            let h = w.key(a, &mut sh, true);
            assert_ne!(h, Handled::Ignored, "the {name} window let {a:?} through");
            if a == Action::Back {
                assert_eq!(h, Handled::Close, "Esc in the {name} window");
            }
            draws(&w, &sh, true);
        }
    }
}

/// What a pane's help says it takes (wherever the focus is, and only with
/// it), set against the actions it takes in every state.
fn help_against_keys<S>(
    name: &str,
    pane: &dyn Fn() -> Box<dyn Component<S>>,
    state: &dyn Fn(usize) -> S,
    states: usize,
) {
    let help = pane().help();
    let said = |keys: &[(Action, &str)]| {
        let mut v: Vec<String> = keys.iter().map(|k| format!("{:?}", k.0)).collect();
        v.sort();
        v.dedup();
        v
    };
    let (mut anywhere, mut only_focused) = (Vec::new(), Vec::new());
    for a in actions() {
        for i in 0..states {
            let takes = |focused| pane().key(a, &mut state(i), focused) != Handled::Ignored;
            let (unfocused, focused) = (takes(false), takes(true));
            if unfocused {
                anywhere.push(format!("{a:?}"));
            } else if focused {
                only_focused.push(format!("{a:?}"));
            }
        }
    }
    for v in [&mut anywhere, &mut only_focused] {
        v.sort();
        v.dedup();
    }
    assert_eq!(
        said(help.anywhere),
        anywhere,
        "{name}: keys taken wherever the focus is"
    );
    assert_eq!(
        said(help.focused),
        only_focused,
        "{name}: keys taken only with the focus"
    );
}

#[test]
fn each_panes_help_names_the_keys_it_takes_and_no_other() {
    for (name, _) in panes() {
        let pane = || panes().into_iter().find(|p| p.0 == name).unwrap().1;
        help_against_keys(name, &pane, &state, STATES);
    }
}

#[test]
fn the_help_names_every_action_of_the_keymap_once_wherever_the_focus_is() {
    // The explorer's own keys and the panes' keys taken wherever the focus
    // is: every action of the keymap, each once (the router gives a key to
    // one of them); the focused panes' own meanings come on top.
    let parts = btx::tui::demo().panes.help();
    let mut named: Vec<String> = parts
        .iter()
        .flat_map(|p| p.anywhere.iter().map(|k| format!("{:?}", k.0)))
        .collect();
    named.sort();
    let mut all: Vec<String> = actions().iter().map(|a| format!("{a:?}")).collect();
    all.sort();
    assert_eq!(named, all);
    // And the keys the app keeps are those no pane takes unfocused.
    let own = &parts[0];
    for (a, _) in own.anywhere {
        for (name, mut p) in panes() {
            let mut sh = shared();
            assert_eq!(
                p.key(*a, &mut sh, false),
                Handled::Ignored,
                "{name} takes {a:?}"
            );
        }
    }
}

#[test]
fn every_components_hints_name_keys_that_are_bound() {
    let keymap = Keymap::default();
    let dir = tempfile::tempdir().unwrap();
    let mut sh = shared();
    let windows = windows(&mut sh, dir.path());
    let mut all: Vec<(&str, &dyn Component)> = Vec::new();
    let panes = panes();
    for (n, p) in &panes {
        all.push((n, p.as_ref()));
    }
    for (n, w) in &windows {
        all.push((n, w));
    }
    for (name, c) in all {
        match c.hints(&sh) {
            Hints::Keys(keys) => {
                assert!(!keys.is_empty(), "{name}");
                for (a, _) in keys {
                    assert!(keymap.key_of(*a).is_some(), "{name} hints {a:?}, unbound");
                }
            }
            Hints::Text(t) => assert!(t.contains("Esc"), "{name}: {t}"),
        }
    }
}

/// The fleet view's shared state over the shipped kitting sessions.
fn fleet_shared() -> FleetShared {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    let files = btx::fleet::files(&common::kitting_fleet()).unwrap();
    let opts = btx::xml::LoadOptions::default();
    let fleet = btx::fleet::Fleet::read(&files, &opts, None, None, &|| {});
    let sh = btx::tui::fleet::FleetApp::new(fleet, opts).shared;
    assert!(!sh.nodes.is_empty() && sh.shown.len() > 1);
    sh
}

type FleetPart = Box<dyn Component<FleetShared>>;

fn fleet_panes() -> Vec<(&'static str, FleetPart)> {
    vec![
        ("failures", Box::new(Failures)),
        ("spells", Box::new(Spells)),
        ("runs", Box::new(Runs)),
        ("run detail", Box::new(RunDetail)),
    ]
}

fn fleet_fingerprint(sh: &FleetShared) -> String {
    format!(
        "{} {} {:?} {:?} {:?}",
        sh.node, sh.run, sh.shown, sh.only, sh.message
    )
}

#[test]
fn every_key_of_every_fleet_component_in_isolation() {
    for (name, _) in fleet_panes() {
        for focused in [true, false] {
            for a in actions() {
                let mut sh = fleet_shared();
                let mut pane = fleet_panes().into_iter().find(|p| p.0 == name).unwrap().1;
                let before = fleet_fingerprint(&sh);
                let h = pane.key(a, &mut sh, focused);
                if h == Handled::Ignored {
                    assert_eq!(fleet_fingerprint(&sh), before, "{name} ignored {a:?}");
                }
                if matches!(name, "spells" | "run detail") {
                    assert_eq!(h, Handled::Ignored, "{name} only draws, yet took {a:?}");
                }
                for (w, hgt) in [(80, 24), (24, 6)] {
                    let mut t = ratatui::Terminal::new(ratatui::backend::TestBackend::new(w, hgt))
                        .expect("a backend");
                    t.draw(|f| pane.draw(&sh, f, f.area(), focused))
                        .expect("drawing into memory");
                }
            }
        }
    }
    // The router hands a key to the focused list, then the other: no two
    // take a key unfocused.
    for a in actions() {
        let takers: Vec<&str> = fleet_panes()
            .into_iter()
            .filter_map(|(name, mut p)| {
                let mut sh = fleet_shared();
                sh.only = Some(0);
                (p.key(a, &mut sh, false) != Handled::Ignored).then_some(name)
            })
            .collect();
        assert!(takers.len() <= 1, "{a:?} is taken by {takers:?}");
    }
    // The help takes every key; Esc closes it.
    for a in actions() {
        let mut sh = fleet_shared();
        let mut help = FleetHelp {
            keymap: Keymap::default(),
            parts: Vec::new(),
            scroll: Default::default(),
        };
        let h = help.key(a, &mut sh, true);
        assert_ne!(h, Handled::Ignored, "the fleet's help let {a:?} through");
        if a == Action::Back {
            assert_eq!(h, Handled::Close);
        }
    }
    // Each list's help names the keys it takes (Esc only once a node has
    // picked the runs listed).
    let state = |i| {
        let mut sh = fleet_shared();
        sh.only = (i == 1).then_some(0);
        sh.node = 1;
        sh.run = 1;
        sh
    };
    for (name, _) in fleet_panes() {
        let pane = || fleet_panes().into_iter().find(|p| p.0 == name).unwrap().1;
        help_against_keys(name, &pane, &state, 2);
    }
    // Enter on an action lists the runs it failed in, and says it picked.
    let mut sh = fleet_shared();
    assert_eq!(
        Failures.key(Action::Toggle, &mut sh, true),
        Handled::Pick(0)
    );
    assert_eq!(sh.only, Some(0));
    assert!(sh.shown.len() < fleet_shared().shown.len());
    assert_eq!(Runs.key(Action::Back, &mut sh, false), Handled::Taken);
    assert_eq!(sh.shown.len(), fleet_shared().shown.len());
}

/// The diff of the nominal kitting run and the one where look at chuck
/// fails once.
fn diff_shared() -> DiffShared {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    btx::tui::open_diff(
        std::path::Path::new("tests/fixtures/logs/kitting_nominal.btlog"),
        std::path::Path::new("tests/fixtures/logs/kitting_lookat_fails_once.btlog"),
        &Default::default(),
    )
    .unwrap()
    .shared
}

type DiffPart = Box<dyn Component<DiffShared>>;

fn diff_panes() -> Vec<(&'static str, DiffPart)> {
    vec![
        ("trees", Box::new(Trees)),
        ("summary", Box::new(Summary)),
        ("timelines", Box::new(Timelines)),
    ]
}

fn diff_fingerprint(sh: &DiffShared) -> String {
    format!(
        "{} {} {} {:?} {:?} {:?}",
        sh.a.pos, sh.b.pos, sh.selected, sh.divergence, sh.answer, sh.message
    )
}

#[test]
fn every_key_of_every_diff_component_in_isolation() {
    let base = diff_shared();
    let mut takers: std::collections::BTreeMap<String, Vec<&str>> = Default::default();
    for (name, _) in diff_panes() {
        for a in actions() {
            let mut sh = diff_shared();
            let mut pane = diff_panes().into_iter().find(|p| p.0 == name).unwrap().1;
            let before = diff_fingerprint(&sh);
            let h = pane.key(a, &mut sh, true);
            if h == Handled::Ignored {
                assert_eq!(diff_fingerprint(&sh), before, "{name} ignored {a:?}");
            } else {
                takers.entry(format!("{a:?}")).or_default().push(name);
            }
            for (w, hgt) in [(80, 24), (24, 6)] {
                let mut t = ratatui::Terminal::new(ratatui::backend::TestBackend::new(w, hgt))
                    .expect("a backend");
                t.draw(|f| pane.draw(&sh, f, f.area(), true))
                    .expect("drawing into memory");
            }
        }
    }
    // The diff has no focus: a key goes to each pane in turn, so each key
    // is one pane's.
    for (a, names) in &takers {
        assert_eq!(names.len(), 1, "{a} is taken by {names:?}");
    }
    // The diff has no focus: each pane's help names as taken wherever the
    // focus is what it takes (it is always handed keys as focused).
    for (name, _) in diff_panes() {
        let help = diff_panes()
            .into_iter()
            .find(|p| p.0 == name)
            .unwrap()
            .1
            .help();
        let mut said: Vec<String> = help.anywhere.iter().map(|k| format!("{:?}", k.0)).collect();
        said.sort();
        let mut taken: Vec<String> = takers
            .iter()
            .filter(|(_, names)| names.contains(&name))
            .map(|(a, _)| a.clone())
            .collect();
        taken.sort();
        assert_eq!(said, taken, "{name}");
        assert!(help.focused.is_empty(), "{name}");
    }
    // Its keys: ↑↓ the trees, d D w Esc the summary, n p . , g G time.
    assert_eq!(takers["NextDivergence"], ["summary"]);
    assert_eq!(takers["StepForward"], ["timelines"]);
    assert_eq!(takers["Down"], ["trees"]);
    // The help stays open for ↑↓ only; any other key closes it.
    for a in actions() {
        let mut sh = diff_shared();
        let mut help = DiffHelp {
            keymap: Keymap::default(),
            parts: Vec::new(),
            scroll: Default::default(),
        };
        let h = help.key(a, &mut sh, true);
        assert_ne!(h, Handled::Ignored, "the diff's help let {a:?} through");
        if a == Action::Back {
            assert_eq!(h, Handled::Close);
        }
    }
    // d moves both timelines to the divergence's tick.
    let mut sh = diff_shared();
    assert_eq!(
        Summary.key(Action::NextDivergence, &mut sh, true),
        Handled::Taken
    );
    assert_ne!(sh.b.pos, base.b.pos);
    assert!(sh
        .message
        .as_deref()
        .unwrap()
        .starts_with("divergence 1 of"));
}
