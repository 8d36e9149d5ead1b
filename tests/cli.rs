//! The CLI forms of the foundation issue, called as a user calls them.

mod common;
use common::*;

fn path(p: std::path::PathBuf) -> String {
    p.display().to_string()
}

#[test]
fn ask_answers_one_line_per_question_in_order() {
    let f = path(fixture("kitting-tree.v3.xml"));
    let (ok, out, _) = btx(&[
        "ask",
        &f,
        "--node",
        "go insert large gear/move to see chuck",
        "What are you doing?",
        "Why are you doing this?",
        "What is your subgoal?",
        "What is your goal?",
        "How do you achieve your subgoal?",
        "How do you achieve your goal?",
    ]);
    assert!(ok);
    assert_eq!(
        out,
        "I move to see chuck.\n\
         I move to see chuck in order to go insert large gear.\n\
         My subgoal is to go insert large gear.\n\
         My goal is to build a gearbox kit.\n\
         To achieve the subgoal \"go insert large gear\", I need to do 3 steps. 1. move to see chuck. 2. detect chuck. 3. insert large gear.\n\
         To achieve the goal \"build a gearbox kit\", I need to do 3 steps. 1. go insert large gear. 2. go pick screw. 3. go place screw.\n"
    );
    let (ok, short, _) = btx(&[
        "ask",
        &f,
        "--node",
        "#6",
        "q1",
        "q2",
        "q3",
        "q4",
        "q5-subgoal",
        "q5-goal",
    ]);
    assert!(ok);
    assert_eq!(short, out);
}

#[test]
fn ask_json_names_question_answer_and_nodes() {
    let f = path(shipped("taxi.xml"));
    let (ok, out, _) = btx(&[
        "ask",
        &f,
        "--node",
        "drop off passenger",
        "q2",
        "--format",
        "json",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["schema"], "btx.answers/1");
    assert_eq!(v["node"]["uid"], 21);
    let a = &v["answers"][0];
    // The question as typed, and what btx understood it to ask.
    assert_eq!(a["question"], "q2");
    assert_eq!(a["understood"], "Why are you doing this?");
    assert_eq!(a["short"], "q2");
    assert_eq!(
        a["answer"],
        "I drop off passenger in order to go drop off passenger."
    );
    assert_eq!(a["nodes"][1]["uid"], 13);
}

#[test]
fn ask_rejects_unknown_questions_and_nodes() {
    let f = path(shipped("kitting.xml"));
    let (ok, out, err) = btx(&["ask", &f, "--node", "#6", "why not?"]);
    assert!(!ok);
    assert!(out.starts_with("I don't know how to answer that."), "{out}");
    assert!(err.contains("question was not answered"), "{err}");
    let (ok, _, err) = btx(&["ask", &f, "--node", "lift torso", "q1"]);
    assert!(!ok);
    assert!(
        err.contains("matches 3 nodes") && err.contains("#37"),
        "{err}"
    );
}

#[test]
fn tree_text_shows_kind_description_uid_and_ports() {
    let (ok, out, _) = btx(&["tree", &path(shipped("kitting.xml"))]);
    assert!(ok);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 79);
    assert_eq!(lines[0], "build a gearbox kit  [Sequence #1]");
    assert!(
        lines[5].ends_with("move to see chuck  [Action move_to #6]  in:place=\"chuck place\""),
        "{}",
        lines[5]
    );
    assert!(
        out.contains("detect chuck  [Action detect_chuck #12]  out:output={object pose}"),
        "{out}"
    );
}

#[test]
fn tree_framed_text_and_json() {
    let f = path(shipped("kitting.xml"));
    let (ok, out, _) = btx(&["tree", &f, "--framed"]);
    assert!(ok);
    assert!(out.starts_with("goal: build a gearbox kit  #1\n├─ subgoal: go insert large gear  #2 (with #3 #4)\n│  ├─ action: move to see chuck  #6\n│  ├─ step: detect chuck  #9\n"), "{out}");
    assert!(out.contains(
        "steps of \"go insert large gear\": move to see chuck, detect chuck, insert large gear\n"
    ));
    let (ok, out, _) = btx(&["tree", &f, "--framed", "--format", "json"]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["schema"], "btx.framed/1");
    assert_eq!(v["goal"]["description"], "build a gearbox kit");
    assert_eq!(v["subgoals"].as_array().unwrap().len(), 3);
    let steps: Vec<&str> = v["subgoals"][0]["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["description"].as_str().unwrap())
        .collect();
    assert_eq!(
        steps,
        ["move to see chuck", "detect chuck", "insert large gear"]
    );
    assert_eq!(v["actions"].as_array().unwrap().len(), 48);
}

#[test]
fn tree_json_is_a_flat_node_list() {
    let (ok, out, _) = btx(&[
        "tree",
        &path(fixture("kitting-tree.v3.xml")),
        "--format",
        "json",
        "-q",
    ]);
    assert!(ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["schema"], "btx.tree/2");
    assert_eq!(v["btcpp_format"], 3);
    assert_eq!(v["node_count"], 79);
    let n6 = &v["nodes"][5];
    assert_eq!(n6["uid"], 6);
    assert_eq!(n6["kind"], "action");
    assert_eq!(n6["id"], "move to");
    assert_eq!(n6["description"], "move to see chuck");
    assert_eq!(n6["parent"], 5);
    assert_eq!(n6["ports"][0]["kind"], "literal");
    assert_eq!(n6["source"]["line"], 36);
    let n12 = &v["nodes"][11];
    assert_eq!(n12["ports"][0]["key"], "object pose");
    assert_eq!(n12["has_name"], false);
}

#[test]
fn tree_dot_is_a_graphviz_digraph() {
    let (ok, out, _) = btx(&["tree", &path(shipped("taxi.xml")), "--format", "dot"]);
    assert!(ok);
    assert!(out.starts_with("digraph btx {"));
    assert_eq!(out.matches(" -> ").count(), 20);
    assert!(
        out.contains("n21 [label=\"Action drop_off\\ndrop off passenger\\n#21\""),
        "{out}"
    );
    let (ok, out, _) = btx(&[
        "tree",
        &path(shipped("taxi.xml")),
        "--framed",
        "--format",
        "dot",
    ]);
    assert!(ok);
    assert!(out.starts_with("digraph btx_framed {"));
}

#[test]
fn tree_xml_converts_v3_to_v4() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, out, err) = btx(&[
        "tree",
        &path(fixture("kitting-tree.v3.xml")),
        "--format",
        "xml",
    ]);
    assert!(ok);
    assert!(
        err.contains("no BTCPP_format"),
        "the v3 guess is reported: {err}"
    );
    assert!(out.starts_with("<root BTCPP_format=\"4\" main_tree_to_execute=\"MainTree\">"));
    assert!(!out.contains("RetryUntilSuccesful"));
    let p = dir.path().join("k4.xml");
    std::fs::write(&p, &out).unwrap();
    let (ok, answers, err) = btx(&["ask", &path(p), "--node", "#6", "q5-goal"]);
    assert!(ok, "{err}");
    assert!(
        err.is_empty(),
        "a converted file loads without warnings: {err}"
    );
    assert_eq!(answers, "To achieve the goal \"build a gearbox kit\", I need to do 3 steps. 1. go insert large gear. 2. go pick screw. 3. go place screw.\n");
    let (ok, _, err) = btx(&[
        "tree",
        &path(shipped("taxi.xml")),
        "--framed",
        "--format",
        "xml",
    ]);
    assert!(!ok);
    assert!(err.contains("drop --framed"), "{err}");
}

#[test]
fn btcpp_flag_overrides_detection() {
    // Read as v4, the v3 file's SubTree names come from `name` (empty here, so the ID).
    let f = path(fixture("kitting-tree.v3.xml"));
    let (ok, out, err) = btx(&["ask", &f, "--btcpp", "4", "--node", "#6", "q5-goal"]);
    assert!(ok, "{err}");
    assert!(out.contains("2. go pick first screw."), "{out}");
    assert!(
        err.contains("RetryUntilSuccesful"),
        "the v3 spelling is reported: {err}"
    );
}

#[test]
fn run_with_a_domain_and_with_worlds() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cs.jsonl");
    let (ok, _, err) = btx(&[
        "run",
        &path(shipped("case-study.xml")),
        "--domain",
        &path(shipped("case-study.domain.toml")),
        "--out",
        &path(out.clone()),
    ]);
    assert!(ok, "{err}");
    assert!(
        err.contains("1 ticks, 10 transitions, root SUCCESS"),
        "{err}"
    );
    let (ok, log, _) = btx(&["log", &path(out), "--node", "L2"]);
    assert!(ok);
    assert!(
        log.lines().nth(1).unwrap().ends_with("SUCCESS  Action2"),
        "{log}"
    );

    let out = dir.path().join("taxi.jsonl");
    let (ok, _, err) = btx(&[
        "run",
        &path(shipped("taxi.xml")),
        "--world",
        "taxi",
        "--out",
        &path(out.clone()),
    ]);
    assert!(ok, "{err}");
    let (ok, a, _) = btx(&["ask", &path(out), "--at", "8", "q1", "q2"]);
    assert!(ok);
    assert_eq!(
        a,
        "I move right.\nI move right in order to navigate to destination.\n"
    );
    let (ok, _, err) = btx(&[
        "run",
        &path(shipped("kitting.xml")),
        "--world",
        "taxi",
        "--out",
        &path(dir.path().join("x.jsonl")),
    ]);
    assert!(!ok);
    assert!(
        err.contains("the taxi world moves, picks up and drops off; it cannot run"),
        "{err}"
    );
    let (ok, _, err) = btx(&[
        "run",
        &path(shipped("kitting.xml")),
        "--world",
        "kitting",
        "--seed",
        "9",
        "--out",
        &path(dir.path().join("y.jsonl")),
    ]);
    assert!(!ok);
    assert!(err.contains("seeds 0 to 5"), "{err}");
    let (ok, out, _) = btx(&["world", "taxi", "--tree"]);
    assert!(ok);
    assert!(
        out.contains("<Sequence name=\"navigate to passenger\">"),
        "{out}"
    );
}

#[test]
fn ask_with_run_questions_needs_a_session() {
    let (ok, out, _) = btx(&[
        "ask",
        &path(shipped("kitting.xml")),
        "--node",
        "#6",
        "wrong",
    ]);
    assert!(!ok);
    assert!(out.contains("is about a run: ask it of a session"), "{out}");
    let (ok, a, _) = btx(&[
        "ask",
        &path(shipped("kitting.xml")),
        "--node",
        "#27",
        "Can you insert large gear?",
    ]);
    assert!(ok);
    assert_eq!(
        a,
        "Yes. I will insert large gear after go insert large gear.\n"
    );
}

#[test]
fn moments_count_from_the_end_of_the_run_everywhere_one_is_taken() {
    let s = "sessions/kitting-nominal.jsonl";
    for (rel, abs) in [
        ("-1", "46"),
        ("last", "46"),
        ("end", "46"),
        ("-2:1", "45:1"),
    ] {
        for args in [
            vec!["ask", s, "--at", rel, "q1", "q3"],
            vec!["why", s, "executed(#28)", "--at", rel],
            vec!["graph", s, "--at", rel],
        ] {
            let (ok, out, err) = btx(&args);
            assert!(ok, "{args:?}: {err}");
            let args_abs: Vec<&str> = args
                .iter()
                .map(|a| if *a == rel { abs } else { a })
                .collect();
            let (_, want, _) = btx(&args_abs);
            assert_eq!(out, want, "{args:?}");
        }
    }
    let (ok, _, err) = btx(&["ask", s, "--at", "-47", "q1"]);
    assert!(!ok);
    assert_eq!(err, "  × \"-47\": the run has 46 ticks\n");
}

#[test]
fn a_session_says_how_its_run_ended() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, _, out) = run_planned(
        dir.path(),
        r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence><AlwaysSuccess/><MyControl><AlwaysSuccess/><AlwaysFailure/></MyControl></Sequence></BehaviorTree></root>"#,
        "",
    );
    assert!(!ok);
    let s = btx::session::Session::load(&out).unwrap();
    assert_eq!(
        s.ending(),
        "stopped at tick 1 by an error: tick 1: MyControl #3: custom control node \"MyControl\" has no behaviour in btx"
    );
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let s = btx::session::Session::load(&root.join("sessions/kitting-nominal.jsonl")).unwrap();
    assert_eq!(
        s.ending(),
        "ended at tick 46: root SUCCESS (root completed)"
    );
}

#[test]
fn trees_and_models_print_as_mermaid() {
    let (ok, out, err) = btx(&["tree", "trees/case-study.xml", "--format", "mermaid"]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("flowchart TD\n  n1[/\"Fallback<br/>CaseStudyFallback #35;1\"/]\n"),
        "{out}"
    );
    assert!(out.contains("  n2 --> n4\n"), "{out}");
    let (ok, out, err) = btx(&[
        "tree",
        "trees/kitting.xml",
        "--framed",
        "--format",
        "mermaid",
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("[[\"subgoal<br/>go insert large gear #35;2\"]]"),
        "{out}"
    );
    let (ok, out, err) = btx(&["graph", "sessions/case-study.jsonl", "--format", "mermaid"]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("%% explanation model of tick 1: 19 variables, 34 edges\nflowchart TD\n"),
        "{out}"
    );
    assert_eq!(out.matches(" --> ").count(), 34);
}

#[test]
fn a_bare_ampersand_in_a_script_is_text_as_behaviortree_cpp_reads_it() {
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("t.xml");
    std::fs::write(
        &tree,
        r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><Sequence><Script code="a:=1; b:=2"/><ScriptCondition code="a==1 && b==2"/></Sequence></BehaviorTree></root>"#,
    )
    .unwrap();
    let (ok, out, err) = btx(&["tree", tree.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(out.contains(r#"in:code="a==1 && b==2""#), "{out}");
    // Written back as XML, it is escaped, and reads back the same.
    let (ok, xml, err) = btx(&["tree", tree.to_str().unwrap(), "--format", "xml"]);
    assert!(ok, "{err}");
    assert!(xml.contains(r#"code="a==1 &amp;&amp; b==2""#), "{xml}");
    let xml_text = std::fs::read_to_string(&tree).unwrap();
    let (ok, err, _) = run_planned(dir.path(), &xml_text, "");
    assert!(ok, "{err}");
    assert!(err.contains("root SUCCESS"), "{err}");
}

#[test]
fn editor_metadata_is_kept_apart_from_ports_and_written_back() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("t.xml");
    std::fs::write(
        &p,
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence _description="does things" _collapsed="true"><AlwaysSuccess/></Sequence></BehaviorTree></root>"#,
    )
    .unwrap();
    let (ok, out, err) = common::btx(&["tree", p.to_str().unwrap()]);
    assert!(ok, "{err}");
    assert!(
        out.starts_with("Sequence  [Sequence #1]  (metadata: _description=\"does things\", _collapsed=\"true\")\n"),
        "{out}"
    );
    let t = btx::xml::load_file(&p, &Default::default()).unwrap().tree;
    assert!(t.node(1).ports.is_empty());
    let (ok, xml, _) = common::btx(&["tree", p.to_str().unwrap(), "--format", "xml"]);
    assert!(ok);
    assert!(
        xml.contains(r#"<Sequence _description="does things" _collapsed="true">"#),
        "{xml}"
    );
}

#[test]
fn set_with_a_plan_seeds_the_root_blackboard_and_re_runs_start_from_it() {
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("t.xml");
    let plan = dir.path().join("t.plan");
    std::fs::write(
        &tree,
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><ScriptCondition code="goal == 3"/><a name="a"/><Script code="@mode := 1"/></Sequence></BehaviorTree></root>"#,
    )
    .unwrap();
    std::fs::write(&plan, "a = 1RS\n").unwrap();
    let run = |out: &std::path::Path, set: &[&str]| {
        let mut args = vec![
            "-q",
            "run",
            tree.to_str().unwrap(),
            "--plan",
            plan.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(set);
        common::btx(&args)
    };
    let out = dir.path().join("s.jsonl");
    let (ok, _, err) = run(&out, &["--set", "goal=3", "--set", "@mode=0"]);
    assert!(ok, "{err}");
    let s = match btx::input::open(&out, &Default::default()).unwrap() {
        btx::input::Input::Session(s) => *s,
        _ => panic!("a session"),
    };
    assert!(s
        .header
        .blackboard
        .iter()
        .any(|(e, v)| e.key == "goal" && *v == serde_json::json!(3)));
    // Without the seed the script has nothing to read.
    let (ok, _, err) = run(&dir.path().join("s2.jsonl"), &[]);
    assert!(!ok);
    assert!(err.contains("\"goal\" is not on the blackboard"), "{err}");
    // It says how to supply it (an enum the robot's code registers reads
    // the same way).
    assert!(err.contains("--set goal=VALUE"), "{err}");
    // A re-run reproduces the run from what it started with.
    let (ok, text, err) = common::btx(&[
        "why",
        out.to_str().unwrap(),
        "status(#1)",
        "--at",
        "2",
        "--detail",
        "full",
    ]);
    assert!(ok, "{err}");
    assert!(
        text.contains("Checked: running the tree again to tick 2"),
        "{text}"
    );
}

#[test]
fn nav2s_navigator_runs_and_its_recovery_is_explained() {
    // Nav2's own navigator tree and models file (tests/fixtures/realworld).
    let nav2 = |f: &str| {
        fixture(&format!("realworld/nav2/{f}"))
            .display()
            .to_string()
    };
    let (tree, models) = (
        nav2("navigate_to_pose_w_replanning_and_recovery.xml"),
        nav2("nav2_tree_nodes.xml"),
    );
    let dir = tempfile::tempdir().unwrap();
    let run = |plan: &str, name: &str| {
        let p = dir.path().join(format!("{name}.plan"));
        std::fs::write(&p, plan).unwrap();
        let out = dir.path().join(format!("{name}.jsonl"));
        let (ok, text, err) = btx(&[
            "-q",
            "run",
            &tree,
            "--models",
            &models,
            "--plan",
            p.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        (out, format!("{text}{err}"))
    };
    // Han's Q2 skips a parent named as the node is (the RecoveryNode around
    // ComputePathToPose), comparing the names as written.
    let (ok, said, err) = btx(&["ask", &tree, "--models", &models, "--node", "#5", "q2"]);
    assert!(ok, "{err}");
    assert_eq!(
        said,
        "I run ComputePathToPose in order to run NavigateWithReplanning.\n"
    );
    let (_, text) = run("@default_action = 1RS\n@default_condition = S\n", "nominal");
    assert!(text.contains("root SUCCESS (root completed)"), "{text}");
    // FollowPath fails once; the goal is not updated, so the recovery
    // clears the local costmap, and FollowPath runs again.
    let (out, text) = run(
        "@default_action = 1RS\n@default_condition = S\nFollowPath = 1RF, 1RS\nGoalUpdated = F\n",
        "follow-path-fails",
    );
    assert!(text.contains("root SUCCESS (root completed)"), "{text}");
    let out = out.to_str().unwrap();
    let (ok, log, _) = btx(&["log", out]);
    assert!(ok);
    assert!(
        log.contains("FollowPath                               RUNNING  -> FAILURE")
            && log.contains("ClearLocalCostmap-Context                IDLE     -> RUNNING"),
        "{log}"
    );
    let (ok, said, err) = btx(&["ask", out, "--at", "3", "wrong", "handled"]);
    assert!(ok, "{err}");
    assert_eq!(
        said,
        "I could not run FollowPath because FollowPath failed.\n\
         When FollowPath failed, I fell back to FollowPathRecoveryFallback.\n"
    );
}

/// Every Nav2 navigator of the corpus (tests/fixtures/realworld/SOURCES),
/// with Nav2's models file, runs to completion under default outcomes; the
/// one that follows a point forever ends when FollowPath fails; where
/// FollowPath has its own recovery, a failure of it runs the recovery, and
/// "What went wrong?" names it.
#[test]
fn every_nav2_navigator_of_the_corpus_runs_and_explains_its_recovery() {
    // Each navigator with the model file of its release (SOURCES).
    let tmp = tempfile::tempdir().unwrap();
    let names = common::nav2_navigators();
    assert!(names.len() >= 15, "{names:?}");
    let run = |tree: &std::path::Path, plan: &str, name: &str| {
        let p = tmp.path().join(format!("{name}.plan"));
        std::fs::write(&p, plan).unwrap();
        let out = tmp.path().join(format!("{name}.jsonl"));
        let models = common::nav2_models_for(tree);
        let models = models.to_str().unwrap();
        let (ok, text, err) = btx(&[
            "run",
            tree.to_str().unwrap(),
            "--models",
            models,
            "--plan",
            p.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{}: {err}", tree.display());
        (out, format!("{text}{err}"))
    };
    let mut recovered = 0;
    for (i, tree) in names.iter().enumerate() {
        let name = tree.file_name().unwrap().to_string_lossy().to_string();
        let xml = std::fs::read_to_string(tree).unwrap();
        let defaults = "@default_action = 1RS\n@default_condition = S\n";
        // The route's ends far from robot and goal (see below).
        let far = if name == "navigate_on_route_graph_w_recovery.xml" {
            "ArePosesNear = F\n"
        } else {
            ""
        };
        let (_, text) = if name == "follow_point.xml" {
            // KeepRunningUntilFailure over FollowPath: it ends only then.
            let (out, text) = run(
                tree,
                &format!("{defaults}FollowPath = 1RS, 1RS, 1RF\n"),
                &format!("n{i}"),
            );
            assert!(
                text.contains("root FAILURE (root completed)"),
                "{name}: {text}"
            );
            (out, text)
        } else if name == "navigate_on_route_graph_w_recovery.xml" {
            // When the route already starts at the robot, the Inverter over
            // ArePosesNear fails the first-mile ReactiveSequence, and with
            // it ComputeAndSmoothRoute: under the defaults the navigator
            // retries, recovers and at last fails, as BehaviorTree.CPP
            // would. With the route's ends far from robot and goal it
            // succeeds.
            let (out, text) = run(tree, defaults, &format!("n{i}"));
            assert!(
                text.contains("root FAILURE (root completed)"),
                "{name}: {text}"
            );
            let (ok, said, err) = btx(&["ask", out.to_str().unwrap(), "--at", "last", "wrong"]);
            assert!(ok, "{err}");
            assert_eq!(
                said,
                "The task failed: ComputeAndSmoothRoute stopped because ArePosesNear succeeded and the inverter above it turned that into a failure.\n",
                "{name}"
            );
            let (out, text) = run(tree, &format!("{defaults}{far}"), &format!("m{i}"));
            assert!(
                text.contains("root SUCCESS (root completed)"),
                "{name}: {text}"
            );
            (out, text)
        } else {
            let (out, text) = run(tree, defaults, &format!("n{i}"));
            assert!(
                text.contains("root SUCCESS (root completed)"),
                "{name}: {text}"
            );
            (out, text)
        };
        // With the models, nothing is unknown but what Nav2's own model
        // file leaves out; a v3 file is said to be one.
        let mut unknown: Vec<_> = text
            .lines()
            .filter(|l| l.starts_with("warning:") && !l.contains("no BTCPP_format attribute"))
            .filter_map(|l| {
                let id = l.split("unknown node \"").nth(1)?.split('"').next()?;
                Some(id.to_string())
            })
            .collect();
        unknown.sort();
        let expected: &[&str] =
            if name == "navigate_w_routing_global_planning_and_control_w_recovery.xml" {
                &[
                    "AppendGoalPoseToGoals",
                    "ExtractRouteNodesAsGoals",
                    "GetNextFewGoals",
                ]
            } else {
                &[]
            };
        assert_eq!(unknown, expected, "{name}: {text}");
        let warnings = text
            .lines()
            .filter(|l| l.starts_with("warning:") && !l.contains("no BTCPP_format attribute"))
            .count();
        // One line per unknown ID and one hint naming --models.
        let hint = usize::from(!expected.is_empty());
        assert_eq!(warnings, expected.len() + hint, "{name}: {text}");
        if !xml.contains(r#"<RecoveryNode number_of_retries="1" name="FollowPath">"#) {
            continue;
        }
        recovered += 1;
        let (out, _) = run(
            tree,
            &format!("{defaults}{far}FollowPath = 1RF, 1RS\nGoalUpdated = F\n"),
            &format!("f{i}"),
        );
        let out = out.to_str().unwrap();
        let (ok, log, _) = btx(&["log", out, "--format", "json"]);
        assert!(ok);
        let log: serde_json::Value = serde_json::from_str(&log).unwrap();
        let rows = log["transitions"].as_array().unwrap();
        let failed = rows
            .iter()
            .find(|r| r["node"] == "FollowPath" && r["status"] == "FAILURE")
            .unwrap_or_else(|| panic!("{name}: FollowPath never failed"));
        let tick = failed["tick"].as_u64().unwrap();
        assert!(
            rows.iter()
                .any(|r| r["node"] == "ClearLocalCostmap-Context" && r["status"] == "RUNNING"),
            "{name}: the recovery did not run"
        );
        let (ok, said, err) = btx(&["ask", out, "--at", &tick.to_string(), "wrong"]);
        assert!(ok, "{err}");
        assert_eq!(
            said, "I could not run FollowPath because FollowPath failed.\n",
            "{name}"
        );
    }
    assert!(recovered >= 2);
}

/// BehaviorTree.CPP's own include tests (tests/trees of the library): an
/// `<include path>` is read relative to the file that holds it, through a
/// child directory, back up to the parent's and beside itself, as the
/// library's parser does; each parent runs to SUCCESS through every level.
/// Its example log_test.xml has two trees and no main_tree_to_execute: btx
/// asks which, as the library's createTree(ID) does.
#[test]
fn behaviortree_cpps_include_tests_load_and_run() {
    let dir = fixture("realworld/btcpp/tests/trees");
    let tmp = tempfile::tempdir().unwrap();
    let plan = tmp.path().join("empty.plan");
    std::fs::write(&plan, "").unwrap();
    for (file, deepest) in [
        ("parent_no_include.xml", "[Action AlwaysSuccess #1]"),
        ("parent_include_child.xml", "[SubTree ChildNoInclude #2]"),
        (
            "parent_include_child_include_child.xml",
            "[SubTree ChildChildNoInclude #4]",
        ),
        (
            "parent_include_child_include_parent.xml",
            "[SubTree ParentNoInclude #4]",
        ),
        (
            "parent_include_child_include_sibling.xml",
            "[SubTree ChildNoInclude #4]",
        ),
    ] {
        let tree = dir.join(file);
        let tree = tree.to_str().unwrap();
        let (ok, shown, err) = btx(&["tree", tree]);
        assert!(ok, "{file}: {err}");
        assert!(err.is_empty(), "{file}: {err}");
        assert!(shown.contains(deepest), "{file}: {shown}");
        let out = tmp.path().join(format!("{file}.jsonl"));
        let (ok, text, err) = btx(&[
            "run",
            tree,
            "--plan",
            plan.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{file}: {err}");
        assert!(
            format!("{text}{err}").contains("root SUCCESS (root completed)"),
            "{file}: {text}{err}"
        );
    }
    let log_test = fixture("realworld/btcpp/test_files/log_test.xml");
    let log_test = log_test.to_str().unwrap();
    let (ok, _, err) = btx(&["tree", log_test]);
    assert!(!ok);
    // The report wraps to the terminal's width.
    let flat = err
        .split_whitespace()
        .filter(|w| *w != "│")
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        flat.contains("no main_tree_to_execute") && flat.contains("the trees are: Main, Subtree"),
        "{err}"
    );
    let out = tmp.path().join("log_test.jsonl");
    let (ok, text, err) = btx(&[
        "run",
        log_test,
        "--main-tree",
        "Main",
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        format!("{text}{err}").contains("root SUCCESS (root completed)"),
        "{text}{err}"
    );
    let (ok, log, _) = btx(&["log", out.to_str().unwrap()]);
    assert!(ok);
    assert!(
        log.contains("FirstSubtree                             RUNNING  -> SUCCESS")
            && log.contains("SecondSubtree                            RUNNING  -> SUCCESS"),
        "{log}"
    );
}

/// A PlanSys2 action tree and an auto-apms mission (the corpus,
/// SOURCES): they load, run and read as English. PlanSys2 names its leaves
/// after their IDs in lower case (`<Move name="move">`): a name a person
/// wrote, so a step. auto-apms declares a SubTree's ports in its
/// `<TreeNodesModel>` and sets one with a script from another.
#[test]
fn plansys2_and_auto_apms_trees_load_run_and_read_as_english() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = |text: &str, name: &str| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let transport = fixture("realworld/plansys2/transport.xml");
    let transport = transport.to_str().unwrap();
    let (ok, said, err) = btx(&["ask", transport, "--node", "move", "q5-goal"]);
    assert!(ok, "{err}");
    assert_eq!(
        said,
        "To achieve the goal \"root_sequence\", I need to do 5 steps. 1. open gripper. 2. approach object. 3. close gripper. 4. move. 5. open gripper.\n"
    );
    // Its leaves are the robot's own: said once per ID, and one hint.
    assert_eq!(err.matches("unknown node").count(), 4, "{err}");
    assert_eq!(err.matches("--models FILE").count(), 1, "{err}");
    let out = tmp.path().join("transport.jsonl");
    let (ok, text, err) = btx(&[
        "run",
        transport,
        "--plan",
        &plan("@default_action = 1RS\n", "t.plan"),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        format!("{text}{err}").contains("root SUCCESS (root completed)"),
        "{text}{err}"
    );

    let hogwarts = fixture("realworld/auto-apms/hogwarts.xml");
    let out = tmp.path().join("hogwarts.jsonl");
    let (ok, text, err) = btx(&[
        "run",
        hogwarts.to_str().unwrap(),
        "--plan",
        &plan(
            "HasParameter = F\nPlaceObject = S, F\n@default_action = 1RS\n",
            "h.plan",
        ),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(!err.contains("warning"), "{err}");
    assert!(
        format!("{text}{err}").contains("root FAILURE (root completed)"),
        "{text}{err}"
    );
    // With no parameter, the script in the SubTree writes the default its
    // caller gave to the caller's `student`, which the actions read.
    let session = std::fs::read_to_string(&out).unwrap();
    assert!(
        session.contains(r#""entry":{"scope":0,"key":"student"},"value":"potter""#),
        "{session}"
    );
    let (ok, said, err) = btx(&["ask", out.to_str().unwrap(), "--at", "last", "wrong"]);
    assert!(ok, "{err}");
    assert_eq!(said, "The task failed: PlaceObject failed.\n");
}

#[test]
fn a_name_several_nodes_answer_to_is_said_to_mean_the_outermost() {
    // Nav2 names the RecoveryNode around ComputePathToPose after it.
    let nav2 = fixture("realworld/nav2");
    let (ok, text, err) = btx(&[
        "ask",
        nav2.join("navigate_to_pose_w_replanning_goal_patience_and_recovery.xml")
            .to_str()
            .unwrap(),
        "--models",
        nav2.join("nav2_tree_nodes.f875f62.xml").to_str().unwrap(),
        "--node",
        "ComputePathToPose",
        "q1",
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        text,
        "About #6 NavigateRecovery/NavigateWithReplanning/ComputePathToPose (\"ComputePathToPose\" also names #7):\nI run ComputePathToPose.\n"
    );
    // A uid is exact: nothing to say.
    let (ok, text, _) = btx(&["ask", "trees/kitting.xml", "--node", "#2", "q1"]);
    assert!(ok);
    assert_eq!(text, "I go insert large gear.\n");
}

#[test]
fn a_misspelt_name_or_the_wrong_file_is_said_with_what_to_do() {
    // #30 item 7: `inverter` stopped the run at tick 1 with no hint; a plan
    // key `Followpath` "matches no leaf" with no suggestion; a plan opened
    // as a tree said "byte offset 0 is 0x40".
    let dir = tempfile::tempdir().unwrap();
    let tree = dir.path().join("t.xml");
    std::fs::write(&tree, "<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\"><Sequence><inverter><AlwaysFailure/></inverter><Action ID=\"FollowPath\"/></Sequence></BehaviorTree></root>").unwrap();
    let plan = dir.path().join("p.plan");
    std::fs::write(&plan, "@default_action = S\nFollowpath = S\n").unwrap();
    let out = dir.path().join("s.jsonl");
    let (ok, _, err) = common::btx(&[
        "run",
        tree.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(
        err.contains(
            "p.plan:2:1: \"Followpath\" matches no leaf of the tree; did you mean \"FollowPath\"?"
        ),
        "{err}"
    );
    assert!(
        err.contains(
            "custom decorator \"inverter\" has no behaviour in btx; did you mean \"Inverter\"?"
        ),
        "{err}"
    );
    for (file, says) in [
        (
            plan.clone(),
            "not a tree or a session: this is a plan (leaf = outcomes); give it with --plan FILE",
        ),
        (
            common::fixture("serial-recall-excerpt.domain.toml"),
            "not a tree or a session: this is a domain file; give it with --domain FILE",
        ),
    ] {
        let (ok, _, err) = common::btx(&["tree", file.to_str().unwrap()]);
        assert!(!ok);
        assert!(err.replace("\n  │ ", " ").contains(says), "{err}");
    }
    let keys = dir.path().join("keys.toml");
    std::fs::write(&keys, "step_forward = [\"Z\", \"Right\"]\n").unwrap();
    let (ok, _, err) = common::btx(&["log", keys.to_str().unwrap()]);
    assert!(!ok);
    assert!(
        err.replace("\n  │ ", " ")
            .contains("a keymap; give it to the explorer with --keys FILE"),
        "{err}"
    );
}

#[test]
fn main_s_current_replanning_navigator_runs_to_completion() {
    // Under @default_action = 1RS its ReactiveSequence restarted
    // TruncatePathLocal every tick, and the run never finished (#30 item 6):
    // TruncatePathLocal is a BT::ActionNodeBase that completes in its tick.
    let dir = common::fixture("realworld/nav2-a3a9704");
    let tmp = tempfile::tempdir().unwrap();
    let plan = tmp.path().join("default.plan");
    std::fs::write(&plan, "@default_action = 1RS\n@default_condition = S\n").unwrap();
    let out = tmp.path().join("s.jsonl");
    let tree = dir.join("nav_to_pose_with_consistent_replanning_and_if_path_becomes_invalid.xml");
    let models = dir.join("nav2_tree_nodes.xml");
    let (ok, text, err) = btx(&[
        "run",
        tree.to_str().unwrap(),
        "--models",
        models.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "--max-ticks",
        "100",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let said = format!("{text}{err}");
    assert!(said.contains("root SUCCESS (root completed)"), "{said}");
    let s = btx::session::Session::load(&out).unwrap();
    // TruncatePathLocal: IDLE → RUNNING → SUCCESS within each tick it runs.
    let uid = common::uid_of(&s.tree, "TruncatePathLocal");
    let mine: Vec<_> = s
        .index
        .transitions
        .iter()
        .filter(|t| t.uid == uid)
        .collect();
    assert!(!mine.is_empty());
    for t in &mine {
        let same_tick: Vec<_> = mine.iter().filter(|u| u.tick == t.tick).collect();
        assert!(
            same_tick.iter().any(|u| u.status.is_completed()),
            "tick {}",
            t.tick
        );
    }
}

#[test]
fn the_readme_s_nav2_table_is_the_code_s() {
    // #30 item 6: one table, in the code and in the README (grouped; each
    // node with its releases and source file in docs/nav2.md).
    let table = |file: &str, head: &str| -> Vec<String> {
        let text =
            std::fs::read_to_string(format!("{}/{file}", env!("CARGO_MANIFEST_DIR"))).unwrap();
        text.lines()
            .skip_while(|l| !l.starts_with(head))
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(str::to_string)
            .collect()
    };
    let rows: Vec<String> = btx::model::nav2::NODES
        .iter()
        .map(btx::model::nav2::readme_row)
        .collect();
    assert_eq!(table("docs/nav2.md", "| Nav2 node "), rows);
    assert_eq!(
        table("README.md", "| base class | finishes |"),
        btx::model::nav2::readme_groups()
    );
    assert_eq!(rows.len(), 80);
}

/// Asked at the step the failure happened, what handles it has not run
/// yet: "not yet", never "nothing handled it" while the run goes on
/// (reset arm, the fallback's next child, runs at 10:7).
#[test]
fn a_failure_asked_at_its_own_moment_is_not_handled_yet() {
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    let (ok, out, err) = btx(&["ask", log, "--at", "10:1", "how was it handled?"]);
    assert!(ok, "{err}");
    assert!(
        out.contains("Nothing has handled it yet at 10:1: the run goes on."),
        "{out}"
    );
    let (_, out, _) = btx(&["ask", log, "--at", "10:7", "how was it handled?"]);
    assert!(out.contains("I fell back to reset arm."), "{out}");
}

/// "Did the task succeed?" asks whether the run came through, not what
/// the goal is (a user's trial read it as "What is your goal?").
#[test]
fn whether_the_task_succeeded_is_asked_of_the_run() {
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    for q in ["did the task succeed?", "did the robot finish the task?"] {
        let (ok, out, err) = btx(&["ask", log, q]);
        assert!(ok, "{q}: {err}");
        assert!(out.contains("Build a gearbox kit (#1) "), "{q}: {out}");
        assert!(
            out.contains("once by the end of the run at tick 54: at 54:28"),
            "{q}: {out}"
        );
        assert!(!out.contains("My goal is"), "{q}: {out}");
    }
}

/// Asked while the task still runs, whether it succeeded is "not yet".
#[test]
fn whether_the_task_succeeded_while_it_runs_is_not_yet() {
    let log = "tests/fixtures/logs/kitting_lookat_fails_once.btlog";
    let (_, out, _) = btx(&["ask", log, "--at", "10:1", "did the task succeed?"]);
    assert!(
        out.contains("never succeeded by moment 10:1: it is still running then."),
        "{out}"
    );
}

/// A session recorded from the middle of a run (btx attached to a running
/// robot) whose header says look at chuck had last failed: not "Nothing
/// went wrong", but what the states read show, and that the rest is not
/// in the session.
#[test]
fn a_failure_before_recording_began_is_said_from_the_states_read() {
    let s = "tests/fixtures/joined_after_failure.jsonl";
    let (ok, out, err) = btx(&["ask", s, "was there anything wrong?"]);
    assert!(ok, "{err}");
    assert_eq!(
        out.trim_end(),
        "Nothing went wrong since recording began. Before recording began, look at chuck had last failed: how, and what handled it, is not in the session."
    );
}

/// `btx --help` says what `btx` and `btx FILE` do; each command's help
/// lists its own options (the explorer's only where the explorer opens);
/// every error is drawn alike, whatever the command.
#[test]
fn help_says_each_commands_own_options_and_errors_come_in_one_style() {
    let (ok, help, _) = btx(&["--help"]);
    assert!(ok);
    assert!(help.contains("`btx FILE` opens"), "{help}");
    assert!(
        help.contains("`btx` alone opens the explorer's demo"),
        "{help}"
    );
    for command in [
        "log", "ask", "serve", "why", "tree", "run", "import", "watch",
    ] {
        let (ok, help, _) = btx(&[command, "--help"]);
        assert!(ok, "{command}");
        assert!(
            !help.contains("--keys") && !help.contains("--ascii"),
            "btx {command} --help lists the explorer's options:\n{help}"
        );
        assert!(help.contains("--quiet"), "{command}");
    }
    for command in ["open", "fleet"] {
        let (_, help, _) = btx(&[command, "--help"]);
        assert!(
            help.contains("--keys") && help.contains("--ascii"),
            "{command}"
        );
    }
    let errors: Vec<String> = [
        vec!["nosuch.btlog"],
        vec!["open", "nosuch.btlog"],
        vec!["log", "nosuch.btlog"],
        vec!["ask", "nosuch.btlog", "q1"],
        vec!["why", "nosuch.btlog", "status(#1)"],
        vec!["tree", "nosuch.btlog"],
    ]
    .iter()
    .map(|args| {
        let (ok, _, err) = btx(args);
        assert!(!ok, "{args:?}");
        err
    })
    .collect();
    for e in &errors {
        assert_eq!(
            e, "  × nosuch.btlog: cannot read the file: No such file or directory (os error 2)\n",
            "{errors:#?}"
        );
    }
}
