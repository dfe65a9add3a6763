//! Tests of `batches.rs`: items sorted into runs per chain, batches merged by tessellation,
//! fading surfaces apart, coverage-ranked chains and front-to-back order.

use super::*;

#[test]
fn items_sort_by_chain_and_form_runs() {
    let order = ChainOrder::new(&[2, 0, 2, 1, 0]);
    assert_eq!(order.sorted_to_input, vec![1, 4, 3, 0, 2]);
    assert_eq!(order.runs, vec![(0, 0, 2), (1, 2, 3), (2, 3, 5)]);
    assert_eq!(order.chains_needed(), 3);
    assert_eq!(
        order.sorted(&['a', 'b', 'c', 'd', 'e']),
        vec!['b', 'e', 'd', 'a', 'c']
    );
    assert_eq!(ChainOrder::new(&[]).chains_needed(), 0);
}

#[test]
fn batches_merge_equal_tessellation_and_skip_empty_chains() {
    let order = ChainOrder::new(&[0, 0, 1, 2, 3, 3]);
    let chain = |nodes, along| GpuChain {
        first_node: 0,
        node_count: nodes,
        along_segments: along,
        around_segments: 4,
        coverage: 1.0,
        ..GpuChain::default()
    };
    let chains = [chain(5, 8), chain(5, 8), chain(0, 8), chain(5, 4)];
    let (mut list, mut batches) = (Vec::new(), Vec::new());
    order.listed_batches(&chains, &mut list, &mut batches);
    assert_eq!(list, vec![0, 1, 2, 4, 5]);
    let expected = vec![
        Batch {
            items: 0..3,
            along_segments: 8,
            around_segments: 4,
            thin: false,
            dissolving: false,
        },
        Batch {
            items: 3..5,
            along_segments: 4,
            around_segments: 4,
            thin: false,
            dissolving: false,
        },
    ];
    assert_eq!(batches, expected);
    assert_eq!(expected[1].ribbon_vertices(), 10);
    assert_eq!(expected[1].surface_vertices(1), 10);
    assert_eq!(expected[1].surface_vertices(3), 34);
}

#[test]
fn fading_surfaces_get_their_own_batches_and_strands_merge() {
    let order = ChainOrder::new(&[0, 1, 2]);
    let chain = |coverage| GpuChain {
        node_count: 5,
        along_segments: 8,
        around_segments: 4,
        coverage,
        ..GpuChain::default()
    };
    let distances = [0.0, 1.0, 2.0];
    let mut batches = Vec::new();
    let chains = [chain(1.0), chain(0.5), chain(1.0)];
    order.batches_front_to_back(&chains, &distances, &mut Vec::new(), &mut batches);
    let fading: Vec<(std::ops::Range<u32>, bool)> = batches
        .iter()
        .map(|b| (b.items.clone(), b.dissolving))
        .collect();
    assert_eq!(fading, vec![(0..1, false), (1..2, true), (2..3, false)]);
    // Strands fade by rank in the shader: one draw over the listed items.
    let (mut list, mut batches) = (Vec::new(), Vec::new());
    order.listed_batches(&chains, &mut list, &mut batches);
    assert_eq!(list, vec![0, 1, 2]);
    let merged: Vec<(std::ops::Range<u32>, bool)> = batches
        .iter()
        .map(|b| (b.items.clone(), b.dissolving))
        .collect();
    assert_eq!(merged, vec![(0..3, false)]);
    // A chain faded out (coverage 0: the last frame of its blend) draws nothing, either way;
    // the screen door would have dropped every pixel after shading none.
    let chains = [chain(1.0), chain(0.0), chain(1.0)];
    let mut batches = Vec::new();
    order.batches_front_to_back(&chains, &distances, &mut Vec::new(), &mut batches);
    let drawn: Vec<std::ops::Range<u32>> = batches.iter().map(|b| b.items.clone()).collect();
    assert_eq!(drawn, vec![0..1, 2..3]);
    let (mut list, mut batches) = (Vec::new(), Vec::new());
    order.listed_batches(&chains, &mut list, &mut batches);
    assert_eq!(list, vec![0, 2]);
    assert_eq!(batches.len(), 1);
}

/// A ranked chain at coverage `c` draws `round(c·n)` of its `n` items (ranks `(k + ½)/n`
/// below `c`: `k < c·n − ½`), the same items at every coverage they are drawn at, and a
/// chain at coverage 0 none.
#[test]
fn ranked_chains_draw_only_the_items_their_coverage_shows() {
    let item_chains: Vec<u32> = (0..83).map(|i| [1, 0, 2][i % 3]).chain([2; 17]).collect();
    let order = ChainOrder::with_dissolve_ranks(&item_chains);
    assert_eq!(order.runs, vec![(0, 0, 28), (1, 28, 56), (2, 56, 100)]);
    for (position, &input) in order.sorted_to_input.iter().enumerate() {
        let run = order
            .runs
            .iter()
            .find(|r| (r.1..r.2).contains(&(position as u32)));
        assert_eq!(run.unwrap().0, item_chains[input as usize]);
    }
    let chain = |coverage| GpuChain {
        node_count: 5,
        along_segments: 8,
        coverage,
        ..GpuChain::default()
    };
    let mut previous: Vec<Vec<u32>> = vec![Vec::new(); 3];
    for step in 0..=20 {
        let coverage = step as f32 / 20.0;
        let (mut list, mut batches) = (Vec::new(), Vec::new());
        order.listed_batches(
            &[chain(coverage), chain(1.0), chain(coverage)],
            &mut list,
            &mut batches,
        );
        let drawn: Vec<u32> = batches
            .iter()
            .flat_map(|b| b.items.clone())
            .map(|i| list[i as usize])
            .collect();
        for &(chain_index, start, end) in &order.runs {
            let n = (end - start) as f32;
            let expected = if chain_index == 1 {
                n as usize
            } else {
                (coverage * n).round() as usize
            };
            let kept: Vec<u32> = drawn
                .iter()
                .copied()
                .filter(|p| (start..end).contains(p))
                .collect();
            assert_eq!(kept.len(), expected, "chain {chain_index} at {coverage}");
            // Monotone: what a lower coverage draws, a higher one draws too.
            assert!(kept.starts_with(&previous[chain_index as usize]));
            previous[chain_index as usize] = kept;
        }
    }
    // Unranked items (surfaces) always draw their whole run.
    let surfaces = ChainOrder::new(&item_chains);
    let mut batches = Vec::new();
    surfaces.batches_front_to_back(
        &[chain(0.1), chain(0.1), chain(0.1)],
        &[0.0, 1.0, 2.0],
        &mut Vec::new(),
        &mut batches,
    );
    let total: u32 = batches.iter().map(|b| b.items.len() as u32).sum();
    assert_eq!(total, 100);
}

/// Nearest chain first; runs merge only where they stay consecutive; ties keep chain order;
/// chains without nodes are skipped.
#[test]
fn front_to_back_batches_follow_root_distance() {
    let order = ChainOrder::new(&[0, 1, 2, 3, 4]);
    let chain = |nodes| GpuChain {
        node_count: nodes,
        along_segments: 8,
        around_segments: 4,
        coverage: 1.0,
        ..GpuChain::default()
    };
    let chains = [chain(5), chain(5), chain(5), chain(0), chain(5)];
    let distances = [1.5, 1.0, 1.2, 0.1, 1.5];
    let mut scratch = Vec::new();
    let mut batches = Vec::new();
    order.batches_front_to_back(&chains, &distances, &mut scratch, &mut batches);
    let items: Vec<std::ops::Range<u32>> = batches.iter().map(|b| b.items.clone()).collect();
    // Chain 3 is nearest but has no nodes; chains 1 and 2 follow each other (one draw);
    // chains 0 and 4 tie at 1.5 m and keep their order.
    assert_eq!(items, vec![1..3, 0..1, 4..5]);
}

#[test]
fn chain_table_follows_camera_distance() {
    let positions = [
        Vec3::ZERO,
        Vec3::NEG_Y,
        Vec3::new(0.0, 0.0, -3.0),
        Vec3::ONE,
    ];
    let axes = [Vec3::X; 4];
    let frame = SkeletonFrame {
        chain_offsets: &[0, 2, 2, 4],
        node_positions: &positions,
        node_normals: &axes,
        node_binormals: &axes,
        chain_coverage: &[],
        chain_gives_way: &[],
        chain_simulated_at: &[],
    };
    let mut table = Vec::new();
    let mut distances = Vec::new();
    let tessellation = Tessellation::default();
    let mut table_for = |geometry, table: &mut Vec<GpuChain>| {
        chain_table(
            &frame,
            &tessellation,
            geometry,
            Vec3::new(0.0, 0.0, 1.0),
            1000.0,
            &[0.01, 0.0, 0.01],
            |d| d > 2.0,
            table,
            &mut distances,
        )
    };
    let samples = table_for(ClusterGeometry::Tube, &mut table);
    assert_eq!(table.len(), 3);
    assert_eq!(table[2].first_sample, table[0].along_segments + 1);
    assert_eq!(
        samples,
        table[0].along_segments + table[2].along_segments + 2
    );
    assert_eq!((table[0].first_node, table[0].node_count), (0, 2));
    assert_eq!(table[1].node_count, 0);
    assert_eq!(table[0].along_segments, tessellation.segments_at(1.0));
    assert_eq!(table[2].along_segments, tessellation.segments_at(4.0));
    assert!(table[2].along_segments < table[0].along_segments);
    // Ring radius 1 cm at 1.0 m and at 3.2 m with a 1000 px focal length: 10 px and 3.1 px.
    assert_eq!(
        table[0].around_segments,
        tessellation.around_segments_for(0.01, 1.0, 1000.0)
    );
    assert!(table[2].around_segments < table[0].around_segments);
    assert_eq!((table[0].thin, table[2].thin), (0, 1));
    // Impostors: the same bands across at any distance.
    table_for(ClusterGeometry::Impostor, &mut table);
    assert_eq!(table[0].around_segments, crate::IMPOSTOR_BANDS);
    assert_eq!(table[2].around_segments, crate::IMPOSTOR_BANDS);
}
