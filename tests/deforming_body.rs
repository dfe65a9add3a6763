//! A head that deforms (`[body] animation = "talk"`: the jaw opens and closes, the head squashes
//! and stretches, and the scene's nod moves it on top): every root rides its triangle, keeping
//! its rest offset from its barycentric point in the triangle's own frame (the procedural head's
//! roots lie on its analytic surface, up to 0.24 mm off the tessellated mesh), and no node ends a
//! frame more than 0.1 mm inside the deformed body, through a 2 s run at each fixed level and
//! with automatic levels; drawn as strands from patches or from automatic levels, every drawn
//! strand group starts on its own carried root too. The reference is the deformed mesh itself, sampled by the test from
//! the scene's motion and measured with `attach_roots` (closest points) and `penetration_depth` (signed distances).

use glam::{Mat3, Vec3};
use hairlod::accuracy::penetration_depth;
use hairlod::collide::{CollisionBody, attach_roots};
use hairlod::render::ActiveSkeletons;
use hairlod::{Level, SceneFile};

/// A triangle's orthonormal frame: first edge, in-plane perpendicular, normal.
fn triangle_frame([a, b, c]: [Vec3; 3]) -> Mat3 {
    let edge = (b - a).normalize();
    let normal = (b - a).cross(c - a).normalize();
    Mat3::from_cols(edge, normal.cross(edge), normal)
}

/// Penetration tolerance [m] (the 0.1 mm).
const TOLERANCE: f32 = 1e-4;

/// How far a root may lie from where its triangle carries it [m]: f32 rounding of positions a
/// few decimetres from the origin, through the carry's rotation and the nod's.
const ROOT_TOLERANCE: f32 = 1e-5;

/// Runs the talking head 2 s at level mode `mode`, drawn as `drawn_as` (`level` or
/// `strands`), and checks every frame's roots, depths and (drawn as strands) drawn roots.
fn run(mode: &str, drawn_as: &str) {
    let text = format!(
        "[groom]\npreset = \"straight\"\nsection_count = 10\nstrands_per_group = 1\n\
         [body]\nanimation = \"talk\"\n[motion]\nkind = \"nod\"\namplitude_degrees = 8.0\n\
         [lod]\nmode = \"{mode}\"\ndrawn_as = \"{drawn_as}\"\n\
         [frames]\ncount = 120\nsize = \"320x180\"\n"
    );
    let shot = SceneFile::parse(&text).unwrap().resolve().unwrap();
    let scene = shot.build_scene().unwrap();
    let motion = scene.body_motion.clone().expect("a deforming head");
    // Where each groom skeleton chain's root rides, measured on the rest mesh.
    let rest = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
    let roots = &scene.groom.skeletons.root_positions;
    let (attachments, report) = attach_roots(&rest, roots).unwrap();
    // Each root's offset from its point, in its triangle's rest frame.
    let vertices = |mesh: &hairlod::core::TriangleMesh, triangle: u32| {
        mesh.triangles[triangle as usize].map(|v| mesh.positions[v as usize])
    };
    let offsets: Vec<Vec3> = attachments
        .iter()
        .zip(roots)
        .map(|(a, &root)| {
            triangle_frame(vertices(&scene.head.mesh, a.triangle)).transpose()
                * (root - a.point_on(&scene.head.mesh))
        })
        .collect();
    assert!(report.max < 3e-4, "roots near the mesh: {report:?}");
    let mut pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let (mut worst_root, mut worst_depth, mut moved) = (0.0f32, 0.0f32, 0.0f32);
    let (mut worst_drawn, mut drawn_chains) = (0.0f32, 0usize);
    let mut active = ActiveSkeletons::new();
    for frame in 0..shot.frames {
        pipeline.advance(&shot.camera(frame)).unwrap();
        let time = pipeline.time();
        let mesh = motion.mesh_at(time);
        let head = pipeline.head_pose();
        // Where chain `chain`'s root is carried: its rest offset turned with its triangle.
        let carried = |chain: usize| {
            let attachment = &attachments[chain];
            let on_mesh = attachment.point_on(&mesh)
                + triangle_frame(vertices(&mesh, attachment.triangle)) * offsets[chain];
            head.transform_point(on_mesh)
        };
        let mut body = CollisionBody::from_mesh(&mesh).unwrap();
        body.set_pose(head.rotation, head.translation).unwrap();
        for level in Level::ALL {
            let block = pipeline.block(level);
            let positions = &block.state.node_positions;
            if positions.is_empty() {
                continue;
            }
            // Every root on its barycentric point of the deformed, posed mesh.
            let nodes_per_chain = positions.len() / block.chains.len();
            for (k, &chain) in block.chains.iter().enumerate() {
                let root = positions[k * nodes_per_chain];
                worst_root = worst_root.max(root.distance(carried(chain)));
            }
        }
        // Drawn as strands, every strand group drawn (rebuilt from the level simulated) starts
        // on its own carried root.
        if drawn_as == "strands" {
            pipeline.gather_drawn(&mut active).unwrap();
            let frame = active.frame();
            for chain in scene.groom.level_chains(Level::StrandGroup) {
                let start = frame.chain_offsets[chain] as usize;
                if frame.chain_offsets[chain + 1] as usize > start {
                    let root = frame.node_positions[start];
                    worst_drawn = worst_drawn.max(root.distance(carried(chain)));
                    drawn_chains += 1;
                }
            }
        }
        // No node inside by more than the tolerance (signed distances to the deformed mesh
        // where the sign is sure: `CollisionBody::signed_distance`).
        worst_depth = worst_depth.max(penetration_depth(&pipeline, &body));
        // How far the scalp moved from rest: what a rigid head's collision would have missed.
        for (a, b) in mesh.positions.iter().zip(&scene.head.mesh.positions) {
            moved = moved.max(a.distance(*b));
        }
    }
    eprintln!(
        "{mode}: roots within {worst_root} m, deepest node {worst_depth} m inside, the mesh \
         moved up to {moved} m; {drawn_chains} strand groups drawn within {worst_drawn} m"
    );
    if drawn_as == "strands" {
        assert!(drawn_chains > 0, "{mode}: no strand group drawn");
        assert!(
            worst_drawn <= ROOT_TOLERANCE,
            "{mode}: a drawn strand group's root {worst_drawn} m from its place"
        );
    }
    // The head deformed by far more than the tolerance (centimetres): the collision followed it.
    assert!(moved > 0.01, "{mode}: the mesh moved only {moved} m");
    assert!(
        worst_root <= ROOT_TOLERANCE,
        "{mode}: a root {worst_root} m from its place"
    );
    assert!(
        worst_depth <= TOLERANCE,
        "{mode}: a node {worst_depth} m inside"
    );
}

#[test]
fn roots_ride_a_talking_head_and_no_node_enters_it_at_the_strand_level() {
    run("strands", "level");
}

#[test]
fn roots_ride_a_talking_head_and_no_node_enters_it_as_patches_drawn_as_strands() {
    run("patches", "strands");
}

#[test]
fn roots_ride_a_talking_head_and_no_node_enters_it_with_automatic_levels_drawn_as_strands() {
    run("auto", "strands");
}

/// The shipped deforming scene resolves to the talking head and runs a frame with it.
#[test]
fn the_shipped_talking_head_scene_deforms() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/talking-head.toml");
    let mut shot = SceneFile::read(std::path::Path::new(path))
        .unwrap()
        .resolve()
        .unwrap();
    assert_eq!(
        shot.body_animation,
        Some(hairlod::body_animation::BodyAnimation::talk())
    );
    shot.frames = 2;
    let scene = shot.build_scene().unwrap();
    let motion = scene.body_motion.as_ref().expect("a deforming head");
    assert!(motion.is_animated());
    let mut pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let report = pipeline.advance(&shot.camera(0)).unwrap();
    assert!(report.body_update > 0.0, "{report:?}");
}

/// The level selection's occluder boxes on the talking head (`carried_occluders` through the
/// rest field's rigid fit, as the pipeline carries them every frame): at every frame of its 2 s
/// animation, every point of a 5 × 5 × 5 grid over every carried box is inside the deformed
/// mesh (the exact signed distance is negative), and no box is shrunk away. The reference is
/// the deformed mesh itself.
#[test]
fn carried_occluder_boxes_stay_inside_the_talking_head() {
    use hairlod::collide::RestField;
    let shot = SceneFile::parse("[body]\nanimation = \"talk\"\n")
        .unwrap()
        .resolve()
        .unwrap();
    let scene = shot.build_scene().unwrap();
    let motion = scene.body_motion.clone().expect("a deforming head");
    let rest_boxes = scene.head.occluder_boxes();
    let volume = |boxes: &[(Vec3, Vec3)]| -> f32 {
        boxes
            .iter()
            .map(|(l, h)| (*h - *l).max(Vec3::ZERO).element_product())
            .sum()
    };
    let field = RestField::of(&CollisionBody::from_mesh(&scene.head.mesh).unwrap());
    let prepared = field.boxes(&rest_boxes);
    let (mut carried, mut worst, mut least_kept, mut rest_out) = (Vec::new(), f32::MIN, 1.0f32, 0);
    let mut fewest = usize::MAX;
    for frame in 0..120 {
        let mesh = motion.mesh_at(frame as f64 / 60.0);
        let zero = vec![Vec3::ZERO; mesh.positions.len()];
        let body = CollisionBody::from_moving_mesh(&mesh, zero)
            .unwrap()
            .reading_rest_field(&field)
            .unwrap();
        assert!(body.carried_occluders(&prepared, &mut carried));
        least_kept = least_kept.min(volume(&carried) / volume(&rest_boxes));
        fewest = fewest.min(carried.len());
        let grid = |(low, high): (Vec3, Vec3)| {
            (0..125).map(move |i| {
                let t = Vec3::new((i % 5) as f32, ((i / 5) % 5) as f32, (i / 25) as f32) / 4.0;
                low + (high - low) * t
            })
        };
        let depth = |p: Vec3| body.closest_local_surface_point(p).unwrap().signed_distance;
        for p in carried.iter().flat_map(|&b| grid(b)) {
            worst = worst.max(depth(p));
        }
        rest_out += rest_boxes
            .iter()
            .flat_map(|&b| grid(b))
            .filter(|&p| depth(p) > 0.0)
            .count();
    }
    eprintln!(
        "carried boxes: nearest the surface {} m inside, at least {least_kept} of their volume \
         kept; rest boxes' grid points outside the deformed head: {rest_out}",
        -worst
    );
    assert!(
        worst < 0.0,
        "a carried box's point {worst} m outside the deformed head"
    );
    // Every box survives every frame: the head's boxes lie well inside it, and the talk
    // moves its surface by millimetres near them.
    assert_eq!(fewest, rest_boxes.len(), "boxes shrunk away");
}
