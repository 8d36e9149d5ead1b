//! The words Nav2 engineers use for the nodes of a navigator, beside the
//! nodes' own names (`nav2.rs` holds their classes): "the controller" is
//! the FollowPath action, "the planner" the ComputePathTo… actions, "the
//! local costmap" the clearing node whose service is the local costmap.
//! A question reader finds a node by these as by its name.

/// What a field word points at in a tree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Nodes of these IDs (registration names).
    Ids(&'static [&'static str]),
    /// Nodes of these IDs whose `service_name` (or any port) value holds
    /// this text: a costmap's clearing node.
    IdsWithPort(&'static [&'static str], &'static str),
    /// What nodes of these IDs do, said as an activity ("replan", "follow
    /// the path"): the nodes of these IDs and the nodes named as they are
    /// (a RecoveryNode named FollowPath wraps the following as a whole),
    /// where "the planner", a server, is the action alone.
    Doing(&'static [&'static str]),
    /// The nodes named so (a navigator's `RecoveryFallback`), else the
    /// second child of the root when it is a RecoveryNode.
    RecoveryBranch,
    /// The tree's root: the navigation as a whole.
    Root,
}

const CLEARING: &[&str] = &[
    "ClearEntireCostmap",
    "ClearCostmapExceptRegion",
    "ClearCostmapAroundRobot",
    "ClearCostmapAroundPose",
];
const PLANNERS: &[&str] = &[
    "ComputePathToPose",
    "ComputePathThroughPoses",
    "ComputeRoute",
    "ComputeAndTrackRoute",
];

/// (phrase, what it names). Phrases are lower case; a reader compares
/// them by word stems, so "planning" finds "plan".
pub const WORDS: &[(&str, Target)] = &[
    ("controller", Target::Ids(&["FollowPath"])),
    ("the controller server", Target::Ids(&["FollowPath"])),
    ("local planner", Target::Ids(&["FollowPath"])),
    ("path following", Target::Doing(&["FollowPath"])),
    ("follow the path", Target::Doing(&["FollowPath"])),
    ("following the path", Target::Doing(&["FollowPath"])),
    ("drive along the path", Target::Doing(&["FollowPath"])),
    ("planner", Target::Ids(PLANNERS)),
    ("global planner", Target::Ids(PLANNERS)),
    ("planner server", Target::Ids(PLANNERS)),
    ("planning", Target::Doing(PLANNERS)),
    ("replanning", Target::Doing(PLANNERS)),
    ("replan", Target::Doing(PLANNERS)),
    ("path planning", Target::Doing(PLANNERS)),
    ("plan a path", Target::Doing(PLANNERS)),
    ("compute a path", Target::Doing(PLANNERS)),
    ("compute the path", Target::Doing(PLANNERS)),
    ("recompute the path", Target::Doing(PLANNERS)),
    ("recompute a path", Target::Doing(PLANNERS)),
    ("get a path", Target::Doing(PLANNERS)),
    ("the path", Target::Ids(PLANNERS)),
    (
        "local costmap",
        Target::IdsWithPort(CLEARING, "local_costmap"),
    ),
    (
        "global costmap",
        Target::IdsWithPort(CLEARING, "global_costmap"),
    ),
    (
        "clear the local costmap",
        Target::IdsWithPort(CLEARING, "local_costmap"),
    ),
    (
        "clear the global costmap",
        Target::IdsWithPort(CLEARING, "global_costmap"),
    ),
    ("costmap clearing", Target::Ids(CLEARING)),
    ("clear the costmaps", Target::Ids(CLEARING)),
    ("recovery", Target::RecoveryBranch),
    ("recoveries", Target::RecoveryBranch),
    ("recovery behaviors", Target::RecoveryBranch),
    ("recovery behaviours", Target::RecoveryBranch),
    ("recovery actions", Target::RecoveryBranch),
    ("recovery branch", Target::RecoveryBranch),
    ("navigation", Target::Root),
    ("navigating", Target::Root),
    ("navigate", Target::Root),
    ("the bt", Target::Root),
    ("bt navigator", Target::Root),
    ("nav", Target::Root),
    ("nav2", Target::Root),
    ("rotate", Target::Ids(&["Spin"])),
    ("turn in place", Target::Ids(&["Spin"])),
    ("reverse", Target::Ids(&["BackUp"])),
    ("drive backwards", Target::Ids(&["BackUp"])),
    ("back off", Target::Ids(&["BackUp"])),
    ("dock", Target::Ids(&["DockRobot"])),
    ("docking", Target::Ids(&["DockRobot"])),
    ("undock", Target::Ids(&["UndockRobot"])),
    (
        "battery",
        Target::Ids(&["IsBatteryLow", "IsBatteryCharging"]),
    ),
    (
        "new goal",
        Target::Ids(&["GoalUpdated", "GlobalUpdatedGoal"]),
    ),
    (
        "goal update",
        Target::Ids(&["GoalUpdated", "GlobalUpdatedGoal"]),
    ),
    ("stuck check", Target::Ids(&["IsStuck"])),
    (
        "progress checker",
        Target::Ids(&["ProgressCheckerSelector"]),
    ),
];

/// Whether a tree holds any of Nav2's nodes, so that its words apply.
pub fn applies<'a>(mut ids: impl Iterator<Item = &'a str>) -> bool {
    ids.any(|id| super::nav2::lookup(id).is_some())
}
