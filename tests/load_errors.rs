//! Every way a tree file can be wrong gets an error naming file:line:column,
//! never a panic; and the includes that are right are followed.

use btx::xml::{load_file, LoadOptions};
use std::path::{Path, PathBuf};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, text).unwrap();
    p
}

/// Loads `text` and returns the error, checking it names `line:col`.
fn error_at(text: &str, line: usize, col: usize) -> String {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "tree.xml", text);
    let e = load_file(&p, &LoadOptions::default())
        .expect_err("should not load")
        .to_string();
    let want = format!("{}:{line}:{col}: ", p.display());
    assert!(e.starts_with(&want), "expected {want}..., got {e}");
    e[want.len()..].to_string()
}

#[test]
fn malformed_xml() {
    let m = error_at("<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <Sequence>\n  </BehaviorTree>\n</root>", 4, 3);
    assert!(m.starts_with("malformed XML"), "{m}");
    let m = error_at(
        "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <A x=\"1\" x=\"2\"/>",
        3,
        5,
    );
    assert!(m.contains("malformed XML attribute"), "{m}");
    let m = error_at("<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <AlwaysSuccess/>\n  </BehaviorTree>\n", 1, 1);
    assert!(m.contains("never closed"), "{m}");
}

#[test]
fn unknown_subtree_id_suggests_the_closest() {
    let m = error_at(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\">\n  <BehaviorTree ID=\"M\">\n    <SubTree ID=\"GoPick\"/>\n  </BehaviorTree>\n  <BehaviorTree ID=\"GoPickScrew\"><AlwaysSuccess/></BehaviorTree>\n</root>",
        3,
        5,
    );
    assert!(m.starts_with("unknown SubTree ID \"GoPick\""), "{m}");
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "t.xml", "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\"><BehaviorTree ID=\"M\"><SubTree ID=\"GoPick\"/></BehaviorTree><BehaviorTree ID=\"GoPickScrew\"><AlwaysSuccess/></BehaviorTree></root>");
    let e = load_file(&p, &LoadOptions::default()).unwrap_err();
    let help = e.help.as_deref().unwrap_or("");
    assert!(help.contains("GoPickScrew"), "{help}");
    // A MoveIt Pro objective calling another file's SubTree: the help
    // points at --with (#30 item 7), and a case slip is named.
    assert!(help.contains("--with FILE|DIR"), "{help}");
    let p = write(dir.path(), "c.xml", "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\"><BehaviorTree ID=\"M\"><SubTree ID=\"gopickscrew\"/></BehaviorTree><BehaviorTree ID=\"GoPickScrew\"><AlwaysSuccess/></BehaviorTree></root>");
    let e = load_file(&p, &LoadOptions::default()).unwrap_err();
    let help = e.help.as_deref().unwrap_or("");
    assert!(help.starts_with("did you mean \"GoPickScrew\"? Else a tree defined in another file is read with --with FILE|DIR"), "{help}");
}

#[test]
fn an_id_off_by_case_or_a_letter_is_named() {
    // Nav2's docking example has <inverter>: BehaviorTree.CPP refuses it;
    // btx took it for a custom decorator and stopped at tick 1 (#30 item 7).
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "t.xml", "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Sequence><inverter><AlwaysFailure/></inverter><Sequense/></Sequence></BehaviorTree></root>");
    let l = load_file(&p, &LoadOptions::default()).unwrap();
    let said: Vec<String> = l.warnings.iter().map(|w| w.message.clone()).collect();
    assert!(said.iter().any(|w| w.contains("unknown node \"inverter\"") && w.ends_with("; did you mean \"Inverter\"? BehaviorTree.CPP has no \"inverter\" (IDs are case-sensitive) and refuses to load the tree unless your code registers it")), "{said:?}");
    assert!(
        said.iter()
            .any(|w| w.contains("did you mean \"Sequence\"?")),
        "{said:?}"
    );
    // A custom node far from every known one is not taken for a typo.
    let p = write(dir.path(), "u.xml", "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><MyFallback><AlwaysFailure/></MyFallback></BehaviorTree></root>");
    let l = load_file(&p, &LoadOptions::default()).unwrap();
    assert!(
        l.warnings
            .iter()
            .all(|w| !w.message.contains("did you mean")),
        "{:?}",
        l.warnings
    );
}

#[test]
fn subtree_cycles_direct_and_indirect() {
    let m = error_at(
        "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"A\">\n    <SubTree ID=\"A\"/>\n  </BehaviorTree>\n</root>",
        3,
        5,
    );
    assert_eq!(m, "SubTree \"A\" includes itself: A → A");
    let m = error_at(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\">\n<BehaviorTree ID=\"M\"><SubTree ID=\"A\"/></BehaviorTree>\n<BehaviorTree ID=\"A\"><Sequence><SubTree ID=\"B\"/></Sequence></BehaviorTree>\n<BehaviorTree ID=\"B\"><SubTree ID=\"A\"/></BehaviorTree>\n</root>",
        4,
        22,
    );
    assert_eq!(m, "SubTree \"A\" includes itself: A → B → A");
}

#[test]
fn a_subtree_used_twice_is_not_a_cycle() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "t.xml", "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\"><BehaviorTree ID=\"M\"><Sequence><SubTree ID=\"A\" name=\"one\"/><SubTree ID=\"A\" name=\"two\"/></Sequence></BehaviorTree><BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree></root>");
    let t = load_file(&p, &LoadOptions::default()).unwrap().tree;
    assert_eq!(t.len(), 5);
    assert_eq!(t.node(4).name, "two");
}

#[test]
fn child_counts() {
    let wrap = |body: &str| {
        format!("<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    {body}\n  </BehaviorTree>\n</root>")
    };
    let m = error_at(
        &wrap("<Inverter><AlwaysSuccess/><AlwaysFailure/></Inverter>"),
        3,
        5,
    );
    assert_eq!(
        m,
        "Decorator \"Inverter\" must have exactly one child, found 2"
    );
    let m = error_at(&wrap("<Inverter></Inverter>"), 3, 5);
    assert_eq!(
        m,
        "Decorator \"Inverter\" must have exactly one child, found 0"
    );
    let m = error_at(
        &wrap("<Sequence><AlwaysSuccess><AlwaysFailure/></AlwaysSuccess></Sequence>"),
        3,
        15,
    );
    assert_eq!(m, "Action \"AlwaysSuccess\" must have no children, found 1");
    let m = error_at(&wrap("<TryCatch><AlwaysSuccess/></TryCatch>"), 3, 5);
    assert_eq!(
        m,
        "Control \"TryCatch\" must have at least 2 children, found 1"
    );
    let m = error_at(
        &wrap("<Switch2 variable=\"{x}\"><AlwaysSuccess/><AlwaysSuccess/></Switch2>"),
        3,
        5,
    );
    assert_eq!(
        m,
        "Control \"Switch2\" must have exactly 3 children, found 2"
    );
    let m = error_at(&wrap("<Sequence></Sequence>"), 3, 5);
    assert_eq!(
        m,
        "Control \"Sequence\" must have at least 1 child, found 0"
    );
    let m = error_at(
        &wrap("<Sequence><SubTree ID=\"M\"><AlwaysSuccess/></SubTree></Sequence>"),
        3,
        15,
    );
    assert_eq!(m, "SubTree \"M\" must have no children, found 1");
    let m = error_at(&wrap("<Decorator ID=\"MyDeco\"/>"), 3, 5);
    assert_eq!(
        m,
        "Decorator \"MyDeco\" must have exactly one child, found 0"
    );
    let m = error_at("<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <AlwaysSuccess/>\n    <AlwaysSuccess/>\n  </BehaviorTree>\n</root>", 2, 3);
    assert_eq!(
        m,
        "<BehaviorTree ID=\"M\"> must have exactly one child, found 2"
    );
}

#[test]
fn main_tree_rules() {
    let m = error_at("<root BTCPP_format=\"4\">\n<BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree>\n<BehaviorTree ID=\"B\"><AlwaysSuccess/></BehaviorTree>\n</root>", 1, 1);
    assert!(
        m.starts_with("no main tree: 2 <BehaviorTree> elements"),
        "{m}"
    );
    let m = error_at("<root BTCPP_format=\"4\" main_tree_to_execute=\"C\">\n<BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree>\n<BehaviorTree ID=\"B\"><AlwaysSuccess/></BehaviorTree>\n</root>", 1, 1);
    assert!(m.starts_with("main_tree_to_execute names \"C\""), "{m}");
    let m = error_at("<root BTCPP_format=\"4\">\n</root>", 1, 1);
    assert_eq!(m, "no main tree: the file has no <BehaviorTree>");
    let m = error_at("<root BTCPP_format=\"4\" main_tree_to_execute=\"A\">\n<BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree>\n<BehaviorTree><AlwaysSuccess/></BehaviorTree>\n</root>", 3, 1);
    assert_eq!(
        m,
        "a <BehaviorTree> needs an ID when the file has more than one"
    );
    let m = error_at("<root BTCPP_format=\"4\" main_tree_to_execute=\"A\">\n<BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree>\n<BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree>\n</root>", 3, 1);
    assert_eq!(m, "a <BehaviorTree> with ID \"A\" is defined twice");
    // A single tree needs no main_tree_to_execute, nor an ID.
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "one.xml",
        "<root BTCPP_format=\"4\"><BehaviorTree><AlwaysSuccess/></BehaviorTree></root>",
    );
    assert_eq!(
        load_file(&p, &LoadOptions::default()).unwrap().tree.len(),
        1
    );
    // --main-tree picks another.
    let p = write(dir.path(), "two.xml", "<root BTCPP_format=\"4\"><BehaviorTree ID=\"A\"><AlwaysSuccess/></BehaviorTree><BehaviorTree ID=\"B\"><Inverter><AlwaysSuccess/></Inverter></BehaviorTree></root>");
    let opts = LoadOptions {
        main_tree: Some("B".into()),
        ..Default::default()
    };
    assert_eq!(load_file(&p, &opts).unwrap().tree.len(), 2);
}

#[test]
fn other_structural_errors() {
    let m = error_at("<Root>\n</Root>", 1, 1);
    assert_eq!(m, "the top element must be <root>, found <Root>");
    let m = error_at("<root BTCPP_format=\"5\">\n</root>", 1, 1);
    assert!(m.contains("BTCPP_format=\"5\""), "{m}");
    let m = error_at("<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <Action name=\"x\"/>\n  </BehaviorTree>\n</root>", 3, 5);
    assert_eq!(m, "<Action> needs an ID attribute");
}

#[test]
fn unreadable_files() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope.xml");
    let e = load_file(&missing, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("{}: cannot read the tree file", missing.display())),
        "{e}"
    );
    let m = error_at(
        "<root BTCPP_format=\"4\">\n  <include path=\"missing/other.xml\"/>\n</root>",
        2,
        3,
    );
    assert!(m.starts_with("cannot read included file"), "{m}");
    let m = error_at(
        "<root BTCPP_format=\"4\">\n  <include ros_pkg=\"p\" path=\"a.xml\"/>\n</root>",
        2,
        3,
    );
    assert!(m.contains("ROS"), "{m}");
    let p = write(dir.path(), "empty.xml", "");
    let e = load_file(&p, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no element"), "{e}");
    let p = dir.path().join("bin.xml");
    std::fs::write(&p, [0xff, 0xfe, 0x00, 0x3c]).unwrap();
    let e = load_file(&p, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with(&p.display().to_string()), "{e}");
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "sub/b.xml", "<root BTCPP_format=\"4\">\n  <include path=\"../c.xml\"/>\n  <BehaviorTree ID=\"B\"><SubTree ID=\"C\"/></BehaviorTree>\n</root>");
    write(dir.path(), "c.xml", "<root BTCPP_format=\"4\">\n  <include path=\"main.xml\"/>\n  <BehaviorTree ID=\"C\"><act name=\"act in c\"/></BehaviorTree>\n</root>");
    let main = write(dir.path(), "main.xml", "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\">\n  <include path=\"sub/b.xml\"/>\n  <BehaviorTree ID=\"M\"><Sequence name=\"top\"><SubTree ID=\"B\"/></Sequence></BehaviorTree>\n</root>");
    let loaded = load_file(&main, &LoadOptions::default()).unwrap();
    let t = loaded.tree;
    assert_eq!(t.len(), 4);
    assert_eq!(t.description(4), "act in c");
    let (file, line, col) = t.location(4);
    assert!(file.ends_with("c.xml"), "{file}");
    assert_eq!((line, col), (3, 24));
    // An unknown leaf with no model is read as an action, with a warning.
    let w: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        w.iter()
            .any(|w| w.contains("c.xml:3:24: unknown node \"act\" has no model")),
        "{w:?}"
    );
}

#[test]
fn the_cli_exits_non_zero_and_shows_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "bad.xml", "<root BTCPP_format=\"4\">\n  <BehaviorTree ID=\"M\">\n    <Inverter/>\n  </BehaviorTree>\n</root>");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .arg("tree")
        .arg(&p)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.xml:3:5"), "{err}");
    assert!(
        err.contains("<Inverter/>"),
        "the offending line is shown: {err}"
    );
}

#[test]
fn a_childless_manual_selector_loads_in_v3_as_behaviortree_cpp_3_loads_it() {
    // 3.8's VerifyXML asks for a child of Sequence, SequenceStar, Fallback
    // and FallbackStar only; 4's of every control node.
    let dir = tempfile::tempdir().unwrap();
    let v3 = write(
        dir.path(),
        "v3.xml",
        r#"<root main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence><ManualSelector/><AlwaysSuccess/></Sequence></BehaviorTree></root>"#,
    );
    let t = load_file(&v3, &LoadOptions::default()).unwrap().tree;
    assert!(t.node(2).children.is_empty());
    let m = error_at(
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><ManualSelector/><AlwaysSuccess/></Sequence></BehaviorTree></root>"#,
        1,
        55,
    );
    assert!(m.contains("must have at least 1 child"), "{m}");
    // An empty Sequence is refused by both.
    let v3 = write(
        dir.path(),
        "empty.xml",
        r#"<root main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence/></BehaviorTree></root>"#,
    );
    assert!(load_file(&v3, &LoadOptions::default()).is_err());
}

/// Nav2's navigator tree and Nav2's models file, as shipped (see
/// tests/fixtures/realworld/SOURCES).
fn nav2(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/realworld/nav2")
        .join(name)
        .display()
        .to_string()
}

fn btx(args: &[&str]) -> (bool, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_btx"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

#[test]
fn a_models_file_gives_nav2s_nodes_their_kinds_and_port_directions() {
    let tree = nav2("navigate_to_pose_w_replanning_and_recovery.xml");
    let (ok, out, err) = btx(&["tree", &tree]);
    assert!(ok, "{err}");
    // Nav2's controls are known by name; its leaves are not.
    assert_eq!(err.matches("unknown node").count(), 7, "{err}");
    assert!(
        err.contains("7 node IDs have no model") && err.contains("--models FILE"),
        "{err}"
    );
    assert!(
        out.contains("GoalUpdated  [Action GoalUpdated #7]"),
        "{out}"
    );
    let models = nav2("nav2_tree_nodes.xml");
    let (ok, out, err) = btx(&["tree", &tree, "--models", &models]);
    assert!(ok, "{err}");
    assert!(
        !err.contains("unknown node") && !err.contains("no model"),
        "{err}"
    );
    // Kinds and directions from the models file.
    assert!(
        out.contains("GoalUpdated  [Condition GoalUpdated #7]"),
        "{out}"
    );
    assert!(
        out.contains("[Action ComputePathToPose #5]  in:goal={goal}, out:path={path}"),
        "{out}"
    );
    // Every command that reads a tree takes it.
    let (ok, _, err) = btx(&["ask", &tree, "--models", &models, "--node", "#10", "q2"]);
    assert!(ok, "{err}");
    assert!(!err.contains("unknown node"), "{err}");
    // A tree file is not a models file.
    let (ok, _, err) = btx(&["tree", &tree, "--models", &tree]);
    assert!(!ok);
    assert!(
        err.contains("--models: this file has no") && err.contains("with --with"),
        "{err}"
    );
}

#[test]
fn trees_in_other_files_are_registered_with_with() {
    let dir = tempfile::tempdir().unwrap();
    let main = write(
        dir.path(),
        "main.xml",
        r#"<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main"><Sequence><SubTree ID="Pick"/><SubTree ID="Place"/></Sequence></BehaviorTree>
</root>"#,
    );
    let lib = dir.path().join("lib");
    write(
        &lib,
        "pick.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Pick"><AlwaysSuccess name="grasp"/></BehaviorTree></root>"#,
    );
    write(
        &lib,
        "place.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Place"><AlwaysSuccess name="release"/></BehaviorTree></root>"#,
    );
    let main = main.to_str().unwrap();
    let (ok, _, err) = btx(&["tree", main]);
    assert!(!ok);
    assert!(err.contains("Pick"), "{err}");
    // Each file, or the directory: the main tree stays the first file's.
    let pick = lib.join("pick.xml");
    let place = lib.join("place.xml");
    for args in [
        vec!["--with", pick.to_str().unwrap(), place.to_str().unwrap()],
        vec!["--with", lib.to_str().unwrap()],
    ] {
        let mut a = vec!["tree", main];
        a.extend(args);
        let (ok, out, err) = btx(&a);
        assert!(ok, "{err}");
        assert!(out.contains("grasp") && out.contains("release"), "{out}");
        assert!(out.lines().next().unwrap().contains("Sequence"), "{out}");
    }
    // Without a main_tree_to_execute, the first file's one tree is the main
    // one, whatever the other files hold.
    let lone = write(
        dir.path(),
        "lone.xml",
        r#"<root BTCPP_format="4"><BehaviorTree ID="Lone"><SubTree ID="Pick"/></BehaviorTree></root>"#,
    );
    let (ok, out, err) = btx(&[
        "tree",
        lone.to_str().unwrap(),
        "--with",
        lib.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("grasp") && !out.contains("release"), "{out}");
}

#[test]
fn a_subtree_models_port_without_default_must_be_remapped() {
    // BehaviorTree.CPP 4 reads the SubTree models: a port the instance does
    // not remap takes the model's default, and with none the tree is
    // refused (xml_parsing.cpp, loadSubtreeModel).
    let m = error_at(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"M\">\n<BehaviorTree ID=\"M\">\n  <SubTree ID=\"Sub\"/>\n</BehaviorTree>\n<BehaviorTree ID=\"Sub\"><AlwaysSuccess/></BehaviorTree>\n<TreeNodesModel><SubTree ID=\"Sub\"><input_port name=\"speed\"/></SubTree></TreeNodesModel>\n</root>",
        3,
        3,
    );
    assert!(
        m.contains(
            "declares the port \"speed\" with no default, and this SubTree does not remap it"
        ),
        "{m}"
    );
}
