//! Balanced k-means on strand features: greedy k-means++ seeding from a fixed seed, Lloyd
//! iterations, then a capacity-limited reassignment so that no cluster grows past a size.
//!
//! Deterministic whatever the thread count: work per point runs in parallel and is collected in
//! order, and every sum over points runs in a fixed order (in chunks of fixed size, then the
//! chunks in order).

use rayon::prelude::*;

use crate::random::SplitMix64;

/// Number of features per strand: root (3), middle − root (3), tip − root (3).
pub(crate) const FEATURE_COUNT: usize = 9;

/// One strand's features [m] (shape parts already weighted).
pub(crate) type Feature = [f32; FEATURE_COUNT];

/// Points per chunk of the deterministic parallel sums.
const CHUNK: usize = 512;

/// Lloyd iterations at most.
const LLOYD_ITERATIONS: usize = 100;

/// Balancing rounds (reassign with capacities, move the centres) at most.
const BALANCE_ROUNDS: usize = 10;

/// Candidate centres a point is offered during balancing: its nearest ones.
const BALANCE_CANDIDATES: usize = 16;

/// Squared distance between two features [m²].
pub(crate) fn distance_squared(a: &Feature, b: &Feature) -> f32 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

/// The sum of `values` in a fixed order (chunks summed in parallel, then in order, in f64).
fn ordered_sum(values: &[f32]) -> f64 {
    let chunks: Vec<f64> = values
        .par_chunks(CHUNK)
        .map(|chunk| chunk.iter().map(|&v| f64::from(v)).sum::<f64>())
        .collect();
    chunks.iter().sum()
}

/// Index of the nearest centre to `point` (the lowest index on a tie) and its squared distance.
fn nearest(point: &Feature, centres: &[Feature]) -> (usize, f32) {
    let mut best = (0, f32::INFINITY);
    for (c, centre) in centres.iter().enumerate() {
        let d = distance_squared(point, centre);
        if d < best.1 {
            best = (c, d);
        }
    }
    best
}

/// Picks an index with probability proportional to `weights` (all ≥ 0, total `total` > 0).
fn pick_weighted(weights: &[f32], total: f64, rng: &mut SplitMix64) -> usize {
    let target = rng.next_f32() as f64 * total;
    let mut running = 0.0;
    for (i, &w) in weights.iter().enumerate() {
        running += f64::from(w);
        if running > target && w > 0.0 {
            return i;
        }
    }
    // Rounding: the last point with a weight.
    weights.iter().rposition(|&w| w > 0.0).unwrap_or(0)
}

/// Greedy k-means++ seeding (Arthur & Vassilvitskii 2007; the greedy variant of scikit-learn):
/// each new centre is the best, by the resulting potential, of `2 + ⌊ln k⌋` candidates drawn with
/// probability proportional to the squared distance to the nearest centre so far.
fn seed_centres(features: &[Feature], k: usize, rng: &mut SplitMix64) -> Vec<Feature> {
    let n = features.len();
    let first = (rng.next_u64() % n as u64) as usize;
    let mut centres = vec![features[first]];
    let mut nearest_d2: Vec<f32> = features
        .par_iter()
        .map(|f| distance_squared(f, &features[first]))
        .collect();
    let trials = 2 + (k as f64).ln().floor() as usize;
    while centres.len() < k {
        let total = ordered_sum(&nearest_d2);
        if total.is_nan() || total <= 0.0 {
            // Fewer distinct points than centres: the rest repeat the first.
            centres.push(features[first]);
            continue;
        }
        let mut best: Option<(f64, usize, Vec<f32>)> = None;
        for _ in 0..trials {
            let candidate = pick_weighted(&nearest_d2, total, rng);
            let updated: Vec<f32> = features
                .par_iter()
                .zip(&nearest_d2)
                .map(|(f, &d)| d.min(distance_squared(f, &features[candidate])))
                .collect();
            let potential = ordered_sum(&updated);
            if best.as_ref().is_none_or(|(p, _, _)| potential < *p) {
                best = Some((potential, candidate, updated));
            }
        }
        if let Some((_, candidate, updated)) = best {
            centres.push(features[candidate]);
            nearest_d2 = updated;
        }
    }
    centres
}

/// The mean feature of each cluster (in f64, points in order); an empty cluster keeps its centre.
fn update_centres(features: &[Feature], labels: &[u32], centres: &mut [Feature]) {
    let k = centres.len();
    let mut sums = vec![[0f64; FEATURE_COUNT]; k];
    let mut counts = vec![0usize; k];
    for (f, &label) in features.iter().zip(labels) {
        let label = label as usize;
        counts[label] += 1;
        for (s, v) in sums[label].iter_mut().zip(f) {
            *s += f64::from(*v);
        }
    }
    for ((centre, sum), count) in centres.iter_mut().zip(&sums).zip(&counts) {
        if *count > 0 {
            for (c, s) in centre.iter_mut().zip(sum) {
                *c = (s / *count as f64) as f32;
            }
        }
    }
}

/// Assigns every point to a centre so that no centre gets more than `capacity` points, plus one
/// where that is needed to place everyone: all (point, candidate centre) pairs sorted by distance
/// (then point, then centre) are taken greedily while the centre has room; a point left over goes
/// to the nearest centre with fewer than `max(capacity, ⌊n/k⌋ + 1)` points. With
/// `capacity = ⌊n/k⌋` the sizes are within one of each other; when every centre's nearest points
/// fit, this is the nearest assignment.
fn assign_with_capacity(features: &[Feature], centres: &[Feature], capacity: usize) -> Vec<u32> {
    let k = centres.len();
    let candidates = BALANCE_CANDIDATES.min(k);
    let mut pairs: Vec<(f32, u32, u32)> = features
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, f)| {
            let mut near: Vec<(f32, u32, u32)> = centres
                .iter()
                .enumerate()
                .map(|(c, centre)| (distance_squared(f, centre), i as u32, c as u32))
                .collect();
            // The `candidates` nearest in order: the comparison is a total order (centres
            // differ), so selecting them first and sorting only those is the full sort's prefix.
            let order =
                |a: &(f32, u32, u32), b: &(f32, u32, u32)| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2));
            if candidates < near.len() {
                near.select_nth_unstable_by(candidates, order);
                near.truncate(candidates);
            }
            near.sort_unstable_by(order);
            near
        })
        .collect();
    pairs.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut labels = vec![u32::MAX; features.len()];
    let mut sizes = vec![0usize; k];
    for &(_, point, centre) in &pairs {
        let (point, centre) = (point as usize, centre as usize);
        if labels[point] == u32::MAX && sizes[centre] < capacity {
            labels[point] = centre as u32;
            sizes[centre] += 1;
        }
    }
    // `k · limit ≥ n`, so a centre with room always exists.
    let limit = capacity.max(features.len() / k + 1);
    for (point, label) in labels.iter_mut().enumerate() {
        if *label == u32::MAX {
            let mut best = (0, f32::INFINITY);
            for (c, centre) in centres.iter().enumerate() {
                let d = distance_squared(&features[point], centre);
                if sizes[c] < limit && d < best.1 {
                    best = (c, d);
                }
            }
            *label = best.0 as u32;
            sizes[best.0] += 1;
        }
    }
    labels
}

/// Clusters `features` into `k` clusters (`1 ≤ k ≤ n`) of at most
/// `max(⌊(n / k) · (1 + slack)⌋, ⌊n / k⌋ + 1)` points each (with `slack = 0`, sizes within one
/// of each other); returns each point's cluster. Deterministic for a
/// given seed, whatever the thread count.
pub(crate) fn balanced_kmeans(features: &[Feature], k: usize, slack: f32, seed: u64) -> Vec<u32> {
    let n = features.len();
    if n == 0 {
        return Vec::new();
    }
    let k = k.clamp(1, n);
    let mut rng = SplitMix64::new(seed);
    let mut centres = seed_centres(features, k, &mut rng);
    let mut labels: Vec<u32> = vec![u32::MAX; n];
    for _ in 0..LLOYD_ITERATIONS {
        let next: Vec<u32> = features
            .par_iter()
            .map(|f| nearest(f, &centres).0 as u32)
            .collect();
        if next == labels {
            break;
        }
        labels = next;
        update_centres(features, &labels, &mut centres);
    }
    let even = n / k;
    let capacity = ((n as f64 / k as f64) * (1.0 + f64::from(slack))).floor() as usize;
    let capacity = capacity.max(even);
    for _ in 0..BALANCE_ROUNDS {
        let next = assign_with_capacity(features, &centres, capacity);
        if next == labels {
            break;
        }
        labels = next;
        update_centres(features, &labels, &mut centres);
    }
    labels
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blob(centre: [f32; 3], count: usize, spread: f32, seed: u64) -> Vec<Feature> {
        let mut rng = SplitMix64::new(seed);
        (0..count)
            .map(|_| {
                let mut f = [0.0; FEATURE_COUNT];
                for (axis, c) in centre.iter().enumerate() {
                    f[axis] = c + rng.range(-spread, spread);
                }
                f
            })
            .collect()
    }

    #[test]
    fn separated_blobs_are_found_and_sizes_are_capped() {
        let mut features = blob([0.0, 0.0, 0.0], 30, 0.01, 1);
        features.extend(blob([1.0, 0.0, 0.0], 30, 0.01, 2));
        features.extend(blob([0.0, 1.0, 0.0], 30, 0.01, 3));
        let labels = balanced_kmeans(&features, 3, 0.25, 7);
        for b in 0..3 {
            let first = labels[30 * b];
            assert!(labels[30 * b..30 * (b + 1)].iter().all(|&l| l == first));
        }
        // One blob of 60 asked for 2 clusters with no slack: 30 and 30.
        let features = blob([0.0, 0.0, 0.0], 60, 0.01, 4);
        let labels = balanced_kmeans(&features, 2, 0.0, 7);
        assert_eq!(labels.iter().filter(|&&l| l == 0).count(), 30);
    }

    #[test]
    fn identical_points_and_more_clusters_than_points_do_not_panic() {
        let features = vec![[0.5; FEATURE_COUNT]; 10];
        let labels = balanced_kmeans(&features, 4, 0.0, 1);
        let mut sizes = [0; 4];
        labels.iter().for_each(|&l| sizes[l as usize] += 1);
        assert!(sizes.iter().all(|&s| s <= 3), "{sizes:?}");
        assert_eq!(balanced_kmeans(&features[..2], 5, 0.0, 1).len(), 2);
        assert!(balanced_kmeans(&[], 3, 0.0, 1).is_empty());
    }
}
