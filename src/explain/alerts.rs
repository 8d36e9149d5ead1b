//! Faults said as they happen (#40). A watched robot's transitions, read
//! one by one as they come, give one line for each fault (what failed,
//! what its failure makes fail, and what handles it) and one more when
//! the handling ends: recovered, or not. The faults are those of
//! `fault::is_fault`, decided from what has come so far: an action's
//! failure at once, a check's at the end of its tick (whether it went up
//! to a goal is known only then).

use super::fault::{goes_up_to_a_goal, is_action, verifies};
use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::Status;

/// A transition as a watch reads it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Row {
    pub tick: u32,
    pub step: u32,
    pub uid: Uid,
    pub prev: Status,
    pub status: Status,
    /// The robot's clock, µs since the epoch, where the source has one.
    pub time_us: Option<i64>,
}

/// A recorded run's transitions as a watch reads them: numbered within
/// their tick, with the robot's time where the run keeps it (`times_us`,
/// one a transition, or empty).
pub fn rows<'a>(
    idx: &'a crate::session::Index,
    times_us: &'a [i64],
) -> impl Iterator<Item = Row> + 'a {
    let timed = times_us.len() == idx.transitions.len();
    let (mut tick, mut step) = (0, 0);
    idx.transitions.iter().enumerate().map(move |(i, t)| {
        if t.tick != tick {
            (tick, step) = (t.tick, 0);
        }
        step += 1;
        Row {
            tick: t.tick,
            step,
            uid: t.uid,
            prev: t.prev,
            status: t.status,
            time_us: timed.then(|| times_us[i]),
        }
    })
}

/// What an alert says happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum What {
    /// A fault, and what handles it.
    Fault,
    /// The handler of a fault succeeded.
    Recovered,
    /// The handler failed or was halted, or the task failed.
    NotRecovered,
    /// The root went back to IDLE after SUCCESS or FAILURE.
    RunEnded,
}

/// One line said as it happened.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Alert {
    pub what: What,
    pub tick: u32,
    pub step: u32,
    /// The robot's clock at the transition that showed it, if known.
    pub time_us: Option<i64>,
    /// The node that failed (a fault), the handler (recovered or not), the
    /// root (a run's end).
    pub node: Uid,
    /// The leaf whose failure is the root cause, as far as the
    /// transitions so far show it.
    pub root_cause: Option<Uid>,
    /// The node that handles the fault, if any does.
    pub handler: Option<Uid>,
    /// The run's outcome (a run's end).
    pub outcome: Option<Status>,
    /// The line, with its moment first ("10:1 look at chuck failed; …").
    pub text: String,
}

/// A fault being handled.
#[derive(Debug, Clone)]
struct Handling {
    /// `None`: nothing handles it, the task fails.
    handler: Option<Uid>,
    cause: Uid,
    /// The nodes between the fault and the handler, which fail with it.
    path: Vec<Uid>,
    /// The handler was halted: not recovered, unless it ends otherwise in
    /// the same tick (Nav2 halts a node within its own call).
    halted: Option<Row>,
}

/// Reads a run's transitions as they come and says its faults.
pub struct Alerts {
    /// Shared, so that a line can be made while the state changes.
    tree: std::sync::Arc<Tree>,
    /// The last leaf fault below each node in its call so far.
    below: Vec<Option<Uid>>,
    /// A Retry's attempts, a RecoveryNode's recoveries, in the call so far.
    tries: Vec<u32>,
    /// The tick read so far from a check's failure on, until the tick ends.
    held: Vec<Row>,
    tick: u32,
    open: Vec<Handling>,
    runs: u32,
    /// The root's last completion, for a run's end.
    ended: Option<Status>,
    /// Every fault decided, to check against `fault::is_fault`.
    #[cfg(test)]
    decided: Vec<(u32, u32)>,
}

impl Alerts {
    pub fn new(tree: Tree) -> Alerts {
        let tree = std::sync::Arc::new(tree);
        let n = tree.nodes.iter().map(|n| n.uid).max().unwrap_or(0) as usize + 1;
        Alerts {
            tree,
            below: vec![None; n],
            tries: vec![0; n],
            held: Vec::new(),
            tick: 0,
            open: Vec::new(),
            runs: 0,
            ended: None,
            #[cfg(test)]
            decided: Vec::new(),
        }
    }

    /// Reads one transition; the lines it lets be said.
    pub fn push(&mut self, row: Row) -> Vec<Alert> {
        let mut out = Vec::new();
        if row.tick != self.tick {
            out.extend(self.flush());
            out.extend(self.settle());
            self.tick = row.tick;
        }
        if (row.uid as usize) >= self.below.len() {
            return out;
        }
        if !self.held.is_empty() || self.undecided(row) {
            self.held.push(row);
        } else {
            self.read(row, &[], &mut out);
        }
        out
    }

    /// The tick is over (or no more will come for now): the rows held for
    /// a check's failure are read with the rest of their tick.
    pub fn flush(&mut self) -> Vec<Alert> {
        let held = std::mem::take(&mut self.held);
        let mut out = Vec::new();
        for (i, &row) in held.iter().enumerate() {
            self.read(row, &held[i + 1..], &mut out);
        }
        out
    }

    /// No more will come: what is held is decided, and handlers halted
    /// in the last tick are not recovered.
    pub fn finish(&mut self) -> Vec<Alert> {
        let mut out = self.flush();
        out.extend(self.settle());
        out
    }

    /// Handlers halted in a tick that is over: not recovered.
    pub fn settle(&mut self) -> Vec<Alert> {
        let mut out = Vec::new();
        let (halted, open): (Vec<Handling>, Vec<Handling>) = std::mem::take(&mut self.open)
            .into_iter()
            .partition(|h| h.halted.is_some());
        self.open = open;
        for h in halted {
            let (Some(row), Some(u)) = (h.halted, h.handler) else {
                continue;
            };
            let mut a = self.alert(
                What::NotRecovered,
                row,
                u,
                Some(h.cause),
                format!(
                    "{} not recovered: {} was halted",
                    at(row),
                    self.tree.told(u)
                ),
            );
            a.handler = Some(u);
            out.push(a);
        }
        out
    }

    /// A check's failure, which is a fault only if it goes up to a goal
    /// in its tick.
    fn undecided(&self, row: Row) -> bool {
        let n = self.tree.node(row.uid);
        row.status == Status::Failure
            && n.kind.is_leaf()
            && row.uid != Tree::ROOT
            && !is_action(&self.tree, row.uid)
            && !verifies(&self.tree, row.uid)
    }

    fn is_fault(&self, row: Row, rest: &[Row]) -> bool {
        if row.status != Status::Failure {
            return false;
        }
        let n = self.tree.node(row.uid);
        if is_action(&self.tree, row.uid) || row.uid == Tree::ROOT {
            return true;
        }
        if !n.kind.is_leaf() {
            return self.below[row.uid as usize].is_some();
        }
        verifies(&self.tree, row.uid)
            || goes_up_to_a_goal(&self.tree, row.uid, 0usize, |parent, from| {
                rest.iter()
                    .enumerate()
                    .skip(from)
                    .find(|(_, r)| {
                        r.uid == parent && matches!(r.status, Status::Success | Status::Failure)
                    })
                    .map(|(i, r)| (i + 1, r.status))
            })
    }

    fn read(&mut self, row: Row, rest: &[Row], out: &mut Vec<Alert>) {
        let tree = std::sync::Arc::clone(&self.tree);
        let tree = &*tree;
        let u = row.uid;
        // Decided before a start resets what was below: a node Nav2 halts
        // within its call (RUNNING → IDLE → FAILURE) fails for what failed
        // in the call that went before, as `Index::call_start` reads it.
        let fault = self.is_fault(row, rest);
        if row.prev == Status::Idle && row.status != Status::Idle {
            self.started(u);
        }
        if fault {
            #[cfg(test)]
            self.decided.push((row.tick, row.step));
            let cause = if tree.node(u).kind.is_leaf() {
                u
            } else {
                self.below[u as usize].unwrap_or(u)
            };
            for a in tree.ancestors(u).filter(|&a| a != u) {
                self.below[a as usize] = Some(cause);
            }
            self.fault(row, cause, out);
        } else if row.status == Status::Failure {
            // A handler that failed with no fault below it.
            if let Some(i) = self.open.iter().position(|h| h.handler == Some(u)) {
                self.open.remove(i);
                out.push(self.alert(
                    What::NotRecovered,
                    row,
                    u,
                    None,
                    format!("{} not recovered: {} failed", at(row), tree.told(u)),
                ));
            }
        }
        if let Some(i) = self.open.iter().position(|h| h.handler == Some(u)) {
            let h = self.open[i].clone();
            match (row.prev, row.status) {
                (_, Status::Success) => {
                    self.open.remove(i);
                    let text = format!("{} recovered: {} succeeded", at(row), tree.told(u));
                    let mut a = self.alert(What::Recovered, row, u, Some(h.cause), text);
                    a.handler = Some(u);
                    out.push(a);
                }
                (Status::Running, Status::Idle) => self.open[i].halted = Some(row),
                _ => {}
            }
        }
        if u == Tree::ROOT {
            self.root(row, out);
        }
    }

    /// Node `u` started: what failed below it and its tries are of its
    /// earlier calls; a Retry's child or a RecoveryNode's recovery
    /// starting is one more try of its parent.
    fn started(&mut self, u: Uid) {
        self.below[u as usize] = None;
        self.tries[u as usize] = 0;
        if let Some(p) = self.tree.parent(u) {
            let pn = self.tree.node(p);
            let counts = match pn.builtin {
                Some(Builtin::RetryUntilSuccessful) => true,
                Some(Builtin::RecoveryNode) => pn.children.get(1) == Some(&u),
                _ => false,
            };
            if counts {
                self.tries[p as usize] += 1;
            }
        }
        if u == Tree::ROOT {
            self.ended = None;
        }
    }

    /// The root's transitions: its outcome, and when it is reset, the run's
    /// end (the handlings still open are over unrecovered).
    fn root(&mut self, row: Row, out: &mut Vec<Alert>) {
        let u = row.uid;
        match (row.prev, row.status) {
            (_, s @ (Status::Success | Status::Failure)) => self.ended = Some(s),
            (Status::Success | Status::Failure, Status::Idle) => {
                let s = self.ended.take().unwrap_or(row.prev);
                self.runs += 1;
                for h in std::mem::take(&mut self.open) {
                    if h.handler.is_some() {
                        out.push(self.alert(
                            What::NotRecovered,
                            row,
                            h.handler.unwrap_or(u),
                            Some(h.cause),
                            format!("{} not recovered: the run ended", at(row)),
                        ));
                    }
                }
                let mut a = self.alert(
                    What::RunEnded,
                    row,
                    u,
                    None,
                    format!(
                        "run {} ended at tick {}: {}",
                        self.runs,
                        row.tick,
                        s.as_str()
                    ),
                );
                a.outcome = Some(s);
                out.push(a);
            }
            _ => {}
        }
    }

    /// A fault at `row` whose root cause is `cause`.
    fn fault(&mut self, row: Row, cause: Uid, out: &mut Vec<Alert>) {
        let tree = std::sync::Arc::clone(&self.tree);
        let tree = &*tree;
        let u = row.uid;
        if u == Tree::ROOT {
            return self.task_failed(row, cause, out);
        }
        // The handler itself failed: its handling is over.
        let mut after = None;
        if let Some(i) = self.open.iter().position(|h| h.handler == Some(u)) {
            let h = self.open.remove(i);
            let mut a = self.alert(
                What::NotRecovered,
                row,
                u,
                Some(h.cause),
                format!("{} not recovered: {} failed", at(row), tree.told(u)),
            );
            a.handler = Some(u);
            out.push(a);
            after = Some(h.cause);
        } else if self.open.iter().any(|h| h.path.contains(&u)) {
            // A node between a fault and its handler, failing with it.
            return;
        }
        let (path, handler, handling) = self.handled(u);
        let mut text = format!("{} {} failed", at(row), self.name(u));
        if let Some(c) = after.filter(|&c| c != u) {
            text.push_str(&format!(" (the root cause: {} failed)", self.name(c)));
        }
        for part in &self.fails_with(u, &path) {
            text.push_str("; ");
            text.push_str(part);
        }
        text.push_str("; ");
        text.push_str(&handling);
        // A handling this failure goes past is over: this line says who
        // handles it now.
        self.open.retain(|h| {
            h.handler.map_or(handler.is_some(), |x| {
                !path.contains(&x) && Some(x) != handler
            })
        });
        self.open.push(Handling {
            handler,
            cause,
            path,
            halted: None,
        });
        let mut a = self.alert(What::Fault, row, u, Some(cause), text);
        a.handler = handler;
        out.push(a);
    }

    /// The root failed: the task's failure, and every handling still open
    /// is over without recovering.
    fn task_failed(&mut self, row: Row, cause: Uid, out: &mut Vec<Alert>) {
        let u = row.uid;
        let open = std::mem::take(&mut self.open);
        if open.is_empty() {
            let text = if cause == u {
                format!("{} the task failed", at(row))
            } else {
                format!(
                    "{} the task failed; the root cause: {} failed",
                    at(row),
                    self.tree.spoken(cause)
                )
            };
            out.push(self.alert(What::Fault, row, u, Some(cause), text));
        }
        for h in open {
            let mut a = self.alert(
                What::NotRecovered,
                row,
                h.handler.unwrap_or(u),
                Some(h.cause),
                format!("{} not recovered: the task failed", at(row)),
            );
            a.handler = h.handler;
            out.push(a);
        }
    }

    /// What fails with `u` on its `path` up to its handler, as the user
    /// knows it: the nodes named, and a Retry or RecoveryNode that has no
    /// tries left; each once.
    fn fails_with(&self, u: Uid, path: &[Uid]) -> Vec<String> {
        let tree = &*self.tree;
        let mut said: Vec<String> = Vec::new();
        let mut child = u;
        for &p in path {
            let n = tree.node(p);
            let first = n.children.first() == Some(&child);
            child = p;
            let tries = self.tries[p as usize];
            let part = match n.builtin {
                Some(Builtin::RetryUntilSuccessful) => {
                    Some(format!("{} gave up after {tries} attempts", tree.told(p),))
                }
                Some(Builtin::RecoveryNode) if first => Some(format!(
                    "{} gave up after {tries} {}",
                    tree.told(p),
                    if tries == 1 { "retry" } else { "retries" }
                )),
                _ if p != Tree::ROOT
                    && !n.name.is_empty()
                    && n.name != n.id
                    && tree.description(p) != tree.description(u) =>
                {
                    Some(format!("{} failed", tree.spoken(p)))
                }
                _ => None,
            };
            if let Some(part) = part.filter(|x| !said.contains(x)) {
                said.push(part);
            }
        }
        said
    }

    /// A node as a line names it: its name, with its kind and uid where
    /// other nodes share the name.
    fn name(&self, u: Uid) -> String {
        let tree = std::sync::Arc::clone(&self.tree);
        let tree = &*tree;
        let d = tree.description(u);
        let n = tree.node(u);
        let shared = tree
            .nodes
            .iter()
            .any(|m| m.uid != u && tree.description(m.uid) == d);
        if shared || !n.kind.is_leaf() {
            tree.told(u)
        } else {
            tree.spoken(u)
        }
    }

    /// The nodes a failure of `u` makes fail, the node that handles it,
    /// and what that one does, as the tree's nodes work.
    fn handled(&self, u: Uid) -> (Vec<Uid>, Option<Uid>, String) {
        let tree = std::sync::Arc::clone(&self.tree);
        let tree = &*tree;
        let mut path = Vec::new();
        let mut child = u;
        while let Some(p) = tree.parent(child) {
            if let Some(says) = self.handles(p, child) {
                return (path, Some(p), says);
            }
            path.push(p);
            child = p;
        }
        (
            path,
            None,
            "nothing above handles it, so the task fails".into(),
        )
    }

    /// What `p` does when its child `child` fails, if it handles it.
    fn handles(&self, p: Uid, child: Uid) -> Option<String> {
        let tree = std::sync::Arc::clone(&self.tree);
        let tree = &*tree;
        let n = tree.node(p);
        let who = tree.told(p);
        let index = n.children.iter().position(|&c| c == child)?;
        let tries = self.tries[p as usize];
        let by_design = |c: Uid| {
            matches!(
                tree.node(c).builtin,
                Some(Builtin::ForceFailure | Builtin::AlwaysFailure)
            )
        };
        match n.builtin? {
            Builtin::Fallback
            | Builtin::ReactiveFallback
            | Builtin::AsyncFallback
            | Builtin::RoundRobin => {
                let next = n.children[index + 1..]
                    .iter()
                    .copied()
                    .find(|&c| !by_design(c))?;
                Some(format!("{who} tries {} next", tree.spoken(next)))
            }
            Builtin::RecoveryNode if index == 0 => {
                let most = count(tree, p, "number_of_retries").unwrap_or(1);
                if (tries as i64) >= most {
                    return None;
                }
                let branch = n
                    .children
                    .get(1)
                    .map_or_else(String::new, |&b| tree.spoken(b));
                Some(format!(
                    "{who} runs its recovery {branch}, retry {} of {most}",
                    tries + 1
                ))
            }
            Builtin::RetryUntilSuccessful => {
                let most = count(tree, p, "num_attempts");
                match most {
                    Some(m) if m >= 0 && tries as i64 >= m => None,
                    Some(m) if m >= 0 => {
                        Some(format!("{who} tries again, attempt {} of {m}", tries + 1))
                    }
                    _ => Some(format!("{who} tries again, attempt {}", tries + 1)),
                }
            }
            Builtin::Inverter | Builtin::ForceSuccess => {
                Some(format!("{who} turns the failure into success"))
            }
            Builtin::IfThenElse | Builtin::WhileDoElse if index == 0 => {
                Some(format!("{who} takes its else branch"))
            }
            Builtin::TryCatch if index + 1 < n.children.len() => Some(format!(
                "{who} runs its catch branch {}",
                tree.spoken(*n.children.last()?)
            )),
            Builtin::Parallel | Builtin::ParallelAll => {
                Some(format!("what follows is up to {who}, by its thresholds"))
            }
            _ => None,
        }
    }

    fn alert(&self, what: What, row: Row, node: Uid, cause: Option<Uid>, text: String) -> Alert {
        Alert {
            what,
            tick: row.tick,
            step: row.step,
            time_us: row.time_us,
            node,
            root_cause: cause,
            handler: None,
            outcome: None,
            text,
        }
    }
}

/// The lines a recorded run would have given as it happened; `run`, its
/// number among the runs of its log, when the log holds several (a
/// watch numbers each run's end as it comes).
pub fn of_run(s: &crate::session::Session) -> Vec<Alert> {
    let mut a = Alerts::new(s.tree.clone());
    a.runs = s.run.map_or(0, |(k, _)| k as u32 - 1);
    read_with(a, &s.index, &s.times_us)
}

/// A run's faults in numbers: said, still being handled, recovered, not.
/// Each fault is counted once, by how the handling it started ended:
/// a Retry's attempt that fails again hands its fault on to the next
/// attempt, and a handler that gives up hands it on to the handler above,
/// so a recovery (or a failure) there ends every fault handed on to it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Tally {
    pub faults: usize,
    pub open: usize,
    pub recovered: usize,
    pub not_recovered: usize,
    /// The handler of each fault not ended yet (`None`: nothing handles
    /// it, the run's end will).
    pending: Vec<Option<Uid>>,
}

impl Tally {
    pub fn of_run(tree: &Tree, idx: &crate::session::Index) -> Tally {
        let mut t = Tally::default();
        for a in &read_run(tree, idx) {
            t.add(tree, a);
        }
        t
    }

    /// Counts a line said.
    pub fn add(&mut self, tree: &Tree, a: &Alert) {
        let ended = |by: Option<Uid>, h: &Option<Uid>| match (by, h) {
            (None, _) => true,
            (Some(by), Some(h)) => by == *h || tree.is_ancestor(by, *h),
            (Some(_), None) => false,
        };
        let (by, recovered) = match a.what {
            What::Fault => {
                self.faults += 1;
                self.pending.push(a.handler);
                self.open = self.pending.len();
                return;
            }
            What::Recovered => (a.handler, true),
            What::NotRecovered => (a.handler, false),
            What::RunEnded => (None, a.outcome == Some(Status::Success)),
        };
        let before = self.pending.len();
        self.pending.retain(|h| !ended(by, h));
        let n = before - self.pending.len();
        if recovered {
            self.recovered += n;
        } else {
            self.not_recovered += n;
        }
        self.open = self.pending.len();
    }
}

fn read_run(tree: &Tree, idx: &crate::session::Index) -> Vec<Alert> {
    read_with(Alerts::new(tree.clone()), idx, &[])
}

fn read_with(mut a: Alerts, idx: &crate::session::Index, times_us: &[i64]) -> Vec<Alert> {
    let mut out: Vec<Alert> = rows(idx, times_us).flat_map(|r| a.push(r)).collect();
    out.extend(a.finish());
    out
}

fn at(row: Row) -> String {
    format!("{}:{}", row.tick, row.step)
}

/// A port's number as the XML writes it, or its default; `None` when a
/// blackboard entry gives it.
fn count(tree: &Tree, u: Uid, port: &str) -> Option<i64> {
    let n = tree.node(u);
    match n.ports.iter().find(|p| p.name == port) {
        Some(p) => p.value.to_xml().trim().parse().ok(),
        None if n.kind == Kind::Decorator || n.kind == Kind::Control => match port {
            "number_of_retries" => Some(1),
            _ => None,
        },
        None => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::open;
    use crate::xml::LoadOptions;

    /// The lines said of a recorded run read as a watch reads it, and the
    /// faults decided, against those `fault::is_fault` finds in the whole run.
    fn said(file: &str) -> Vec<String> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let input = open(&root.join(file), &LoadOptions::default()).unwrap();
        let s = input.session().unwrap();
        let mut a = Alerts::new(input.tree().clone());
        let mut out: Vec<Alert> = rows(&s.index, &[]).flat_map(|r| a.push(r)).collect();
        out.extend(a.finish());
        let whole: Vec<(u32, u32)> = (1..=s.index.transitions.len() as u32)
            .filter(|&p| crate::explain::fault::is_fault(input.tree(), &s.index, p))
            .map(|p| {
                let m = s.index.moment(p);
                (m.tick, m.step.unwrap_or(0))
            })
            .collect();
        assert_eq!(a.decided, whole, "{file}");
        out.into_iter().map(|a| a.text).collect()
    }

    #[test]
    fn the_kitting_fault_is_said_with_its_handler_and_its_recovery() {
        assert_eq!(
            said("sessions/kitting-lookat-fails-once.jsonl"),
            [
                "10:1 look at chuck failed; insert large gear failed; RetryUntilSuccessful (#7) tries again, attempt 2 of 3",
                "26:20 recovered: RetryUntilSuccessful (#7) succeeded",
                "run 1 ended at tick 54: SUCCESS",
            ]
        );
    }

    #[test]
    fn nav2s_followpath_fails_twice_and_the_navigator_recovers() {
        assert_eq!(
            said("tests/fixtures/questions/nav2-followpath-fails-twice.jsonl"),
            [
                "4:1 the FollowPath action (#10) failed; the FollowPath recovery node (#9) runs its recovery FollowPathRecoveryFallback, retry 1 of 1",
                "6:1 the FollowPath action (#10) failed; the FollowPath recovery node (#9) gave up after 1 retry; NavigateWithReplanning failed; NavigateRecovery (#1) runs its recovery RecoveryFallback, retry 1 of 6",
                "10:10 recovered: NavigateRecovery (#1) succeeded",
                "run 1 ended at tick 10: SUCCESS",
            ]
        );
    }

    #[test]
    fn a_retry_that_runs_out_hands_the_fault_up() {
        assert_eq!(
            said("tests/fixtures/logs/kitting_detect_chuck_always_fails.btlog"),
            [
                "6:1 the detect chuck action (#12) failed; RetryUntilSuccessful (#7) tries again, attempt 2 of 3",
                "9:1 the detect chuck action (#12) failed; RetryUntilSuccessful (#7) tries again, attempt 3 of 3",
                "12:1 the detect chuck action (#12) failed; RetryUntilSuccessful (#7) gave up after 3 attempts; go insert large gear failed; the go insert large gear fallback (#3) tries ask next",
                "13:4 recovered: the go insert large gear fallback (#3) succeeded",
                "run 1 ended at tick 41: SUCCESS",
            ]
        );
    }

    #[test]
    fn a_check_that_fails_the_task_is_a_fault_and_a_branch_is_not() {
        assert_eq!(
            said("tests/fixtures/logs/patrol_battery_drops.btlog"),
            [
                "7:5 battery ok failed; guarded patrol step failed; patrol twice failed; nothing above handles it, so the task fails",
                "7:14 not recovered: the task failed",
                "run 1 ended at tick 7: FAILURE",
            ]
        );
        // Conditions that answer no, under a Fallback that goes on, are
        // branches: no line.
        assert_eq!(
            said("tests/fixtures/logs/taxi_nominal.btlog"),
            ["run 1 ended at tick 15: SUCCESS"]
        );
        said("sessions/case-study.jsonl");
        said("tests/fixtures/questions/patrol.jsonl");
    }

    /// Every recorded run the project holds: the faults said as they come
    /// are the faults of the whole run.
    #[test]
    fn the_faults_read_as_they_come_are_the_runs_faults() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut n = 0;
        for dir in ["sessions", "tests/fixtures/logs"] {
            for e in std::fs::read_dir(root.join(dir)).unwrap() {
                let p = e.unwrap().path();
                let ext = p.extension().and_then(|x| x.to_str()).unwrap_or("");
                if !["jsonl", "btlog"].contains(&ext) {
                    continue;
                }
                let rel = p.strip_prefix(root).unwrap().to_str().unwrap().to_string();
                let Ok(crate::input::Input::Session(s)) = open(&p, &LoadOptions::default()) else {
                    continue;
                };
                said(&rel);
                // Each fault is counted once, by how its handling ended.
                let t = Tally::of_run(&s.tree, &s.index);
                assert_eq!(
                    t.faults,
                    t.open + t.recovered + t.not_recovered,
                    "{rel}: {t:?}"
                );
                n += 1;
            }
        }
        assert!(n >= 10, "{n} runs");
    }

    /// The numbers the live explorer's timeline shows.
    #[test]
    fn a_runs_faults_are_tallied() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let tally = |f: &str| {
            let input = open(&root.join(f), &LoadOptions::default()).unwrap();
            let s = input.session().unwrap();
            Tally::of_run(&s.tree, &s.index)
        };
        // (faults, open, recovered, not). Attempts 2 and 3 of the Retry
        // fail again, it gives up, and the fallback above it recovers: three
        // faults, each recovered there; then asking for help fails too:
        // four, none recovered.
        for (f, want) in [
            ("sessions/kitting-lookat-fails-once.jsonl", (1, 0, 1, 0)),
            (
                "tests/fixtures/logs/patrol_battery_drops.btlog",
                (1, 0, 0, 1),
            ),
            (
                "sessions/kitting-detect-chuck-always-fails.jsonl",
                (3, 0, 3, 0),
            ),
            ("sessions/kitting-help-fails.jsonl", (4, 0, 0, 4)),
        ] {
            let t = tally(f);
            assert_eq!(
                (t.faults, t.open, t.recovered, t.not_recovered),
                want,
                "{f}"
            );
        }
        // Cut while the Retry handles the failure: one open.
        let input = open(
            &root.join("sessions/kitting-lookat-fails-once.jsonl"),
            &LoadOptions::default(),
        )
        .unwrap();
        let s = input.session().unwrap();
        let mut a = Alerts::new(s.tree.clone());
        let mut t = Tally::default();
        for r in rows(&s.index, &[]).take_while(|r| r.tick <= 12) {
            for alert in a.push(r) {
                t.add(&s.tree, &alert);
            }
        }
        assert_eq!((t.faults, t.open), (1, 1));
    }
}
