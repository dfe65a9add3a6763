//! Sparse grooms (guides only) detected by their roots' density on the scalp, and the child
//! strands grown around each guide by default ([`auto_children`]), as TressFX grows follow hairs:
//! a DCC export whose children were never applied, or a guide set such as Sintel's 228 strands,
//! would otherwise look bald.

use glam::Vec3;
use hair_core::groom::ChildStrands;
use serde::Serialize;

/// Below this many strands per square metre of scalp a groom is sparse (2 per cm²; a human
/// scalp holds about 150 per cm², real-time grooms 10–40 per cm²).
pub const SPARSE_STRANDS_PER_M2: f32 = 2.0e4;

/// The density [strands/m²] children are grown to (20 per cm²).
pub const CHILD_TARGET_STRANDS_PER_M2: f32 = 2.0e5;

/// Children are grown to at most this many strands in all (the paper's curly groom has 37,765).
pub const MAX_GROWN_STRANDS: usize = 40_000;

/// A groom with at least this many strands is not measured and never sparse: a head at
/// [`SPARSE_STRANDS_PER_M2`] holds a few thousand strands at most.
pub const DENSE_STRAND_COUNT: usize = 20_000;

/// Neighbours of the density estimate.
const NEIGHBOURS: usize = 8;

/// Roots measured, at most (evenly spaced through the groom).
const MEASURED_ROOTS: usize = 512;

/// What the automatic children did.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GrownChildren {
    /// The file's strands per square metre of scalp (median of the roots' local densities).
    pub root_density: f32,
    /// Children grown per file strand.
    pub per_strand: usize,
    /// The disc radius [m] children are spread over around their guide.
    pub spread: f32,
}

/// The roots' density on the scalp [strands/m²]: at each measured root, `(k − 1)/(π·r_k²)` with
/// `r_k` the distance to its `k`-th nearest other root (k = 8), the median over at most 512
/// roots spread evenly through the groom. `None` for fewer than `k + 1` roots, or where the
/// `k`-th neighbour lies on the root itself (stacked roots).
///
/// For roots on a square grid of spacing `s` the 8th neighbour lies at `s·√2`, so the estimate
/// is `7/(2π s²) = 1.11/s²` for a true `1/s²`: within 11 %, enough to tell a guide set (well
/// under [`SPARSE_STRANDS_PER_M2`]) from a groom.
pub fn root_density(roots: &[Vec3]) -> Option<f32> {
    if roots.len() <= NEIGHBOURS {
        return None;
    }
    let stride = roots.len().div_ceil(MEASURED_ROOTS);
    let mut densities = Vec::new();
    let mut nearest = [f32::INFINITY; NEIGHBOURS];
    for (index, root) in roots.iter().enumerate().step_by(stride) {
        nearest.fill(f32::INFINITY);
        for (other, point) in roots.iter().enumerate() {
            if other == index {
                continue;
            }
            let squared = root.distance_squared(*point);
            if squared < nearest[NEIGHBOURS - 1] {
                // Insert, keeping the k nearest sorted.
                let mut slot = NEIGHBOURS - 1;
                while slot > 0 && nearest[slot - 1] > squared {
                    nearest[slot] = nearest[slot - 1];
                    slot -= 1;
                }
                nearest[slot] = squared;
            }
        }
        let radius_squared = nearest[NEIGHBOURS - 1];
        if radius_squared > 0.0 {
            densities.push((NEIGHBOURS - 1) as f32 / (std::f32::consts::PI * radius_squared));
        }
    }
    if densities.is_empty() {
        return None;
    }
    densities.sort_by(f32::total_cmp);
    Some(densities[densities.len() / 2])
}

/// The children a groom of `roots` (its file strands' roots [m]) gets by default: `None` when it
/// is not sparse (at least [`DENSE_STRAND_COUNT`] strands, too few roots to measure, or a
/// density of at least [`SPARSE_STRANDS_PER_M2`]). A sparse groom gets enough children per
/// strand to reach [`CHILD_TARGET_STRANDS_PER_M2`], at most 1000 and at most
/// [`MAX_GROWN_STRANDS`] strands in all, spread over the disc a guide stands for: radius
/// `√(1/(π·density))`. `spread` (when given) replaces that radius; `clump` is `base`'s.
pub fn auto_children(
    roots: &[Vec3],
    spread: Option<f32>,
    base: &ChildStrands,
) -> Option<(ChildStrands, GrownChildren)> {
    if roots.len() >= DENSE_STRAND_COUNT {
        return None;
    }
    let density = root_density(roots)?;
    if density >= SPARSE_STRANDS_PER_M2 {
        return None;
    }
    let wanted = (CHILD_TARGET_STRANDS_PER_M2 / density).ceil() as usize - 1;
    let room = (MAX_GROWN_STRANDS / roots.len()).saturating_sub(1);
    let per_strand = wanted.min(room).min(1000);
    if per_strand == 0 {
        return None;
    }
    let spread = spread.unwrap_or((1.0 / (std::f32::consts::PI * density)).sqrt());
    let children = ChildStrands {
        per_strand,
        spread,
        clump: base.clump,
    };
    Some((
        children,
        GrownChildren {
            root_density: density,
            per_strand,
            spread,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Roots on an `n × n` grid of spacing `s` [m] in the XZ plane.
    fn grid(n: usize, s: f32) -> Vec<Vec3> {
        (0..n * n)
            .map(|i| Vec3::new((i % n) as f32 * s, 0.0, (i / n) as f32 * s))
            .collect()
    }

    #[test]
    fn the_density_of_a_grid_is_one_over_its_spacing_squared_within_the_estimates_bias() {
        // 1 cm spacing: 10⁴ strands/m². Interior roots estimate 7/(2π s²) = 1.114·10⁴; roots
        // on the border (a quarter of a 30 × 30 grid's) see their 8th neighbour farther, so the
        // median lies between 1/(π·(2s)²)·7 = 0.56·10⁴ and 1.114·10⁴.
        let density = root_density(&grid(30, 0.01)).unwrap();
        assert!((0.56e4..=1.115e4).contains(&density), "{density}");
        // Density scales as 1/s²: half the spacing, four times the density.
        let finer = root_density(&grid(30, 0.005)).unwrap();
        assert!((finer / density - 4.0).abs() < 1e-3, "{finer} {density}");
        assert_eq!(root_density(&grid(2, 0.01)), None);
        assert_eq!(root_density(&[Vec3::ZERO; 20]), None);
    }

    #[test]
    fn a_guide_set_grows_children_to_the_target_density_and_a_groom_does_not() {
        // 15 × 15 guides 1 cm apart: about 10⁴ per m², sparse.
        let guides = grid(15, 0.01);
        let (children, grown) = auto_children(&guides, None, &ChildStrands::default()).unwrap();
        let density = root_density(&guides).unwrap();
        assert_eq!(grown.root_density, density);
        // (per + 1)·density reaches the target, per·density does not.
        let per = children.per_strand as f32;
        assert!((per + 1.0) * density >= CHILD_TARGET_STRANDS_PER_M2);
        assert!(per * density < CHILD_TARGET_STRANDS_PER_M2);
        // The disc a guide stands for: π·spread² = 1/density.
        let area = std::f32::consts::PI * children.spread * children.spread;
        assert!((area * density - 1.0).abs() < 1e-4);
        assert_eq!(children.clump, ChildStrands::default().clump);
        // A given spread is kept.
        let (given, _) = auto_children(&guides, Some(0.003), &ChildStrands::default()).unwrap();
        assert_eq!(given.spread, 0.003);
        // 2 mm apart: 2.5·10⁵ per m², dense.
        assert!(auto_children(&grid(15, 0.002), None, &ChildStrands::default()).is_none());
        // The total stays within MAX_GROWN_STRANDS: 100 × 100 guides 5 cm apart.
        let wide = grid(100, 0.05);
        let (capped, _) = auto_children(&wide, None, &ChildStrands::default()).unwrap();
        assert!(wide.len() * (capped.per_strand + 1) <= MAX_GROWN_STRANDS);
        assert_eq!(capped.per_strand, MAX_GROWN_STRANDS / wide.len() - 1);
    }
}
