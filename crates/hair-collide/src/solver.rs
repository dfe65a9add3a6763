//! The collision stage of a simulation step: refit the hair hierarchy from the active skeletons,
//! query the bodies, write response, friction (and optional hair–hair) forces into the state's
//! F_col slot before the step, and project penetrating nodes out after it.
//!
//! ```text
//! solver.before_step(&simulation, &mut state, &environment)?;   // F_col for this step
//! simulation.step(&mut state, &environment)?;                    // any integrator
//! solver.after_step(&simulation, &mut state, &environment)?;     // positional guarantee
//! ```
//! or [`CollisionSolver::step`], which does the three. Bodies are given in head space and move
//! rigidly with `environment.head`.

use glam::Vec3;
use hair_core::dynamics::{Environment, RootMode, Simulation, SimulationState};

use crate::body::CollisionBody;
use crate::broad_phase::BroadPhase;
use crate::bvh::HairBvh;
use crate::clearance::{Clearance, carry_clearances};
use crate::error::{CollideError, Result};
use crate::field_contacts::{FieldContacts, query_body_field};
use crate::gather::ActiveHair;
use crate::hair_hair::add_repulsion_forces;
use crate::layout::CollisionChain;
use crate::other_forces::external_force;
use crate::projection_pass::ProjectionPass;
use crate::query::{SegmentContacts, query_body_near, query_body_volumes};
use crate::response::{
    approach_speed, average_normal, friction_force, response_force, rigid_point_velocity,
};
pub use crate::solver_settings::{
    CollisionSettings, CollisionStepReport, ContactReport, PENETRATION_TOLERANCE, ProjectionReport,
    STRETCH_WARNING, VelocityMemory,
};

/// The collision stage of one set of active chains: their hierarchy, the velocity memory of the
/// response and all scratch (nothing is allocated per step once the layout is set, except when
/// the contact count grows). The bodies are not the solver's: every step is handed them (posed
/// there), so several solvers (one per level of detail) share one body per mesh.
pub struct CollisionSolver {
    settings: CollisionSettings,
    /// The number of bodies the clearance cache is laid out for.
    body_count: usize,
    hair: ActiveHair,
    hierarchy: Option<HairBvh>,
    layout_changed: bool,
    rebuild_count: u64,
    contacts: SegmentContacts,
    field_contacts: FieldContacts,
    /// Per touching segment of the body being answered: `(segment, normal in the body's frame)`.
    segment_normals: Vec<(u32, Vec3)>,
    /// With a deforming body: each touching segment's surface velocity besides the pose's
    /// \[m/s\] (body frame), the mean of its touched triangles' vertex velocities, in
    /// `segment_normals`' order.
    segment_surface: Vec<Vec3>,
    chain_sections: Vec<u32>,
    /// Per gathered node: sum of the unit normals of its touching segments.
    node_normals: Vec<Vec3>,
    /// Per gathered node: hair–hair forces.
    gathered_forces: Vec<Vec3>,
    /// Per model node: positions at the previous `before_step`.
    previous_positions: Vec<Vec3>,
    previous_time: Option<f64>,
    /// Per gathered node and body (node-major): the clearance cache of the projection.
    clearances: Vec<Clearance>,
    /// Per active chain: whether the projection's first pass found every node clear.
    all_clear: Vec<bool>,
    /// Per active chain: what the projection's walk along it did.
    chain_reports: Vec<ProjectionReport>,
}

impl std::fmt::Debug for CollisionSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CollisionSolver")
            .field("settings", &self.settings)
            .field("body_count", &self.body_count)
            .field("chains", &self.hair.chains.len())
            .field("rebuild_count", &self.rebuild_count)
            .finish_non_exhaustive()
    }
}

impl CollisionSolver {
    /// A solver with `settings`; no chains yet (see [`CollisionSolver::set_chains`]). The bodies
    /// (meshes in head space, moved by the head) come with every step.
    pub fn new(settings: CollisionSettings) -> Result<Self> {
        settings.validate()?;
        Ok(CollisionSolver {
            settings,
            body_count: 0,
            hair: ActiveHair::default(),
            hierarchy: None,
            layout_changed: true,
            rebuild_count: 0,
            contacts: SegmentContacts::new(),
            field_contacts: FieldContacts::new(),
            segment_normals: Vec::new(),
            segment_surface: Vec::new(),
            chain_sections: Vec::new(),
            node_normals: Vec::new(),
            gathered_forces: Vec::new(),
            previous_positions: Vec::new(),
            previous_time: None,
            clearances: Vec::new(),
            all_clear: Vec::new(),
            chain_reports: Vec::new(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &CollisionSettings {
        &self.settings
    }

    /// Changes the settings (validated).
    pub fn set_settings(&mut self, settings: CollisionSettings) -> Result<()> {
        settings.validate()?;
        self.settings = settings;
        Ok(())
    }

    /// The velocity memory of the response (see [`VelocityMemory`]): part of a run's state, which
    /// a resumed run restores with [`set_velocity_memory`](Self::set_velocity_memory) to step as
    /// the uninterrupted run did.
    pub fn velocity_memory(&self) -> VelocityMemory {
        VelocityMemory {
            positions: self.previous_positions.clone(),
            time: self.previous_time,
        }
    }

    /// Restores the velocity memory saved with [`velocity_memory`](Self::velocity_memory).
    pub fn set_velocity_memory(&mut self, memory: &VelocityMemory) {
        self.previous_positions.clear();
        self.previous_positions.extend_from_slice(&memory.positions);
        self.previous_time = memory.time;
    }

    /// Shrinks every node's clearance from the bodies by `moved` \[m\]: for bodies that changed
    /// shape (a deforming body built again at a new time) with no point of their surface moved
    /// farther than `moved` in their own frame. A node's distance to the new surface is at least
    /// its distance to the old one less `moved` (each surface point is a blend of vertices, none
    /// of which moved farther), so the shrunk clearances still bound it; a clearance that
    /// reaches zero certifies nothing and the next projection measures that node again. A
    /// non-finite or negative `moved` forgets them all.
    pub fn shrink_clearances(&mut self, moved: f32) {
        if !(moved.is_finite() && moved >= 0.0) {
            self.clearances.fill(Clearance::default());
            return;
        }
        for cache in &mut self.clearances {
            cache.clearance = (cache.clearance - moved).max(0.0);
        }
    }

    /// Lays the clearance cache out for `count` bodies (emptied when the count changes: an empty
    /// clearance only costs a closest-point search).
    fn use_bodies(&mut self, count: usize) {
        if self.body_count != count {
            self.body_count = count;
            self.clearances.clear();
        }
        let wanted = self.hair.model_nodes.len() * count;
        if self.clearances.len() != wanted {
            self.clearances.clear();
            self.clearances.resize(wanted, Clearance::default());
        }
    }

    /// Sets the active chains of `simulation`'s model. When they differ from the current ones
    /// (a section changed level) the hierarchy is rebuilt at the next step; otherwise nothing
    /// happens and it keeps being refitted. Errors on an unknown or repeated chain or bad sizes.
    pub fn set_chains(&mut self, simulation: &Simulation, chains: &[CollisionChain]) -> Result<()> {
        if self.hierarchy.is_some() && self.hair.chains == chains {
            return Ok(());
        }
        let model = simulation.model();
        let old_chains = std::mem::take(&mut self.hair.chains);
        let old_offsets = self.hair.chain_offsets.clone();
        if let Err(error) = self.hair.set_layout(&model.rest, chains) {
            self.hair.chains = old_chains;
            return Err(error);
        }
        self.hair.masses.clear();
        self.hair.masses.extend(
            self.hair
                .model_nodes
                .iter()
                .map(|&m| model.node_masses[m as usize]),
        );
        self.layout_changed = true;
        let nodes = self.hair.model_nodes.len();
        self.node_normals.resize(nodes, Vec3::ZERO);
        self.gathered_forces.resize(nodes, Vec3::ZERO);
        self.clearances = carry_clearances(
            (&old_chains, &old_offsets, &self.clearances),
            (&self.hair.chains, &self.hair.chain_offsets),
            self.body_count,
        );
        self.chain_sections.clear();
        self.chain_sections.extend(chains.iter().map(|c| c.section));
        Ok(())
    }

    /// The active chains.
    pub fn chains(&self) -> &[CollisionChain] {
        &self.hair.chains
    }

    /// How many times the hierarchy has been built (once, then once per layout change).
    pub fn rebuild_count(&self) -> u64 {
        self.rebuild_count
    }

    /// The hair hierarchy of the last step, in head space (the bodies' own frame, where
    /// [`query_body`](crate::query_body) takes it); `None` before the first. Its tree is refitted
    /// only with hair–hair contact on; its volumes are always the step's.
    pub fn hierarchy(&self) -> Option<&HairBvh> {
        self.hierarchy.as_ref()
    }

    /// Refits (or, after a layout change, rebuilds) the hierarchy from `state` with the bodies at
    /// the head pose of `state.time`, queries every body and writes F_col into
    /// `state.collision_forces`: response, friction and hair–hair forces on the active nodes,
    /// zero elsewhere.
    pub fn before_step(
        &mut self,
        bodies: &mut [CollisionBody],
        simulation: &Simulation,
        state: &mut SimulationState,
        environment: &Environment,
    ) -> Result<ContactReport> {
        let model = simulation.model();
        check_state(state, model.node_count())?;
        let time_step = simulation.settings().time_step;
        let attached = simulation.settings().roots == RootMode::Attached;
        let head = environment.head.transform_at(state.time);
        let head_before = environment
            .head
            .transform_at(state.time - f64::from(time_step));
        for body in bodies.iter_mut() {
            body.set_pose(head.rotation, head.translation)?;
        }
        self.use_bodies(bodies.len());
        self.hair
            .gather(&model.rest, &state.node_positions, &head)?;
        let mut report = ContactReport::default();
        // The bodies are queried volume by volume through their own trees
        // (`query_body_volumes`): the hair's tree is refitted only for hair–hair contact.
        let volumes_only = self.settings.hair_hair.is_none();
        let use_field = self.settings.broad_phase == BroadPhase::DistanceField;
        let hierarchy = match self.hierarchy.as_mut() {
            Some(hierarchy) if !self.layout_changed => {
                if volumes_only {
                    hierarchy.update_volumes(&self.hair.positions, &self.hair.control_points)?;
                } else {
                    hierarchy.refit(&self.hair.positions, &self.hair.control_points)?;
                }
                hierarchy
            }
            _ => {
                report.rebuilt = true;
                self.rebuild_count += 1;
                self.layout_changed = false;
                self.hierarchy.insert(HairBvh::build(
                    &self.hair.chain_offsets,
                    &self.hair.chain_volumes,
                    &self.hair.positions,
                    &self.hair.control_points,
                )?)
            }
        };
        state.collision_forces.fill(Vec3::ZERO);
        // Node velocities over the last step (positions' change), else the state's.
        let elapsed = self
            .previous_time
            .map_or(0.0, |previous| (state.time - previous) as f32);
        let finite_difference =
            elapsed > 0.0 && self.previous_positions.len() == state.node_positions.len();
        let respond = self.settings.response || self.settings.friction > 0.0;
        self.node_normals.fill(Vec3::ZERO);
        for body in bodies.iter() {
            self.segment_normals.clear();
            self.segment_surface.clear();
            if self.settings.broad_phase == BroadPhase::FieldContacts {
                query_body_field(hierarchy.volumes(), body, &mut self.field_contacts);
                report.contact_segments += self.field_contacts.contacts.len();
                report.exact_fallbacks += self.field_contacts.exact_fallbacks;
                report.remembered += self.field_contacts.remembered;
                self.segment_normals
                    .extend_from_slice(&self.field_contacts.contacts);
                self.segment_surface
                    .extend_from_slice(&self.field_contacts.velocities);
            } else {
                if use_field {
                    query_body_near(hierarchy.volumes(), body, &mut self.contacts);
                } else {
                    query_body_volumes(hierarchy.volumes(), body, &mut self.contacts);
                }
                report.contact_segments += self.contacts.segment_count();
                report.contact_pairs += self.contacts.pair_count();
                let triangles = body.local_triangles();
                let deforming = body.is_deforming();
                for (segment, touched) in self.contacts.iter() {
                    if let Some(normal) = average_normal(triangles, touched) {
                        self.segment_normals.push((segment, normal));
                        if deforming {
                            self.segment_surface
                                .push(body.local_deformation_velocity_of(touched));
                        }
                    }
                }
            }
            if !respond {
                continue;
            }
            for (index, &(segment, local_normal)) in self.segment_normals.iter().enumerate() {
                let normal = head.rotation * local_normal;
                let top = hierarchy.segment_top_nodes()[segment as usize] as usize;
                for node in [top, top + 1] {
                    if attached && self.hair.is_root[node] {
                        continue;
                    }
                    self.node_normals[node] += normal;
                    if !self.settings.response {
                        continue;
                    }
                    let m = self.hair.model_nodes[node] as usize;
                    let p = state.node_positions[m];
                    let velocity = if finite_difference {
                        (p - self.previous_positions[m]) / elapsed
                    } else {
                        state.node_velocities[m]
                    };
                    let deformation = match self.segment_surface.get(index) {
                        Some(local) => head.rotation * *local,
                        // A rigid body's field contacts name no surface velocity: the
                        // closest point's (zero on a rigid body).
                        None => body.deformation_velocity(p),
                    };
                    let surface =
                        rigid_point_velocity(&head_before, &head, p, time_step) + deformation;
                    let speed = approach_speed(velocity, surface, normal);
                    state.collision_forces[m] +=
                        response_force(model.node_masses[m], speed, time_step, normal);
                }
            }
        }
        report.contact_nodes = self
            .node_normals
            .iter()
            .filter(|n| **n != Vec3::ZERO)
            .count();
        if let Some(hair_hair) = &self.settings.hair_hair {
            self.gathered_forces.fill(Vec3::ZERO);
            report.hair_hair_pairs = add_repulsion_forces(
                hierarchy,
                &self.chain_sections,
                &self.hair.masses,
                hair_hair,
                &mut self.gathered_forces,
            )?;
            // The hierarchy is in head space: the forces turn back into the world.
            for (node, force) in self.gathered_forces.iter().enumerate() {
                if !(attached && self.hair.is_root[node]) {
                    state.collision_forces[self.hair.model_nodes[node] as usize] +=
                        head.rotation * *force;
                }
            }
        }
        if self.settings.friction > 0.0 {
            for (node, normal) in self.node_normals.iter().enumerate() {
                let Some(n) = normal.try_normalize() else {
                    continue;
                };
                let m = self.hair.model_nodes[node] as usize;
                let other = external_force(
                    model,
                    environment,
                    m,
                    state.node_positions[m],
                    state.node_velocities[m],
                    state.time,
                );
                state.collision_forces[m] += friction_force(other, n, self.settings.friction);
            }
        }
        self.previous_positions.clear();
        self.previous_positions
            .extend_from_slice(&state.node_positions);
        self.previous_time = Some(state.time);
        Ok(report)
    }

    /// The positional guarantee: with the bodies at the head pose of `state.time`, every active
    /// node inside a body (except attached roots) moves to its closest surface point plus
    /// [`CollisionSettings::skin`], and loses the inward part of its velocity relative to the
    /// surface. Nodes further down a chain than a projected node are first carried after it
    /// (follow-the-leader: each keeps its segment's rest length and direction), so a chain is
    /// pushed out whole instead of torn, and a projected segment is turned about its parent where
    /// that keeps its length (`restore_length`). Afterwards no such node is deeper than
    /// [`PENETRATION_TOLERANCE`] in a closed body, whatever the integrator did, and segments keep
    /// their lengths within 0.1 % unless a parent is itself inside. Does nothing when projection
    /// is off.
    ///
    /// Cost: nodes are skipped while they stay within their last measured clearance (in head
    /// space), so only nodes near a surface pay for a closest-point search.
    pub fn after_step(
        &mut self,
        bodies: &mut [CollisionBody],
        simulation: &Simulation,
        state: &mut SimulationState,
        environment: &Environment,
    ) -> Result<ProjectionReport> {
        if !self.settings.project_positions {
            return Ok(ProjectionReport::default());
        }
        check_state(state, simulation.model().node_count())?;
        let time_step = simulation.settings().time_step;
        let attached = simulation.settings().roots == RootMode::Attached;
        let head = environment.head.transform_at(state.time);
        let head_before = environment
            .head
            .transform_at(state.time - f64::from(time_step));
        for body in bodies.iter_mut() {
            body.set_pose(head.rotation, head.translation)?;
        }
        self.use_bodies(bodies.len());
        let pass = ProjectionPass {
            bodies,
            to_head: head.inverse(),
            head_before,
            head,
            time_step,
            skin: self.settings.skin,
            // The field's certified bounds skip the nodes clear of a body (both field modes).
            use_field: self.settings.broad_phase != BroadPhase::Hierarchies,
            attached,
            chain_offsets: &self.hair.chain_offsets,
            model_nodes: &self.hair.model_nodes,
            is_root: &self.hair.is_root,
            lengths: &simulation.model().rest.segment_rest_lengths,
        };
        let report = pass.run(
            &mut state.node_positions,
            &mut state.node_velocities,
            &mut self.clearances,
            &mut self.all_clear,
            &mut self.chain_reports,
        );
        Ok(report)
    }

    /// One full step: [`before_step`](Self::before_step), `simulation.step`,
    /// [`after_step`](Self::after_step). A dynamics failure is returned as
    /// [`CollideError::Dynamics`] (the state is then as the dynamics left it).
    pub fn step(
        &mut self,
        bodies: &mut [CollisionBody],
        simulation: &mut Simulation,
        state: &mut SimulationState,
        environment: &Environment,
    ) -> Result<CollisionStepReport> {
        let contacts = self.before_step(bodies, simulation, state, environment)?;
        let dynamics = simulation.step(state, environment)?;
        let projection = self.after_step(bodies, simulation, state, environment)?;
        Ok(CollisionStepReport {
            contacts,
            dynamics,
            projection,
        })
    }
}

fn check_state(state: &SimulationState, node_count: usize) -> Result<()> {
    for (what, actual) in [
        ("node_positions", state.node_positions.len()),
        ("node_velocities", state.node_velocities.len()),
        ("collision_forces", state.collision_forces.len()),
    ] {
        if actual != node_count {
            return Err(CollideError::SizeMismatch {
                what,
                actual,
                expected: node_count,
            });
        }
    }
    Ok(())
}
