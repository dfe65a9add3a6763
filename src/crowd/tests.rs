//! Crowd tests: a crowd of one is its pipeline bit for bit, one budget sends detail to the
//! character that needs it, the grooms are drawn on offset chains, and every character shows in
//! the picture.

use glam::Vec3;
use hair_core::lod::{CostModel, CostRates};
use hair_core::{Camera, Level};

use super::render::concatenated_geometry;
use super::*;
use crate::pipeline::{Character, DrawnSource, LodMode, Pipeline, PipelineSettings};
use crate::scene_file::SceneFile;
use crate::shot::Shot;

/// A small groom (grown, not hung: quick to build) for every character.
const GROOM: &str = "[groom]\npreset = \"straight\"\nsection_count = 8\nstrands_per_group = 4\n\
                     rest_pose = \"grown\"\n[dynamics]\nsettle_seconds = 0.0\n";

pub(super) fn shot(characters: &str) -> Shot {
    SceneFile::parse(&format!("{GROOM}{characters}"))
        .and_then(|file| file.resolve())
        .unwrap()
}

fn camera_at(position: Vec3, target: Vec3) -> Camera {
    let mut camera = Camera::orbit(Vec3::ZERO, 1.0, 0.0, 0.0, 35f32.to_radians());
    camera.position = position;
    camera.target = target;
    camera
}

#[test]
fn a_crowd_of_one_is_its_pipeline_bit_for_bit() {
    let shot = shot("[[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"shake\" }\n");
    let model = CrowdModel::build(&shot).unwrap();
    let member = &model.members[0];
    let mut crowd = Crowd::new(&model, shot.settings).unwrap();
    let mut alone = Pipeline::new(
        member.scene.clone(),
        member.character.environment.clone(),
        shot.settings,
    )
    .unwrap();
    let camera = shot.camera(0);
    for _ in 0..4 {
        let summed = crowd.advance(&camera).unwrap();
        let own = alone.advance(&camera).unwrap();
        assert_eq!(summed.sections_at, own.sections_at);
        assert_eq!(summed.simulated_nodes, own.simulated_nodes);
        assert_eq!(summed.drawn_at, own.drawn_at);
    }
    let pipeline = &crowd.world().characters()[0];
    for level in Level::ALL {
        assert_eq!(
            pipeline.block(level).state.node_positions,
            alone.block(level).state.node_positions,
            "{} block",
            level.name()
        );
    }
}

#[test]
fn one_budget_sends_detail_to_the_near_character() {
    // Two characters with the same groom, one 0.8 m from the camera and one 12 m away, both
    // facing it. The near one's sections project ~15× larger, so each pixel of error it saves
    // costs the same as the far one's: the greedy choice refines it first.
    let shot = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n\
         [[character]]\nposition = [0.2, 0.0, -11.2]\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    assert!(matches!(shot.settings.lod, LodMode::Auto(_)));
    let camera = camera_at(Vec3::new(0.0, 0.05, 0.8), Vec3::new(0.0, 0.0, -1.0));
    let rates = CostRates::default();
    let mean_rank = |pipeline: &Character| {
        let levels = pipeline.section_levels();
        levels.iter().map(|&l| l as usize as f64).sum::<f64>() / levels.len() as f64
    };
    // Budgets from the floors' cost up to all strands (a section's strands cost ~0.3 ms under
    // the priors): wherever the two differ, the near character is the finer.
    let mut differed = 0;
    for k in 1..=16 {
        let budget = rates.overhead + f64::from(k) * 3e-4;
        let mut crowd = Crowd::new(&model, shot.settings).unwrap();
        crowd
            .set_frame_budget(Some((budget, CostModel::new(rates).unwrap())))
            .unwrap();
        crowd.advance(&camera).unwrap();
        let outcome = crowd.budget_outcome().expect("a budgeted frame");
        assert!(
            outcome.over_budget || outcome.cost <= budget - rates.overhead + 1e-12,
            "{outcome:?} over {budget}"
        );
        let (near, far) = (
            mean_rank(&crowd.world().characters()[0]),
            mean_rank(&crowd.world().characters()[1]),
        );
        assert!(
            near >= far,
            "budget {budget}: near {near} coarser than far {far}"
        );
        differed += usize::from(near > far);
        crowd.set_frame_budget(None).unwrap();
        assert!(crowd.budget_outcome().is_none());
    }
    assert!(
        differed >= 4,
        "the budgets hardly separated the two: {differed}"
    );
}

#[test]
fn grooms_are_drawn_on_chains_after_the_characters_before() {
    let shot = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n\
         [[character]]\nposition = [1.0, 0.0, 0.0]\ngroom = { preset = \"curly\", section_count = 5, \
         strands_per_group = 3, rest_pose = \"grown\" }\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    let [first, second] = [&model.members[0].scene.groom, &model.members[1].scene.groom];
    let geometry = concatenated_geometry(&model);
    let strands = first.strands.strand_count();
    assert_eq!(
        geometry.strand_chain.len(),
        strands + second.strands.strand_count()
    );
    let offset = first.skeletons.chain_count() as u32;
    let own = hair_render::GroomGeometry::new(second);
    assert_eq!(
        geometry.strand_chain[strands..],
        own.strand_chain
            .iter()
            .map(|c| c + offset)
            .collect::<Vec<_>>()[..]
    );
    assert_eq!(
        geometry.patch_chain[first.section_count()..],
        own.patch_chain
            .iter()
            .map(|c| c + offset)
            .collect::<Vec<_>>()[..]
    );
    for values in [&geometry.strand_lengths, &geometry.strand_tip_scales] {
        assert!(values.is_empty() || values.len() == geometry.strand_chain.len());
    }
}

#[test]
fn scene_file_characters_are_placed_and_their_errors_named() {
    let shot =
        shot("[[character]]\nname = \"left\"\nposition = [-1.0, 0.0, -3.0]\nyaw_degrees = 90.0\n");
    let character = &shot.characters[0];
    assert_eq!(character.name, "left");
    // The head's centre (head-space origin) stands at the position at every time.
    let centre = character
        .environment
        .head
        .transform_at(0.3)
        .transform_point(Vec3::ZERO);
    assert!(
        (centre - Vec3::new(-1.0, 0.0, -3.0)).length() < 1e-6,
        "{centre}"
    );
    let facing = character.placement.transform_vector(Vec3::Z);
    assert!((facing - Vec3::X).length() < 1e-6, "{facing}");
    let error = SceneFile::parse(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n[[character]]\nposition = [1.0, 0.0, 0.0]\n\
         groom = { preset = \"mohawk\" }\n",
    )
    .unwrap_err();
    assert!(
        error.to_string().contains("character[1].groom.preset"),
        "{error}"
    );
    let error = SceneFile::parse("[[character]]\nposition = [0.0, 0.0, 0.0]\nyaw_degrees = nan\n")
        .unwrap_err();
    assert!(
        error.to_string().contains("character[0].yaw_degrees"),
        "{error}"
    );
}

#[test]
fn every_character_shows_in_the_picture() {
    // Two characters side by side seen from the front; the same crowd without the right one
    // leaves the right half of the picture as empty as the background.
    let both = shot(
        "[[character]]\nposition = [-0.3, 0.0, 0.0]\n[[character]]\nposition = [0.3, 0.0, 0.0]\n",
    );
    let left = shot("[[character]]\nposition = [-0.3, 0.0, 0.0]\n");
    let camera = camera_at(Vec3::new(0.0, 0.0, 1.6), Vec3::ZERO);
    let settings = PipelineSettings {
        lod: LodMode::Fixed(Level::Cluster),
        ..both.settings
    };
    let options = hair_render::RendererOptions::from_env().unwrap();
    let right_half_changed = |shot: &Shot| {
        let model = CrowdModel::build(shot).unwrap();
        let mut crowd = Crowd::new(&model, settings).unwrap();
        crowd.advance(&camera).unwrap();
        let mut renderer = CrowdRenderer::new(&options, &model).unwrap();
        let (image, _) = renderer
            .render(
                &mut crowd,
                &camera,
                (128, 72),
                hair_render::ShadingMode::Shaded,
            )
            .unwrap();
        let background = *image.get_pixel(127, 0);
        let changed = |x0: u32, x1: u32| {
            (x0..x1)
                .flat_map(|x| (0..72).map(move |y| (x, y)))
                .filter(|&(x, y)| *image.get_pixel(x, y) != background)
                .count()
        };
        (changed(0, 64), changed(64, 128))
    };
    let (both_left, both_right) = right_half_changed(&both);
    let (only_left, only_right) = right_half_changed(&left);
    assert!(
        both_left > 200 && only_left > 200,
        "{both_left} {only_left}"
    );
    assert!(
        both_right > 200,
        "the right character is drawn: {both_right} pixels"
    );
    assert!(
        only_right < both_right / 4,
        "{only_right} against {both_right}"
    );
}

#[test]
fn characters_stepped_side_by_side_do_not_depend_on_the_thread_count() {
    let shot = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"shake\" }\n\
         [[character]]\nposition = [0.4, 0.0, -0.3]\nwind = { speed = 3.0, gusts = 2.0 }\n\
         [[character]]\nposition = [-0.4, 0.0, -0.6]\nmotion = { kind = \"nod\" }\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    let run = |threads: usize| -> Vec<Vec<Vec3>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut crowd = Crowd::new(&model, shot.settings).unwrap();
            for frame in 0..6 {
                crowd.advance(&shot.camera(frame)).unwrap();
            }
            crowd
                .world()
                .characters()
                .iter()
                .flat_map(|p| Level::ALL.map(|l| p.block(l).state.node_positions.clone()))
                .collect()
        })
    };
    let one = run(1);
    assert!(one == run(4), "one thread and four differ");
    // The characters move differently (the comparison can fail).
    assert!(one[0] != one[3]);
}

#[test]
fn stepping_side_by_side_charges_the_frame_its_wall_time() {
    // Two characters each measured 30 ms of dynamics and 10 ms of collision: 80 ms summed, but
    // the frame took 50 ms. The frame keeps 50 ms, split 3 : 1 as the characters' own times.
    let mut report = crate::pipeline::FrameReport::default();
    report.times.dynamics = 0.060;
    report.times.collision = 0.020;
    report.level_seconds = [0.020, 0.0, 0.060];
    crate::pipeline::charge_wall_time(&mut report, 0.050);
    assert!((report.times.dynamics - 0.0375).abs() < 1e-12);
    assert!((report.times.collision - 0.0125).abs() < 1e-12);
    assert!((report.level_seconds[0] - 0.0125).abs() < 1e-12);
    assert!((report.level_seconds[2] - 0.0375).abs() < 1e-12);
    // Nothing measured: nothing to share.
    let mut idle = crate::pipeline::FrameReport::default();
    crate::pipeline::charge_wall_time(&mut idle, 0.050);
    assert_eq!(idle.times.dynamics, 0.0);
}

/// Every character's pipeline collides with one shared body: the head's mesh and tree are held
/// once, and each pipeline poses its own copy.
#[test]
fn the_characters_share_one_collision_body() {
    let shot = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"shake\" }\n\
         [[character]]\nposition = [1.0, 0.0, 0.0]\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    let mut crowd = Crowd::new(&model, shot.settings).unwrap();
    crowd.advance(&shot.camera(0)).unwrap();
    crowd.advance(&shot.camera(1)).unwrap();
    assert_eq!(crowd.world().characters().len(), 2);
    let (a, b) = (
        crowd.collision_body(0).unwrap(),
        crowd.collision_body(1).unwrap(),
    );
    assert!(a.shares_shape_with(b) && a.shares_shape_with(&model.members[0].body));
    // Each is posed at its own head: the second character stands 1 m to the side.
    let (pose_a, pose_b) = (a.pose(), b.pose());
    assert!((pose_b.1 - pose_a.1).x > 0.5, "{pose_a:?} {pose_b:?}");
}

/// The memory estimate counts the shared head once and each character's pipeline once per
/// character, and a crowd over what is available is refused before its pipelines are built,
/// naming its size and the estimate.
#[test]
fn a_crowd_over_the_available_memory_is_refused_before_it_is_built() {
    let one = shot("[[character]]\nposition = [0.0, 0.0, 0.0]\n");
    let three = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n\
         [[character]]\nposition = [1.0, 0.0, 0.0]\n\
         [[character]]\nposition = [2.0, 0.0, 0.0]\n",
    );
    let one = CrowdModel::build(&one).unwrap();
    let three = CrowdModel::build(&three).unwrap();
    // The three characters wear one groom: one scene and one collision body, shared.
    assert!(std::sync::Arc::ptr_eq(
        &three.members[0].scene,
        &three.members[2].scene
    ));
    assert!(
        three.members[0]
            .body
            .shares_shape_with(&three.members[2].body)
    );
    let settings = three.shot.settings;
    let triangles = three.members[0].scene.head.mesh.triangles.len() as u64;
    let body = triangles * memory::BYTES_PER_BODY_TRIANGLE;
    let alone = memory::estimated_bytes(&one, &settings);
    let each = alone - body;
    assert!(alone > body);
    assert_eq!(memory::estimated_bytes(&three, &settings), body + 3 * each);
    // Without collision there is no body to hold.
    let no_collision = PipelineSettings {
        collision: false,
        ..settings
    };
    assert_eq!(memory::estimated_bytes(&three, &no_collision), 3 * each);
    let needed = body + 3 * each;
    assert!(memory::check_fits(&three, &settings, Some(needed)).is_ok());
    assert!(memory::check_fits(&three, &settings, None).is_ok());
    let error = memory::check_fits(&three, &settings, Some(needed - 1))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("3 characters") && error.contains("GiB") && error.contains("collision"),
        "{error}"
    );
}

/// Characters with different grooms on one head share the head's collision body: it is built
/// once per head, not once per groom.
#[test]
fn different_grooms_on_one_head_share_its_collision_body() {
    let shot = shot(
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n\
         [[character]]\nposition = [1.0, 0.0, 0.0]\ngroom = { preset = \"curly\", section_count = 5, \
         strands_per_group = 3, rest_pose = \"grown\" }\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    let [first, second] = [&model.members[0], &model.members[1]];
    assert!(!std::sync::Arc::ptr_eq(&first.scene, &second.scene));
    assert!(first.body.shares_shape_with(&second.body));
}

/// A crowd on a deforming head draws each head deformed: the joined mesh holds, for each
/// character, its body's mesh at the time the skeletons are at, placed by its head's pose
/// (reference: the sequence's own interpolation, `MeshSequence::mesh_at`, posed). It is made
/// again every frame, as the body moves every frame; a rigid crowd's is made only when a pose
/// or a tessellation changed.
#[test]
fn a_crowd_on_a_deforming_head_draws_each_head_deformed() {
    let shot = shot(
        "[body]\nanimation = \"talk\"\n[frames]\ncount = 30\n\
         [[character]]\nposition = [0.0, 0.0, 0.0]\nmotion = { kind = \"nod\" }\n\
         [[character]]\nposition = [1.0, 0.0, 0.0]\n",
    );
    let model = CrowdModel::build(&shot).unwrap();
    let mut crowd = Crowd::new(&model, shot.settings).unwrap();
    let camera = shot.camera(0);
    let mut heads = super::heads::CrowdHeads::new(&model);
    for frame in 0..3 {
        crowd.advance(&shot.camera(frame)).unwrap();
    }
    let poses = crowd.head_poses();
    let deformed = crowd.deformed_bodies();
    assert_eq!(deformed.len(), 2);
    let mesh = heads
        .mesh_to_draw(&poses, &deformed, &camera, 540)
        .expect("a first mesh");
    let time = crowd.world().characters()[0].time();
    let motion = model.members[0].scene.body_motion.as_ref().unwrap();
    let at_time = motion.mesh_at(time);
    let rest = &model.members[0].scene.head.mesh;
    assert_eq!(at_time.positions.len(), rest.positions.len());
    let count = at_time.positions.len();
    assert_eq!(mesh.positions.len(), 2 * count);
    assert_eq!(mesh.triangles.len(), 2 * at_time.triangles.len());
    let mut moved = 0.0f32;
    for (k, pose) in poses.iter().enumerate() {
        for (v, &p) in at_time.positions.iter().enumerate() {
            let expected = pose.transform_point(p);
            let drawn = mesh.positions[k * count + v];
            // The same arithmetic on the same inputs: equal to rounding.
            assert!(
                drawn.distance(expected) < 1e-6,
                "{k} {v}: {drawn} {expected}"
            );
            moved = moved.max(drawn.distance(pose.transform_point(rest.positions[v])));
        }
    }
    // The talking head has deformed by now (the jaw and the squash move millimetres): the
    // drawn heads are not the rest mesh posed.
    assert!(moved > 1e-3, "moved {moved} m");
    // A deforming head's mesh is made again with the same poses.
    assert!(
        heads
            .mesh_to_draw(&poses, &deformed, &camera, 540)
            .is_some()
    );
    // Rigid heads (no body given): made once, then not again while nothing changes.
    let mut rigid = super::heads::CrowdHeads::new(&model);
    assert!(rigid.mesh_to_draw(&poses, &[], &camera, 540).is_some());
    assert!(rigid.mesh_to_draw(&poses, &[], &camera, 540).is_none());
}
