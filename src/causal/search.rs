//! The counterfactual search (Love et al., Algorithm 6): interventions on
//! the ancestors of the queried variables, smallest sets first; every
//! satisfying assignment of the first size that has one.

use super::model::{Evaluator, Model, Val, VarId};
use crate::source::Located;
use rayon::prelude::*;

/// why(V = v, V ∈ foils): the queried variables and their foil values.
#[derive(Debug, Clone)]
pub struct Query {
    pub targets: Vec<VarId>,
    /// Per target, the values that satisfy the query.
    pub foils: Vec<Vec<Val>>,
}

/// Interventions on one set of variables that all led to the same foil.
#[derive(Debug, Clone, PartialEq)]
pub struct Explanation {
    /// The variables intervened on; their factual values are the reasons.
    pub vars: Vec<VarId>,
    /// Every satisfying assignment to `vars`, in range order.
    pub values: Vec<Vec<Val>>,
    /// The queried variables' values under those interventions.
    pub outcome: Vec<Val>,
    /// When the model cannot say the outcome: what the tree would have
    /// done instead of reaching it.
    pub next: Option<Next>,
}

/// What follows a change when the model cannot give the final value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// The tree would have ticked this leaf, whose outcome nothing recorded.
    Unknown(crate::model::Uid),
    /// This RetryUntilSuccessful (or Repeat) would have ticked its child
    /// again within the tick: attempt (cycle) `attempt` of `of` (−1: no limit).
    Retry {
        node: crate::model::Uid,
        attempt: i64,
        of: i64,
        repeat: bool,
    },
    /// What followed would have rested on this control node, whose way on
    /// the model does not follow (`Model::opaque`).
    Opaque(crate::model::Uid),
}

#[derive(Debug, Clone)]
pub struct Answer {
    /// The size of the explanations (`None`: none up to `max_depth`).
    pub depth: Option<usize>,
    pub max_depth: usize,
    pub explanations: Vec<Explanation>,
    /// Variables the search could intervene on.
    pub candidates: usize,
    /// Interventions evaluated.
    pub evaluated: usize,
    /// The search stopped before this depth, which would have evaluated
    /// this many interventions (more than `SEARCH_WORK_MAX` allows).
    pub stopped: Option<(usize, u128)>,
    /// Explanations found past the first `EXPLANATIONS_MAX` (the nearest
    /// causes), left out: not checked, merged or shown.
    pub omitted: usize,
    /// Candidates not searched at the answer's depth: the whole depth was
    /// past the bound, and only the nearest `NEAREST_MAX` were.
    pub unsearched: usize,
    /// Nodes that decide by the blackboard (a pre-condition script, a
    /// Switch, …), which the model holds as recorded and which a change
    /// could reach through a script: where none could be re-run, whether
    /// an explanation exists through them is unknown.
    pub held: Vec<crate::model::Uid>,
    /// Whether each single change of a leaf's outcome was tried through
    /// them by running the tree again (and none gave a foil).
    pub held_tried: bool,
}

impl Answer {
    /// No explanation found: the search stopped at a depth past its bound
    /// (`stopped`), where that many interventions would have been tried.
    fn stopped(candidates: usize, evaluated: usize, max_depth: usize, at: (usize, u128)) -> Answer {
        Answer {
            depth: None,
            max_depth,
            explanations: Vec::new(),
            candidates,
            evaluated,
            stopped: Some(at),
            omitted: 0,
            held: Vec::new(),
            held_tried: false,
            unsearched: 0,
        }
    }
}

/// The most explanations of one size kept. A chain of 10,000 decorators has
/// 10,000 single causes of its root's status; each kept one is re-run and
/// merged, and nobody reads past the first few dozen.
pub const EXPLANATIONS_MAX: usize = 50;

/// Where a whole depth of single changes is past the bound, the candidates
/// nearest the target searched instead (a chain of 10,000 SubTrees: the
/// root's status depends on every node below it, and the answer is in the
/// few nearest).
pub const NEAREST_MAX: usize = 4 * EXPLANATIONS_MAX;

/// The most work a search does: interventions × the variables each one
/// evaluates. Serial recall's queries take about 10^5; a depth-1 search on a
/// 9,600-node chain about 1.8·10^8 (4 s on the development machine); the
/// depth-2 search there would take 10^12. The bound is counted, not timed,
/// so an answer does not depend on the machine.
pub const SEARCH_WORK_MAX: u128 = 400_000_000;

/// The work past which the single changes are searched nearest first, only
/// `NEAREST_MAX` of them: each single change re-evaluates the variables
/// between it and the target, so on a chain they cost the square of its
/// length. Past 2·10^7 (0.2 s) the search grows with the chain, not its
/// square. No tree of the fixtures, Nav2's or the papers' comes near it
/// (kitting's singles take about 10^5).
pub const SINGLES_WORK_MAX: u128 = 20_000_000;

/// How many interventions the sets of `k` of these candidates make: the
/// k-th elementary symmetric polynomial of their numbers of values.
fn interventions(alts: &[usize], k: usize) -> u128 {
    let mut e = vec![0u128; k + 1];
    e[0] = 1;
    for &a in alts {
        for j in (1..=k).rev() {
            e[j] = e[j].saturating_add(e[j - 1].saturating_mul(a as u128));
        }
    }
    e[k]
}

/// Every `k`-subset of `0..n`, in lexicographic order.
fn subsets(n: usize, k: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    if k == 0 || k > n {
        return out;
    }
    let mut idx: Vec<usize> = (0..k).collect();
    loop {
        out.push(idx.clone());
        let mut i = k;
        while i > 0 && idx[i - 1] == n - k + i - 1 {
            i -= 1;
        }
        if i == 0 {
            return out;
        }
        idx[i - 1] += 1;
        for j in i..k {
            idx[j] = idx[j - 1] + 1;
        }
    }
}

/// A variable that may be changed, with the values it may take instead of
/// its fact.
type Candidate = (VarId, Vec<Val>);

pub fn search(model: &Model, q: &Query, max_depth: usize) -> Result<Answer, Located> {
    let within = model.ancestors(&q.targets);
    let candidates = candidates(model, q, &within);
    let mut evaluated = 0;
    // One evaluator per thread for the whole search, so each keeps what it
    // learnt of the leaf functions (their memo) from set to set and depth
    // to depth.
    let threads = rayon::current_num_threads().max(1);
    let mut evaluators: Vec<_> = (0..threads).map(|_| model.evaluator(&within)).collect();
    let alts: Vec<usize> = candidates.iter().map(|(_, a)| a.len()).collect();
    let mut work: u128 = 0;
    let dist = model.distances_to(&q.targets);
    for depth in 1..=max_depth.min(candidates.len()) {
        let n = interventions(&alts, depth);
        work = work.saturating_add(n.saturating_mul(within.len().max(1) as u128));
        let Some((sets, unsearched)) = sets_within(&candidates, &dist, depth, work) else {
            return Ok(Answer::stopped(
                candidates.len(),
                evaluated,
                max_depth,
                (depth, n),
            ));
        };
        let (mut explanations, n_run) = run_sets(model, q, &candidates, &mut evaluators, &sets)?;
        evaluated += n_run;
        // Nearest causes first (fewest edges to the target), then by variable.
        explanations.sort_by_key(|e| {
            (
                e.vars.iter().map(|&v| dist[v]).max().unwrap_or(0),
                e.vars.clone(),
            )
        });
        if !explanations.is_empty() {
            let omitted = explanations.len().saturating_sub(EXPLANATIONS_MAX);
            explanations.truncate(EXPLANATIONS_MAX);
            return Ok(Answer {
                omitted,
                depth: Some(depth),
                max_depth,
                explanations,
                candidates: candidates.len(),
                evaluated,
                stopped: None,
                held: Vec::new(),
                held_tried: false,
                unsearched,
            });
        }
        if unsearched > 0 {
            // None among the nearest: the rest is past the bound, unknown.
            return Ok(Answer::stopped(
                candidates.len(),
                evaluated,
                max_depth,
                (depth, n),
            ));
        }
    }
    Ok(Answer {
        depth: None,
        max_depth,
        explanations: Vec::new(),
        candidates: candidates.len(),
        evaluated,
        stopped: None,
        omitted: 0,
        held: Vec::new(),
        held_tried: false,
        unsearched: 0,
    })
}

/// The variables of `within` (the targets' ancestors) that may be set, by
/// id, each with its other values; the targets themselves are not.
fn candidates(model: &Model, q: &Query, within: &[VarId]) -> Vec<Candidate> {
    let mut ids = within.to_vec();
    ids.sort_unstable();
    ids.into_iter()
        .filter(|v| !q.targets.contains(v) && model.vars[*v].intervene)
        .map(|v| {
            let alts: Vec<Val> = model.vars[v]
                .range
                .iter()
                .filter(|x| **x != model.fact[v])
                .cloned()
                .collect();
            (v, alts)
        })
        .filter(|(_, alts)| !alts.is_empty())
        .collect()
}

/// The sets of `depth` candidates to try, as indices, and how many
/// candidates were left out; none when the search is past its bound.
/// Single changes past their own bound are the ones nearest the target.
fn sets_within(
    candidates: &[Candidate],
    dist: &[usize],
    depth: usize,
    work: u128,
) -> Option<(Vec<Vec<usize>>, usize)> {
    if work > SINGLES_WORK_MAX && depth == 1 {
        let mut near: Vec<usize> = (0..candidates.len()).collect();
        near.sort_by_key(|&c| (dist[candidates[c].0], c));
        near.truncate(NEAREST_MAX);
        let unsearched = candidates.len() - near.len();
        near.sort_unstable();
        Some((near.into_iter().map(|c| vec![c]).collect(), unsearched))
    } else if work > SEARCH_WORK_MAX {
        None
    } else {
        Some((subsets(candidates.len(), depth), 0))
    }
}

/// Runs the sets on every thread, each with its own evaluator: the
/// explanations found and how many assignments were run.
fn run_sets(
    model: &Model,
    q: &Query,
    candidates: &[Candidate],
    evaluators: &mut [Evaluator],
    sets: &[Vec<usize>],
) -> Result<(Vec<Explanation>, usize), Located> {
    let chunk = sets.len().div_ceil(evaluators.len()).max(1);
    let found: Vec<Result<(Vec<Explanation>, usize), Located>> = evaluators
        .par_iter_mut()
        .zip(sets.par_chunks(chunk))
        .map(|(ev, chunk)| {
            let mut groups = Vec::new();
            let mut count = 0;
            for set in chunk {
                let (g, n) = explanations_of(model, q, candidates, ev, set)?;
                groups.extend(g);
                count += n;
            }
            Ok((groups, count))
        })
        .collect();
    let mut explanations = Vec::new();
    let mut evaluated = 0;
    for r in found {
        let (g, n) = r?;
        evaluated += n;
        explanations.extend(g);
    }
    Ok((explanations, evaluated))
}

/// Every assignment of other values to the candidates of `set`, run
/// through the model: the ones that give the foil, grouped by outcome, and
/// how many were run.
fn explanations_of(
    model: &Model,
    q: &Query,
    candidates: &[Candidate],
    ev: &mut Evaluator,
    set: &[usize],
) -> Result<(Vec<Explanation>, usize), Located> {
    let mut groups: Vec<Explanation> = Vec::new();
    let mut count = 0;
    let mut choice = vec![0usize; set.len()];
    loop {
        let dos: Vec<(VarId, Val)> = set
            .iter()
            .zip(&choice)
            .map(|(&c, &i)| (candidates[c].0, candidates[c].1[i].clone()))
            .collect();
        ev.run(&dos)?;
        count += 1;
        let outcome: Vec<Val> = q.targets.iter().map(|&t| ev.value(t).clone()).collect();
        if outcome
            .iter()
            .zip(&q.targets)
            .zip(&q.foils)
            .all(|((o, &t), f)| f.contains(&model.snap(t, o)))
        {
            keep(model, &mut groups, dos, outcome);
        }
        // Next assignment, odometer-style.
        let mut i = set.len();
        loop {
            if i == 0 {
                return Ok((groups, count));
            }
            i -= 1;
            choice[i] += 1;
            if choice[i] < candidates[set[i]].1.len() {
                break;
            }
            choice[i] = 0;
        }
    }
}

/// Keeps an assignment that gives the foil, with the others of its outcome.
fn keep(
    model: &Model,
    groups: &mut Vec<Explanation>,
    mut dos: Vec<(VarId, Val)>,
    outcome: Vec<Val>,
) {
    dos.sort_by_key(|(v, _)| model.display_key(*v));
    let vars: Vec<VarId> = dos.iter().map(|(v, _)| *v).collect();
    let values: Vec<Val> = dos.into_iter().map(|(_, x)| x).collect();
    match groups.iter_mut().find(|g| g.outcome == outcome) {
        Some(g) => g.values.push(values),
        None => groups.push(Explanation {
            vars,
            values: vec![values],
            outcome,
            next: None,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::{interventions, subsets};

    #[test]
    fn interventions_count_every_assignment_of_every_set() {
        // Sets of 2 of {2, 3, 1} values: 2·3 + 2·1 + 3·1.
        assert_eq!(interventions(&[2, 3, 1], 2), 11);
        assert_eq!(interventions(&[2, 3, 1], 1), 6);
        assert_eq!(interventions(&[2, 3, 1], 3), 6);
        assert_eq!(interventions(&[3; 10_000], 2), 9 * 10_000 * 9_999 / 2);
    }

    #[test]
    fn subsets_are_all_and_ordered() {
        assert_eq!(
            subsets(4, 2),
            vec![
                vec![0, 1],
                vec![0, 2],
                vec![0, 3],
                vec![1, 2],
                vec![1, 3],
                vec![2, 3]
            ]
        );
        assert_eq!(subsets(3, 3), vec![vec![0, 1, 2]]);
        assert!(subsets(2, 3).is_empty());
    }
}
