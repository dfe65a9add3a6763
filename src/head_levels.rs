//! Head meshes by size on screen: a procedural head tessellated coarser and coarser, each
//! tessellation with its measured deviation from the finest, and the choice of the coarsest
//! whose deviation projects within half a pixel.
//!
//! A crowd's heads 10–40 m away cover a few dozen pixels, yet each was drawn with the full
//! 12,096 triangles of the default head; the paper's zoom-out ends with the head 10 m away.
//! Both renderers ([`crate::pipeline::PipelineRenderer`], [`crate::crowd::CrowdRenderer`]) draw
//! each head at [`HeadLevels::select`]'s choice. The choice depends only on the camera and the
//! head's place, never on the hair's levels, so every mode of a benchmark draws the same heads
//! and the comparisons between modes are unchanged.

use std::sync::Mutex;

use glam::Vec3;
use hair_collide::Triangle;
use hair_collide::closest::closest_point_on_triangle;
use hair_core::head::tessellation::tessellate;
use hair_core::{Camera, Head, RigidTransform, TriangleMesh};

/// Largest projected deviation \[pixels\] of the head mesh drawn from the finest one.
pub const HEAD_PIXEL_TOLERANCE: f32 = 0.5;

/// Fewest bands, latitude or longitude, of a coarser tessellation (the procedural head's
/// minimum).
const MIN_BANDS: usize = 8;

/// One tessellation of a head.
#[derive(Debug, Clone)]
pub struct HeadLevel {
    /// The mesh in head space \[m\].
    pub mesh: TriangleMesh,
    /// The largest distance from a vertex of the finest mesh to this mesh \[m\] (0 for the finest).
    pub deviation: f32,
}

/// A head's tessellations, finest first, with the bounding sphere of the finest.
#[derive(Debug, Clone)]
pub struct HeadLevels {
    levels: Vec<HeadLevel>,
    /// Centre of the finest mesh's bounding box, head space \[m\].
    centre: Vec3,
    /// Largest distance from `centre` to a vertex of the finest mesh \[m\].
    radius: f32,
}

impl HeadLevels {
    /// The levels of `head`: its own mesh, then for the procedural head the same surface with
    /// half the latitude and longitude bands, and half again, while both stay at least 8. A
    /// mesh read from a file has its own mesh only.
    pub fn new(head: &Head) -> HeadLevels {
        let finest = &head.mesh;
        let mut levels = vec![HeadLevel {
            mesh: finest.clone(),
            deviation: 0.0,
        }];
        if head.is_procedural() {
            let (mut latitude, mut longitude) =
                (head.params.latitude_bands, head.params.longitude_bands);
            while latitude / 2 >= MIN_BANDS && longitude / 2 >= MIN_BANDS {
                latitude /= 2;
                longitude /= 2;
                let mesh = tessellate(latitude, longitude);
                let key = [
                    head.params.latitude_bands,
                    head.params.longitude_bands,
                    latitude,
                    longitude,
                ];
                let deviation = cached_deviation(key, || deviation_from(finest, &mesh));
                levels.push(HeadLevel { mesh, deviation });
            }
        }
        let (low, high) = finest.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
        let centre = 0.5 * (low + high);
        let radius = finest
            .positions
            .iter()
            .map(|p| p.distance(centre))
            .fold(0.0, f32::max);
        HeadLevels {
            levels,
            centre,
            radius,
        }
    }

    /// The tessellations, finest first.
    pub fn levels(&self) -> &[HeadLevel] {
        &self.levels
    }

    /// The index of the coarsest level whose deviation, seen from `camera` in an image
    /// `height` pixels tall with the head at `pose`, spans at most `tolerance` pixels. The
    /// deviation is projected at the head's nearest possible point (the centre's distance less
    /// the bounding radius), so no part of the head errs by more; a camera within the bounding
    /// sphere gets the finest.
    pub fn select(
        &self,
        camera: &Camera,
        height: u32,
        pose: &RigidTransform,
        tolerance: f32,
    ) -> usize {
        let distance = pose.transform_point(self.centre).distance(camera.position) - self.radius;
        if distance.is_nan() || distance <= 0.0 {
            return 0;
        }
        let pixels_per_metre = camera.focal_length_pixels(height) / distance;
        self.levels
            .iter()
            .rposition(|level| level.deviation * pixels_per_metre <= tolerance)
            .unwrap_or(0)
    }
}

/// The procedural surface's deviations measured so far, by the bands of the finest and the
/// coarser tessellation (the surface is fixed, so the bands say which meshes they were).
static DEVIATIONS: Mutex<Vec<([usize; 4], f32)>> = Mutex::new(Vec::new());

/// `measure()` the first time `key` is asked for in this process, the stored value after.
fn cached_deviation(key: [usize; 4], measure: impl FnOnce() -> f32) -> f32 {
    let known = DEVIATIONS
        .lock()
        .map(|known| known.iter().find(|(k, _)| *k == key).map(|&(_, d)| d))
        .unwrap_or(None);
    if let Some(deviation) = known {
        return deviation;
    }
    let deviation = measure();
    if let Ok(mut known) = DEVIATIONS.lock() {
        known.push((key, deviation));
    }
    deviation
}

/// The largest distance \[m\] from a vertex of `fine` to the surface of `coarse` (brute force over
/// `coarse`'s triangles, pruned by their bounding spheres).
pub fn deviation_from(fine: &TriangleMesh, coarse: &TriangleMesh) -> f32 {
    let triangles: Vec<(Triangle, Vec3, f32)> = coarse
        .triangles
        .iter()
        .map(|t| {
            let vertices = t.map(|i| coarse.positions[i as usize]);
            let centre = (vertices[0] + vertices[1] + vertices[2]) / 3.0;
            let radius = vertices
                .iter()
                .map(|v| v.distance(centre))
                .fold(0.0, f32::max);
            (
                Triangle::new(vertices[0], vertices[1], vertices[2]),
                centre,
                radius,
            )
        })
        .collect();
    let mut worst = 0.0f32;
    for &p in &fine.positions {
        let mut best = f32::INFINITY;
        for (triangle, centre, radius) in &triangles {
            if p.distance(*centre) - radius >= best {
                continue;
            }
            let (closest, _) = closest_point_on_triangle(p, triangle);
            best = best.min(p.distance(closest));
        }
        worst = worst.max(best);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use hair_core::HeadParams;

    fn head() -> Head {
        Head::procedural(&HeadParams::default()).unwrap()
    }

    #[test]
    fn a_plane_lifted_by_a_distance_deviates_by_that_distance() {
        // Two triangles of the unit square at z = 0, and the same square's vertices at z = 0.003:
        // every lifted vertex lies 0.003 m above the square's interior or edge.
        let square = TriangleMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let mut lifted = square.clone();
        for p in &mut lifted.positions {
            p.z += 0.003;
        }
        assert!((deviation_from(&lifted, &square) - 0.003).abs() < 1e-7);
        assert_eq!(deviation_from(&square, &square), 0.0);
    }

    #[test]
    fn coarser_levels_halve_the_bands_and_deviate_more() {
        let head = head();
        let levels = HeadLevels::new(&head);
        let levels = levels.levels();
        // 64 × 96 bands, then 32 × 48, 16 × 24, 8 × 12: 2·lon·(lat − 1) triangles each.
        let triangles: Vec<usize> = levels.iter().map(|l| l.mesh.triangles.len()).collect();
        assert_eq!(
            triangles,
            [2 * 96 * 63, 2 * 48 * 31, 2 * 24 * 15, 2 * 12 * 7]
        );
        assert_eq!(levels[0].deviation, 0.0);
        for pair in levels.windows(2) {
            assert!(
                pair[1].deviation > pair[0].deviation,
                "{:?}",
                levels.iter().map(|l| l.deviation).collect::<Vec<_>>()
            );
        }
        // Against the sagitta of the widest ring: a chord of a circle of radius r cut by n equal
        // sides lies r·(1 − cos(π/n)) inside it, 2.5 mm for the cranium's 0.074 m half-width at
        // 12 longitude bands, and no level can do better than its ring's sagitta. The neck's
        // ends, rounded over 8 mm (`shape.rs`), are sharper than any ring: at 7 latitude bands
        // a band corner cuts them by up to about a centimetre, still under a tenth of the
        // head's height.
        let sagitta = |r: f32, n: f32| r * (1.0 - (std::f32::consts::PI / n).cos());
        for (level, n) in levels[1..].iter().zip([48.0, 24.0, 12.0]) {
            assert!(
                level.deviation >= sagitta(0.074, n),
                "{} m at {n}",
                level.deviation
            );
        }
        assert!(levels[3].deviation < 0.02, "{} m", levels[3].deviation);
    }

    #[test]
    fn a_file_mesh_has_one_level() {
        let procedural = head();
        let mesh = Head::from_mesh(procedural.mesh.clone(), Vec::new()).unwrap();
        assert_eq!(HeadLevels::new(&mesh).levels().len(), 1);
    }

    #[test]
    fn selection_is_the_coarsest_level_within_the_tolerance() {
        let levels = HeadLevels::new(&head());
        let pose = RigidTransform::default();
        let height = 540;
        for distance in [0.05, 0.5, 1.0, 3.0, 10.0, 40.0] {
            let camera = Camera::looking_at(Vec3::new(0.0, 0.0, distance), Vec3::ZERO, 0.6);
            let chosen = levels.select(&camera, height, &pose, HEAD_PIXEL_TOLERANCE);
            let near = camera.position.distance(levels.centre) - levels.radius;
            let pixels = |level: &HeadLevel| {
                if near <= 0.0 {
                    f32::INFINITY
                } else {
                    level.deviation * camera.focal_length_pixels(height) / near
                }
            };
            let all = levels.levels();
            if near > 0.0 {
                assert!(pixels(&all[chosen]) <= HEAD_PIXEL_TOLERANCE, "{distance} m");
            } else {
                assert_eq!(chosen, 0);
            }
            if let Some(coarser) = all.get(chosen + 1) {
                assert!(pixels(coarser) > HEAD_PIXEL_TOLERANCE, "{distance} m");
            }
        }
        // Up close the finest, 40 m away the coarsest.
        let near = Camera::looking_at(Vec3::new(0.0, 0.0, 0.5), Vec3::ZERO, 0.6);
        let far = Camera::looking_at(Vec3::new(0.0, 0.0, 40.0), Vec3::ZERO, 0.6);
        assert_eq!(levels.select(&near, height, &pose, HEAD_PIXEL_TOLERANCE), 0);
        assert_eq!(levels.select(&far, height, &pose, HEAD_PIXEL_TOLERANCE), 3);
    }
}
