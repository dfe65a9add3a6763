//! Tests of the selector's look ahead ([`LodSettings::blend_lead`]): the extrapolation of a
//! section's errors against steady motions worked by hand, and the level changes of a selector
//! that looks `k` frames ahead against one that does not, on a camera receding and approaching
//! at a constant speed.

use super::tests::{front_camera, observations};
use super::*;
use crate::level::Level;
use crate::scene::Scene;
use crate::transform::RigidTransform;

/// Frames the selector looks ahead in these tests: `blend_lead · blend_time / frame_time` =
/// 0.5 · 0.24 s / 0.02 s.
const LEAD_FRAMES: usize = 6;

fn settings() -> LodSettings {
    LodSettings {
        occlusion: false,
        blend_time: 0.24,
        blend_lead: 0.5,
        ..LodSettings::default()
    }
}

/// Each section's levels over the frames at camera distances `distances` [m].
fn levels_over(selector: &mut LodSelector, scene: &Scene, distances: &[f32]) -> Vec<Vec<Level>> {
    let observed = observations(scene, Level::Patch, 0.0);
    let mut levels = vec![Vec::new(); scene.groom.section_count()];
    for &distance in distances {
        let choices = selector
            .select(
                &observed,
                &front_camera(distance),
                &RigidTransform::IDENTITY,
            )
            .unwrap();
        for (section, choice) in choices.iter().enumerate() {
            levels[section].push(choice.level);
        }
    }
    levels
}

/// The frames at which `levels` changes, with the level it changes to.
fn changes(levels: &[Level]) -> Vec<(usize, Level)> {
    levels
        .windows(2)
        .enumerate()
        .filter(|(_, pair)| pair[0] != pair[1])
        .map(|(frame, pair)| (frame + 1, pair[1]))
        .collect()
}

/// The selectors with and without the look ahead.
fn selectors(scene: &Scene) -> (LodSelector, LodSelector) {
    let occluders = scene.head.occluder_boxes();
    let mut ahead = LodSelector::new(&scene.groom, &occluders, settings()).unwrap();
    ahead.set_frame_time(0.02).unwrap();
    assert!((ahead.lead_frames() - LEAD_FRAMES as f32).abs() < 1e-4);
    let now = LodSelector::new(&scene.groom, &occluders, settings()).unwrap();
    assert_eq!(now.lead_frames(), 0.0, "no look ahead without a frame time");
    (ahead, now)
}

#[test]
fn error_ahead_extrapolates_steady_motions() {
    let k = 7.5;
    // Receding at a constant 0.1 m a frame: z_ahead = z + k·Δz exactly, errors go as 1/z.
    let factor = error_ahead(1.0, 1.1, k, 0.01);
    assert!((factor - 1.1 / (1.1 + k * 0.1)).abs() < 1e-6, "{factor}");
    // Approaching: z_ahead = z·(z/z_prev)^k, errors grow by (z_prev/z)^k.
    let factor = error_ahead(1.1, 1.0, k, 0.01);
    assert!((factor - 1.1f32.powf(k)).abs() < 1e-4, "{factor}");
    // A geometric recession z_n = z_0·qⁿ (the paper's zoom-out): the linear extrapolation
    // foresees no more than the motion makes, the factor stays at or above q^-k.
    for q in [1.01f32, 1.056, 1.2] {
        let factor = error_ahead(2.0, 2.0 * q, k, 0.01);
        assert!(factor >= q.powf(-k) && factor < 1.0, "q {q}: {factor}");
    }
    // Bounded, and 1 where a depth is unknown or there is nothing to look ahead.
    assert_eq!(error_ahead(1.0, 10.0, k, 0.01), 0.25);
    assert_eq!(error_ahead(10.0, 1.0, k, 0.01), 4.0);
    for (previous, now) in [
        (0.0, 1.0),
        (1.0, 0.0),
        (-1.0, 1.0),
        (f32::NAN, 1.0),
        (0.005, 1.0),
    ] {
        assert_eq!(
            error_ahead(previous, now, k, 0.01),
            1.0,
            "{previous} → {now}"
        );
    }
    assert_eq!(error_ahead(1.0, 2.0, 0.0, 0.01), 1.0);
}

#[test]
fn a_receding_camera_is_met_k_frames_early() {
    // The eye recedes 5 cm a frame. Looking k frames ahead, the selector's values at frame n are
    // the plain selector's at frame n + k (the depth is extrapolated exactly at a constant
    // speed, and the deviation model's errors go as 1/depth), so each section passes through the
    // same levels k frames earlier. The first frame cannot look ahead (no depth before it), so
    // sections with a change in the first k + 1 frames are left out.
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut ahead, mut now) = selectors(&scene);
    let distances: Vec<f32> = (0..120).map(|n| 0.4 + 0.05 * n as f32).collect();
    let with_lead = levels_over(&mut ahead, &scene, &distances);
    let without = levels_over(&mut now, &scene, &distances);
    let mut compared = 0;
    for (section, (with_lead, without)) in with_lead.iter().zip(&without).enumerate() {
        let plain = changes(without);
        if plain.is_empty() || plain[0].0 <= LEAD_FRAMES + 1 {
            continue;
        }
        let expected: Vec<(usize, Level)> = plain
            .iter()
            .map(|&(frame, level)| (frame - LEAD_FRAMES, level))
            .collect();
        assert_eq!(changes(with_lead), expected, "section {section}");
        compared += 1;
    }
    assert!(
        compared >= 20,
        "only {compared} sections changed level late enough"
    );
}

#[test]
fn foreseen_share_is_the_crossing_over_the_lead() {
    // A switch to clusters that the errors k frames ahead ask for from k = 3 on, looked for 7.5
    // frames ahead: the new level is to be fully in (half the blend) at frame 3, so the blend
    // is 3 / 7.5 = 0.4 of the whole, found by bisection to 1/4096 of the lead (above it).
    let level_at = |k: f32| {
        if k >= 3.0 {
            Level::Cluster
        } else {
            Level::StrandGroup
        }
    };
    let share = foreseen_share(level_at, Level::Cluster, 7.5);
    assert!((0.4..=0.4 + 1.0 / 4096.0).contains(&share), "{share}");
    // The whole blend where the look ahead did not bring the switch forward: the current frame
    // already asks for the level, the lead does not reach it, or there is no look ahead.
    assert_eq!(foreseen_share(|_| Level::Cluster, Level::Cluster, 7.5), 1.0);
    assert_eq!(foreseen_share(level_at, Level::Patch, 7.5), 1.0);
    assert_eq!(foreseen_share(level_at, Level::Cluster, 0.0), 1.0);
    assert_eq!(foreseen_share(level_at, Level::Cluster, f32::NAN), 1.0);
}

#[test]
fn a_switch_foreseen_within_the_lead_blends_over_its_share() {
    // At a steady recession the selector looking k frames ahead sees, at frame n, the errors
    // the plain one sees at frame n + k, for any real k (the depth is extrapolated exactly
    // at a constant speed). A section the plain selector switches at frame m crossed its limit
    // at some c in (m − 1, m]. The looking selector switches it at n = m − k, or at frame 1 (the
    // first that has a depth to look ahead from) when m ≤ k + 1, and foresees the crossing
    // c − n frames ahead: its share of the blend is (c − n) / k, the whole blend (within a
    // frame) in steady motion and less for the sections whose crossing comes in the first k
    // frames of the shot.
    // The eye recedes 10 cm a frame from 1.45 m: the first sections reach their limits within
    // the first k frames.
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut ahead, mut now) = selectors(&scene);
    let distances: Vec<f32> = (0..120).map(|n| 1.45 + 0.1 * n as f32).collect();
    let observed = observations(&scene, Level::Patch, 0.0);
    let head = RigidTransform::IDENTITY;
    let sections = scene.groom.section_count();
    // Each section's first switch with the look ahead: (frame, share of the blend).
    let mut first_switch: Vec<Option<(usize, f32)>> = vec![None; sections];
    let mut previous: Vec<Level> = Vec::new();
    for (frame, &distance) in distances.iter().enumerate() {
        let camera = front_camera(distance);
        let levels: Vec<Level> = ahead
            .select(&observed, &camera, &head)
            .unwrap()
            .iter()
            .map(|c| c.level)
            .collect();
        for section in 0..sections {
            let share = ahead.blend_shares()[section];
            assert!(share > 0.0 && share <= 1.0, "section {section}: {share}");
            let switched = frame > 0 && levels[section] != previous[section];
            if !switched {
                continue;
            }
            first_switch[section].get_or_insert((frame, share));
        }
        previous = levels;
    }
    let without = levels_over(&mut now, &scene, &distances);
    let k = LEAD_FRAMES as f32;
    let slack = 1e-3;
    let (mut steady, mut shortened) = (0, 0);
    for (section, without) in without.iter().enumerate() {
        let Some(&(m, _)) = changes(without).first() else {
            continue;
        };
        let (n, share) = first_switch[section].expect("the looking selector switches too");
        if n == m {
            // A switch the errors do not govern (a per-section rule stops applying as the
            // section shrinks below `rules_min_pixels`): nothing foreseen, the whole blend.
            assert_eq!(share, 1.0, "section {section}: unforeseen switch at {m}");
            continue;
        }
        let expected_n = m.saturating_sub(LEAD_FRAMES).max(1);
        assert_eq!(n, expected_n, "section {section}: plain switch at {m}");
        let (low, high) = if m == 1 {
            (1.0, 1.0)
        } else {
            ((m - 1 - n) as f32 / k, (m - n) as f32 / k)
        };
        assert!(
            share >= low - slack && share <= high + slack,
            "section {section}: switched at {n} (plain {m}), share {share} not in [{low}, {high}]"
        );
        if m > LEAD_FRAMES + 1 {
            steady += 1;
        } else if share < 1.0 - 1.0 / k {
            shortened += 1;
        }
    }
    assert!(
        steady >= 20,
        "only {steady} sections switched in steady motion"
    );
    assert!(shortened > 0, "no switch came within the lead");
}

#[test]
fn an_approaching_camera_is_met_early_but_never_late() {
    // The eye comes 5 cm a frame closer. The geometric extrapolation of an approach falls short
    // of a constant speed, so a section refines between 0 and k frames earlier than without the
    // look ahead, through the same levels, and some do refine earlier.
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut ahead, mut now) = selectors(&scene);
    let distances: Vec<f32> = (0..120).map(|n| 6.35 - 0.05 * n as f32).collect();
    let with_lead = levels_over(&mut ahead, &scene, &distances);
    let without = levels_over(&mut now, &scene, &distances);
    let (mut compared, mut earlier) = (0, 0);
    for (section, (with_lead, without)) in with_lead.iter().zip(&without).enumerate() {
        let plain = changes(without);
        if plain.is_empty() || plain[0].0 <= LEAD_FRAMES + 1 {
            continue;
        }
        let led = changes(with_lead);
        assert_eq!(
            led.len(),
            plain.len(),
            "section {section}: {led:?} {plain:?}"
        );
        for (&(led_frame, led_level), &(frame, level)) in led.iter().zip(&plain) {
            assert_eq!(led_level, level, "section {section}");
            assert!(
                led_frame <= frame && led_frame + LEAD_FRAMES >= frame,
                "section {section}: to {level} at frame {led_frame}, without looking ahead {frame}"
            );
            earlier += usize::from(led_frame < frame);
        }
        compared += 1;
    }
    assert!(
        compared >= 20,
        "only {compared} sections refined late enough"
    );
    assert!(earlier > 0, "no refinement came earlier");
}

#[test]
fn a_budgeted_choice_weighs_the_errors_k_frames_ahead() {
    // The eye recedes 5 cm a frame. A budgeted choice that looks k frames ahead weighs, at frame
    // n, the errors that one which does not look ahead sees at frame n + k: the depth is
    // extrapolated exactly at a constant speed and the deviation model's errors go as 1/depth.
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut ahead, mut now) = selectors(&scene);
    let observed = observations(&scene, Level::Patch, 0.0);
    let model = CostModel::new(CostRates::default()).unwrap();
    let work = vec![
        SectionWork {
            nodes: [13, 39, 65],
            drawn_segments: [12, 36, 4980],
        };
        scene.groom.section_count()
    ];
    let head = RigidTransform::IDENTITY;
    let step = 0.05;
    let (frame, later) = (1.0, 1.0 + LEAD_FRAMES as f32 * step);
    ahead
        .budget_options(&observed, &front_camera(frame - step), &head, &model, &work)
        .unwrap();
    let led: Vec<[f32; 3]> = ahead
        .budget_options(&observed, &front_camera(frame), &head, &model, &work)
        .unwrap()
        .iter()
        .map(|option| option.errors)
        .collect();
    let plain: Vec<[f32; 3]> = now
        .budget_options(&observed, &front_camera(later), &head, &model, &work)
        .unwrap()
        .iter()
        .map(|option| option.errors)
        .collect();
    let mut compared = 0;
    for (section, (led, plain)) in led.iter().zip(&plain).enumerate() {
        for level in 0..3 {
            // Both are e·f/z up to the rounding of z + k·Δz against the depth at n + k.
            let (a, b) = (led[level], plain[level]);
            assert!(
                (a - b).abs() <= 1e-4 * b.abs(),
                "section {section} level {level}: {a} px looking ahead, {b} px at frame n + k"
            );
            compared += usize::from(b > 0.0);
        }
    }
    assert!(compared >= 20, "only {compared} non-zero errors compared");
    // Without a frame time the budgeted choice sees the current frame only.
    let current: Vec<[f32; 3]> = now
        .budget_options(&observed, &front_camera(frame), &head, &model, &work)
        .unwrap()
        .iter()
        .map(|option| option.errors)
        .collect();
    assert!(current.iter().zip(&led).any(|(c, l)| c[0] > l[0]));
}

#[test]
fn look_ahead_inputs_are_checked() {
    let scene = Scene::preset("paper-curly").unwrap();
    let (mut selector, _) = selectors(&scene);
    for bad in [0.0, -0.01, f32::NAN, f32::INFINITY] {
        let error = selector.set_frame_time(bad).unwrap_err().to_string();
        assert!(error.contains("LOD frame time"), "{error}");
    }
    let error = selector.restore_depths(&[1.0; 3]).unwrap_err().to_string();
    assert!(error.contains("section depths"), "{error}");
    selector.restore_depths(&[]).unwrap();
    assert!(selector.depths().iter().all(|&z| z == 0.0));
    for bad in [-0.1, 1.5, f32::NAN] {
        let settings = LodSettings {
            blend_lead: bad,
            ..settings()
        };
        let error = settings.validate().unwrap_err().to_string();
        assert!(error.contains("blend lead"), "{error}");
    }
}
