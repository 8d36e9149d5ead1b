//! The taxi domain of Han et al. §7.2 (after Dietterich's): a small grid
//! with walls and a toll, solved by value iteration; the behaviour tree is
//! generated from the optimal policy by grouping its state–action switches.
//!
//! ```text
//!   row 3 | .   .  | P   .      P: the passenger (column 3, row 3)
//!         |        |            T: the toll      (column 3, row 2)
//!   row 2 | .   .  | T   .      S: the start and the destination
//!         |        |               (column 1, row 1)
//!   row 1 | S   .    .   .      |: walls, between columns 2 and 3 in
//!           1   2    3   4         rows 2 and 3
//! ```
//! Through the toll the passenger is 4 moves away, around it 6; with a
//! toll that costs more than 2 moves the optimal taxi goes round by column 4,
//! there and back, as the authors' tree does.

use crate::model::{Tree, Uid};
use crate::run::blackboard::EntryId;
use crate::run::exec::{LeafCall, LeafOutcome, Leaves};
use crate::run::Status;
use serde_json::Value;
use std::collections::HashMap;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Action {
    MoveRight,
    MoveLeft,
    MoveUp,
    MoveDown,
    PickUp,
    DropOff,
}

impl Action {
    pub const ALL: [Action; 6] = [
        Action::MoveRight,
        Action::MoveLeft,
        Action::MoveUp,
        Action::MoveDown,
        Action::PickUp,
        Action::DropOff,
    ];

    /// The leaf name the generated tree uses.
    pub fn name(self) -> &'static str {
        match self {
            Action::MoveRight => "move right",
            Action::MoveLeft => "move left",
            Action::MoveUp => "move up",
            Action::MoveDown => "move down",
            Action::PickUp => "pick up passenger",
            Action::DropOff => "drop off passenger",
        }
    }

    pub fn id(self) -> &'static str {
        match self {
            Action::MoveRight => "move_right",
            Action::MoveLeft => "move_left",
            Action::MoveUp => "move_up",
            Action::MoveDown => "move_down",
            Action::PickUp => "pick_up",
            Action::DropOff => "drop_off",
        }
    }

    /// Reads a leaf: by its name or its ID, v3 spellings included.
    pub fn of_leaf(name: &str, id: &str) -> Option<Action> {
        let norm = |s: &str| s.replace('_', " ").to_lowercase();
        let (n, i) = (norm(name), norm(id));
        Action::ALL.into_iter().find(|a| {
            let (an, ai) = (norm(a.name()), norm(a.id()));
            n == an || n == ai || i == ai || i == an
        })
    }

    fn delta(self) -> (i32, i32) {
        match self {
            Action::MoveRight => (1, 0),
            Action::MoveLeft => (-1, 0),
            Action::MoveUp => (0, 1),
            Action::MoveDown => (0, -1),
            _ => (0, 0),
        }
    }
}

/// Where the passenger is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Passenger {
    Waiting,
    InTaxi,
    Delivered,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TaxiState {
    pub x: i32,
    pub y: i32,
    pub passenger: Passenger,
}

/// What a step costs: the optimal driver's, or a person's who thinks a
/// toll is cheap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Costs {
    pub step: f64,
    pub toll: f64,
}

impl Costs {
    /// The robot's: one toll costs more than the two extra moves round it.
    pub const OPTIMAL: Costs = Costs {
        step: 1.0,
        toll: 3.0,
    };
    /// A person's expectation (Han §7.2.1): a toll is cheaper than a detour.
    pub const EXPECTED: Costs = Costs {
        step: 1.0,
        toll: 1.0,
    };
}

#[derive(Debug, Clone)]
pub struct Grid {
    pub width: i32,
    pub height: i32,
    /// Blocked moves, as (from, to) cell pairs (both directions listed).
    pub walls: Vec<((i32, i32), (i32, i32))>,
    pub tolls: Vec<(i32, i32)>,
    pub start: (i32, i32),
    pub passenger: (i32, i32),
    pub destination: (i32, i32),
}

impl Grid {
    /// The grid documented above.
    pub fn han() -> Grid {
        let mut walls = Vec::new();
        for row in [2, 3] {
            walls.push(((2, row), (3, row)));
            walls.push(((3, row), (2, row)));
        }
        Grid {
            width: 4,
            height: 3,
            walls,
            tolls: vec![(3, 2)],
            start: (1, 1),
            passenger: (3, 3),
            destination: (1, 1),
        }
    }

    pub fn initial(&self) -> TaxiState {
        TaxiState {
            x: self.start.0,
            y: self.start.1,
            passenger: Passenger::Waiting,
        }
    }

    /// The result of an action: the next state, whether it did anything, and
    /// whether it paid a toll.
    pub fn step(&self, s: TaxiState, a: Action) -> (TaxiState, bool, bool) {
        match a {
            Action::PickUp => {
                if s.passenger == Passenger::Waiting && (s.x, s.y) == self.passenger {
                    (
                        TaxiState {
                            passenger: Passenger::InTaxi,
                            ..s
                        },
                        true,
                        false,
                    )
                } else {
                    (s, false, false)
                }
            }
            Action::DropOff => {
                if s.passenger == Passenger::InTaxi && (s.x, s.y) == self.destination {
                    (
                        TaxiState {
                            passenger: Passenger::Delivered,
                            ..s
                        },
                        true,
                        false,
                    )
                } else {
                    (s, false, false)
                }
            }
            m => {
                let (dx, dy) = m.delta();
                let to = (s.x + dx, s.y + dy);
                let inside = to.0 >= 1 && to.0 <= self.width && to.1 >= 1 && to.1 <= self.height;
                if !inside || self.walls.contains(&((s.x, s.y), to)) {
                    (s, false, false)
                } else {
                    (
                        TaxiState {
                            x: to.0,
                            y: to.1,
                            ..s
                        },
                        true,
                        self.tolls.contains(&to),
                    )
                }
            }
        }
    }

    fn states(&self) -> Vec<TaxiState> {
        let mut v = Vec::new();
        for p in [Passenger::Waiting, Passenger::InTaxi, Passenger::Delivered] {
            for y in 1..=self.height {
                for x in 1..=self.width {
                    v.push(TaxiState { x, y, passenger: p });
                }
            }
        }
        v
    }

    fn cost(&self, s: TaxiState, a: Action, c: Costs) -> (TaxiState, f64) {
        let (n, did, toll) = self.step(s, a);
        // An action that does nothing wastes a step, and a bit more, so that
        // it is never optimal.
        let cost = c.step + if toll { c.toll } else { 0.0 } + if did { 0.0 } else { 10.0 };
        (n, cost)
    }

    /// Value iteration over the cost to deliver; the policy picks the cheapest
    /// action, the first in `Action::ALL` on ties.
    pub fn solve(&self, c: Costs) -> HashMap<TaxiState, Action> {
        let states = self.states();
        let mut v: HashMap<TaxiState, f64> = states.iter().map(|s| (*s, 0.0)).collect();
        for _ in 0..1000 {
            let mut delta: f64 = 0.0;
            for s in &states {
                if s.passenger == Passenger::Delivered {
                    continue;
                }
                let best = Action::ALL
                    .iter()
                    .map(|&a| {
                        let (n, cost) = self.cost(*s, a, c);
                        cost + v[&n]
                    })
                    .fold(f64::INFINITY, f64::min);
                delta = delta.max((best - v[s]).abs());
                v.insert(*s, best);
            }
            if delta < 1e-9 {
                break;
            }
        }
        states
            .iter()
            .filter(|s| s.passenger != Passenger::Delivered)
            .map(|s| {
                let mut best = (Action::ALL[0], f64::INFINITY);
                for a in Action::ALL {
                    let (n, cost) = self.cost(*s, a, c);
                    let q = cost + v[&n];
                    if q < best.1 - 1e-9 {
                        best = (a, q);
                    }
                }
                (*s, best.0)
            })
            .collect()
    }

    /// The actions the policy takes from the start until it delivers.
    pub fn rollout(&self, policy: &HashMap<TaxiState, Action>) -> Vec<Action> {
        let mut s = self.initial();
        let mut out = Vec::new();
        while s.passenger != Passenger::Delivered && out.len() < 100 {
            let a = policy[&s];
            out.push(a);
            s = self.step(s, a).0;
        }
        out
    }
}

/// The behaviour tree of a policy (Fig. 13): moves before the pick-up form
/// "navigate to passenger", moves before the drop-off "navigate to
/// destination", under the subgoals "go pick up passenger" and "go drop off
/// passenger".
pub fn policy_tree_xml(actions: &[Action]) -> String {
    let split = actions
        .iter()
        .position(|a| *a == Action::PickUp)
        .map_or(actions.len(), |i| i + 1);
    let (pick, drop) = actions.split_at(split);
    let mut x = String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"DeliverPassenger\">\n  <BehaviorTree ID=\"DeliverPassenger\">\n    <Sequence name=\"go deliver passenger\">\n      <SubTree ID=\"GoPickUpPassenger\" name=\"go pick up passenger\"/>\n      <SubTree ID=\"GoDropOffPassenger\" name=\"go drop off passenger\"/>\n    </Sequence>\n  </BehaviorTree>\n");
    for (id, goal, nav, part) in [
        (
            "GoPickUpPassenger",
            "go pick up passenger",
            "navigate to passenger",
            pick,
        ),
        (
            "GoDropOffPassenger",
            "go drop off passenger",
            "navigate to destination",
            drop,
        ),
    ] {
        x.push_str(&format!("  <BehaviorTree ID=\"{id}\">\n    <Sequence name=\"{goal}\">\n      <Sequence name=\"{nav}\">\n"));
        let (moves, last) = match part.last() {
            Some(a @ (Action::PickUp | Action::DropOff)) => (&part[..part.len() - 1], Some(*a)),
            _ => (part, None),
        };
        for m in moves {
            x.push_str(&format!("        <{} name=\"{}\"/>\n", m.id(), m.name()));
        }
        x.push_str("      </Sequence>\n");
        if let Some(a) = last {
            x.push_str(&format!("      <{} name=\"{}\"/>\n", a.id(), a.name()));
        }
        x.push_str("    </Sequence>\n  </BehaviorTree>\n");
    }
    x.push_str("  <TreeNodesModel>\n");
    for a in Action::ALL {
        x.push_str(&format!("    <Action ID=\"{}\"/>\n", a.id()));
    }
    x.push_str("  </TreeNodesModel>\n</root>\n");
    x
}

/// The taxi world as the leaves of a tree: each action takes one tick, then
/// succeeds if it could be done (a move into a wall, a pick-up away from the
/// passenger fail). The taxi's position, the passenger and the tolls paid are
/// written to the root blackboard.
pub struct TaxiLeaves {
    pub grid: Grid,
    pub state: TaxiState,
    pub tolls: i64,
    started: HashMap<Uid, Action>,
}

impl TaxiLeaves {
    pub fn new(grid: Grid) -> TaxiLeaves {
        let state = grid.initial();
        TaxiLeaves {
            grid,
            state,
            tolls: 0,
            started: HashMap::new(),
        }
    }

    fn entries(&self) -> Vec<(EntryId, Value)> {
        let passenger = match self.state.passenger {
            Passenger::Waiting => "waiting",
            Passenger::InTaxi => "in taxi",
            Passenger::Delivered => "delivered",
        };
        vec![
            (
                EntryId {
                    scope: 0,
                    key: "taxi column".into(),
                },
                Value::from(self.state.x),
            ),
            (
                EntryId {
                    scope: 0,
                    key: "taxi row".into(),
                },
                Value::from(self.state.y),
            ),
            (
                EntryId {
                    scope: 0,
                    key: "passenger".into(),
                },
                Value::from(passenger),
            ),
            (
                EntryId {
                    scope: 0,
                    key: "tolls paid".into(),
                },
                Value::from(self.tolls),
            ),
        ]
    }

    /// Leaves of the tree that are not taxi actions.
    pub fn unknown_leaves(tree: &Tree) -> Vec<String> {
        tree.nodes
            .iter()
            .filter(|n| {
                n.kind.is_leaf() && n.builtin.is_none() && Action::of_leaf(&n.name, &n.id).is_none()
            })
            .map(|n| format!("{} #{}", tree.description(n.uid), n.uid))
            .collect()
    }
}

impl Leaves for TaxiLeaves {
    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        self.entries()
    }

    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let n = call.tree.node(call.uid);
        let Some(a) = Action::of_leaf(&n.name, &n.id) else {
            return LeafOutcome {
                status: Status::Failure,
                decision: None,
            };
        };
        if !call.resumed {
            self.started.insert(call.uid, a);
            return LeafOutcome {
                status: Status::Running,
                decision: Some(a.name().to_string()),
            };
        }
        self.started.remove(&call.uid);
        let before = self.entries();
        let (next, did, toll) = self.grid.step(self.state, a);
        self.state = next;
        if toll {
            self.tolls += 1;
        }
        for (e, v) in self.entries().into_iter().zip(before) {
            if e.1 != v.1 {
                call.write_entry(e.0, e.1);
            }
        }
        LeafOutcome {
            status: if did {
                Status::Success
            } else {
                Status::Failure
            },
            decision: None,
        }
    }

    fn halt(&mut self, uid: Uid) {
        self.started.remove(&uid);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_optimal_taxi_avoids_the_toll_and_a_cheap_toll_is_taken() {
        let g = Grid::han();
        let opt = g.rollout(&g.solve(Costs::OPTIMAL));
        use Action::*;
        assert_eq!(
            opt,
            vec![
                MoveRight, MoveRight, MoveRight, MoveUp, MoveUp, MoveLeft, PickUp, MoveRight,
                MoveDown, MoveDown, MoveLeft, MoveLeft, MoveLeft, DropOff
            ]
        );
        let exp = g.rollout(&g.solve(Costs::EXPECTED));
        assert_eq!(
            exp,
            vec![
                MoveRight, MoveRight, MoveUp, MoveUp, PickUp, MoveDown, MoveDown, MoveLeft,
                MoveLeft, DropOff
            ]
        );
    }

    #[test]
    fn leaves_are_read_by_name_or_id() {
        assert_eq!(Action::of_leaf("", "move right"), Some(Action::MoveRight));
        assert_eq!(Action::of_leaf("move up", "move_up"), Some(Action::MoveUp));
        assert_eq!(
            Action::of_leaf("pick up passenger", "pick up"),
            Some(Action::PickUp)
        );
        assert_eq!(Action::of_leaf("fly", "fly"), None);
    }
}
