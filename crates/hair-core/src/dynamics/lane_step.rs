//! A run of chains (consecutive chains of one node count, see
//! [`LaneModel`](crate::dynamics::lane_model::LaneModel)) stepped by the lane kernels, the
//! position-based ([`position_based`](crate::dynamics::position_based)) or XPBD
//! ([`xpbd`](crate::dynamics::xpbd)) one, compiled for the CPU at hand; with the failure policy
//! (a failing chain redone with half the substep) and XPBD's adaptive substeps (a chain whose first
//! Newton move was too long redone with twice the substeps), both of which redo a chain from its
//! start through the same kernel with `substeps << halvings` substeps.

use glam::Vec3;

use crate::dynamics::error::ChainFailure;
use crate::dynamics::lane_batch::{Attempt, BatchState, BatchStep, LaneOutcome, substeps_halved};
use crate::dynamics::lane_model::{LaneNode, LaneRoots, LaneRun, MAX_CHAIN_NODES};
use crate::dynamics::lanes::{LANES, Lanes};
use crate::dynamics::params::{FailurePolicy, IntegratorKind};
use crate::dynamics::position_based::step_position_based;
use crate::dynamics::xpbd::{MAX_ADAPTIVE_HALVINGS, step_xpbd};

/// XPBD's adaptive substeps halve again only while a halving shrinks the first Newton move
/// below this fraction of the last one (a step too long for the motion moves about half as far
/// at half the substep; a fold moves as far at any substep).
const SHRINKING_MOVE: f32 = 0.75;

/// The state of a run: its chains' nodes at the step's start, where the new state goes (same
/// length, chain-major from the run's first node), and one failure and halving count per chain
/// (in: the adaptive substeps' doublings each chain starts from; out: the halvings it took
/// beyond them).
pub(crate) struct RunState<'a> {
    pub positions: &'a [Vec3],
    pub velocities: &'a [Vec3],
    pub collision: &'a [Vec3],
    pub new_positions: &'a mut [Vec3],
    pub new_velocities: &'a mut [Vec3],
    pub failures: &'a mut [Option<ChainFailure>],
    pub halvings: &'a mut [u32],
}

/// Steps a run through the step: every chain that passes is written into the new state with
/// the halvings it took; a chain whose failure remains after the halvings its policy allows
/// gets its [`ChainFailure`] (its new state is not written). A chain's result does not depend on
/// the other chains of its run.
///
/// Each chain goes the way the failure policy and XPBD's adaptive substeps take it: a chain whose
/// first Newton move of some substep was too long (XPBD, while adapting and below
/// [`MAX_ADAPTIVE_HALVINGS`]) is redone with twice the substeps where that move shrank below
/// [`SHRINKING_MOVE`] of the last one, else (a fold) redone at the same count without adapting; a
/// chain that failed the check is redone with half the substep while its policy allows. Each try
/// steps the run's lanes at the smallest halving count still pending and keeps the lanes at that
/// count. A chain starts at the doublings its adaptive substeps chose ([`RunState::halvings`]);
/// the limits of both retries count from there.
pub(crate) fn step_run_with_retries(step: &BatchStep, run: &LaneRun, state: RunState) {
    let settings = step.settings;
    let chains = run.end_chain - run.first_chain;
    let max_halvings = match settings.on_failure {
        FailurePolicy::Error => 0,
        FailurePolicy::HalveSubstep { max_halvings } => max_halvings,
    };
    let xpbd = settings.integrator == IntegratorKind::Xpbd;
    let mut seeds = [0u32; LANES];
    seeds[..chains].copy_from_slice(&state.halvings[..chains]);
    let mut halvings = seeds;
    let mut adapting = [true; LANES];
    let mut last_move = [f32::INFINITY; LANES];
    let mut pending: u32 = (1 << chains) - 1;
    while pending != 0 {
        let waiting = |lane: usize| pending & (1 << lane) != 0;
        let current = (0..chains)
            .filter(|&lane| waiting(lane))
            .map(|lane| halvings[lane])
            .min()
            .unwrap_or(0);
        let mut write = 0u32;
        let mut adaptive = Lanes::splat(0.0);
        for lane in (0..chains).filter(|&lane| waiting(lane) && halvings[lane] == current) {
            write |= 1 << lane;
            if xpbd && adapting[lane] && current - seeds[lane] < MAX_ADAPTIVE_HALVINGS {
                adaptive.0[lane] = 1.0;
            }
        }
        let outcome = step_run(
            step,
            BatchState {
                first_chain: run.first_chain,
                end_chain: run.end_chain,
                positions: state.positions,
                velocities: state.velocities,
                collision: state.collision,
                new_positions: &mut *state.new_positions,
                new_velocities: &mut *state.new_velocities,
            },
            run,
            Attempt {
                halvings: current,
                adaptive,
                write,
            },
        );
        for lane in (0..chains).filter(|&lane| write & (1 << lane) != 0) {
            if let Some(moved) = outcome.too_long[lane] {
                if moved < SHRINKING_MOVE * last_move[lane] {
                    halvings[lane] += 1;
                    last_move[lane] = moved;
                } else {
                    // Halving did not shorten the move: the step is not too long, the chain is
                    // in a configuration where the Newton step is large at any substep (a
                    // fold). Redo this count without adapting.
                    adapting[lane] = false;
                }
                continue;
            }
            let failure = match outcome.failures[lane] {
                Some(_) if halvings[lane] - seeds[lane] < max_halvings => {
                    halvings[lane] += 1;
                    continue;
                }
                Some((quantity, node)) => Some(ChainFailure {
                    integrator: settings.integrator,
                    time: step.time,
                    substep: substeps_halved(settings, halvings[lane]).1,
                    halvings: halvings[lane],
                    chain: run.first_chain + lane,
                    node,
                    quantity,
                }),
                None => None,
            };
            pending &= !(1 << lane);
            state.failures[lane] = failure;
            state.halvings[lane] = halvings[lane] - seeds[lane];
        }
    }
}

/// Steps a run of chains once (`attempt`: the halvings of its substep, the lanes that adapt,
/// the lanes written); returns how each lane ended.
// The one `unsafe` of the workspace (`unsafe_code` is denied in the root Cargo.toml): calling the
// AVX2 instance after checking at run time that the CPU has AVX2.
#[allow(unsafe_code)]
fn step_run(step: &BatchStep, state: BatchState, run: &LaneRun, attempt: Attempt) -> LaneOutcome {
    let (nodes, roots) = (run.nodes, run.roots);
    let xpbd = step.settings.integrator == IntegratorKind::Xpbd;
    let n = nodes.len();
    debug_assert!((2..=MAX_CHAIN_NODES).contains(&n));
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe {
                match (xpbd, n <= 16, n <= 32) {
                    (true, true, _) => kernel_avx2::<16, true>(step, state, nodes, roots, attempt),
                    (true, false, true) => {
                        kernel_avx2::<32, true>(step, state, nodes, roots, attempt)
                    }
                    (true, false, false) => {
                        kernel_avx2::<MAX_CHAIN_NODES, true>(step, state, nodes, roots, attempt)
                    }
                    (false, true, _) => {
                        kernel_avx2::<16, false>(step, state, nodes, roots, attempt)
                    }
                    (false, false, true) => {
                        kernel_avx2::<32, false>(step, state, nodes, roots, attempt)
                    }
                    (false, false, false) => {
                        kernel_avx2::<MAX_CHAIN_NODES, false>(step, state, nodes, roots, attempt)
                    }
                }
            };
        }
    }
    match (xpbd, n <= 16, n <= 32) {
        (true, true, _) => kernel::<16, true>(step, state, nodes, roots, attempt),
        (true, false, true) => kernel::<32, true>(step, state, nodes, roots, attempt),
        (true, false, false) => kernel::<MAX_CHAIN_NODES, true>(step, state, nodes, roots, attempt),
        (false, true, _) => kernel::<16, false>(step, state, nodes, roots, attempt),
        (false, false, true) => kernel::<32, false>(step, state, nodes, roots, attempt),
        (false, false, false) => {
            kernel::<MAX_CHAIN_NODES, false>(step, state, nodes, roots, attempt)
        }
    }
}

/// One instance of the run kernels: chains of at most `N` nodes, XPBD or the position-based
/// step. Each instance is a function of its own (never inlined into [`step_run`]), so a
/// run's stack frame holds one instance's scratch (up to about 80 KiB of lane arrays), not
/// all six: nested rayon jobs can stack several batch frames on one worker thread, and with the
/// six instances in one frame a crowd of 100 small characters overflowed the 2 MiB worker
/// stacks.
#[inline(never)]
fn kernel<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
    attempt: Attempt,
) -> LaneOutcome {
    kernel_body::<N, XPBD>(step, state, nodes, roots, attempt)
}

/// [`kernel`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
fn kernel_avx2<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
    attempt: Attempt,
) -> LaneOutcome {
    kernel_body::<N, XPBD>(step, state, nodes, roots, attempt)
}

#[inline(always)]
fn kernel_body<const N: usize, const XPBD: bool>(
    step: &BatchStep,
    state: BatchState,
    nodes: &[LaneNode],
    roots: &LaneRoots,
    attempt: Attempt,
) -> LaneOutcome {
    if XPBD {
        step_xpbd::<N>(step, state, nodes, roots, attempt)
    } else {
        step_position_based::<N>(step, state, nodes, roots, attempt)
    }
}
