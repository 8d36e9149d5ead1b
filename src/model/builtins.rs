//! The built-in nodes of BehaviorTree.CPP 3.8 and 4.10, with the facts the
//! loader, the writer and (later) the executor need: kind, how many children
//! they take, their canonical v4 spelling and their ports.

use super::{Direction, Kind};

/// Which built-in behaviour a node has. Custom nodes have none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Builtin {
    // controls
    Sequence,
    AsyncSequence,
    SequenceWithMemory,
    Fallback,
    AsyncFallback,
    ReactiveSequence,
    ReactiveFallback,
    Parallel,
    ParallelAll,
    IfThenElse,
    WhileDoElse,
    TryCatch,
    Switch(u8),
    ManualSelector,
    // Nav2's controls (nav2_behavior_tree/plugins/control), which its
    // bt_navigator registers for every navigator tree
    PipelineSequence,
    RecoveryNode,
    RoundRobin,
    PersistentSequence,
    NonblockingSequence,
    PauseResumeController,
    // decorators
    // Nav2's (nav2_behavior_tree/plugins/decorator)
    RateController,
    DistanceController,
    SpeedController,
    GoalUpdatedController,
    GoalUpdater,
    PathLongerOnApproach,
    SingleTrigger,
    Inverter,
    RetryUntilSuccessful,
    KeepRunningUntilFailure,
    Repeat,
    Timeout,
    Delay,
    RunOnce,
    ForceSuccess,
    ForceFailure,
    Precondition,
    LoopInt,
    LoopBool,
    LoopDouble,
    LoopString,
    SkipUnlessUpdated,
    WaitValueUpdate,
    BlackboardCheckInt,
    BlackboardCheckDouble,
    BlackboardCheckString,
    BlackboardCheckBool,
    // leaves
    AlwaysSuccess,
    AlwaysFailure,
    Script,
    ScriptCondition,
    SetBlackboard,
    UnsetBlackboard,
    Sleep,
    WasEntryUpdated,
    // the subtree node itself
    SubTree,
}

/// Which library versions register a spelling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Availability {
    Both,
    V3Only,
    V4Only,
    /// Not BehaviorTree.CPP's: Nav2's, registered by its bt_navigator
    /// (with BehaviorTree.CPP 3 up to Humble, 4 from Jazzy).
    Nav2,
}

/// One spelling of a built-in node.
#[derive(Debug, Clone, Copy)]
pub struct BuiltinSpec {
    pub spelling: &'static str,
    pub builtin: Builtin,
    pub kind: Kind,
    pub availability: Availability,
    /// Minimum and maximum number of children (`None` = unbounded).
    pub children: (usize, Option<usize>),
    /// Ports: name, direction, default value.
    pub ports: &'static [(&'static str, Direction, Option<&'static str>)],
}

use Availability::*;
use Direction::{In, InOut, Out};
use Kind::{Action, Condition, Control, Decorator};

macro_rules! spec {
    ($sp:expr, $b:expr, $k:expr, $av:expr, $min:expr, $max:expr, [$($p:expr),* $(,)?]) => {
        BuiltinSpec { spelling: $sp, builtin: $b, kind: $k, availability: $av, children: ($min, $max), ports: &[$($p),*] }
    };
    ($sp:expr, $b:expr, $k:expr, $av:expr, $min:expr, $max:expr, $ports:ident) => {
        BuiltinSpec { spelling: $sp, builtin: $b, kind: $k, availability: $av, children: ($min, $max), ports: $ports }
    };
}

const ONE: Option<usize> = Some(1);
const ANY: Option<usize> = None;

/// Every spelling we accept, including v3's and the misspelled retry.
pub const BUILTINS: &[BuiltinSpec] = &[
    spec!("Sequence", Builtin::Sequence, Control, Both, 1, ANY, []),
    spec!(
        "PipelineSequence",
        Builtin::PipelineSequence,
        Control,
        Nav2,
        1,
        ANY,
        []
    ),
    spec!(
        "RecoveryNode",
        Builtin::RecoveryNode,
        Control,
        Nav2,
        2,
        Some(2),
        [("number_of_retries", In, Some("1"))]
    ),
    spec!("RoundRobin", Builtin::RoundRobin, Control, Nav2, 1, ANY, []),
    spec!(
        "PersistentSequence",
        Builtin::PersistentSequence,
        Control,
        Nav2,
        1,
        ANY,
        [("current_child_idx", InOut, None)]
    ),
    spec!(
        "NonblockingSequence",
        Builtin::NonblockingSequence,
        Control,
        Nav2,
        1,
        ANY,
        []
    ),
    spec!(
        "PauseResumeController",
        Builtin::PauseResumeController,
        Control,
        Nav2,
        1,
        Some(4),
        [
            ("pause_service_name", In, None),
            ("resume_service_name", In, None)
        ]
    ),
    spec!(
        "DistanceController",
        Builtin::DistanceController,
        Decorator,
        Nav2,
        1,
        ONE,
        [
            ("distance", In, Some("1.0")),
            ("global_frame", In, None),
            ("robot_base_frame", In, None)
        ]
    ),
    spec!(
        "SpeedController",
        Builtin::SpeedController,
        Decorator,
        Nav2,
        1,
        ONE,
        [
            ("min_rate", In, Some("0.1")),
            ("max_rate", In, Some("1.0")),
            ("min_speed", In, Some("0.0")),
            ("max_speed", In, Some("0.5")),
            ("filter_duration", In, Some("0.3"))
        ]
    ),
    spec!(
        "GoalUpdatedController",
        Builtin::GoalUpdatedController,
        Decorator,
        Nav2,
        1,
        ONE,
        [("goal", In, None), ("goals", In, None)]
    ),
    spec!(
        "GoalUpdater",
        Builtin::GoalUpdater,
        Decorator,
        Nav2,
        1,
        ONE,
        [
            ("input_goal", In, None),
            ("output_goal", Out, None),
            ("input_goals", In, None),
            ("output_goals", Out, None)
        ]
    ),
    spec!(
        "PathLongerOnApproach",
        Builtin::PathLongerOnApproach,
        Decorator,
        Nav2,
        1,
        ONE,
        [
            ("path", In, None),
            ("prox_len", In, Some("3.0")),
            ("length_factor", In, Some("2.0"))
        ]
    ),
    spec!(
        "SingleTrigger",
        Builtin::SingleTrigger,
        Decorator,
        Nav2,
        1,
        ONE,
        [("is_global", In, Some("false"))]
    ),
    spec!(
        "RateController",
        Builtin::RateController,
        Decorator,
        Nav2,
        1,
        ONE,
        [("hz", In, Some("10.0"))]
    ),
    spec!(
        "AsyncSequence",
        Builtin::AsyncSequence,
        Control,
        V4Only,
        1,
        ANY,
        []
    ),
    spec!(
        "SequenceWithMemory",
        Builtin::SequenceWithMemory,
        Control,
        V4Only,
        1,
        ANY,
        []
    ),
    spec!(
        "SequenceStar",
        Builtin::SequenceWithMemory,
        Control,
        V3Only,
        1,
        ANY,
        []
    ),
    spec!("Fallback", Builtin::Fallback, Control, Both, 1, ANY, []),
    spec!(
        "AsyncFallback",
        Builtin::AsyncFallback,
        Control,
        V4Only,
        1,
        ANY,
        []
    ),
    spec!(
        "ReactiveSequence",
        Builtin::ReactiveSequence,
        Control,
        Both,
        1,
        ANY,
        []
    ),
    spec!(
        "ReactiveFallback",
        Builtin::ReactiveFallback,
        Control,
        Both,
        1,
        ANY,
        []
    ),
    spec!(
        "Parallel",
        Builtin::Parallel,
        Control,
        Both,
        1,
        ANY,
        [
            ("success_count", In, Some("-1")),
            ("failure_count", In, Some("1")),
            ("success_threshold", In, None),
            ("failure_threshold", In, Some("1")),
        ]
    ),
    spec!(
        "ParallelAll",
        Builtin::ParallelAll,
        Control,
        V4Only,
        1,
        ANY,
        [("max_failures", In, Some("1"))]
    ),
    spec!(
        "IfThenElse",
        Builtin::IfThenElse,
        Control,
        Both,
        2,
        Some(3),
        []
    ),
    spec!(
        "WhileDoElse",
        Builtin::WhileDoElse,
        Control,
        Both,
        2,
        Some(3),
        []
    ),
    spec!(
        "TryCatch",
        Builtin::TryCatch,
        Control,
        V4Only,
        2,
        ANY,
        [("catch_on_halt", In, Some("false"))]
    ),
    spec!(
        "Switch2",
        Builtin::Switch(2),
        Control,
        Both,
        3,
        Some(3),
        SWITCH_PORTS
    ),
    spec!(
        "Switch3",
        Builtin::Switch(3),
        Control,
        Both,
        4,
        Some(4),
        SWITCH_PORTS
    ),
    spec!(
        "Switch4",
        Builtin::Switch(4),
        Control,
        Both,
        5,
        Some(5),
        SWITCH_PORTS
    ),
    spec!(
        "Switch5",
        Builtin::Switch(5),
        Control,
        Both,
        6,
        Some(6),
        SWITCH_PORTS
    ),
    spec!(
        "Switch6",
        Builtin::Switch(6),
        Control,
        Both,
        7,
        Some(7),
        SWITCH_PORTS
    ),
    spec!(
        "ManualSelector",
        Builtin::ManualSelector,
        Control,
        Both,
        1,
        ANY,
        [("repeat_last_selection", In, Some("false"))]
    ),
    spec!("Inverter", Builtin::Inverter, Decorator, Both, 1, ONE, []),
    spec!(
        "RetryUntilSuccessful",
        Builtin::RetryUntilSuccessful,
        Decorator,
        Both,
        1,
        ONE,
        [("num_attempts", In, None)]
    ),
    spec!(
        "RetryUntilSuccesful",
        Builtin::RetryUntilSuccessful,
        Decorator,
        V3Only,
        1,
        ONE,
        [("num_attempts", In, None)]
    ),
    spec!(
        "KeepRunningUntilFailure",
        Builtin::KeepRunningUntilFailure,
        Decorator,
        Both,
        1,
        ONE,
        []
    ),
    spec!(
        "Repeat",
        Builtin::Repeat,
        Decorator,
        Both,
        1,
        ONE,
        [("num_cycles", In, None)]
    ),
    spec!(
        "Timeout",
        Builtin::Timeout,
        Decorator,
        Both,
        1,
        ONE,
        [("msec", In, None)]
    ),
    spec!(
        "Delay",
        Builtin::Delay,
        Decorator,
        Both,
        1,
        ONE,
        [("delay_msec", In, None)]
    ),
    spec!(
        "RunOnce",
        Builtin::RunOnce,
        Decorator,
        V4Only,
        1,
        ONE,
        [("then_skip", In, Some("true"))]
    ),
    spec!(
        "ForceSuccess",
        Builtin::ForceSuccess,
        Decorator,
        Both,
        1,
        ONE,
        []
    ),
    spec!(
        "ForceFailure",
        Builtin::ForceFailure,
        Decorator,
        Both,
        1,
        ONE,
        []
    ),
    spec!(
        "Precondition",
        Builtin::Precondition,
        Decorator,
        V4Only,
        1,
        ONE,
        [("if", In, None), ("else", In, Some("FAILURE"))]
    ),
    spec!(
        "LoopInt",
        Builtin::LoopInt,
        Decorator,
        V4Only,
        1,
        ONE,
        LOOP_PORTS
    ),
    spec!(
        "LoopBool",
        Builtin::LoopBool,
        Decorator,
        V4Only,
        1,
        ONE,
        LOOP_PORTS
    ),
    spec!(
        "LoopDouble",
        Builtin::LoopDouble,
        Decorator,
        V4Only,
        1,
        ONE,
        LOOP_PORTS
    ),
    spec!(
        "LoopString",
        Builtin::LoopString,
        Decorator,
        V4Only,
        1,
        ONE,
        LOOP_PORTS
    ),
    spec!(
        "SkipUnlessUpdated",
        Builtin::SkipUnlessUpdated,
        Decorator,
        V4Only,
        1,
        ONE,
        [("entry", In, None)]
    ),
    spec!(
        "WaitValueUpdate",
        Builtin::WaitValueUpdate,
        Decorator,
        V4Only,
        1,
        ONE,
        [("entry", In, None)]
    ),
    spec!(
        "BlackboardCheckInt",
        Builtin::BlackboardCheckInt,
        Decorator,
        V3Only,
        1,
        ONE,
        BB_CHECK_PORTS
    ),
    spec!(
        "BlackboardCheckDouble",
        Builtin::BlackboardCheckDouble,
        Decorator,
        V3Only,
        1,
        ONE,
        BB_CHECK_PORTS
    ),
    spec!(
        "BlackboardCheckString",
        Builtin::BlackboardCheckString,
        Decorator,
        V3Only,
        1,
        ONE,
        BB_CHECK_PORTS
    ),
    spec!(
        "BlackboardCheckBool",
        Builtin::BlackboardCheckBool,
        Decorator,
        V3Only,
        1,
        ONE,
        BB_CHECK_PORTS
    ),
    spec!(
        "AlwaysSuccess",
        Builtin::AlwaysSuccess,
        Action,
        Both,
        0,
        Some(0),
        []
    ),
    spec!(
        "AlwaysFailure",
        Builtin::AlwaysFailure,
        Action,
        Both,
        0,
        Some(0),
        []
    ),
    spec!(
        "Script",
        Builtin::Script,
        Action,
        V4Only,
        0,
        Some(0),
        [("code", In, None)]
    ),
    spec!(
        "ScriptCondition",
        Builtin::ScriptCondition,
        Condition,
        V4Only,
        0,
        Some(0),
        [("code", In, None)]
    ),
    spec!(
        "SetBlackboard",
        Builtin::SetBlackboard,
        Action,
        Both,
        0,
        Some(0),
        [("value", In, None), ("output_key", InOut, None)]
    ),
    spec!(
        "UnsetBlackboard",
        Builtin::UnsetBlackboard,
        Action,
        V4Only,
        0,
        Some(0),
        [("key", In, None)]
    ),
    spec!(
        "Sleep",
        Builtin::Sleep,
        Action,
        V4Only,
        0,
        Some(0),
        [("msec", In, None)]
    ),
    spec!(
        "WasEntryUpdated",
        Builtin::WasEntryUpdated,
        Condition,
        V4Only,
        0,
        Some(0),
        [("entry", In, None)]
    ),
];

const SWITCH_PORTS: &[(&str, Direction, Option<&str>)] = &[
    ("variable", In, None),
    ("case_1", In, None),
    ("case_2", In, None),
    ("case_3", In, None),
    ("case_4", In, None),
    ("case_5", In, None),
    ("case_6", In, None),
];
const LOOP_PORTS: &[(&str, Direction, Option<&str>)] = &[
    ("queue", InOut, None),
    ("value", Out, None),
    ("if_empty", In, Some("SUCCESS")),
];
const BB_CHECK_PORTS: &[(&str, Direction, Option<&str>)] = &[
    ("value_A", In, None),
    ("value_B", In, None),
    ("return_on_mismatch", In, None),
];

/// Looks a spelling up.
pub fn lookup(spelling: &str) -> Option<&'static BuiltinSpec> {
    BUILTINS.iter().find(|s| s.spelling == spelling)
}

/// Every spelling btx knows, of either version.
pub fn spellings() -> impl Iterator<Item = &'static str> {
    BUILTINS.iter().map(|s| s.spelling)
}

impl Builtin {
    /// The spelling BehaviorTree.CPP 4 registers for this node, if it has one.
    pub fn v4_name(self) -> Option<&'static str> {
        BUILTINS
            .iter()
            .find(|s| s.builtin == self && s.availability != V3Only)
            .map(|s| s.spelling)
    }

    /// The spelling BehaviorTree.CPP 3 registers for this node, if it has one.
    pub fn v3_name(self) -> Option<&'static str> {
        BUILTINS
            .iter()
            .find(|s| s.builtin == self && s.availability != V4Only)
            .map(|s| s.spelling)
    }

    /// The canonical spec (the v4 spelling where there is one).
    pub fn spec(self) -> &'static BuiltinSpec {
        BUILTINS
            .iter()
            .find(|s| s.builtin == self && s.availability != V3Only)
            .or_else(|| BUILTINS.iter().find(|s| s.builtin == self))
            .expect("every builtin has a spec")
    }

    /// Registered by BehaviorTree.CPP itself (not by Nav2): a tree file
    /// needs no model for it.
    pub fn is_btcpp(self) -> bool {
        // SubTree has no spec: it is the library's.
        BUILTINS
            .iter()
            .find(|s| s.builtin == self)
            .is_none_or(|s| s.availability != Nav2)
    }

    /// A retry or repeat node, whose attempt counts matter to explanations.
    pub fn is_retry(self) -> bool {
        matches!(self, Builtin::RetryUntilSuccessful)
    }
}

/// Whether a spelling is one of the element names that are not nodes.
pub fn is_reserved_element(tag: &str) -> bool {
    matches!(
        tag,
        "root"
            | "BehaviorTree"
            | "TreeNodesModel"
            | "include"
            | "Action"
            | "Condition"
            | "Control"
            | "Decorator"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v3_spellings_map_to_v4_builtins() {
        assert_eq!(
            lookup("SequenceStar").unwrap().builtin.v4_name(),
            Some("SequenceWithMemory")
        );
        assert_eq!(
            lookup("RetryUntilSuccesful").unwrap().builtin.v4_name(),
            Some("RetryUntilSuccessful")
        );
        assert_eq!(
            lookup("BlackboardCheckInt").unwrap().builtin.v4_name(),
            None
        );
        assert_eq!(Builtin::SequenceWithMemory.v3_name(), Some("SequenceStar"));
    }

    #[test]
    fn nav2s_nodes_are_not_the_librarys() {
        assert!(!Builtin::RecoveryNode.is_btcpp());
        assert!(Builtin::Sequence.is_btcpp());
        assert!(Builtin::SubTree.is_btcpp());
    }

    #[test]
    fn child_counts_follow_the_library() {
        assert_eq!(lookup("Switch3").unwrap().children, (4, Some(4)));
        assert_eq!(lookup("TryCatch").unwrap().children, (2, None));
        assert_eq!(lookup("Inverter").unwrap().children, (1, Some(1)));
        assert!(lookup("MoveTo").is_none());
    }
}
