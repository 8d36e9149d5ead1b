//! Trees generated over BehaviorTree.CPP's built-in nodes, with random
//! plans: the differential tests run them in the real library and in btx,
//! and the truth tests ask `why` about their runs.
#![allow(dead_code)]

use btx::run::world::random::Rng;

/// A generated case: the tree, its plan, and how many ticks to run.
pub struct Case {
    pub xml: String,
    pub plan: String,
    pub max_ticks: u32,
    /// Wall time between ticks for the library, and the simulated time
    /// between ticks for btx (Timeout, Delay and Sleep).
    pub tick_ms: u64,
}

struct Gen<'a> {
    rng: &'a mut Rng,
    leaves: Vec<(String, bool)>,
    /// Scripts, blackboard nodes, Switch, Precondition and the pre/post
    /// script attributes, over one integer entry `k`.
    scripted: bool,
    /// Parts of the tree made SubTrees (remapped automatically, so that
    /// scripts share `k`), with their definitions.
    with_subtrees: bool,
    subtrees: Vec<String>,
    /// Nav2's controls and a RateController among the nodes (btx only:
    /// the library does not register them).
    nav2: bool,
}

impl Gen<'_> {
    /// A script condition over `k`, in the syntax both sides read.
    fn test(&mut self) -> String {
        let op = ["==", "!=", "<", ">", "<=", ">="][self.rng.range(0, 5)];
        format!("k {op} {}", self.rng.range(0, 4))
    }

    /// A script that changes `k`.
    fn change(&mut self) -> String {
        match self.rng.range(0, 3) {
            0 => format!("k := {}", self.rng.range(0, 4)),
            1 => "k += 1".into(),
            2 => "k -= 1".into(),
            _ => format!("k := k + {}", self.rng.range(1, 2)),
        }
    }

    /// Pre/post script attributes, sometimes.
    fn attributes(&mut self) -> String {
        if !self.scripted || self.rng.range(0, 3) != 0 {
            return String::new();
        }
        let (name, code) = match self.rng.range(0, 7) {
            0 => ("_skipIf", self.test()),
            1 => ("_successIf", self.test()),
            2 => ("_failureIf", self.test()),
            3 => ("_while", self.test()),
            4 => ("_onSuccess", self.change()),
            5 => ("_onFailure", self.change()),
            6 => ("_post", self.change()),
            _ => ("_onHalted", self.change()),
        };
        format!(" {name}=\"{}\"", xml_escape(&code))
    }

    fn leaf(&mut self) -> String {
        let n = self.leaves.len();
        if self.scripted && self.rng.range(0, 5) == 0 {
            // SetBlackboard writes a string: it gets an entry of its own
            // (`m`), which scripts only compare (see the README on what the
            // library does to a script's number overwritten with a string).
            if self.rng.range(0, 19) == 0 {
                return "<UnsetBlackboard key=\"m\"/>".into();
            }
            return match self.rng.range(0, 4) {
                0 => format!("<Script code=\"{}\"/>", xml_escape(&self.change())),
                1 => format!("<ScriptCondition code=\"{}\"/>", xml_escape(&self.test())),
                2 => format!(
                    "<SetBlackboard output_key=\"m\" value=\"{}\"/>",
                    self.rng.range(0, 4)
                ),
                3 => {
                    let op = ["==", "!=", "<", ">"][self.rng.range(0, 3)];
                    let v = self.rng.range(0, 4);
                    format!(
                        "<ScriptCondition code=\"{}\"/>",
                        xml_escape(&format!("m {op} {v}"))
                    )
                }
                _ => "<AlwaysSuccess/>".into(),
            };
        }
        if self.rng.range(0, 9) == 0 {
            return if self.rng.coin() {
                "<AlwaysSuccess/>".into()
            } else {
                "<AlwaysFailure/>".into()
            };
        }
        let condition = self.rng.range(0, 2) == 0;
        let id = if condition { "Check" } else { "Act" };
        self.leaves.push((format!("n{n}"), condition));
        let attrs = self.attributes();
        format!("<{id} name=\"n{n}\"{attrs}/>")
    }

    fn children(&mut self, depth: u32, lo: usize, hi: usize) -> String {
        let k = self.rng.range(lo, hi);
        (0..k).map(|_| self.node(depth + 1)).collect()
    }

    fn node(&mut self, depth: u32) -> String {
        if depth >= 4 || self.rng.range(0, 9) < 3 + depth as usize {
            return self.leaf();
        }
        if self.with_subtrees && self.rng.range(0, 5) == 0 {
            let inner = self.node(depth + 1);
            let j = self.subtrees.len();
            self.subtrees
                .push(format!("<BehaviorTree ID=\"S{j}\">{inner}</BehaviorTree>"));
            return format!("<SubTree ID=\"S{j}\" name=\"s{j}\" _autoremap=\"true\"/>");
        }
        let kinds = [
            "Sequence",
            "Fallback",
            "ReactiveSequence",
            "ReactiveFallback",
            "SequenceWithMemory",
            "AsyncSequence",
            "AsyncFallback",
            "Parallel",
            "ParallelAll",
            "IfThenElse",
            "WhileDoElse",
            "Inverter",
            "ForceSuccess",
            "ForceFailure",
            "RetryUntilSuccessful",
            "Repeat",
            "KeepRunningUntilFailure",
            "RunOnce",
        ];
        if self.scripted && self.rng.range(0, 5) == 0 {
            return match self.rng.coin() {
                true => {
                    let cases = self.rng.range(2, 3);
                    let body = (0..=cases)
                        .map(|_| self.node(depth + 1))
                        .collect::<String>();
                    let attrs: String = (1..=cases)
                        .map(|i| format!(" case_{i}=\"{}\"", self.rng.range(0, 3)))
                        .collect();
                    format!("<Switch{cases} variable=\"{{k}}\"{attrs}>{body}</Switch{cases}>")
                }
                false => {
                    let body = self.node(depth + 1);
                    let cond = xml_escape(&self.test());
                    let other = ["SUCCESS", "FAILURE"][self.rng.range(0, 1)];
                    format!("<Precondition if=\"{cond}\" else=\"{other}\">{body}</Precondition>")
                }
            };
        }
        let nav2 = [
            "PipelineSequence",
            "RecoveryNode",
            "RoundRobin",
            "RateController",
        ];
        let kind = if self.nav2 && self.rng.range(0, 2) == 0 {
            nav2[self.rng.range(0, nav2.len() - 1)]
        } else {
            kinds[self.rng.range(0, kinds.len() - 1)]
        };
        let attrs = self.attributes();
        let node = self.composite(kind, depth);
        // The attributes go on the element's opening tag.
        match node.find('>') {
            Some(i) if !attrs.is_empty() => format!("{}{attrs}{}", &node[..i], &node[i..]),
            _ => node,
        }
    }

    fn composite(&mut self, kind: &str, depth: u32) -> String {
        match kind {
            "Parallel" => {
                let body = self.children(depth, 2, 3);
                let n = body.matches("/>").count().max(2) as i64;
                let s = self.rng.range(1, 2) as i64;
                let f = self.rng.range(1, 2) as i64;
                let _ = n;
                format!("<Parallel success_count=\"{s}\" failure_count=\"{f}\">{body}</Parallel>")
            }
            "ParallelAll" => {
                let body = self.children(depth, 2, 3);
                let m = self.rng.range(1, 2);
                format!("<ParallelAll max_failures=\"{m}\">{body}</ParallelAll>")
            }
            "IfThenElse" | "WhileDoElse" => {
                let body = self.children(depth, 2, 3);
                format!("<{kind}>{body}</{kind}>")
            }
            "RetryUntilSuccessful" => {
                let body = self.node(depth + 1);
                let a = self.rng.range(1, 3);
                format!("<RetryUntilSuccessful num_attempts=\"{a}\">{body}</RetryUntilSuccessful>")
            }
            "Repeat" => {
                let body = self.node(depth + 1);
                let a = self.rng.range(1, 3);
                format!("<Repeat num_cycles=\"{a}\">{body}</Repeat>")
            }
            "RunOnce" => {
                let body = self.node(depth + 1);
                let skip = self.rng.coin();
                format!("<RunOnce then_skip=\"{skip}\">{body}</RunOnce>")
            }
            "RecoveryNode" => {
                let body = self.children(depth, 2, 2);
                let n = self.rng.range(1, 2);
                format!("<RecoveryNode number_of_retries=\"{n}\">{body}</RecoveryNode>")
            }
            "RateController" => {
                let body = self.node(depth + 1);
                format!("<RateController hz=\"20\">{body}</RateController>")
            }
            "Inverter" | "ForceSuccess" | "ForceFailure" | "KeepRunningUntilFailure" => {
                let body = self.node(depth + 1);
                format!("<{kind}>{body}</{kind}>")
            }
            _ => {
                let body = self.children(depth, 1, 3);
                format!("<{kind}>{body}</{kind}>")
            }
        }
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

pub fn generate(seed: u64) -> Case {
    generate_with(seed, false)
}

/// A generated case with Nav2's PipelineSequence, RecoveryNode, RoundRobin
/// and RateController among its nodes, and no scripts (Nav2's controls
/// refuse a SKIPPED child).
pub fn generate_nav2(seed: u64) -> Case {
    generate_with(seed & !1, true)
}

fn generate_with(seed: u64, nav2: bool) -> Case {
    let mut rng = Rng::new(seed);
    // Every other case uses scripts and the blackboard, starting from k = 0.
    let scripted = seed % 2 == 1;
    let mut g = Gen {
        rng: &mut rng,
        leaves: Vec::new(),
        scripted,
        with_subtrees: seed % 4 >= 2,
        subtrees: Vec::new(),
        nav2,
    };
    let mut body = g.node(0);
    if scripted {
        body = format!("<Sequence><Script code=\"k := 0\"/><SetBlackboard output_key=\"m\" value=\"1\"/>{body}</Sequence>");
    }
    let leaves = g.leaves;
    let subtrees = g.subtrees.concat();
    let mut plan = String::from("@default_action = 1RS\n@default_condition = S\n");
    for (name, condition) in &leaves {
        let k = rng.range(1, 3);
        let list: Vec<&str> = (0..k)
            .map(|_| {
                if *condition {
                    ["S", "F"][rng.range(0, 1)]
                } else {
                    ["S", "F", "1RS", "1RF", "2RS", "2RF"][rng.range(0, 5)]
                }
            })
            .collect();
        plan.push_str(&format!("{name} = {}\n", list.join(", ")));
    }
    let xml = format!(
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"Main\"><BehaviorTree ID=\"Main\">{body}</BehaviorTree>{subtrees}<TreeNodesModel><Action ID=\"Act\"/><Condition ID=\"Check\"/></TreeNodesModel></root>"
    );
    Case {
        xml,
        plan,
        max_ticks: 24,
        tick_ms: 0,
    }
}
