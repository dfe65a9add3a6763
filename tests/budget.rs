//! The frame-budget modes on a real pipeline, whatever the machine's speed (no timing is
//! asserted).
//!
//! - The tolerance controller: a budget no frame can meet drives the pixel tolerance to its
//!   largest value and is reported as never met, and a budget every frame meets by far drives it
//!   to its smallest; the larger tolerance keeps no more sections detailed than a fixed 1 px run.
//! - The greedy method (least estimated error within the budget): a budget no frame can meet
//!   keeps every section at its floor (no strands; clusters only where a rule or motion asks),
//!   and a budget every frame meets by far puts every visible section at strand level (the only
//!   level with no estimated error).

use hairlod::Scene;
use hairlod::benchmark::{paper_shot, resized, run_budgeted, run_mode};
use hairlod::core::lod::{BudgetMethod, BudgetSettings, LodSettings};
use hairlod::pipeline::{LodMode, PipelineRenderer, PipelineSettings};
use hairlod::render::RendererOptions;
use hairlod::shot::Shot;

fn benchmark() -> Shot {
    resized(&paper_shot(false), 12, 96, 54)
}

fn run(budget_seconds: f64) -> hairlod::benchmark::BudgetedRun {
    run_with(budget_seconds, BudgetMethod::Tolerance)
}

fn run_with(budget_seconds: f64, method: BudgetMethod) -> hairlod::benchmark::BudgetedRun {
    let benchmark = benchmark();
    let scene = Scene::preset("curly").unwrap();
    let mut renderer =
        PipelineRenderer::new(&RendererOptions::from_env().unwrap(), &scene).unwrap();
    let lod = LodSettings {
        pixel_tolerance: 1.0,
        ..benchmark.lod_settings()
    };
    let settings = BudgetSettings {
        min_tolerance: 0.5,
        max_tolerance: 32.0,
        method,
        ..BudgetSettings::new(budget_seconds)
    };
    let mut seen = 0;
    let run = run_budgeted(
        &benchmark,
        &scene,
        lod,
        settings,
        &mut renderer,
        |_, _, _| seen += 1,
    )
    .unwrap();
    assert_eq!(seen, benchmark.frames);
    run
}

#[test]
fn an_impossible_budget_saturates_the_tolerance_and_is_never_met() {
    // 1 µs: no frame (dynamics, collision and a render) is that fast. Each frame's cost ratio to
    // the aim is at least 1000, so with gain 0.5 and smoothing 0.5 the tolerance grows by a factor
    // of at least about √500 ≈ 22 per frame and reaches the 32 px cap from 1 px within 2 frames.
    let run = run(1e-6);
    assert_eq!(run.budget.met, 0, "{:?}", run.budget);
    assert_eq!(run.tolerances[0], 1.0);
    assert!(
        run.tolerances[3..].iter().all(|&t| t == 32.0),
        "{:?}",
        run.tolerances
    );
    assert_eq!(run.budget.max_tolerance, 32.0);
    // A larger tolerance never asks for more detail: at the last frame, no more sections are at
    // strand level, and no more at cluster level or finer, than in the same run at 1 px.
    let benchmark = benchmark();
    let fixed = run_mode(
        &benchmark,
        &Scene::preset("curly").unwrap(),
        PipelineSettings {
            lod: LodMode::Auto(LodSettings {
                pixel_tolerance: 1.0,
                ..benchmark.lod_settings()
            }),
            ..PipelineSettings::default()
        },
        None,
        |_| Ok(()),
    )
    .unwrap();
    let [_, budget_clusters, budget_strands] = run.run.frames.last().unwrap().sections_at;
    let [_, clusters, strands] = fixed.frames.last().unwrap().sections_at;
    assert!(budget_strands <= strands, "{budget_strands} > {strands}");
    assert!(budget_strands + budget_clusters <= strands + clusters);
    assert!(strands + clusters > 0, "the 1 px run keeps some detail");
}

#[test]
fn a_generous_budget_lowers_the_tolerance_to_its_floor_and_is_always_met() {
    // 1000 s per frame: every frame costs far less than the 900 s aim, so the tolerance shrinks
    // by a large factor each frame down to the 0.5 px floor, and every frame meets the budget.
    let run = run(1000.0);
    assert_eq!(run.budget.met, run.budget.frames);
    assert!(
        run.tolerances[3..].iter().all(|&t| t == 0.5),
        "{:?}",
        run.tolerances
    );
}

#[test]
fn greedy_an_impossible_budget_keeps_every_section_at_its_floor() {
    let run = run_with(1e-6, BudgetMethod::Greedy);
    assert_eq!(run.budget.met, 0, "{:?}", run.budget);
    assert_eq!(run.budget.method, BudgetMethod::Greedy);
    // The first frame starts every section at strand level and hands it down; from then on
    // nothing is refined: no strands (calm air, still head: no motion floor), and the
    // part-line and face rule keeps clusters at most.
    for report in &run.run.frames[1..] {
        let [_, _, strands] = report.sections_at;
        assert_eq!(
            strands, 0,
            "frame {}: {:?}",
            report.frame, report.sections_at
        );
    }
    // The tolerance is not steered.
    assert!(
        run.tolerances.iter().all(|&t| t == 1.0),
        "{:?}",
        run.tolerances
    );
}

#[test]
fn greedy_a_generous_budget_draws_every_visible_section_as_strands() {
    let run = run_with(1000.0, BudgetMethod::Greedy);
    assert_eq!(run.budget.met, run.budget.frames);
    for report in &run.run.frames {
        let [_, _, strands] = report.sections_at;
        assert_eq!(
            strands, report.visible_sections,
            "frame {}: {:?}, {} visible",
            report.frame, report.sections_at, report.visible_sections
        );
    }
}
