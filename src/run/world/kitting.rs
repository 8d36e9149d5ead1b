//! The kitting task (Han et al. §4, §7.1.3) as a built-in world: the seed
//! picks a scenario, each a plan of leaf outcomes, so every run is the same
//! for the same seed.

use crate::run::plan::Plan;
use std::path::Path;

/// The scenarios, by seed.
pub const SCENARIOS: [(&str, &str); 6] = [
    (
        "nominal",
        include_str!("../../../trees/plans/kitting-nominal.plan"),
    ),
    (
        "lookat-fails-once",
        include_str!("../../../trees/plans/kitting-lookat-fails-once.plan"),
    ),
    (
        "navigation-fails-once",
        include_str!("../../../trees/plans/kitting-navigation-fails-once.plan"),
    ),
    (
        "lift-torso-fails-once",
        include_str!("../../../trees/plans/kitting-lift-torso-fails-once.plan"),
    ),
    (
        "detect-chuck-always-fails",
        include_str!("../../../trees/plans/kitting-detect-chuck-always-fails.plan"),
    ),
    (
        "grasp-check-fails-first",
        include_str!("../../../trees/plans/kitting-grasp-check-fails-first.plan"),
    ),
];

/// The scenario of a seed (0 to 5).
pub fn scenario(seed: u64) -> Result<(&'static str, Plan), String> {
    let Some((name, text)) = SCENARIOS.get(seed as usize) else {
        let list: Vec<String> = SCENARIOS
            .iter()
            .enumerate()
            .map(|(i, (n, _))| format!("{i} {n}"))
            .collect();
        return Err(format!(
            "the kitting world has scenarios for seeds 0 to {}: {}",
            SCENARIOS.len() - 1,
            list.join(", ")
        ));
    };
    let path = format!("kitting world, scenario {name}");
    let plan = Plan::parse(Path::new(&path), text).map_err(|e| e.to_string())?;
    Ok((name, plan))
}
