//! Nav2's behaviour tree nodes (`nav2_behavior_tree/plugins`), each with
//! the base class its source gives it, which decides whether it finishes
//! in the tick it starts: `BT::ActionNodeBase` and `BT::SyncActionNode`
//! actions and every condition do (unless the source returns RUNNING);
//! `BtActionNode`, `BtServiceNode` and `BtCancelActionNode` send a ROS
//! request and wait for it over ticks. Read from the sources of Humble
//! (3c3db59, 2026-06-03), Jazzy (f4108e5, 2026-08-21) and main (a3a9704,
//! 2026-08-21). The README's table of Nav2's nodes is this one.

use super::Version;

/// A node's base class in Nav2's source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Base {
    /// `BT::ActionNodeBase`: its `tick()` says what it returns.
    ActionNodeBase,
    /// `BT::SyncActionNode`: SUCCESS or FAILURE in the tick.
    SyncActionNode,
    /// `nav2_behavior_tree::BtActionNode`: a ROS action, RUNNING until its result.
    BtActionNode,
    /// `nav2_behavior_tree::BtServiceNode`: a ROS service, RUNNING until its reply.
    BtServiceNode,
    /// `nav2_behavior_tree::BtCancelActionNode`: cancels a ROS action, RUNNING until done.
    BtCancelActionNode,
    /// `BT::ConditionNode` (the `WouldA…RecoveryHelp` ones through `AreErrorCodesPresent`).
    Condition,
    /// `BT::DecoratorNode`.
    Decorator,
    /// `BT::ControlNode`.
    Control,
}

impl Base {
    pub fn as_str(self) -> &'static str {
        match self {
            Base::ActionNodeBase => "BT::ActionNodeBase",
            Base::SyncActionNode => "BT::SyncActionNode",
            Base::BtActionNode => "BtActionNode",
            Base::BtServiceNode => "BtServiceNode",
            Base::BtCancelActionNode => "BtCancelActionNode",
            Base::Condition => "BT::ConditionNode",
            Base::Decorator => "BT::DecoratorNode",
            Base::Control => "BT::ControlNode",
        }
    }
}

/// The Nav2 release whose control and decorator nodes a run follows where
/// their sources differ (`RoundRobin`); `--nav2` picks it, main by default.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Release {
    Humble,
    Jazzy,
    #[default]
    Main,
}

impl Release {
    pub fn parse(s: &str) -> Option<Release> {
        match s.trim().to_ascii_lowercase().as_str() {
            "humble" => Some(Release::Humble),
            "jazzy" => Some(Release::Jazzy),
            "main" | "rolling" | "kilted" => Some(Release::Main),
            _ => None,
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            Release::Humble => "humble",
            Release::Jazzy => "jazzy",
            Release::Main => "main",
        }
    }
}

/// Releases, as bits.
pub const HUMBLE: u8 = 1;
pub const JAZZY: u8 = 2;
pub const MAIN: u8 = 4;
const RETURNS_RUNNING: bool = true;

/// One of Nav2's nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Nav2Node {
    pub id: &'static str,
    pub base: Base,
    /// Its source, under `nav2_behavior_tree/plugins/`.
    pub file: &'static str,
    /// The releases that have it.
    pub releases: u8,
    /// The releases in which its `tick()` calls `setStatus(RUNNING)` before
    /// it completes (observers and logs see IDLE → RUNNING → SUCCESS in one
    /// tick).
    pub sets_running: u8,
    /// Its `tick()` can return RUNNING though its base does not wait.
    pub returns_running: bool,
}

impl Nav2Node {
    /// Whether it completes in the tick that starts it: its base does not
    /// wait for ROS, and its source never returns RUNNING.
    pub fn finishes_in_its_tick(&self) -> bool {
        matches!(
            self.base,
            Base::ActionNodeBase | Base::SyncActionNode | Base::Condition
        ) && !self.returns_running
    }

    /// The releases that have it, as words.
    pub fn release_names(&self) -> String {
        [(HUMBLE, "Humble"), (JAZZY, "Jazzy"), (MAIN, "main")]
            .iter()
            .filter(|(bit, _)| self.releases & bit != 0)
            .map(|(_, n)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

const fn node(
    id: &'static str,
    base: Base,
    file: &'static str,
    releases: u8,
    sets_running: u8,
) -> Nav2Node {
    node_running(id, base, file, releases, sets_running, false)
}

const fn node_running(
    id: &'static str,
    base: Base,
    file: &'static str,
    releases: u8,
    sets_running: u8,
    returns_running: bool,
) -> Nav2Node {
    Nav2Node {
        id,
        base,
        file,
        releases,
        sets_running,
        returns_running,
    }
}

use Base::*;

/// Every node Nav2 registers, by ID.
pub const NODES: &[Nav2Node] = &[
    node(
        "AppendGoalPoseToGoals",
        ActionNodeBase,
        "action/append_goal_pose_to_goals_action.cpp",
        MAIN,
        MAIN,
    ),
    node(
        "AreErrorCodesPresent",
        Condition,
        "condition/are_error_codes_present_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "ArePosesNear",
        Condition,
        "condition/are_poses_near_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "AssistedTeleop",
        BtActionNode,
        "action/assisted_teleop_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "BackUp",
        BtActionNode,
        "action/back_up_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelAssistedTeleop",
        BtCancelActionNode,
        "action/assisted_teleop_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelBackUp",
        BtCancelActionNode,
        "action/back_up_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelComputeAndTrackRoute",
        BtCancelActionNode,
        "action/compute_and_track_route_cancel_node.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "CancelControl",
        BtCancelActionNode,
        "action/controller_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelDriveOnHeading",
        BtCancelActionNode,
        "action/drive_on_heading_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelFollowObject",
        BtCancelActionNode,
        "action/follow_object_cancel_node.cpp",
        MAIN,
        0,
    ),
    node(
        "CancelSpin",
        BtCancelActionNode,
        "action/spin_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CancelWait",
        BtCancelActionNode,
        "action/wait_cancel_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "CheckPoseOccupancy",
        BtServiceNode,
        "action/check_pose_occupancy_action.cpp",
        MAIN,
        0,
    ),
    node_running(
        "CheckStopStatus",
        ActionNodeBase,
        "action/check_stop_status_action.cpp",
        MAIN,
        0,
        RETURNS_RUNNING,
    ),
    node(
        "ClearCostmapAroundPose",
        BtServiceNode,
        "action/clear_costmap_service.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "ClearCostmapAroundRobot",
        BtServiceNode,
        "action/clear_costmap_service.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ClearCostmapExceptRegion",
        BtServiceNode,
        "action/clear_costmap_service.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ClearEntireCostmap",
        BtServiceNode,
        "action/clear_costmap_service.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ComputeAndTrackRoute",
        BtActionNode,
        "action/compute_and_track_route_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ComputePathThroughPoses",
        BtActionNode,
        "action/compute_path_through_poses_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ComputePathToPose",
        BtActionNode,
        "action/compute_path_to_pose_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ComputeRoute",
        BtActionNode,
        "action/compute_route_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ConcatenatePaths",
        ActionNodeBase,
        "action/concatenate_paths_action.cpp",
        JAZZY | MAIN,
        JAZZY | MAIN,
    ),
    node(
        "ControllerSelector",
        SyncActionNode,
        "action/controller_selector_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "DistanceController",
        Decorator,
        "decorator/distance_controller.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "DistanceTraveled",
        Condition,
        "condition/distance_traveled_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "DriveOnHeading",
        BtActionNode,
        "action/drive_on_heading_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ExtractRouteNodesAsGoals",
        ActionNodeBase,
        "action/extract_route_nodes_as_goals_action.cpp",
        MAIN,
        MAIN,
    ),
    node(
        "FollowObject",
        BtActionNode,
        "action/follow_object_action.cpp",
        MAIN,
        0,
    ),
    node(
        "FollowPath",
        BtActionNode,
        "action/follow_path_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GetCurrentPose",
        ActionNodeBase,
        "action/get_current_pose_action.cpp",
        JAZZY | MAIN,
        JAZZY | MAIN,
    ),
    node(
        "GetNextFewGoals",
        ActionNodeBase,
        "action/get_next_few_goals_action.cpp",
        MAIN,
        MAIN,
    ),
    node(
        "GetPoseFromPath",
        ActionNodeBase,
        "action/get_pose_from_path_action.cpp",
        HUMBLE | JAZZY | MAIN,
        HUMBLE | JAZZY | MAIN,
    ),
    node(
        "GlobalUpdatedGoal",
        Condition,
        "condition/globally_updated_goal_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GoalCheckerSelector",
        SyncActionNode,
        "action/goal_checker_selector_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GoalReached",
        Condition,
        "condition/goal_reached_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GoalUpdated",
        Condition,
        "condition/goal_updated_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GoalUpdatedController",
        Decorator,
        "decorator/goal_updated_controller.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "GoalUpdater",
        Decorator,
        "decorator/goal_updater_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "InitialPoseReceived",
        Condition,
        "condition/initial_pose_received_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "IsBatteryCharging",
        Condition,
        "condition/is_battery_charging_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "IsBatteryLow",
        Condition,
        "condition/is_battery_low_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "IsGoalNearby",
        Condition,
        "condition/is_goal_nearby_condition.cpp",
        MAIN,
        0,
    ),
    node(
        "IsPathValid",
        Condition,
        "condition/is_path_valid_condition.cpp",
        HUMBLE | JAZZY,
        0,
    ),
    node(
        "IsStuck",
        Condition,
        "condition/is_stuck_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "IsWithinPathTrackingBounds",
        Condition,
        "condition/is_within_path_tracking_bounds_condition.cpp",
        MAIN,
        0,
    ),
    node(
        "NavigateThroughPoses",
        BtActionNode,
        "action/navigate_through_poses_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "NavigateToPose",
        BtActionNode,
        "action/navigate_to_pose_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "NonblockingSequence",
        Control,
        "control/nonblocking_sequence.cpp",
        MAIN,
        0,
    ),
    node(
        "PathExpiringTimer",
        Condition,
        "condition/path_expiring_timer_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "PathHandlerSelector",
        SyncActionNode,
        "action/path_handler_selector_node.cpp",
        MAIN,
        0,
    ),
    node(
        "PathLongerOnApproach",
        Decorator,
        "decorator/path_longer_on_approach.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "PauseResumeController",
        Control,
        "control/pause_resume_controller.cpp",
        MAIN,
        0,
    ),
    node(
        "PersistentSequence",
        Control,
        "control/persistent_sequence.cpp",
        MAIN,
        0,
    ),
    node(
        "PipelineSequence",
        Control,
        "control/pipeline_sequence.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "PlannerSelector",
        SyncActionNode,
        "action/planner_selector_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ProgressCheckerSelector",
        SyncActionNode,
        "action/progress_checker_selector_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "RateController",
        Decorator,
        "decorator/rate_controller.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "RecoveryNode",
        Control,
        "control/recovery_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ReinitializeGlobalLocalization",
        BtServiceNode,
        "action/reinitialize_global_localization_service.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "RemoveInCollisionGoals",
        BtServiceNode,
        "action/remove_in_collision_goals_action.cpp",
        MAIN,
        0,
    ),
    node(
        "RemovePassedGoals",
        ActionNodeBase,
        "action/remove_passed_goals_action.cpp",
        HUMBLE | JAZZY | MAIN,
        HUMBLE,
    ),
    node(
        "RoundRobin",
        Control,
        "control/round_robin_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "SingleTrigger",
        Decorator,
        "decorator/single_trigger_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "SmoothPath",
        BtActionNode,
        "action/smooth_path_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "SmootherSelector",
        SyncActionNode,
        "action/smoother_selector_node.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "SpeedController",
        Decorator,
        "decorator/speed_controller.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "Spin",
        BtActionNode,
        "action/spin_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "TimeExpired",
        Condition,
        "condition/time_expired_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "ToggleCollisionMonitor",
        BtServiceNode,
        "action/toggle_collision_monitor_service.cpp",
        MAIN,
        0,
    ),
    node(
        "TransformAvailable",
        Condition,
        "condition/transform_available_condition.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "TruncatePath",
        ActionNodeBase,
        "action/truncate_path_action.cpp",
        HUMBLE | JAZZY | MAIN,
        HUMBLE | JAZZY | MAIN,
    ),
    node(
        "TruncatePathLocal",
        ActionNodeBase,
        "action/truncate_path_local_action.cpp",
        HUMBLE | JAZZY | MAIN,
        HUMBLE | JAZZY | MAIN,
    ),
    node(
        "ValidatePath",
        BtServiceNode,
        "action/validate_path_action.cpp",
        MAIN,
        0,
    ),
    node(
        "Wait",
        BtActionNode,
        "action/wait_action.cpp",
        HUMBLE | JAZZY | MAIN,
        0,
    ),
    node(
        "WouldAControllerRecoveryHelp",
        Condition,
        "condition/would_a_controller_recovery_help_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "WouldAPlannerRecoveryHelp",
        Condition,
        "condition/would_a_planner_recovery_help_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
    node(
        "WouldARouteRecoveryHelp",
        Condition,
        "condition/would_a_route_recovery_help_condition.cpp",
        MAIN,
        0,
    ),
    node(
        "WouldASmootherRecoveryHelp",
        Condition,
        "condition/would_a_smoother_recovery_help_condition.cpp",
        JAZZY | MAIN,
        0,
    ),
];

/// The node as a row of the README's table: ID, base class, whether it
/// finishes in its tick (and sets RUNNING first), releases, source.
pub fn readme_row(n: &Nav2Node) -> String {
    let when = if !n.finishes_in_its_tick() {
        match n.base {
            Base::Decorator | Base::Control => "as its children".to_string(),
            _ => "over ticks".to_string(),
        }
    } else if n.sets_running == 0 {
        "in its tick".to_string()
    } else if n.sets_running == n.releases {
        "in its tick, RUNNING first".to_string()
    } else {
        let first = Nav2Node {
            releases: n.sets_running,
            ..*n
        };
        format!("in its tick, RUNNING first in {}", first.release_names())
    };
    format!(
        "| `{}` | {} | {} | {} | `{}` |",
        n.id,
        n.base.as_str(),
        when,
        n.release_names(),
        n.file
    )
}

/// The README's short table: the nodes grouped by base class and by when
/// they finish, one row a group (each node's file is in `readme_row`).
pub fn readme_groups() -> Vec<String> {
    let mut groups: Vec<(String, String, Vec<&str>)> = Vec::new();
    for n in NODES {
        let row = readme_row(n);
        let cells: Vec<&str> = row.split(" | ").collect();
        let (base, when) = (cells[1].to_string(), cells[2].to_string());
        match groups.iter_mut().find(|g| g.0 == base && g.1 == when) {
            Some(g) => g.2.push(n.id),
            None => groups.push((base, when, vec![n.id])),
        }
    }
    groups.sort_by(|a, b| (&a.0, &a.1).cmp(&(&b.0, &b.1)));
    groups
        .into_iter()
        .map(|(base, when, ids)| {
            let ids: Vec<String> = ids.iter().map(|i| format!("`{i}`")).collect();
            format!("| {base} | {when} | {} |", ids.join(", "))
        })
        .collect()
}

/// Nav2's node of this ID.
pub fn lookup(id: &str) -> Option<&'static Nav2Node> {
    NODES.iter().find(|n| n.id == id)
}

/// Whether a Nav2 action completes in the tick it starts (no plan's
/// RUNNING applies to it), and if so whether it sets RUNNING first, in
/// the release a tree of `version` runs on (BehaviorTree.CPP 3: Humble).
pub fn at_once(id: &str, version: Version) -> Option<bool> {
    let n = lookup(id)?;
    let release = match version {
        Version::V3 => HUMBLE,
        Version::V4 => JAZZY | MAIN,
    };
    (n.finishes_in_its_tick() && n.base != Base::Condition).then_some(n.sets_running & release != 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_s_nodes_are_read_from_their_sources() {
        // TruncatePathLocal and PathHandlerSelector took RUNNING ticks from
        // a plan, though their sources finish in the tick (#30 item 6).
        assert_eq!(at_once("TruncatePathLocal", Version::V4), Some(true));
        assert_eq!(at_once("PathHandlerSelector", Version::V4), Some(false));
        assert_eq!(at_once("FollowPath", Version::V4), None);
        assert_eq!(at_once("ValidatePath", Version::V4), None);
        assert_eq!(at_once("CheckStopStatus", Version::V4), None);
        // Humble's RemovePassedGoals sets RUNNING first; Jazzy's does not.
        assert_eq!(at_once("RemovePassedGoals", Version::V3), Some(true));
        assert_eq!(at_once("RemovePassedGoals", Version::V4), Some(false));
        assert_eq!(at_once("GoalUpdated", Version::V4), None);
        assert!(lookup("GoalUpdated").unwrap().finishes_in_its_tick());
    }

    #[test]
    fn ids_are_unique_and_sorted() {
        assert!(NODES.windows(2).all(|w| w[0].id < w[1].id));
    }
}
