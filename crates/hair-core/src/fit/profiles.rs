//! Binding a groom file's curves to the strands drawn for them: each curve becomes a residual
//! profile ([`StrandSet::profiles`]), its offsets from the strand's model (skeleton curve plus the
//! tapered root offset) in the skeleton's frames, so that at rest the strand is drawn in the
//! curve's own shape and in motion it is carried by its skeleton.
//!
//! Profiles are measured against the groom's current rest skeletons, so bind again whenever the
//! rest shape changes (after the sag-free rest pose, for example).

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::hierarchy::FittedHierarchy;
use super::resample::resample_into;
use crate::curves::Curves;
use crate::error::{HairError, Result};
use crate::groom::{Groom, PROFILE_SAMPLES};
use crate::level::Level;
use crate::nurbs::NurbsCurve;
use crate::representation::drawn::ChainPoint;
use crate::representation::geometry::degree_for;
use crate::transform::RigidTransform;

/// Gives every strand of `groom` (built from `fit` of `curves` by
/// [`Groom::from_fit_with_children`]: file strand `k` in group order is strand `k · per`, its
/// children the `per − 1` after it) the residual profile of its file curve, measured on the
/// groom's rest skeletons; children share their guide's. Replaces any earlier profiles.
///
/// Errors: a strand count that is not a multiple of the fitted curves; a strand group that
/// does not hold whole families (a curve's strand and its children); a curve index outside
/// `curves`.
pub fn bind_profiles(groom: &mut Groom, fit: &FittedHierarchy, curves: &Curves) -> Result<()> {
    let file_strands = fit.group_strands.len();
    let total = groom.strands.strand_count();
    let per = total / file_strands.max(1);
    if file_strands == 0 || per * file_strands != total {
        return Err(HairError::SizeMismatch {
            what: "groom strands (fitted curves and their children)",
            actual: total,
            expected: file_strands,
        });
    }
    if let Some(&curve) = fit
        .group_strands
        .iter()
        .find(|&&c| c as usize >= curves.curve_count())
    {
        return Err(HairError::invalid(
            "fitted curve",
            curve,
            "a curve of the file that was fitted",
        ));
    }
    // Profile k is guide k's (strand k · per): each group must hold whole families (a guide and
    // its children), or a child would read a neighbour family's profile.
    let strands = &groom.strands;
    if let Some(group) = (0..strands.group_count()).find(|&g| {
        let range = strands.strands(g);
        range.start % per != 0 || range.len() % per != 0
    }) {
        return Err(HairError::invalid(
            "strand group's strands",
            format!("{:?} in group {group}", strands.strands(group)),
            "whole families: a fitted curve's strand followed by its children",
        ));
    }
    let head = RigidTransform::IDENTITY;
    let (positions, frames) = groom.skeletons.rest_pose(&head);
    let chains = groom.level_chains(Level::StrandGroup);
    let per_group: Vec<Vec<Vec3>> = (0..strands.group_count())
        .into_par_iter()
        .map(|group| -> Result<Vec<Vec3>> {
            let nodes = groom.skeletons.nodes(chains.start + group);
            let degree = degree_for(nodes.len());
            let frames = &frames[nodes.clone()];
            let centre = NurbsCurve::clamped(positions[nodes].to_vec(), degree)?;
            let normal = NurbsCurve::clamped(frames.iter().map(|f| f.normal).collect(), degree)?;
            let binormal =
                NurbsCurve::clamped(frames.iter().map(|f| f.binormal).collect(), degree)?;
            let mut file = vec![Vec3::ZERO; PROFILE_SAMPLES];
            let mut out = Vec::new();
            for guide in strands.strands(group).step_by(per) {
                let curve = fit.group_strands[guide / per] as usize;
                let range = curves.offsets[curve] as usize..curves.offsets[curve + 1] as usize;
                if !resample_into(&curves.points[range], &mut file) {
                    // Read curves have two distinct finite points at least; keep the model.
                    out.extend(std::iter::repeat_n(Vec3::ZERO, PROFILE_SAMPLES));
                    continue;
                }
                let length = strands.length(guide);
                let offset: Vec2 = strands.root_offsets[guide];
                let tip = strands.tip_scale(guide);
                for (j, &point) in file.iter().enumerate() {
                    let u = length * j as f32 / (PROFILE_SAMPLES - 1) as f32;
                    let (position, derivative) = centre.point_and_derivative(u);
                    let chain = ChainPoint {
                        position,
                        normal: normal.point(u),
                        binormal: binormal.point(u),
                        derivative,
                    };
                    let model = chain.offset_point(u, offset, tip);
                    out.push(chain.residual_basis().transpose() * (point - model));
                }
            }
            Ok(out)
        })
        .collect::<Result<_>>()?;
    let strands = &mut groom.strands;
    strands.profiles = per_group.concat();
    strands.profile_of = (0..total).map(|strand| (strand / per) as u32).collect();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{FitSettings, SectionCount, fit_hierarchy};
    use crate::groom::{ChildStrands, GroomParams};
    use crate::representation::geometry::strand_polylines;

    /// Curly strands around a line of roots: each its own phase and length, so no two share a
    /// shape and a skeleton cannot draw them all.
    fn curls(count: usize) -> Curves {
        let mut curves = Curves {
            offsets: vec![0],
            ..Curves::default()
        };
        for c in 0..count {
            let phase = c as f32 * 0.7;
            let points = 24 + c % 9;
            let root = Vec3::new(0.004 * c as f32, 0.0, 0.0);
            for k in 0..points {
                let t = k as f32 * 0.01;
                let wiggle = 0.004 * (t * 90.0 + phase).sin();
                curves
                    .points
                    .push(root + Vec3::new(wiggle, -t, 0.004 * (t * 70.0 + phase).cos()));
            }
            curves.offsets.push(curves.points.len() as u32);
        }
        curves
    }

    #[test]
    fn bound_strands_are_drawn_in_their_curves_shapes() {
        let curves = curls(60);
        let settings = FitSettings {
            sections: SectionCount::Fixed(2),
            ..FitSettings::default()
        };
        let fit = fit_hierarchy(&curves, &settings).unwrap();
        let mut groom = Groom::from_fit_with_children(
            &fit,
            &curves,
            &GroomParams::straight(),
            &ChildStrands::default(),
        )
        .unwrap();
        let error = |groom: &Groom| -> f32 {
            let head = RigidTransform::IDENTITY;
            let (positions, frames) = groom.skeletons.rest_pose(&head);
            let drawn = strand_polylines(groom, &positions, &frames, 8).unwrap();
            let (mut a, mut b) = (vec![Vec3::ZERO; 64], vec![Vec3::ZERO; 64]);
            let mut worst = 0.0f32;
            for (k, &curve) in fit.group_strands.iter().enumerate() {
                let c = curve as usize;
                let file =
                    &curves.points[curves.offsets[c] as usize..curves.offsets[c + 1] as usize];
                let line = &drawn.points[drawn.offsets[k] as usize..drawn.offsets[k + 1] as usize];
                assert!(resample_into(file, &mut a) && resample_into(line, &mut b));
                for (p, q) in a.iter().zip(&b) {
                    worst = worst.max(p.distance(*q));
                }
            }
            worst
        };
        let unbound = error(&groom);
        bind_profiles(&mut groom, &fit, &curves).unwrap();
        let bound = error(&groom);
        // Without profiles a strand is drawn as its group's skeleton: the strands differ in
        // length (0.23 to 0.32 m) and in the phase of their curls, so that is centimetres off.
        // Bound, what remains is sampling: the file's points are h = 10 mm apart along the
        // strands (the profile's 64 entries 5 mm), and linear interpolation of a curl
        // A·sin(k·t) (A = 4 mm, k = 90 /m) between samples misses by at most A·(k·h)²/8 ≈
        // 0.43 mm for the file's polyline (0.1 mm for the profile's chords); the chords are a
        // little shorter than the polyline, which shifts the equal-length resampling of the two
        // by a few tenths of a millimetre more.
        assert!(unbound > 10e-3, "unbound {unbound}");
        assert!(bound < 1.5e-3, "bound {bound} against unbound {unbound}");
        assert_eq!(groom.strands.profile_of.len(), groom.strands.strand_count());
    }

    #[test]
    fn children_share_their_guides_profile_and_split_families_are_refused() {
        let curves = curls(20);
        let settings = FitSettings {
            sections: SectionCount::Fixed(1),
            ..FitSettings::default()
        };
        let fit = fit_hierarchy(&curves, &settings).unwrap();
        let children = ChildStrands {
            per_strand: 2,
            ..ChildStrands::default()
        };
        let mut groom =
            Groom::from_fit_with_children(&fit, &curves, &GroomParams::straight(), &children)
                .unwrap();
        bind_profiles(&mut groom, &fit, &curves).unwrap();
        // Each fitted curve's strand is followed by its two children: families of three, one
        // profile each.
        let strands = &groom.strands;
        assert_eq!(strands.strand_count(), 3 * curves.curve_count());
        assert_eq!(
            strands.profiles.len(),
            PROFILE_SAMPLES * curves.curve_count()
        );
        for strand in 0..strands.strand_count() {
            assert_eq!(strands.profile_of[strand] as usize, strand / 3);
        }
        // A group boundary moved into a family: a child would read the next family's profile.
        let mut split = groom.clone();
        split.strands.group_offsets[1] += 1;
        let error = bind_profiles(&mut split, &fit, &curves).unwrap_err();
        assert!(error.to_string().contains("whole families"), "{error}");
    }
}
