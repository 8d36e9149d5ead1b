//! Nav2's own controls and decorators (`nav2_behavior_tree/plugins/control`
//! and `/decorator`), each as its source has it (the commit is named where
//! releases differ). Nav2's bt_navigator registers them for every navigator
//! tree. What a decorator reads from the robot (distance travelled, speed,
//! a goal update, whether a new path is longer) btx reads from the
//! blackboard entry named in `ROBOT_READINGS`, which a plan (`--set`) or a
//! domain writes; time is the simulated clock.

use super::{Executor, Leaves, R};
use crate::model::Uid;
use crate::run::Status;
use serde_json::Value;

/// The blackboard entries btx reads where Nav2's decorators read the
/// robot, what each stands for, and the reading when nothing wrote it.
pub const ROBOT_READINGS: &[(&str, &str, &str)] = &[
    (
        DISTANCE_TRAVELLED,
        "DistanceController: metres the robot has travelled (its pose from tf)",
        "0: the robot has not moved",
    ),
    (
        SPEED,
        "SpeedController: the robot's speed in m/s (its smoothed odometry)",
        "0",
    ),
    (
        GOAL_UPDATE,
        "GoalUpdater: the last goal received on its goal_update topic",
        "none: output_goal is input_goal",
    ),
    (
        PATH_LONGER,
        "PathLongerOnApproach: whether the new path is longer by length_factor while the robot is within prox_len of the goal",
        "false",
    ),
];

pub const DISTANCE_TRAVELLED: &str = "distance_travelled";
pub const SPEED: &str = "speed";
pub const GOAL_UPDATE: &str = "goal_update";
pub const PATH_LONGER: &str = "path_longer_on_approach";

impl<L: Leaves> Executor<'_, L> {
    /// Nav2's `PipelineSequence` (nav2_behavior_tree/plugins/control/
    /// pipeline_sequence.cpp): every child from the first is ticked again
    /// each tick; a child RUNNING at or past the furthest one reached
    /// returns RUNNING, one before it lets the next be ticked. It sets no
    /// RUNNING of its own before its children (unlike Sequence).
    pub(super) fn tick_pipeline(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let kids = &tree.node(uid).children;
        for (i, &c) in kids.iter().enumerate() {
            match self.exec(c)? {
                Status::Failure => {
                    self.reset_children(uid);
                    self.rt(uid).idx = 0;
                    return Ok(Status::Failure);
                }
                Status::Success => {}
                Status::Running if i >= self.rt(uid).idx => {
                    self.rt(uid).idx = i;
                    return Ok(Status::Running);
                }
                Status::Running => {}
                s => {
                    return Err(self.err(
                        uid,
                        format!("a child returned {s}, which Nav2's PipelineSequence refuses"),
                    ))
                }
            }
        }
        self.reset_children(uid);
        self.rt(uid).idx = 0;
        Ok(Status::Success)
    }

    /// Nav2's `halt()` of its controls inside their own tick: BehaviorTree.
    /// CPP's `ControlNode::halt()` (children reset, the node IDLE) and their
    /// counters back to 0.
    pub(super) fn nav2_halt(&mut self, uid: Uid) {
        self.reset_children(uid);
        self.reset_status(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.count = 0;
        r.failures = 0;
    }

    /// Nav2's `RecoveryNode` (plugins/control/recovery_node.cpp): the first
    /// child; when it fails, the second (the recovery), and when that
    /// succeeds the first again, up to `number_of_retries` recoveries.
    pub(super) fn tick_recovery(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let kids = tree.node(uid).children.clone();
        let retries = self.port_int(uid, &["number_of_retries"], Some(1))?;
        self.set_status(uid, Status::Running);
        while self.rt(uid).idx < 2 && self.rt(uid).count <= retries {
            let idx = self.rt(uid).idx;
            self.check_progress(uid, kids[idx])?;
            let s = self.exec(kids[idx])?;
            if idx == 0 {
                match s {
                    Status::Skipped | Status::Success => {
                        self.nav2_halt(uid);
                        return Ok(s);
                    }
                    Status::Running => return Ok(Status::Running),
                    Status::Failure if self.rt(uid).count < retries => {
                        self.halt_child(kids[0]);
                        self.rt(uid).idx = 1;
                    }
                    Status::Failure => {
                        self.nav2_halt(uid);
                        return Ok(Status::Failure);
                    }
                    Status::Idle => unreachable!("exec rejects IDLE"),
                }
            } else {
                match s {
                    // No recovery possible; not counted as a retry.
                    Status::Skipped => {
                        self.rt(uid).idx = 0;
                        self.halt_child(kids[1]);
                        return Ok(Status::Failure);
                    }
                    Status::Running => return Ok(Status::Running),
                    Status::Success => {
                        self.halt_child(kids[1]);
                        let r = self.rt(uid);
                        r.count += 1;
                        r.idx = 0;
                    }
                    Status::Failure => {
                        self.nav2_halt(uid);
                        return Ok(Status::Failure);
                    }
                    Status::Idle => unreachable!("exec rejects IDLE"),
                }
            }
        }
        self.nav2_halt(uid);
        Ok(Status::Failure)
    }

    /// Nav2's `RoundRobin` (plugins/control/round_robin_node.cpp), as the
    /// release of the run has it. In every release a child that completes
    /// moves the index on, so the next tick starts at the child after the
    /// one that succeeded; the first success succeeds the node; a failure
    /// moves on until every child has failed once. Humble wraps around past
    /// the last child; Jazzy too, and counts SKIPPED children (all skipped:
    /// SKIPPED); main wraps only with `wrap_around="true"` (default false):
    /// otherwise the last child's completion, whatever it is, ends the node
    /// with FAILURE (or SKIPPED when every child was skipped).
    pub(super) fn tick_round_robin(&mut self, uid: Uid) -> R<Status> {
        use crate::model::nav2::Release;
        let tree = self.tree;
        let kids = tree.node(uid).children.clone();
        let n = kids.len();
        let release = self.opts.nav2;
        let wrap = self.round_robin_wraps(uid);
        self.set_status(uid, Status::Running);
        let mut skipped = 0;
        while self.rt(uid).failures + skipped < n {
            let c = kids[self.rt(uid).idx];
            self.check_progress(uid, c)?;
            let s = self.exec(c)?;
            if !matches!(s, Status::Running | Status::Idle) {
                let r = self.rt(uid);
                r.idx += 1;
                if r.idx == n {
                    if wrap {
                        r.idx = 0;
                    } else {
                        match s {
                            Status::Skipped => skipped += 1,
                            Status::Failure => r.failures += 1,
                            _ => {}
                        }
                        break;
                    }
                }
            }
            match s {
                Status::Success => {
                    self.rt(uid).failures = 0;
                    self.reset_children(uid);
                    return Ok(Status::Success);
                }
                Status::Failure => self.rt(uid).failures += 1,
                Status::Skipped if release != Release::Humble => skipped += 1,
                Status::Running => return Ok(Status::Running),
                s => {
                    return Err(self.err(
                        uid,
                        format!("a child returned {s}, which Nav2's RoundRobin refuses"),
                    ))
                }
            }
        }
        self.reset_children(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.failures = 0;
        Ok(if skipped == n {
            Status::Skipped
        } else {
            Status::Failure
        })
    }

    /// Nav2's `RateController` (plugins/decorator/rate_controller.cpp):
    /// the child is ticked when the node starts, while it is RUNNING, and
    /// once `1/hz` seconds of the simulated clock have passed since it last
    /// succeeded; otherwise the node stays RUNNING without ticking it. A
    /// completed child is set IDLE at once.
    pub(super) fn tick_rate_controller(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let hz = match self.port_str(uid, "hz") {
            Some(h) => h
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|h| *h > 0.0)
                .ok_or_else(|| self.err(uid, format!("port hz=\"{h}\" is not a rate above 0")))?,
            None => 10.0,
        };
        let now = self.now_ms;
        if self.status(uid) == Status::Idle {
            let r = self.rt(uid);
            r.since_ms = now;
            r.started = true;
        }
        self.set_status(uid, Status::Running);
        let elapsed = now.saturating_sub(self.rt(uid).since_ms) as f64;
        if self.rt(uid).started || self.status(child) == Status::Running || elapsed >= 1000.0 / hz {
            self.rt(uid).started = false;
            let s = self.exec(child)?;
            match s {
                Status::Running => return Ok(Status::Running),
                Status::Success => {
                    self.reset_status(child);
                    self.rt(uid).since_ms = now;
                    return Ok(Status::Success);
                }
                _ => {
                    self.reset_status(child);
                    return Ok(Status::Failure);
                }
            }
        }
        Ok(Status::Running)
    }

    /// A reading of the robot (`ROBOT_READINGS`): the entry `key` of the
    /// node's scope, `None` when nothing wrote it.
    fn robot_reading(&self, uid: Uid, key: &str) -> Option<Value> {
        let n = self.tree.node(uid);
        let e = self.bb.resolve(self.tree, n.scope, key);
        self.bb.get(&e).cloned()
    }

    fn reading_f64(&self, uid: Uid, key: &str) -> R<f64> {
        match self.robot_reading(uid, key) {
            None => Ok(0.0),
            Some(v) => v
                .as_f64()
                .or_else(|| v.as_str().and_then(|s| s.trim().parse().ok()))
                .ok_or_else(|| {
                    self.err(
                        uid,
                        format!("the blackboard entry {key} is {v}, not a number (btx reads it where Nav2 reads the robot)"),
                    )
                }),
        }
    }

    fn port_f64(&self, uid: Uid, name: &str, default: f64) -> R<f64> {
        match self.port_str(uid, name) {
            Some(s) => s
                .trim()
                .parse::<f64>()
                .map_err(|_| self.err(uid, format!("port {name}=\"{s}\" is not a number"))),
            None => Ok(default),
        }
    }

    /// Nav2's `DistanceController` (plugins/decorator/distance_controller.
    /// cpp): the child is ticked when the node starts, while it is
    /// RUNNING, and once the robot has travelled `distance` metres since
    /// the child last succeeded; otherwise the node stays RUNNING. The
    /// child is not reset: it keeps its status until ticked again.
    pub(super) fn tick_distance_controller(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let distance = self.port_f64(uid, "distance", 1.0)?;
        let now = self.reading_f64(uid, DISTANCE_TRAVELLED)?;
        if !self.status(uid).is_active() {
            let r = self.rt(uid);
            r.origin = now;
            r.started = true;
        }
        self.set_status(uid, Status::Running);
        let travelled = (now - self.rt(uid).origin).abs();
        if self.rt(uid).started || self.status(child) == Status::Running || travelled >= distance {
            self.rt(uid).started = false;
            return Ok(match self.exec(child)? {
                Status::Success => {
                    self.rt(uid).origin = now;
                    Status::Success
                }
                s @ (Status::Running | Status::Skipped) => s,
                _ => Status::Failure,
            });
        }
        Ok(Status::Running)
    }

    /// Nav2's `SpeedController` (plugins/decorator/speed_controller.cpp):
    /// as `RateController`, with a period that follows the robot's speed:
    /// `2 / (max_rate + min_rate)` when the node starts, then, each time
    /// it is over, `1 / rate` with the rate scaled from `min_rate` at
    /// `min_speed` to `max_rate` at `max_speed`. The child is not reset.
    pub(super) fn tick_speed_controller(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let min_rate = self.port_f64(uid, "min_rate", 0.1)?;
        let max_rate = self.port_f64(uid, "max_rate", 1.0)?;
        let min_speed = self.port_f64(uid, "min_speed", 0.0)?;
        let max_speed = self.port_f64(uid, "max_speed", 0.5)?;
        if min_rate <= 0.0 || max_rate < min_rate {
            return Err(self.err(uid, format!("the rates min_rate={min_rate} and max_rate={max_rate} make no period (0 < min_rate <= max_rate)")));
        }
        let now = self.now_ms;
        if self.status(uid) == Status::Idle {
            let r = self.rt(uid);
            r.period_s = 2.0 / (max_rate + min_rate);
            r.since_ms = now;
            r.started = true;
        }
        self.set_status(uid, Status::Running);
        let elapsed = now.saturating_sub(self.rt(uid).since_ms) as f64 / 1000.0;
        let over = elapsed >= self.rt(uid).period_s;
        if self.rt(uid).started || self.status(child) == Status::Running || over {
            self.rt(uid).started = false;
            if over {
                let speed = self.reading_f64(uid, SPEED)?;
                let (d_rate, d_speed) = (max_rate - min_rate, max_speed - min_speed);
                let rate = ((speed - min_speed) / d_speed * d_rate + min_rate)
                    .min(max_rate)
                    .max(min_rate);
                // A zero speed range (NaN) keeps the slowest rate.
                let rate = if rate.is_nan() { min_rate } else { rate };
                self.rt(uid).period_s = 1.0 / rate;
            }
            return Ok(match self.exec(child)? {
                Status::Success => {
                    self.rt(uid).since_ms = now;
                    Status::Success
                }
                Status::Running => Status::Running,
                _ => Status::Failure,
            });
        }
        Ok(Status::Running)
    }

    /// Nav2's `GoalUpdatedController` (plugins/decorator/
    /// goal_updated_controller.cpp): the child is ticked when the node
    /// starts, while it is RUNNING, and when the blackboard's `goal` or
    /// `goals` changed since the node last looked.
    pub(super) fn tick_goal_updated_controller(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let goals = |x: &Self| {
            vec![
                x.port_value_or_entry(uid, "goals"),
                x.port_value_or_entry(uid, "goal"),
            ]
        };
        let now = goals(self);
        if !self.status(uid).is_active() {
            let r = self.rt(uid);
            r.seen = now.clone();
            r.started = true;
        }
        self.set_status(uid, Status::Running);
        if self.rt(uid).seen != now {
            let r = self.rt(uid);
            r.seen = now;
            r.started = true;
        }
        if self.status(child) == Status::Running || self.rt(uid).started {
            self.rt(uid).started = false;
            return self.exec(child);
        }
        Ok(Status::Running)
    }

    /// `getInputOrBlackboard`: the port when the node has it, else the
    /// entry of that name.
    fn port_value_or_entry(&self, uid: Uid, name: &str) -> Option<Value> {
        match self.port_str(uid, name) {
            Some(s) => Some(Value::from(s)),
            None => self.robot_reading(uid, name),
        }
    }

    /// Nav2's `GoalUpdater` (plugins/decorator/goal_updater_node.cpp):
    /// writes `output_goal` (the last goal received on its topic, else
    /// `input_goal`) and `output_goals` likewise, then ticks the child and
    /// returns what it returns.
    pub(super) fn tick_goal_updater(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let goal = self
            .robot_reading(uid, GOAL_UPDATE)
            .or_else(|| self.port_value_or_input(uid, "input_goal"));
        if let Some(g) = goal {
            self.write_output(uid, "output_goal", g);
        }
        if let Some(g) = self.port_value_or_input(uid, "input_goals") {
            self.write_output(uid, "output_goals", g);
        }
        self.exec(child)
    }

    /// An input port's value (its literal or its entry), if it has one.
    fn port_value_or_input(&self, uid: Uid, name: &str) -> Option<Value> {
        let n = self.tree.node(uid);
        let p = n.ports.iter().find(|p| p.name == name)?;
        match &p.value {
            crate::model::PortValue::Literal(s) => Some(Value::from(s.clone())),
            v => {
                let e = self.bb.port_entry(self.tree, n.scope, v)?;
                self.bb.get(&e).cloned()
            }
        }
    }

    /// Nav2's `PathLongerOnApproach` (plugins/decorator/
    /// path_longer_on_approach.cpp): when the new path is longer on the
    /// approach (`PATH_LONGER`), and not the first tick for this goal, the
    /// child is ticked and its result returned (a completed child reset);
    /// otherwise SUCCESS without ticking it.
    pub(super) fn tick_path_longer_on_approach(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let longer = match self.robot_reading(uid, PATH_LONGER) {
            None => false,
            Some(Value::Bool(b)) => b,
            Some(v) => v.as_str().and_then(|s| s.trim().parse().ok()).ok_or_else(|| {
                self.err(uid, format!("the blackboard entry {PATH_LONGER} is {v}, not true or false (btx reads it where Nav2 compares the paths)"))
            })?,
        };
        // `first_time_` is set for a new goal; btx knows no goal's pose, so
        // it is the node's first tick.
        let first = !self.rt(uid).started;
        self.rt(uid).started = true;
        self.set_status(uid, Status::Running);
        if longer && !first {
            let s = self.exec(child)?;
            if s.is_completed() {
                self.reset_status(child);
            }
            return Ok(s);
        }
        Ok(Status::Success)
    }

    /// Nav2's `SingleTrigger` (plugins/decorator/single_trigger_node.cpp):
    /// the child is ticked until it completes once per run of the node
    /// (per `run_id` on the blackboard with `is_global`); after that the
    /// node fails without ticking it.
    pub(super) fn tick_single_trigger(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let global = self
            .port_str(uid, "is_global")
            .is_some_and(|s| s.trim() == "true" || s.trim() == "1");
        if !self.status(uid).is_active() && !global {
            self.rt(uid).fired = false;
        }
        if global {
            let run = self.robot_reading(uid, "run_id").ok_or_else(|| {
                self.err(
                    uid,
                    "is_global=true needs run_id on the blackboard (Nav2 throws without it)",
                )
            })?;
            if self.rt(uid).seen.first() != Some(&Some(run.clone())) {
                let r = self.rt(uid);
                r.seen = vec![Some(run)];
                r.fired = false;
            }
        }
        self.set_status(uid, Status::Running);
        if !self.rt(uid).fired {
            let s = self.exec(child)?;
            if s.is_completed() {
                self.rt(uid).fired = true;
            }
            return Ok(s);
        }
        Ok(Status::Failure)
    }

    /// Nav2's `PersistentSequence` (plugins/control/persistent_sequence.
    /// cpp): a Sequence whose current child is the blackboard entry of
    /// `current_child_idx`, so it outlives a halt.
    pub(super) fn tick_persistent_sequence(&mut self, uid: Uid) -> R<Status> {
        let kids = self.tree.node(uid).children.clone();
        let mut idx = match self.port_value_or_input(uid, "current_child_idx") {
            None => return Err(self.err(uid, "current_child_idx has no value: Nav2 reads it from the blackboard; give it with --set")),
            Some(v) => v
                .as_i64()
                .or_else(|| v.as_str().and_then(|s| s.trim().parse().ok()))
                .filter(|i| *i >= 0)
                .ok_or_else(|| self.err(uid, format!("current_child_idx is {v}, not an index")))?
                as usize,
        };
        self.set_status(uid, Status::Running);
        while idx < kids.len() {
            match self.exec(kids[idx])? {
                Status::Running => return Ok(Status::Running),
                Status::Failure => {
                    self.reset_children(uid);
                    self.write_output(uid, "current_child_idx", Value::from(0));
                    return Ok(Status::Failure);
                }
                _ => {
                    idx += 1;
                    self.write_output(uid, "current_child_idx", Value::from(idx));
                }
            }
        }
        self.reset_children(uid);
        self.write_output(uid, "current_child_idx", Value::from(0));
        Ok(Status::Success)
    }

    /// Nav2's `NonblockingSequence` (plugins/control/nonblocking_sequence.
    /// cpp): every child each tick; a failure halts them all and fails;
    /// SUCCESS once all succeed in one tick, else RUNNING.
    pub(super) fn tick_nonblocking_sequence(&mut self, uid: Uid) -> R<Status> {
        let kids = self.tree.node(uid).children.clone();
        let mut all = true;
        for &c in &kids {
            match self.exec(c)? {
                Status::Failure => {
                    self.reset_children(uid);
                    return Ok(Status::Failure);
                }
                Status::Success => {}
                Status::Running => all = false,
                s => {
                    return Err(self.err(
                        uid,
                        format!("a child returned {s}, which Nav2's NonblockingSequence refuses"),
                    ))
                }
            }
        }
        if all {
            self.reset_children(uid);
            return Ok(Status::Success);
        }
        Ok(Status::Running)
    }

    /// Nav2's `PauseResumeController` (plugins/control/
    /// pause_resume_controller.cpp) as it runs when no one calls its pause
    /// service (btx has none): RESUMED, it ticks its first child; SUCCESS
    /// or SKIPPED succeeds, FAILURE fails.
    pub(super) fn tick_pause_resume(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        self.set_status(uid, Status::Running);
        Ok(match self.exec(child)? {
            Status::Running => Status::Running,
            Status::Failure => Status::Failure,
            _ => Status::Success,
        })
    }
}
