//! Shared test support: a seeded xorshift generator, and random geometry.
#![allow(dead_code)]

use glam::{Quat, Vec3};

/// xorshift64* (Vigna 2016): tiny, seeded, deterministic on every platform.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }

    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [low, high).
    pub fn range(&mut self, low: f32, high: f32) -> f32 {
        low + (high - low) * self.unit()
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in the cube [-half, half]³.
    pub fn vec3(&mut self, half: f32) -> Vec3 {
        Vec3::new(
            self.range(-half, half),
            self.range(-half, half),
            self.range(-half, half),
        )
    }

    /// A unit vector, uniform on the sphere.
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec3(1.0);
            let l = v.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }

    /// A uniformly random rotation.
    pub fn rotation(&mut self) -> Quat {
        loop {
            let q = Quat::from_xyzw(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = q.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return q.normalize();
            }
        }
    }
}

/// A UV sphere mesh of `radius` [m] around `center`, counter-clockwise seen from outside.
pub fn uv_sphere(center: Vec3, radius: f32, rings: u32, sectors: u32) -> hair_core::TriangleMesh {
    let mut positions = vec![center + Vec3::Y * radius];
    for ring in 1..rings {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        for sector in 0..sectors {
            let phi = std::f32::consts::TAU * sector as f32 / sectors as f32;
            positions.push(
                center
                    + radius
                        * Vec3::new(
                            theta.sin() * phi.cos(),
                            theta.cos(),
                            theta.sin() * phi.sin(),
                        ),
            );
        }
    }
    positions.push(center - Vec3::Y * radius);
    let bottom = positions.len() as u32 - 1;
    let index = |ring: u32, sector: u32| 1 + (ring - 1) * sectors + sector % sectors;
    let mut triangles = Vec::new();
    for sector in 0..sectors {
        triangles.push([0, index(1, sector + 1), index(1, sector)]);
        triangles.push([
            bottom,
            index(rings - 1, sector),
            index(rings - 1, sector + 1),
        ]);
    }
    for ring in 1..rings - 1 {
        for sector in 0..sectors {
            let (a, b) = (index(ring, sector), index(ring, sector + 1));
            let (c, d) = (index(ring + 1, sector), index(ring + 1, sector + 1));
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    let mut mesh = hair_core::TriangleMesh {
        positions,
        normals: Vec::new(),
        triangles,
    };
    mesh.compute_vertex_normals();
    mesh
}

/// f64 distance from point to segment, an independent reference.
pub fn point_segment_distance_f64(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let (p, a, b) = (p.as_dvec3(), a.as_dvec3(), b.as_dvec3());
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

/// f64 distance from a point to a filled rectangle by clamping local coordinates.
pub fn point_rectangle_distance_f64(p: Vec3, rectangle: &hair_collide::Rectangle) -> f64 {
    let local = (p - rectangle.center).as_dvec3();
    let u = rectangle.axes[0].as_dvec3();
    let v = rectangle.axes[1].as_dvec3();
    let cu = local.dot(u).clamp(
        -rectangle.half_extents[0] as f64,
        rectangle.half_extents[0] as f64,
    );
    let cv = local.dot(v).clamp(
        -rectangle.half_extents[1] as f64,
        rectangle.half_extents[1] as f64,
    );
    (local - u * cu - v * cv).length()
}

/// parry3d's own signed distance to a closed mesh (a `TriMesh` with oriented pseudonormals),
/// an independent reference for `CollisionBody::signed_distance`. Points are in the mesh's frame.
pub struct ParrySignedDistance(parry3d::shape::TriMesh);

impl ParrySignedDistance {
    pub fn new(mesh: &hair_core::TriangleMesh) -> Self {
        let trimesh = parry3d::shape::TriMesh::with_flags(
            mesh.positions.clone(),
            mesh.triangles.clone(),
            parry3d::shape::TriMeshFlags::ORIENTED,
        )
        .expect("a valid mesh");
        ParrySignedDistance(trimesh)
    }

    /// Signed distance [m] of `p` (mesh frame): negative inside.
    pub fn at(&self, p: Vec3) -> f32 {
        use parry3d::query::PointQuery;
        let projection = self.0.project_local_point(p, false);
        let distance = projection.point.distance(p);
        if projection.is_inside {
            -distance
        } else {
            distance
        }
    }
}

/// The active chains of the mixed-level groom as their own skeleton model, and their collision
/// chains renumbered to it.
pub fn mixed_levels(
    groom: &hair_core::Groom,
) -> (hair_core::SkeletonRest, Vec<hair_collide::CollisionChain>) {
    let levels: Vec<hair_core::Level> = (0..groom.section_count())
        .map(|s| hair_core::Level::ALL[s % 3])
        .collect();
    let mut chains = Vec::new();
    hair_collide::groom_active_chains(groom, &levels, &mut chains).unwrap();
    let mut rest = hair_core::SkeletonRest::default();
    let all = &groom.skeletons;
    for (index, chain) in chains.iter_mut().enumerate() {
        let c = chain.chain as usize;
        let nodes = all.nodes(c);
        let angles = hair_core::skeleton::ChainAngles {
            segment_lengths: all.segment_rest_lengths[nodes.clone()].to_vec(),
            polar_angles: all.rest_polar_angles[nodes.clone()].to_vec(),
            azimuth_angles: all.rest_azimuth_angles[nodes].to_vec(),
        };
        rest.push_chain(all.root_positions[c], all.root_frames[c], &angles)
            .unwrap();
        chain.chain = index as u32;
    }
    (rest, chains)
}

/// A position-based simulation of every skeleton of `groom` (all three levels), with the
/// dynamics parameters of its style at the integrator's recommended settings.
pub fn groom_simulation(groom: &hair_core::Groom) -> hair_core::dynamics::Simulation {
    use hair_core::dynamics::{
        DynamicsModel, DynamicsParams, IntegratorKind, Simulation, SimulationSettings,
    };
    let model = DynamicsModel::new(
        groom.skeletons.clone(),
        DynamicsParams::for_style(&groom.params.style),
    )
    .unwrap();
    Simulation::new(
        model,
        SimulationSettings::recommended(IntegratorKind::PositionBased),
    )
    .unwrap()
}

/// Each edge of `mesh` (its two vertex indices, lower first) with the triangles along it.
pub fn mesh_edges(
    mesh: &hair_core::TriangleMesh,
) -> std::collections::HashMap<(u32, u32), Vec<usize>> {
    let mut edges: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    edges
}

/// The angle [rad] between the normals of triangles `f` and `g` of `mesh`.
pub fn bend_between(mesh: &hair_core::TriangleMesh, f: usize, g: usize) -> f32 {
    let normal = |t: usize| {
        let [a, b, c] = mesh.triangles[t].map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a).normalize_or_zero()
    };
    normal(f).dot(normal(g)).clamp(-1.0, 1.0).acos()
}
