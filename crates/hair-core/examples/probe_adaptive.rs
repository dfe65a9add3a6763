//! Throwaway probe (not committed): how often XPBD's adaptive substeps fire.
use glam::Vec3;
use hair_core::dynamics::*;
use hair_core::{GroomParams, HairStyle, HeadParams, Level, Scene};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let smoothness: f32 = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(0.0);
    let substeps: u32 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(8);
    let shake: f32 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(3.0);
    let wind: f32 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(3.0);
    let steps: usize = args.get(5).map(|s| s.parse().unwrap()).unwrap_or(120);
    let base = GroomParams::paper_curly();
    let mut params = base.clone();
    if smoothness > 0.0 {
        params.style = HairStyle {
            smoothness,
            ..base.style
        };
    }
    let scene = Scene::new(&HeadParams::default(), &params).unwrap();
    let groups = level_skeletons(&scene.groom, Level::StrandGroup).unwrap();
    println!("nodes per chain {}", groups.nodes(0).len());
    let dp = DynamicsParams::for_style(&scene.groom.params.style);
    let model = DynamicsModel::new(groups, dp).unwrap();
    let env = Environment {
        head: if shake > 0.0 {
            HeadMotion::shake(0.5, shake)
        } else {
            HeadMotion::default()
        },
        wind: if wind > 0.0 {
            WindField::gusting(Vec3::X * wind, wind / 3.0, 0.7, 0.3, 11)
        } else {
            WindField::Calm
        },
        gravity: STANDARD_GRAVITY,
    };
    let mut sim = Simulation::new(
        model,
        SimulationSettings::new(IntegratorKind::Xpbd, 1.0 / 60.0, substeps),
    )
    .unwrap();
    let mut state = sim.rest_state(&env, 0.0);
    let (mut halved, mut most, mut steps_halved) = (0usize, 0u32, 0usize);
    let t = std::time::Instant::now();
    for _ in 0..steps {
        let r = sim.step(&mut state, &env).unwrap();
        halved += r.halved_chains;
        most = most.max(r.max_halvings);
        steps_halved += usize::from(r.halved_chains > 0);
        if r.halved_chains > 0 && std::env::var("V").is_ok() {
            let vmax = state
                .node_velocities
                .iter()
                .map(|v| v.length())
                .fold(0.0f32, f32::max);
            println!(
                "  t {:.3} halved {} most {} vmax {vmax:.2}",
                state.time, r.halved_chains, r.max_halvings
            );
        }
    }
    println!(
        "x{substeps} shake {shake} wind {wind}: {steps} steps, chain-steps halved {halved}, steps with any {steps_halved}, most halvings {most}, {:.2} s",
        t.elapsed().as_secs_f64()
    );
}
