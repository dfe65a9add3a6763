//! Grooms loaded from files under gravity: the TressFX samples fitted (`hair_core::fit`), their
//! skeletons made sag-free (`make_sag_free`, the code path of the presets' hanging pose) and
//! simulated for 2 s with a still head, no wind and no body, move less than the same skeletons
//! without it. With loose straight hair's stiffness the springs cannot hold all of these shapes
//! (a mohawk stands up, a ponytail's tail leaves its tie sideways): the joints they cannot hold are
//! clamped and sag (printed with `-- --nocapture`); the body's contact, which this test leaves
//! out, and a material as stiff as the style (gel) are what hold the rest.

use hairlod::core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, IntegratorKind, STANDARD_GRAVITY, Simulation,
    SimulationSettings, TurnLimit, make_sag_free,
};
use hairlod::core::fit::{FitSettings, fit_hierarchy};
use hairlod::formats::{ImportAxes, ImportOptions, read_curves_file};
use hairlod::{HairStyle, RigidTransform, SkeletonRest};

/// A TressFX sample (`hairlod::core::samples`); panics naming the file when it is missing.
fn data_file(name: &str) -> std::path::PathBuf {
    hairlod::core::samples::tressfx_file(name).unwrap_or_else(|error| panic!("{error}"))
}

/// Mean and largest node displacement [m] after 2 s of the default integrator.
fn drift(rest: SkeletonRest, params: DynamicsParams) -> (f32, f32) {
    let model = DynamicsModel::new(rest, params).unwrap();
    let settings = SimulationSettings::recommended(IntegratorKind::DEFAULT);
    let mut simulation = Simulation::new(model, settings).unwrap();
    let environment = Environment::default();
    let mut state = simulation.rest_state(&environment, 0.0);
    let start = state.node_positions.clone();
    simulation.run(&mut state, &environment, 120).unwrap();
    let d: Vec<f32> = start
        .iter()
        .zip(&state.node_positions)
        .map(|(a, b)| a.distance(*b))
        .collect();
    (
        d.iter().sum::<f32>() / d.len() as f32,
        d.iter().copied().fold(0.0, f32::max),
    )
}

#[test]
#[ignore = "needs the TressFX samples (HAIRLOD_DATA, or ../shared/data beside the repository); .ci/run runs it"]
fn loaded_grooms_keep_their_shape_under_gravity() {
    let params = DynamicsParams::for_style(&HairStyle::straight(0.02));
    for (file, scale) in [
        ("ratboy_mohawk.tfx", 1.0),
        ("ponytail_back.tfx", 0.01),
        ("ponytail_tail.tfx", 0.01),
    ] {
        let options = ImportOptions {
            axes: ImportAxes {
                scale_to_metres: scale,
                ..ImportAxes::default()
            },
            ..ImportOptions::default()
        };
        let curves = read_curves_file(data_file(file), &options).unwrap();
        let fit = fit_hierarchy(&curves, &FitSettings::default()).unwrap();
        let loaded = fit.skeleton_rest().unwrap();
        let mut balanced = loaded.clone();
        let report = make_sag_free(
            &mut balanced,
            &params,
            &RigidTransform::IDENTITY,
            STANDARD_GRAVITY,
            &[],
            TurnLimit::Clamp,
        )
        .unwrap();
        let (fall_mean, fall_max) = drift(loaded, params);
        let (mean, max) = drift(balanced, params);
        eprintln!(
            "{file}: {} chains, clamped joints {}, largest turn {:.2} rad; 2 s under gravity: \
             mean {:.2} mm (max {:.1} mm) sag-free, {:.1} mm (max {:.1} mm) without",
            report.chains,
            report.clamped_joints,
            report.max_turn,
            mean * 1e3,
            max * 1e3,
            fall_mean * 1e3,
            fall_max * 1e3
        );
        assert!(
            mean < fall_mean,
            "{file}: sag-free moved {mean} m on average, without {fall_mean} m"
        );
    }
}
