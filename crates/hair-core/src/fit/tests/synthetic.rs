//! Synthetic grooms with a known answer: separated tufts, evenly spread rows, curls, bad input.

use glam::Vec3;

use super::{assert_well_formed, curves_from};
use crate::curves::Curves;
use crate::fit::{
    FitSettings, NodeCountScope, Representative, SectionCount, Smoothness, fit_hierarchy,
};
use crate::level::Level;
use crate::random::SplitMix64;

/// A straight strand from `root` along `direction` (unit) of `length` [m] with `points` points.
fn straight(root: Vec3, direction: Vec3, length: f32, points: usize) -> Vec<Vec3> {
    (0..points)
        .map(|i| root + direction * (length * i as f32 / (points - 1) as f32))
        .collect()
}

/// Four tufts 0.5 m apart of `per_tuft` identical straight strands each (0.2 m down −Y), roots
/// spread over a 1 cm disc in the XZ plane (perpendicular to the strands). Strand `t·per_tuft + k`
/// is strand `k` of tuft `t`.
fn four_tufts(per_tuft: usize) -> Curves {
    let centres = [
        Vec3::new(-0.5, 0.0, -0.5),
        Vec3::new(0.5, 0.0, -0.5),
        Vec3::new(-0.5, 0.0, 0.5),
        Vec3::new(0.5, 0.0, 0.5),
    ];
    let mut rng = SplitMix64::new(11);
    let mut strands = Vec::new();
    for centre in centres {
        for _ in 0..per_tuft {
            let (radius, angle) = (
                0.01 * rng.next_f32().sqrt(),
                rng.range(0.0, std::f32::consts::TAU),
            );
            let root = centre + Vec3::new(radius * angle.cos(), 0.0, radius * angle.sin());
            strands.push(straight(root, Vec3::NEG_Y, 0.2, 12));
        }
    }
    curves_from(&strands)
}

#[test]
fn four_separated_tufts_of_identical_straight_strands_fit_exactly() {
    let curves = four_tufts(40);
    for sections in [SectionCount::Fixed(4), SectionCount::StrandsPerSection(40)] {
        let settings = FitSettings {
            sections,
            ..FitSettings::default()
        };
        let fit = fit_hierarchy(&curves, &settings).unwrap();
        assert_well_formed(&fit, 160);
        assert_eq!(fit.section_count(), 4);
        assert_eq!(fit.report.merged_sections, 0);
        // Each section is one tuft, whole.
        for section in 0..4 {
            let tuft = fit.section_of(40 * section);
            for k in 0..40 {
                assert_eq!(fit.section_of(40 * section + k), tuft);
            }
        }
        // Straight identical strands: every skeleton is the same straight line moved, the node
        // frames do not turn, and the root offset carries each strand exactly (its roots lie
        // across the strands, so nothing is lost along the tangent).
        for level in Level::ALL {
            let errors = &fit.report.errors[level];
            assert!(
                errors.drawn.worst_point < 1e-6,
                "{level:?}: {:?}",
                errors.drawn
            );
            assert!(errors.per_node_offsets.worst_point < 1e-6);
            // Without an offset a strand is as far from the skeleton as its root from the
            // centroid: up to the disc's 1 cm radius.
            assert!(errors.centreline.max > 1e-3 && errors.centreline.max < 0.02);
        }
        assert!(fit.report.discretisation.worst_point < 1e-6);
        // A straight 0.2 m skeleton with 2.5 cm segments: 8 segments, 9 nodes.
        assert!(fit.sections.iter().all(|s| s.node_count == 9));
        // Section frames: tangent along the strands.
        for section in &fit.sections {
            assert!((section.root_frame.tangent - Vec3::NEG_Y).length() < 1e-5);
        }
    }
}

#[test]
fn evenly_spread_strands_make_balanced_ordered_groups() {
    // One section of 53 strands whose roots are evenly spaced along X: 5 groups of 10 or 11,
    // laid along X in order (group 0 at one end), clusters {0,1}, {2}, {3,4}.
    let strands: Vec<Vec<Vec3>> = (0..53)
        .map(|i| straight(Vec3::new(0.002 * i as f32, 0.0, 0.0), Vec3::NEG_Y, 0.1, 8))
        .collect();
    let curves = curves_from(&strands);
    let settings = FitSettings {
        sections: SectionCount::Fixed(1),
        ..FitSettings::default()
    };
    let fit = fit_hierarchy(&curves, &settings).unwrap();
    assert_well_formed(&fit, 53);
    // The check fails where the structure breaks: a curve listed in the wrong group, a node
    // that is not finite, a curve count the fit does not hold.
    let mut moved = fit.clone();
    let group = moved.strand_groups[0];
    moved.strand_groups[0] = (group + 1) % 5;
    let error = moved.check_structure(53).unwrap_err().to_string();
    assert!(error.contains("curve 0 is in group"), "{error}");
    let mut broken = fit.clone();
    broken.node_positions[3].x = f32::NAN;
    let error = broken.check_structure(53).unwrap_err().to_string();
    assert!(error.contains("node position is not finite"), "{error}");
    assert!(fit.check_structure(52).is_err());
    let sizes: Vec<usize> = (0..5).map(|g| fit.group_members(g).len()).collect();
    assert!(sizes.iter().all(|&n| n == 10 || n == 11), "{sizes:?}");
    // Runs along X: every strand of group g lies on one side of every strand of group g + 1.
    let xs = |g: usize| -> Vec<f32> {
        fit.group_members(g)
            .iter()
            .map(|&c| curves.curve(c as usize)[0].x)
            .collect()
    };
    let increasing = xs(0)[0] < xs(4)[0];
    for g in 0..4 {
        let (a, b) = (xs(g), xs(g + 1));
        let a_max = a.iter().copied().fold(f32::MIN, f32::max);
        let a_min = a.iter().copied().fold(f32::MAX, f32::min);
        let b_max = b.iter().copied().fold(f32::MIN, f32::max);
        let b_min = b.iter().copied().fold(f32::MAX, f32::min);
        assert!(if increasing {
            a_max < b_min
        } else {
            b_max < a_min
        });
    }
    // The binormal runs across the row (along X), and group 0 lies on its negative side.
    let frame = fit.sections[0].root_frame;
    assert!(frame.binormal.x.abs() > 0.999);
    let side = (curves.curve(fit.group_members(0)[0] as usize)[0] - fit.sections[0].root_position)
        .dot(frame.binormal);
    assert!(side < 0.0);
    // The centre cluster is the centre group: same skeleton.
    let centre_cluster = fit.section_chains(0, Level::Cluster).start + 1;
    let centre_group = fit.section_chains(0, Level::StrandGroup).start + 2;
    assert_eq!(
        fit.chain_positions(centre_cluster),
        fit.chain_positions(centre_group)
    );
    assert_eq!(fit.cluster_of_group(2), centre_cluster);
    // Widths of the patch: the row is 104 mm long, so the patch is about that wide at the root.
    assert!(
        (fit.node_widths[0] - 0.104).abs() < 2e-3,
        "{}",
        fit.node_widths[0]
    );
    assert!((fit.sections[0].width - 0.104).abs() < 1e-4);
}

/// `count` helices (ringlets) of radius `radius` [m], pitch 1 cm per turn, `turns` turns, roots
/// on a row along X, hanging down −Y; 200 points each.
fn ringlets(count: usize, radius: f32, turns: f32) -> Vec<Vec<Vec3>> {
    (0..count)
        .map(|k| {
            let root = Vec3::new(0.003 * k as f32, 0.0, 0.0);
            (0..200)
                .map(|i| {
                    let a = std::f32::consts::TAU * turns * i as f32 / 199.0;
                    root + Vec3::new(
                        radius * (a.cos() - 1.0),
                        -0.01 * turns * i as f32 / 199.0,
                        radius * a.sin(),
                    )
                })
                .collect()
        })
        .collect()
}

#[test]
fn curls_get_more_nodes_than_straight_hair_of_the_same_length() {
    // A helix of radius 1 cm, 5 turns: about 0.32 m long, turning 10π rad. With 20° per segment
    // that asks for ⌈10π / 0.349⌉ = 90 segments: capped at 64 nodes. Straight hair of that length
    // needs ⌈0.32 / 0.025⌉ + 1 = 14 nodes.
    let curls = ringlets(10, 0.01, 5.0);
    let length = crate::fit::curve_length(&curls[0]);
    let settings = FitSettings {
        sections: SectionCount::Fixed(1),
        ..FitSettings::default()
    };
    let curly = fit_hierarchy(&curves_from(&curls), &settings).unwrap();
    assert_well_formed(&curly, 10);
    assert_eq!(curly.sections[0].node_count, 64);
    let lines: Vec<Vec<Vec3>> = (0..10)
        .map(|k| straight(Vec3::X * 0.003 * k as f32, Vec3::NEG_Y, length, 50))
        .collect();
    let straight_fit = fit_hierarchy(&curves_from(&lines), &settings).unwrap();
    assert_eq!(
        straight_fit.sections[0].node_count,
        (length / 0.025).ceil() as usize + 1
    );
    // Every skeleton segment respects the smoothness where the cap did not bind.
    for chain in 0..straight_fit.chain_count() {
        for w in straight_fit.chain_positions(chain).windows(2) {
            assert!(w[0].distance(w[1]) <= 0.025 + 1e-6);
        }
    }
    // Identical ringlets side by side: the constant offset in node frames turns with the curl,
    // so it does not carry a strand translated across the section (the per-node offset model
    // does, up to the tangential part). That is what the constant root offset costs.
    let errors = &curly.report.errors[Level::Patch];
    assert!(errors.drawn.mean > errors.per_node_offsets.mean);
}

#[test]
fn a_fit_is_the_same_on_every_run_and_thread_count() {
    let curves = four_tufts(25);
    let mut strands: Vec<Vec<Vec3>> = curves.iter().map(|c| c.to_vec()).collect();
    strands.extend(ringlets(30, 0.008, 2.0));
    let curves = curves_from(&strands);
    let settings = FitSettings {
        sections: SectionCount::StrandsPerSection(12),
        ..FitSettings::default()
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fit_hierarchy(&curves, &settings).unwrap())
    };
    let one = run(1);
    assert_well_formed(&one, 130);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
    assert_eq!(one, fit_hierarchy(&curves, &settings).unwrap());
    // Another seed may cut differently but is just as well formed.
    let other = fit_hierarchy(
        &curves,
        &FitSettings {
            seed: 99,
            ..settings.clone()
        },
    )
    .unwrap();
    assert_well_formed(&other, 130);
}

#[test]
fn small_sections_are_merged_and_every_option_works() {
    // 12 strands asked for 10 sections: sections under 5 strands are merged until none is left.
    let strands: Vec<Vec<Vec3>> = (0..12)
        .map(|i| straight(Vec3::new(0.01 * i as f32, 0.0, 0.0), Vec3::NEG_Y, 0.1, 5))
        .collect();
    let curves = curves_from(&strands);
    for representative in [
        Representative::Mean,
        Representative::Medoid,
        Representative::Best,
    ] {
        for node_counts in [NodeCountScope::PerSection, NodeCountScope::Uniform] {
            let settings = FitSettings {
                sections: SectionCount::Fixed(10),
                representative,
                node_counts,
                shape_weight: 0.0,
                section_size_slack: 0.0,
                ..FitSettings::default()
            };
            let fit = fit_hierarchy(&curves, &settings).unwrap();
            assert_well_formed(&fit, 12);
            assert!(fit.section_count() <= 2);
            assert_eq!(fit.report.requested_sections, 10);
            assert_eq!(fit.report.merged_sections, 10 - fit.section_count());
        }
    }
}

#[test]
fn bad_input_is_an_error_that_names_it() {
    let good: Vec<Vec<Vec3>> = (0..6)
        .map(|i| straight(Vec3::X * i as f32 * 0.01, Vec3::NEG_Y, 0.1, 4))
        .collect();
    let settings = FitSettings::default();
    let too_few = fit_hierarchy(&curves_from(&good[..4]), &settings).unwrap_err();
    assert!(too_few.to_string().contains("curve count: 4"), "{too_few}");
    let mut flat = good.clone();
    flat[3] = vec![Vec3::ONE; 3];
    let error = fit_hierarchy(&curves_from(&flat), &settings).unwrap_err();
    assert!(error.to_string().contains("curve 3"), "{error}");
    let mut single = good.clone();
    single[2] = vec![Vec3::ONE];
    assert!(fit_hierarchy(&curves_from(&single), &settings).is_err());
    let mut nan = good.clone();
    nan[1][2] = Vec3::NAN;
    assert!(fit_hierarchy(&curves_from(&nan), &settings).is_err());
    let mut broken = curves_from(&good);
    broken.offsets[2] = 100;
    assert!(fit_hierarchy(&broken, &settings).is_err());
    assert!(fit_hierarchy(&Curves::default(), &settings).is_err());
    for bad in [
        FitSettings {
            sections: SectionCount::Fixed(0),
            ..FitSettings::default()
        },
        FitSettings {
            sections: SectionCount::StrandsPerSection(0),
            ..FitSettings::default()
        },
        FitSettings {
            shape_weight: f32::NAN,
            ..FitSettings::default()
        },
        FitSettings {
            samples_per_strand: 2,
            ..FitSettings::default()
        },
        FitSettings {
            smoothness: Smoothness {
                max_segment_length: 0.0,
                ..Smoothness::default()
            },
            ..FitSettings::default()
        },
    ] {
        let error = fit_hierarchy(&curves_from(&good), &bad).unwrap_err();
        assert!(error.to_string().starts_with("invalid"), "{error}");
    }
}

#[test]
fn opposite_strands_in_one_section_fall_back_on_a_medoid() {
    // Half the strands grow up, half down, from the same roots: their mean collapses to a point,
    // so every mean representative gives way to a medoid; nothing panics or goes non-finite.
    let strands: Vec<Vec<Vec3>> = (0..10)
        .map(|i| {
            let direction = if i % 2 == 0 { Vec3::Y } else { Vec3::NEG_Y };
            straight(Vec3::X * 0.001 * (i / 2) as f32, direction, 0.1, 6)
        })
        .collect();
    let settings = FitSettings {
        sections: SectionCount::Fixed(1),
        representative: Representative::Mean,
        shape_weight: 0.0,
        ..FitSettings::default()
    };
    let fit = fit_hierarchy(&curves_from(&strands), &settings).unwrap();
    assert_well_formed(&fit, 10);
    assert_eq!(fit.report.medoid_elements[Level::Patch], 1);
}
