//! Levels that minimise the total estimated error within a cost budget: the greedy refinement of
//! Funkhouser & Séquin (1993, "Adaptive display algorithm for interactive frame rates during
//! visualization of complex virtual environments"), which the paper cites.
//!
//! Every section starts at its floor (the coarsest level its motion and rules allow). Then, while
//! budget remains, the single refinement with the largest error saved per unit of added cost,
//! `(e_now − e_finer) / (c_finer − c_now)`, over all sections and all finer levels of each (so a
//! section may jump from patch to strands when clusters would save little), is applied if it
//! fits (the total stays within the budget; over a budget that the floors already break, nothing
//! is refined). Refinements that do not fit are skipped, and cheaper ones still tried. Ties go to
//! the lower section index and the coarser target, so the result is deterministic.
//!
//! For sections whose error falls convexly with cost (each step saves less per unit cost than the
//! one before), and costs that fill the budget exactly, this is the optimum of the knapsack; in
//! general it is the classic greedy approximation.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::level::Level;

/// One section's options: its estimated error [pixels] and cost [s] at each level (indexed by
/// [`Level`] rank: patch, clusters, strand groups), and the coarsest level it may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionOptions {
    /// Estimated screen-space error at each level [pixels] (0 for a hidden section).
    pub errors: [f32; 3],
    /// Cost of each level [s].
    pub costs: [f64; 3],
    /// The coarsest level allowed.
    pub floor: Level,
}

/// What a budgeted choice came to.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BudgetOutcome {
    /// Sum of the chosen levels' costs [s].
    pub cost: f64,
    /// Sum of the chosen levels' errors [pixels].
    pub error: f64,
    /// Whether even the floors cost more than the budget (then every section is at its floor).
    pub over_budget: bool,
}

/// A candidate refinement in the heap.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    ratio: f64,
    section: usize,
    target: Level,
    /// The section's level when the candidate was made (stale once it changes).
    from: Level,
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Candidate {
    /// Larger ratio first; then lower section; then coarser target.
    fn cmp(&self, other: &Self) -> Ordering {
        self.ratio
            .total_cmp(&other.ratio)
            .then_with(|| other.section.cmp(&self.section))
            .then_with(|| (other.target as usize).cmp(&(self.target as usize)))
    }
}

/// Chooses `levels` (one per section) for `options` within `budget` [s]; see the module docs.
pub fn refine_within_budget(
    options: &[SectionOptions],
    budget: f64,
    levels: &mut [Level],
) -> BudgetOutcome {
    debug_assert_eq!(options.len(), levels.len());
    let mut cost = 0.0;
    for (level, option) in levels.iter_mut().zip(options) {
        *level = option.floor;
        cost += option.costs[option.floor as usize];
    }
    let over_budget = cost > budget;
    let mut heap = BinaryHeap::new();
    let push = |heap: &mut BinaryHeap<Candidate>, section: usize, from: Level| {
        let option = &options[section];
        for target in Level::ALL.into_iter().filter(|&l| l > from) {
            let saved = f64::from(option.errors[from as usize] - option.errors[target as usize]);
            let added = option.costs[target as usize] - option.costs[from as usize];
            if saved <= 0.0 {
                continue;
            }
            let ratio = if added <= 0.0 {
                f64::INFINITY
            } else {
                saved / added
            };
            heap.push(Candidate {
                ratio,
                section,
                target,
                from,
            });
        }
    };
    for (section, &level) in levels.iter().enumerate() {
        push(&mut heap, section, level);
    }
    while let Some(candidate) = heap.pop() {
        let section = candidate.section;
        if levels[section] != candidate.from {
            continue;
        }
        let option = &options[section];
        let added = option.costs[candidate.target as usize] - option.costs[candidate.from as usize];
        if cost + added > budget {
            continue;
        }
        cost += added;
        levels[section] = candidate.target;
        push(&mut heap, section, candidate.target);
    }
    let error = levels
        .iter()
        .zip(options)
        .map(|(&level, option)| f64::from(option.errors[level as usize]))
        .sum();
    BudgetOutcome {
        cost,
        error,
        over_budget,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    /// Every assignment of levels at or above the floors, the cheapest error within budget.
    fn brute_force(options: &[SectionOptions], budget: f64) -> f64 {
        let count = options.len();
        let mut best = f64::INFINITY;
        for code in 0..3usize.pow(count as u32) {
            let mut rest = code;
            let (mut cost, mut error, mut allowed) = (0.0, 0.0, true);
            for option in options {
                let rank = rest % 3;
                rest /= 3;
                allowed &= rank >= option.floor as usize;
                cost += option.costs[rank];
                error += f64::from(option.errors[rank]);
            }
            if allowed && cost <= budget + 1e-12 {
                best = best.min(error);
            }
        }
        best
    }

    #[test]
    fn unit_steps_with_convex_errors_give_the_optimum() {
        // Each level costs one unit more and saves less than the step before: the knapsack's
        // greedy is exact (exchange argument), so it must match the brute force.
        let mut rng = SplitMix64::new(3);
        for _ in 0..200 {
            let options: Vec<SectionOptions> = (0..5)
                .map(|_| {
                    let first = rng.range(0.5, 10.0);
                    let second = rng.range(0.0, first);
                    let strands = 0.0;
                    let clusters = strands + second;
                    let patch = clusters + first.max(second);
                    SectionOptions {
                        errors: [patch, clusters, strands],
                        costs: [1.0, 2.0, 3.0],
                        floor: Level::Patch,
                    }
                })
                .collect();
            let budget = f64::from(rng.range(5.0, 15.0)).floor();
            let mut levels = vec![Level::Patch; 5];
            let outcome = refine_within_budget(&options, budget, &mut levels);
            assert!(outcome.cost <= budget);
            let optimum = brute_force(&options, budget);
            assert!(
                (outcome.error - optimum).abs() < 1e-4,
                "{} against {optimum}",
                outcome.error
            );
        }
    }

    #[test]
    fn general_costs_stay_within_budget_and_near_the_optimum() {
        // Arbitrary costs: the greedy never breaks the budget or a floor, and misses the optimum
        // by at most one section's whole refinement (the bound of greedy against the linear
        // relaxation of the multiple-choice knapsack: one item is left fractional).
        let mut rng = SplitMix64::new(11);
        for _ in 0..200 {
            let options: Vec<SectionOptions> = (0..6)
                .map(|_| {
                    let patch = rng.range(0.1, 1.0);
                    let clusters = patch + rng.range(0.1, 2.0);
                    let strands = clusters + rng.range(0.5, 6.0);
                    let e_strands = 0.0;
                    let e_clusters = rng.range(0.1, 3.0);
                    let e_patch = e_clusters + rng.range(0.0, 6.0);
                    SectionOptions {
                        errors: [e_patch, e_clusters, e_strands],
                        costs: [patch.into(), clusters.into(), strands.into()],
                        floor: if rng.next_f32() < 0.2 {
                            Level::Cluster
                        } else {
                            Level::Patch
                        },
                    }
                })
                .collect();
            let floors: f64 = options.iter().map(|o| o.costs[o.floor as usize]).sum();
            let budget = floors + f64::from(rng.range(0.0, 20.0));
            let mut levels = vec![Level::Patch; options.len()];
            let outcome = refine_within_budget(&options, budget, &mut levels);
            assert!(outcome.cost <= budget + 1e-9);
            for (level, option) in levels.iter().zip(&options) {
                assert!(*level >= option.floor);
            }
            let optimum = brute_force(&options, budget);
            assert!(outcome.error >= optimum - 1e-6);
            let one_section = options
                .iter()
                .map(|o| f64::from(o.errors[o.floor as usize] - o.errors[2]))
                .fold(0.0, f64::max);
            assert!(
                outcome.error - optimum <= one_section + 1e-6,
                "gap {} beyond one section's {one_section}",
                outcome.error - optimum
            );
        }
    }

    #[test]
    fn an_impossible_budget_keeps_the_floors_and_says_so() {
        let options = [SectionOptions {
            errors: [3.0, 1.0, 0.0],
            costs: [1.0, 2.0, 4.0],
            floor: Level::Cluster,
        }];
        let mut levels = [Level::Patch];
        let outcome = refine_within_budget(&options, 0.5, &mut levels);
        assert_eq!(levels, [Level::Cluster]);
        assert!(outcome.over_budget);
        assert_eq!(outcome.cost, 2.0);
    }
}
