//! Tick semantics of the built-in nodes (BehaviorTree.CPP 4.10, as
//! ../shared/docs/behaviortree-cpp.md §1.6 describes them), on small trees.

use btx::run::plan::{Plan, PlanLeaves};
use btx::run::{Event, Executor, RunOptions, Status};
use btx::xml::{load_str, LoadOptions};
use std::path::Path;

/// Runs `body` (the main tree's child) with a plan; returns each tick's
/// transitions as "name:STATUS" and the root's results.
fn run(body: &str, plan: &str, ticks: u32) -> (Vec<Vec<String>>, Vec<Status>) {
    ticked(body, plan, ticks, true)
}

/// `c` is a condition, every other unknown leaf an action.
fn ticked(body: &str, plan: &str, ticks: u32, stop: bool) -> (Vec<Vec<String>>, Vec<Status>) {
    ticked_as(body, plan, ticks, stop, Default::default())
}

/// As `ticked`, following a Nav2 release's nodes.
fn ticked_as(
    body: &str,
    plan: &str,
    ticks: u32,
    stop: bool,
    nav2: btx::model::nav2::Release,
) -> (Vec<Vec<String>>, Vec<Status>) {
    let xml = format!("<root BTCPP_format=\"4\"><BehaviorTree ID=\"M\">{body}</BehaviorTree><TreeNodesModel><Condition ID=\"c\"/></TreeNodesModel></root>");
    let tree = load_str(Path::new("t.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), plan).unwrap();
    let mut ex = Executor::new(
        &tree,
        PlanLeaves::new(plan, &tree),
        RunOptions { tick_ms: 10, nav2 },
    );
    let (mut out, mut roots) = (Vec::new(), Vec::new());
    for _ in 0..ticks {
        let s = ex.tick_once().unwrap_or_else(|e| panic!("{e}"));
        roots.push(s);
        out.push(
            ex.take_events()
                .into_iter()
                .filter_map(|e| match e {
                    Event::Transition { uid, status, .. } => {
                        Some(format!("{}:{}", tree.description(uid), status))
                    }
                    _ => None,
                })
                .collect(),
        );
        if stop && s != Status::Running {
            break;
        }
    }
    (out, roots)
}

fn s(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

#[test]
fn reactive_sequence_reticks_its_condition_every_tick() {
    let (t, roots) = run(
        r#"<ReactiveSequence name="r"><c name="c"/><a name="a"/></ReactiveSequence>"#,
        "c = S\na = 2RS",
        5,
    );
    assert_eq!(t[0], s(&["r:RUNNING", "c:SUCCESS", "a:RUNNING", "c:IDLE"]));
    assert_eq!(t[1], s(&["c:SUCCESS", "c:IDLE"]));
    assert_eq!(
        t[2],
        s(&[
            "c:SUCCESS",
            "a:SUCCESS",
            "c:IDLE",
            "a:IDLE",
            "r:SUCCESS",
            "r:IDLE"
        ])
    );
    assert_eq!(roots, [Status::Running, Status::Running, Status::Success]);
    // A condition that turns false halts the running action.
    let (t, _) = run(
        r#"<ReactiveSequence name="r"><c name="c"/><a name="a"/></ReactiveSequence>"#,
        "c = S, F\na = 3RS",
        5,
    );
    assert_eq!(
        t[1],
        s(&["c:FAILURE", "c:IDLE", "a:IDLE", "r:FAILURE", "r:IDLE"])
    );
}

#[test]
fn sequence_with_memory_resumes_at_the_failed_child() {
    let body = r#"<SequenceWithMemory name="m"><a name="a"/><b name="b"/></SequenceWithMemory>"#;
    // a starts and succeeds within tick 1: the wake-up path returns RUNNING
    // and b runs in tick 2 (BehaviorTree.CPP 4, checked in tests/oracle.rs).
    let (t, roots) = ticked(body, "a = S\nb = F, S", 3, false);
    assert_eq!(roots, [Status::Running, Status::Failure, Status::Success]);
    assert_eq!(t[0], s(&["m:RUNNING", "a:SUCCESS"]));
    assert_eq!(
        t[2],
        s(&[
            "m:RUNNING",
            "b:SUCCESS",
            "a:IDLE",
            "b:IDLE",
            "m:SUCCESS",
            "m:IDLE"
        ]),
        "a is not ticked again"
    );
}

#[test]
fn retry_takes_the_wake_up_path_or_loops_within_the_tick() {
    // A child that starts and fails within one tick: RUNNING, the next
    // attempt in the next tick.
    let (t, roots) = run(
        r#"<RetryUntilSuccessful num_attempts="3"><a name="a"/></RetryUntilSuccessful>"#,
        "a = F, F, S",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Running, Status::Success]);
    assert_eq!(t[0].iter().filter(|x| *x == "a:FAILURE").count(), 1);
    // A child that was RUNNING and then fails is retried at once.
    let (t, roots) = run(
        r#"<RetryUntilSuccessful num_attempts="3"><a name="a"/></RetryUntilSuccessful>"#,
        "a = 1RF, S",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Success]);
    assert!(t[1].contains(&"a:FAILURE".to_string()) && t[1].contains(&"a:SUCCESS".to_string()));
    // The last attempt's failure is the Retry's, with no wake-up.
    let (_, roots) = run(
        r#"<RetryUntilSuccessful num_attempts="2"><a name="a"/></RetryUntilSuccessful>"#,
        "a = F",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Failure]);
}

#[test]
fn parallel_thresholds() {
    let body = r#"<Parallel name="p" success_count="1" failure_count="2"><a name="a"/><b name="b"/></Parallel>"#;
    let (t, roots) = run(body, "a = 2RS\nb = 1RF", 5);
    assert_eq!(roots, [Status::Running, Status::Running, Status::Success]);
    assert!(t[1].contains(&"b:FAILURE".to_string()));
    let (_, roots) = run(
        r#"<Parallel><a name="a"/><b name="b"/></Parallel>"#,
        "a = 1RS\nb = F",
        5,
    );
    assert_eq!(roots, [Status::Failure], "the default failure_count is 1");
    let (_, roots) = run(
        r#"<ParallelAll max_failures="2"><a name="a"/><b name="b"/></ParallelAll>"#,
        "a = 1RS\nb = F",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Success]);
}

#[test]
fn timeout_halts_its_child_on_the_simulated_clock() {
    let (t, roots) = run(
        r#"<Timeout name="t" msec="25"><a name="a"/></Timeout>"#,
        "a = 10RS",
        10,
    );
    assert_eq!(
        roots,
        [
            Status::Running,
            Status::Running,
            Status::Running,
            Status::Failure
        ]
    );
    assert_eq!(t[3], s(&["a:IDLE", "t:FAILURE", "t:IDLE"]));
    let (_, roots) = run(r#"<Delay delay_msec="15"><AlwaysSuccess/></Delay>"#, "", 10);
    assert_eq!(roots, [Status::Running, Status::Running, Status::Success]);
}

#[test]
fn decorators() {
    let (_, r) = run(r#"<Inverter><a name="a"/></Inverter>"#, "a = F", 2);
    assert_eq!(r, [Status::Success]);
    let (_, r) = run(
        r#"<ForceSuccess><a name="a"/></ForceSuccess>"#,
        "a = 1RF",
        3,
    );
    assert_eq!(r, [Status::Running, Status::Success]);
    let (_, r) = run(
        r#"<KeepRunningUntilFailure><a name="a"/></KeepRunningUntilFailure>"#,
        "a = S, S, F",
        5,
    );
    assert_eq!(r, [Status::Running, Status::Running, Status::Failure]);
    // Repeat mirrors Retry: a cycle that completes within its tick wakes up.
    let (t, r) = run(
        r#"<Repeat num_cycles="3"><a name="a"/></Repeat>"#,
        "a = S",
        5,
    );
    assert_eq!(r, [Status::Running, Status::Running, Status::Success]);
    assert_eq!(t[0].iter().filter(|x| *x == "a:SUCCESS").count(), 1);
    let (t, r) = run(
        r#"<Repeat num_cycles="2"><a name="a"/></Repeat>"#,
        "a = 1RS",
        5,
    );
    assert_eq!(r, [Status::Running, Status::Running, Status::Success]);
    assert_eq!(t[1].iter().filter(|x| *x == "a:SUCCESS").count(), 1);
    let (_, r) = run(
        r#"<Sequence><RunOnce><a name="a"/></RunOnce><b name="b"/></Sequence>"#,
        "a = S\nb = 1RS",
        3,
    );
    assert_eq!(r, [Status::Running, Status::Success]);
}

#[test]
fn if_then_else_while_do_else_switch_try_catch() {
    let (_, r) = run(
        r#"<IfThenElse><c name="c"/><a name="a"/><b name="b"/></IfThenElse>"#,
        "c = F\na = F\nb = S",
        2,
    );
    assert_eq!(r, [Status::Success]);
    let (t, r) = run(
        r#"<WhileDoElse name="w"><c name="c"/><a name="a"/><b name="b"/></WhileDoElse>"#,
        "c = S, F\na = 3RS\nb = S",
        4,
    );
    assert_eq!(r, [Status::Running, Status::Success]);
    assert!(
        t[1].contains(&"a:IDLE".to_string()),
        "the do branch is halted: {:?}",
        t[1]
    );
    let body = r#"<Sequence><Script code="mode := 'two'"/><Switch2 variable="{mode}" case_1="one" case_2="two"><a name="a"/><b name="b"/><d name="d"/></Switch2></Sequence>"#;
    let (t, r) = run(body, "a = F\nb = S\nd = F", 2);
    assert_eq!(r, [Status::Success]);
    assert!(t[0].contains(&"b:SUCCESS".to_string()));
    let (t, r) = run(
        r#"<TryCatch><a name="a"/><b name="b"/><fix name="fix"/></TryCatch>"#,
        "a = S\nb = F\nfix = S",
        2,
    );
    assert_eq!(r, [Status::Failure], "TryCatch fails after its catch");
    assert!(t[0].contains(&"fix:SUCCESS".to_string()));
}

#[test]
fn scripts_preconditions_and_script_attributes() {
    let body = r#"<Sequence><Script code="n := 3"/><Precondition if="n > 5" else="SUCCESS"><a name="a"/></Precondition><ScriptCondition code="n == 3"/><b name="b" _skipIf="n == 3"/><c name="c" _onSuccess="n += 1"/><ScriptCondition code="n == 4"/></Sequence>"#;
    let (t, r) = run(body, "a = F\nb = F\nc = S", 2);
    assert_eq!(r, [Status::Success]);
    assert!(
        !t[0]
            .iter()
            .any(|x| x.starts_with("a:") || x.starts_with("b:")),
        "{:?}",
        t[0]
    );
    let (_, r) = run(r#"<a name="a" _failureIf="true"/>"#, "a = S", 1);
    assert_eq!(r, [Status::Failure]);
}

#[test]
fn errors_name_the_node() {
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence><ScriptCondition code="nope > 1"/></Sequence></BehaviorTree></root>"#;
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "").unwrap();
    let mut ex = Executor::new(&tree, PlanLeaves::new(plan, &tree), RunOptions::default());
    let e = ex.tick_once().unwrap_err();
    assert_eq!(e.uid, 2);
    assert!(
        e.to_string().contains("\"nope\" is not on the blackboard"),
        "{e}"
    );
}

#[test]
fn a_loop_over_a_blackboard_queue_says_what_btx_cannot_make() {
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><LoopDouble queue="{q}" value="{v}"><AlwaysSuccess/></LoopDouble></BehaviorTree></root>"#;
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "").unwrap();
    let mut ex = Executor::new(&tree, PlanLeaves::new(plan, &tree), RunOptions::default());
    let e = ex.tick_once().unwrap_err().to_string();
    assert!(
        e.contains("reads its queue from the blackboard ({q})") && e.contains("queue=\"1;2;3\""),
        "{e}"
    );
    // A queue item that is not of the loop's type.
    let xml = xml.replace("{q}", "1;x");
    let tree = load_str(Path::new("t.xml"), &xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "").unwrap();
    let mut ex = Executor::new(&tree, PlanLeaves::new(plan, &tree), RunOptions::default());
    assert_eq!(ex.tick_once().unwrap(), Status::Running);
    let e = ex.tick_once().unwrap_err().to_string();
    assert!(e.contains("queue item \"x\" is not a double"), "{e}");
}

/// Nav2's controls, as their sources (nav2_behavior_tree/plugins/control)
/// run them, followed by hand. Nav2's own `halt()` inside a tick resets the
/// node to IDLE before it returns (BehaviorTree.CPP's `ControlNode::halt`).
#[test]
fn nav2s_controls_run_as_nav2s_sources_do() {
    // PipelineSequence: a is ticked again each tick while b runs; no
    // RUNNING of its own before the children.
    let (t, roots) = run(
        r#"<PipelineSequence name="p"><a name="a"/><b name="b"/></PipelineSequence>"#,
        "a = S\nb = 2RS",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Running, Status::Success]);
    assert_eq!(t[0], s(&["a:SUCCESS", "b:RUNNING", "p:RUNNING"]));
    assert!(t[1].is_empty(), "a ticked again, still SUCCESS: {:?}", t[1]);
    assert_eq!(
        t[2],
        s(&["b:SUCCESS", "a:IDLE", "b:IDLE", "p:SUCCESS", "p:IDLE"])
    );
    // RecoveryNode: a fails, the recovery r succeeds, a again.
    let (t, roots) = run(
        r#"<RecoveryNode name="n" number_of_retries="2"><a name="a"/><r name="r"/></RecoveryNode>"#,
        "a = F, F, S\nr = S",
        5,
    );
    assert_eq!(roots, [Status::Success]);
    assert_eq!(
        t[0],
        s(&[
            "n:RUNNING",
            "a:FAILURE",
            "a:IDLE",
            "r:SUCCESS",
            "r:IDLE",
            "a:FAILURE",
            "a:IDLE",
            "r:SUCCESS",
            "r:IDLE",
            "a:SUCCESS",
            "a:IDLE",
            "n:IDLE",
            "n:SUCCESS",
            "n:IDLE"
        ])
    );
    // Out of retries: the first child's failure fails the node.
    let (_, roots) = run(
        r#"<RecoveryNode name="n" number_of_retries="1"><a name="a"/><r name="r"/></RecoveryNode>"#,
        "a = F
r = S",
        5,
    );
    assert_eq!(roots, [Status::Failure]);
    // RoundRobin (main, wrap_around="true"): a fails, b succeeds; the
    // next time it starts after b, as every release of Nav2 does.
    let (t, roots) = ticked(
        r#"<RoundRobin name="rr" wrap_around="true"><a name="a"/><b name="b"/></RoundRobin>"#,
        "a = F, S\nb = S",
        2,
        false,
    );
    assert_eq!(roots, [Status::Success, Status::Success]);
    assert_eq!(
        t[1],
        s(&["rr:RUNNING", "a:SUCCESS", "a:IDLE", "rr:SUCCESS", "rr:IDLE"]),
        "it starts after the child that succeeded"
    );
}

/// Nav2's decorators and later controls (nav2_behavior_tree/plugins/
/// decorator and /control), followed by hand through their sources. What
/// they read from the robot is a blackboard entry (`btx::run::exec::
/// ROBOT_READINGS`), written here by scripts; time is the simulated clock
/// (10 ms a tick).
#[test]
fn nav2s_decorators_run_as_nav2s_sources_do() {
    // DistanceController: the child runs at the start, then once the
    // robot has moved 1 m since it last succeeded (0.6 m a tick here): it
    // is ticked again in tick 3, not 2, and fails then. (The children are
    // conditions: an action that completed keeps its status when ticked
    // again, as a StatefulActionNode does, and Nav2's decorators do not
    // reset it.)
    let moving = |inner: &str| {
        format!(
            r#"<Sequence><Script code="distance_travelled := 0.0; speed := 0.5"/><PipelineSequence name="p"><Script code="distance_travelled := distance_travelled + 0.6"/>{inner}<b name="b"/></PipelineSequence></Sequence>"#
        )
    };
    let (t, roots) = run(
        &moving(
            r#"<DistanceController name="d" distance="1.0"><c name="a"/></DistanceController>"#,
        ),
        "c = S, F\nb = 9RS",
        10,
    );
    assert_eq!(roots.len(), 3, "{t:?}");
    assert_eq!(roots[2], Status::Failure);
    assert!(t[1].contains(&"d:RUNNING".to_string()), "{:?}", t[1]);
    // SpeedController: the first period is 2 / (min_rate + max_rate) =
    // 50 ms; then 1 / rate, the rate scaled by the speed (0.5 m/s, the top
    // of the range: 30 Hz, 33 ms). The child runs at 0, 50 and 90 ms.
    let speed = r#"<SpeedController name="v" min_rate="10" max_rate="30" min_speed="0.0" max_speed="0.5"><c name="a"/></SpeedController>"#;
    let (_, roots) = run(&moving(speed), "c = S, S, F\nb = 30RS", 30);
    assert_eq!(roots.len(), 10, "fails in tick 10 (90 ms)");
    // At rest the rate is min_rate (10 Hz): after 50 ms, 100 ms more.
    let resting = moving(speed).replace("speed := 0.5", "speed := 0.0");
    let (_, roots) = run(&resting, "c = S, S, F\nb = 30RS", 30);
    assert_eq!(roots.len(), 16, "fails in tick 16 (150 ms)");
    // GoalUpdatedController: the child runs at the start, then only when
    // the blackboard's goal changes (in tick 3).
    let (_, roots) = run(
        r#"<Sequence><Script code="goal := 'A'; n := 0"/><PipelineSequence><Script code="n := n + 1"/><ForceSuccess><ScriptCondition code="n == 3" _onSuccess="goal := 'B'"/></ForceSuccess><GoalUpdatedController><c name="a"/></GoalUpdatedController><b name="b"/></PipelineSequence></Sequence>"#,
        "c = S, F\nb = 9RS",
        10,
    );
    assert_eq!(roots.len(), 3);
    assert_eq!(roots[2], Status::Failure);
    // GoalUpdater: output_goal is the goal update when one came, else
    // input_goal; then the child's result.
    let (t, _) = run(
        r#"<Sequence><Script code="goal := 'A'"/><GoalUpdater input_goal="{goal}" output_goal="{g}"><ScriptCondition code="g == 'A'"/></GoalUpdater><Script code="goal_update := 'B'"/><GoalUpdater input_goal="{goal}" output_goal="{g}"><ScriptCondition name="is b" code="g == 'B'"/></GoalUpdater></Sequence>"#,
        "",
        1,
    );
    assert!(t[0].contains(&"is b:SUCCESS".to_string()), "{:?}", t[0]);
    // PathLongerOnApproach: SUCCESS without its child until the new path
    // is longer on the approach, and never on its first tick.
    let (t, roots) = run(
        r#"<Sequence><Script code="path_longer_on_approach := true"/><PipelineSequence><PathLongerOnApproach name="l" path="{path}"><c name="a"/></PathLongerOnApproach><b name="b"/></PipelineSequence></Sequence>"#,
        "c = F\nb = 5RS",
        10,
    );
    assert_eq!(roots.len(), 2, "{t:?}");
    assert_eq!(roots[1], Status::Failure);
    assert!(t[0].contains(&"l:SUCCESS".to_string()), "{:?}", t[0]);
    // SingleTrigger: its child once while the node stays active (here a
    // PipelineSequence ticks it again without a reset); then FAILURE. A
    // parent that resets it to IDLE arms it again.
    let (t, roots) = run(
        r#"<PipelineSequence><SingleTrigger name="once"><a name="a"/></SingleTrigger><b name="b"/></PipelineSequence>"#,
        "a = S\nb = 3RS",
        10,
    );
    assert_eq!(roots, [Status::Running, Status::Failure]);
    assert!(t[1].contains(&"once:FAILURE".to_string()), "{:?}", t[1]);
    let (t, _) = run(
        r#"<Repeat num_cycles="2"><SingleTrigger><c name="again"/></SingleTrigger></Repeat>"#,
        "c = S, F",
        10,
    );
    assert!(t.concat().contains(&"again:FAILURE".to_string()), "{t:?}");
}

#[test]
fn nav2s_later_controls_run_as_nav2s_sources_do() {
    // PersistentSequence: its current child is a blackboard entry, so it
    // starts where the entry says, and writes where it is.
    let (t, roots) = run(
        r#"<Sequence><Script code="i := 1"/><PersistentSequence name="ps" current_child_idx="{i}"><a name="a"/><b name="b"/><ScriptCondition name="at 2" code="i == 2"/></PersistentSequence></Sequence>"#,
        "a = F\nb = 1RS",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Success], "{t:?}");
    assert!(!t.concat().iter().any(|x| x.starts_with("a:")));
    // NonblockingSequence: every child each tick; SUCCESS once all succeed
    // in one tick; a failure halts them all.
    let (t, roots) = run(
        r#"<NonblockingSequence name="n"><a name="a"/><b name="b"/></NonblockingSequence>"#,
        "a = 1RS\nb = 2RF",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Running, Status::Failure]);
    assert_eq!(t[0], s(&["a:RUNNING", "b:RUNNING", "n:RUNNING"]));
    // PauseResumeController, with no pause requested: its first child.
    let (_, roots) = run(
        r#"<PauseResumeController><a name="a"/><b name="b"/></PauseResumeController>"#,
        "a = 1RS\nb = F",
        5,
    );
    assert_eq!(roots, [Status::Running, Status::Success]);
}

/// Nav2's actions that finish in the tick that starts them (a selector is
/// a SyncActionNode; GetCurrentPose an ActionNodeBase that sets RUNNING,
/// then returns): a plan's RUNNING ticks do not apply, so a
/// ReactiveSequence over two of them ends, as on the robot.
#[test]
fn nav2s_actions_that_finish_at_once_take_no_running_ticks() {
    let (t, roots) = run(
        r#"<ReactiveSequence name="r"><ControllerSelector name="c"/><GetCurrentPose name="g"/><GetPoseFromPath name="p"/><FollowPath name="f"/></ReactiveSequence>"#,
        "@default_action = 2RS",
        5,
    );
    assert_eq!(
        roots,
        [Status::Running, Status::Running, Status::Success],
        "{t:?}"
    );
    assert_eq!(
        t[0],
        s(&[
            "r:RUNNING",
            "c:SUCCESS",
            "g:RUNNING",
            "g:SUCCESS",
            "p:RUNNING",
            "p:SUCCESS",
            "f:RUNNING",
            // ReactiveSequence resets the others while one runs.
            "c:IDLE",
            "g:IDLE",
            "p:IDLE",
        ])
    );
    // Without the rule, the ReactiveSequence would restart GetCurrentPose
    // each tick and halt the one after it for ever.
    let (_, roots) = run(
        r#"<ReactiveSequence name="r"><Mine name="g"/><Other name="p"/></ReactiveSequence>"#,
        "@default_action = 1RS",
        6,
    );
    assert!(roots.iter().all(|&r| r == Status::Running), "{roots:?}");
    // A plan that gives one RUNNING ticks is told they are dropped.
    let xml =
        r#"<root BTCPP_format="4"><BehaviorTree ID="M"><GetCurrentPose/></BehaviorTree></root>"#;
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "GetCurrentPose = 2RF").unwrap();
    let leaves = PlanLeaves::new(plan, &tree);
    assert!(
        leaves
            .warnings
            .iter()
            .any(|w| w.location == "t.plan:1:1" && w.message.contains("never returns RUNNING")),
        "{:?}",
        leaves.warnings
    );
    let mut ex = Executor::new(&tree, leaves, RunOptions::default());
    assert_eq!(ex.tick_once().unwrap(), Status::Failure);
}

/// Scripting as BehaviorTree.CPP 4.10 does it (#14 item 4).
#[test]
fn scripts_join_strings_assign_declared_entries_and_read_enums() {
    // `+` joins two strings; `=` assigns an entry a `{key}` port declared
    // when the tree was built; an enum is declared in the plan.
    let (t, roots) = run(
        r#"<Sequence><Script code="x := 'a' + 'b'"/><ScriptCondition name="ab" code="x == 'ab'"/><Script code="target = 5"/><SetBlackboard value="{target}" output_key="copy"/><ScriptCondition name="five" code="copy == 5"/><ScriptCondition name="green" code="GREEN == 1 &amp;&amp; RED == 0 &amp;&amp; MAX == 9"/></Sequence>"#,
        "@enum Color = RED, GREEN\n@enum MAX = 9",
        1,
    );
    assert_eq!(roots, [Status::Success], "{t:?}");
    // `=` on an entry nothing declared is still refused, as the library does.
    let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Script code="nowhere = 5"/></BehaviorTree></root>"#;
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "").unwrap();
    let mut ex = Executor::new(&tree, PlanLeaves::new(plan, &tree), RunOptions::default());
    let e = ex.tick_once().unwrap_err().to_string();
    assert!(e.contains("create it with :="), "{e}");
    // A SubTree port the instance does not remap takes its model's default.
    let xml = r#"<root BTCPP_format="4" main_tree_to_execute="M"><BehaviorTree ID="M"><SubTree ID="Sub"/></BehaviorTree><BehaviorTree ID="Sub"><ScriptCondition code="speed == 2"/></BehaviorTree><TreeNodesModel><SubTree ID="Sub"><input_port name="speed" default="2"/></SubTree></TreeNodesModel></root>"#;
    let tree = load_str(Path::new("t.xml"), xml, &LoadOptions::default())
        .unwrap()
        .tree;
    let plan = Plan::parse(Path::new("t.plan"), "").unwrap();
    let mut ex = Executor::new(&tree, PlanLeaves::new(plan, &tree), RunOptions::default());
    assert_eq!(ex.tick_once().unwrap(), Status::Success);
}

/// Nav2's own unit tests of RoundRobin (nav2_behavior_tree/test/plugins/
/// control/test_round_robin_node.cpp, main at a3a9704, whose fixture sets
/// wrap_around="true"), each child's statuses made a plan, in every
/// release where the source is the same, and where they differ as each
/// release's source runs them.
#[test]
fn round_robin_runs_nav2s_own_tests_in_each_release() {
    use btx::model::nav2::Release;
    let wrapping = r#"<RoundRobin name="rr" wrap_around="true"><x name="x"/><y name="y"/><z name="z"/></RoundRobin>"#;
    let plain = r#"<RoundRobin name="rr"><x name="x"/><y name="y"/><z name="z"/></RoundRobin>"#;
    for release in [Release::Humble, Release::Jazzy, Release::Main] {
        // test_failure: every child fails in turn.
        let (t, roots) = ticked_as(wrapping, "x = F\ny = 1RF\nz = 1RF", 3, true, release);
        assert_eq!(
            roots,
            [Status::Running, Status::Running, Status::Failure],
            "{release:?}"
        );
        assert!(
            t[2].ends_with(&s(&["rr:FAILURE", "rr:IDLE"])),
            "{release:?} {:?}",
            t[2]
        );
        // test_behavior: after a success the next tick starts at the next
        // child (z), and wraps around to x.
        let (_, roots) = ticked_as(
            wrapping,
            "x = 1RF, 1RF\ny = 1RS, S\nz = 1RF",
            6,
            false,
            release,
        );
        assert_eq!(
            roots,
            [
                Status::Running,
                Status::Running,
                Status::Success,
                Status::Running,
                Status::Running,
                Status::Success
            ],
            "{release:?}"
        );
    }
    // test_wrap_around_disabled (main's default): all fail, FAILURE at once.
    let (_, roots) = ticked_as(plain, "x = F\ny = F\nz = F", 1, true, Release::Main);
    assert_eq!(roots, [Status::Failure]);
    // Where the releases differ: x fails, y fails, z succeeds. Humble and
    // Jazzy succeed; main without wrap_around ends at the last child with
    // FAILURE whatever it returned (its source breaks out of the loop
    // before it looks at the status).
    for (release, want) in [
        (Release::Humble, Status::Success),
        (Release::Jazzy, Status::Success),
        (Release::Main, Status::Failure),
    ] {
        let (_, roots) = ticked_as(plain, "x = F\ny = F\nz = S", 1, true, release);
        assert_eq!(roots, [want], "{release:?}");
    }
    // Without wrap_around (main), a run of successes walks the children
    // once: x, then y, then z ends the node.
    let (_, roots) = ticked_as(plain, "x = S\ny = S\nz = S", 3, false, Release::Main);
    assert_eq!(roots, [Status::Success, Status::Success, Status::Failure]);
    let (_, roots) = ticked_as(plain, "x = S\ny = S\nz = S", 4, false, Release::Humble);
    assert_eq!(
        roots,
        [
            Status::Success,
            Status::Success,
            Status::Success,
            Status::Success
        ]
    );
}
