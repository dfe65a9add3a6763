//! Every strand the renderer draws on a deforming head starts on its own carried root: the
//! skeletons draw each strand at its rest offset from its group's chain, which a stretching skin
//! does not keep, so the frame loop shifts each strand (`Pipeline::strand_root_shifts`, handed
//! to `Renderer::set_strand_root_shifts`) onto where its triangle carries its root.
//!
//! The reference is the deformed mesh itself, sampled by the test from the scene's motion:
//! each strand's rest root (the first point of its rest polyline, `strand_polylines`) keeps its
//! offset from its barycentric point (`attach_roots`, closest points on the rest mesh) in its
//! triangle's own frame. The drawn root (`drawn_strand_root` on the gathered skeletons, the
//! point `strands.wgsl` draws at u = 0) plus its shift must land there, through a 2 s talk with
//! a nod at automatic levels drawn as strands, on skeletons rebuilt from patches, and for each
//! character of a crowd.

use glam::{Mat3, Vec3};
use hairlod::collide::{CollisionBody, RootAttachment, attach_roots};
use hairlod::core::representation::drawn::{ChainStart, drawn_strand_root};
use hairlod::core::representation::geometry::strand_polylines;
use hairlod::core::{Scene, TriangleMesh};
use hairlod::crowd::{Crowd, CrowdModel};
use hairlod::render::{ActiveSkeletons, SkeletonFrame};
use hairlod::{Level, RigidTransform, SceneFile};

/// A triangle's orthonormal frame: first edge, in-plane perpendicular, normal.
fn triangle_frame([a, b, c]: [Vec3; 3]) -> Mat3 {
    let edge = (b - a).normalize();
    let normal = (b - a).cross(c - a).normalize();
    Mat3::from_cols(edge, normal.cross(edge), normal)
}

fn vertices(mesh: &TriangleMesh, triangle: u32) -> [Vec3; 3] {
    mesh.triangles[triangle as usize].map(|v| mesh.positions[v as usize])
}

/// How far a shifted root may lie from where its triangle carries it [m]: f32 rounding of
/// positions a few decimetres from the origin through the carry's rotation and the nod's, as
/// for the skeletons' own roots (`deforming_body.rs`).
const ROOT_TOLERANCE: f32 = 1e-5;

/// Where each strand of a scene's groom rides its rest mesh: its triangle and its rest root's
/// offset in the triangle's frame.
struct Carried {
    attachments: Vec<RootAttachment>,
    offsets: Vec<Vec3>,
}

impl Carried {
    fn of(scene: &Scene) -> Carried {
        let groom = &scene.groom;
        let (positions, frames) = groom.skeletons.rest_pose(&RigidTransform::IDENTITY);
        let lines = strand_polylines(groom, &positions, &frames, 1).unwrap();
        let rest_roots: Vec<Vec3> = (0..lines.curve_count())
            .map(|s| lines.points[lines.offsets[s] as usize])
            .collect();
        let rest = CollisionBody::from_mesh(&scene.head.mesh).unwrap();
        let (attachments, _) = attach_roots(&rest, &rest_roots).unwrap();
        let mesh = &scene.head.mesh;
        let offsets = attachments
            .iter()
            .zip(&rest_roots)
            .map(|(a, &root)| {
                triangle_frame(vertices(mesh, a.triangle)).transpose() * (root - a.point_on(mesh))
            })
            .collect();
        Carried {
            attachments,
            offsets,
        }
    }

    /// Strand `strand`'s carried root on `mesh` (head space) with the head at `head`.
    fn root(&self, strand: usize, mesh: &TriangleMesh, head: &RigidTransform) -> Vec3 {
        let a = &self.attachments[strand];
        head.transform_point(
            a.point_on(mesh) + triangle_frame(vertices(mesh, a.triangle)) * self.offsets[strand],
        )
    }
}

/// What a check saw: the farthest shifted root from its carried place [m], the largest shift
/// [m], the strands drawn and the chains drawn that were rebuilt from another level.
#[derive(Default)]
struct Seen {
    worst: f32,
    largest_shift: f32,
    drawn: usize,
    rebuilt: usize,
}

impl Seen {
    /// Checks one character's strands in `gathered`, its chains from `first_chain` and its
    /// strands' shifts from `first_strand`, its body `mesh` and head `head`.
    #[allow(clippy::too_many_arguments)]
    fn character(
        &mut self,
        scene: &Scene,
        carried: &Carried,
        gathered: &SkeletonFrame<'_>,
        shifts: &[Vec3],
        (first_chain, first_strand): (usize, usize),
        mesh: &TriangleMesh,
        head: &RigidTransform,
    ) {
        let groom = &scene.groom;
        for (group, chain) in groom.level_chains(Level::StrandGroup).enumerate() {
            let chain = first_chain + chain;
            let start = gathered.chain_offsets[chain] as usize;
            if (gathered.chain_offsets[chain + 1] as usize) < start + 2 {
                continue;
            }
            if gathered.chain_simulated_at[chain].is_some() {
                self.rebuilt += 1;
            }
            let chain_start = ChainStart {
                first: gathered.node_positions[start],
                second: gathered.node_positions[start + 1],
                normal: gathered.node_normals[start],
                binormal: gathered.node_binormals[start],
            };
            for strand in groom.strands.strands(group) {
                let root = drawn_strand_root(
                    &chain_start,
                    groom.strands.root_offsets[strand],
                    groom.strands.profile(strand),
                );
                let shift = shifts[first_strand + strand];
                let place = carried.root(strand, mesh, head);
                self.worst = self.worst.max((root + shift).distance(place));
                self.largest_shift = self.largest_shift.max(shift.length());
                self.drawn += 1;
            }
        }
    }

    /// The checks every run makes, `what` naming it.
    fn assert_on_their_roots(&self, what: &str) {
        eprintln!(
            "{what}: {} drawn strands ({} rebuilt chains) within {} m of their carried roots; \
             shifts up to {} m",
            self.drawn, self.rebuilt, self.worst, self.largest_shift
        );
        assert!(self.drawn > 0, "{what}: no strand drawn");
        assert!(
            self.worst <= ROOT_TOLERANCE,
            "{what}: a drawn root {} m from its place",
            self.worst
        );
        // The shifts are what put them there: unshifted, the roots would be off by more than
        // the tolerance (the skin stretches by a few percent under the strands' rest offsets).
        assert!(
            self.largest_shift > 10.0 * ROOT_TOLERANCE,
            "{what}: shifts of at most {} m",
            self.largest_shift
        );
    }
}

/// The talking head's scene text at level mode `mode`, drawn as strands, `more` added.
fn talking_head(mode: &str, more: &str) -> String {
    format!(
        "[groom]\npreset = \"wavy\"\nsection_count = 10\nstrands_per_group = 6\n\
         [body]\nanimation = \"talk\"\n[motion]\nkind = \"nod\"\namplitude_degrees = 8.0\n\
         [lod]\nmode = \"{mode}\"\ndrawn_as = \"strands\"\n\
         [frames]\ncount = 120\nsize = \"320x180\"\n{more}"
    )
}

/// Runs the talking head 2 s at level mode `mode` and checks every drawn strand's shifted root.
fn check_drawn_roots(mode: &str) -> Seen {
    let shot = SceneFile::parse(&talking_head(mode, ""))
        .unwrap()
        .resolve()
        .unwrap();
    let scene = shot.build_scene().unwrap();
    let motion = scene.body_motion.clone().expect("a deforming head");
    let carried = Carried::of(&scene);
    let mut pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
    let (mut active, mut shifts, mut seen) = (ActiveSkeletons::new(), Vec::new(), Seen::default());
    for frame in 0..shot.frames {
        pipeline.advance(&shot.camera(frame)).unwrap();
        let mesh = motion.mesh_at(pipeline.time());
        pipeline.gather_drawn(&mut active).unwrap();
        pipeline.strand_root_shifts(&active, &mut shifts);
        assert_eq!(shifts.len(), scene.groom.strands.strand_count());
        let head = pipeline.head_pose();
        seen.character(
            &scene,
            &carried,
            &active.frame(),
            &shifts,
            (0, 0),
            &mesh,
            &head,
        );
    }
    seen.assert_on_their_roots(mode);
    seen
}

#[test]
fn every_drawn_strand_starts_on_its_own_carried_root_with_automatic_levels() {
    check_drawn_roots("auto");
}

#[test]
fn every_strand_drawn_from_patches_starts_on_its_own_carried_root() {
    let seen = check_drawn_roots("patches");
    assert!(seen.rebuilt > 0, "no chain rebuilt from patches");
}

/// Two talking heads, apart and turned, nodding out of step: each character's strands are
/// shifted on its own chains and its own head, after the strands of the one before.
#[test]
fn every_crowd_characters_drawn_strands_start_on_their_carried_roots() {
    let shot = SceneFile::parse(&talking_head(
        "strands",
        "[[character]]\nposition = [0.0, 0.0, 0.0]\n\
         [[character]]\nposition = [0.5, 0.0, -0.3]\nyaw_degrees = 40.0\n\
         motion = { kind = \"shake\", amplitude_degrees = 15.0 }\n",
    ))
    .unwrap()
    .resolve()
    .unwrap();
    let model = CrowdModel::build(&shot).unwrap();
    let mut crowd = Crowd::new(&model, shot.settings).unwrap();
    let scenes: Vec<_> = crowd
        .world()
        .characters()
        .iter()
        .map(|c| c.model().scene().clone())
        .collect();
    assert_eq!(scenes.len(), 2);
    let carried: Vec<Carried> = scenes.iter().map(Carried::of).collect();
    let (mut active, mut shifts, mut seen) = (ActiveSkeletons::new(), Vec::new(), Seen::default());
    for frame in 0..30 {
        crowd.advance(&shot.camera(frame)).unwrap();
        active.clear();
        crowd.append_drawn(&mut active).unwrap();
        crowd.strand_root_shifts(&active, &mut shifts);
        let (mut first_chain, mut first_strand) = (0, 0);
        for (k, character) in crowd.world().characters().iter().enumerate() {
            let scene = &scenes[k];
            let motion = scene.body_motion.as_ref().expect("a deforming head");
            let mesh = motion.mesh_at(character.time());
            let head = character.head_pose();
            let at = (first_chain, first_strand);
            seen.character(
                scene,
                &carried[k],
                &active.frame(),
                &shifts,
                at,
                &mesh,
                &head,
            );
            first_chain += scene.groom.skeletons.chain_count();
            first_strand += scene.groom.strands.strand_count();
        }
        assert_eq!(shifts.len(), first_strand);
    }
    seen.assert_on_their_roots("crowd");
}

/// The pipeline's renderer draws a deforming head's strands shifted, and a rigid head's not.
#[test]
fn the_pipeline_renderer_shifts_a_deforming_heads_strands_only() {
    for (body, deforming) in [("[body]\nanimation = \"talk\"\n", true), ("", false)] {
        let text = format!("[groom]\nsection_count = 4\n{body}[frames]\ncount = 2\n");
        let shot = SceneFile::parse(&text).unwrap().resolve().unwrap();
        let scene = shot.build_scene().unwrap();
        let mut pipeline = shot.pipeline(&scene, shot.settings, None).unwrap();
        pipeline.advance(&shot.camera(0)).unwrap();
        let options = hairlod::render::RendererOptions::from_env().unwrap();
        let mut renderer = hairlod::pipeline::PipelineRenderer::new(&options, &scene).unwrap();
        renderer
            .render(
                &mut pipeline,
                &shot.camera(0),
                64,
                36,
                hairlod::render::ShadingMode::Shaded,
            )
            .unwrap();
        assert_eq!(renderer.renderer().strands_shifted(), deforming, "{text}");
    }
}
