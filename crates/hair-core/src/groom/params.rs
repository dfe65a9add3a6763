//! Groom parameters, their validation, and the named presets (`paper-curly`, `straight`, `wavy`,
//! `curly`).

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result, require_in_range, require_positive};
use crate::style::HairStyle;

/// Everything that defines a groom on a head: how many sections, how many strands, and the style.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroomParams {
    /// Number of sections (= patches; ×3 clusters; ×5 strand groups), at least 1.
    pub section_count: usize,
    /// Strands carried by each strand-group skeleton, at least 1.
    pub strands_per_group: usize,
    /// Length of every hair [m], > 0.
    pub hair_length: f32,
    /// Rest shape of every skeleton.
    pub style: HairStyle,
    /// Width of a section across the scalp [m]; `None` chooses it from the root spacing
    /// (`section_coverage` × the mean nearest-neighbour distance between section roots; a single
    /// section, which has no neighbour, takes the spacing of two, 9.6 cm on the default head, so
    /// it is 14 cm wide at the presets' coverage).
    pub section_width: Option<f32>,
    /// With `section_width = None`: width as a multiple of the root spacing (> 0; the presets'
    /// 1.5 overlaps neighbouring sections by half a spacing, so the scalp does not show between
    /// them: `tests/scalp_coverage.rs` measured 3.0 % bare scalp from above at 1.2 and 1.8 % at
    /// 1.5).
    pub section_coverage: f32,
    /// A cluster's tip radius as a fraction of its root radius, `0..=1` (the root radius is a sixth
    /// of the section width, so three clusters side by side span it).
    pub cluster_tip_scale: f32,
    /// Angle of the growth direction above the scalp's tangent plane [degrees], `0..=90`.
    pub root_lift_degrees: f32,
    /// Seed of the strand root offsets and shades.
    pub seed: u64,
}

crate::named_enum! {
    /// A built-in groom ([`GroomParams::from`] gives its parameters).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
    pub enum GroomPreset {
        /// The paper's benchmark groom: 91 sections, 37,765 curly strands
        /// ([`GroomParams::paper_curly`]).
        #[default]
        PaperCurly = "paper-curly",
        /// Straight hair ([`GroomParams::straight`]).
        Straight = "straight",
        /// Wavy hair ([`GroomParams::wavy`]).
        Wavy = "wavy",
        /// Ringlet curls ([`GroomParams::curly`]).
        Curly = "curly",
    }
}

/// The names of the built-in presets ([`GroomPreset::NAMES`]).
pub const PRESET_NAMES: [&str; 4] = GroomPreset::NAMES;

impl From<GroomPreset> for GroomParams {
    fn from(preset: GroomPreset) -> Self {
        match preset {
            GroomPreset::PaperCurly => GroomParams::paper_curly(),
            GroomPreset::Straight => GroomParams::straight(),
            GroomPreset::Wavy => GroomParams::wavy(),
            GroomPreset::Curly => GroomParams::curly(),
        }
    }
}

impl GroomParams {
    /// The paper's benchmark groom (§8.2): 91 curly sections = 91 patches = 273 clusters = 455 strand
    /// groups holding 37,765 strands (83 per group).
    pub fn paper_curly() -> Self {
        GroomParams {
            section_count: 91,
            strands_per_group: 83,
            hair_length: 0.25,
            style: HairStyle::curly(50.0, 0.008, 0.03),
            section_width: None,
            section_coverage: 1.5,
            cluster_tip_scale: 0.5,
            root_lift_degrees: 15.0,
            seed: 2002,
        }
    }

    /// A small straight groom (40 sections, 4,800 strands).
    pub fn straight() -> Self {
        GroomParams {
            section_count: 40,
            strands_per_group: 24,
            hair_length: 0.3,
            style: HairStyle::straight(0.025),
            ..Self::paper_curly()
        }
    }

    /// A small wavy groom (40 sections, 4,800 strands).
    pub fn wavy() -> Self {
        GroomParams {
            style: HairStyle::wavy(30.0, 0.004, 0.03),
            ..Self::straight()
        }
    }

    /// A small curly groom (40 sections, 4,800 strands).
    pub fn curly() -> Self {
        GroomParams {
            hair_length: 0.22,
            style: HairStyle::curly(50.0, 0.008, 0.03),
            ..Self::straight()
        }
    }

    /// The preset called `name` (see [`PRESET_NAMES`]).
    pub fn preset(name: &str) -> Result<Self> {
        match name.parse::<GroomPreset>() {
            Ok(preset) => Ok(preset.into()),
            Err(_) => Err(HairError::UnknownName {
                kind: "preset",
                name: name.to_string(),
                known: PRESET_NAMES.join(", "),
            }),
        }
    }

    /// Checks every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<()> {
        if self.section_count == 0 {
            return Err(HairError::invalid("section count", 0, "at least 1 section"));
        }
        if self.strands_per_group == 0 {
            return Err(HairError::invalid(
                "strands per group",
                0,
                "at least 1 strand per strand group",
            ));
        }
        let strands = self.section_count as u64 * 5 * self.strands_per_group as u64;
        if strands > 50_000_000 {
            return Err(HairError::invalid(
                "strand count",
                strands,
                "at most 50,000,000 strands (sections × 5 × strands per group)",
            ));
        }
        require_positive("hair length (m)", self.hair_length)?;
        self.style.validate()?;
        if let Some(width) = self.section_width {
            require_positive("section width (m)", width)?;
        }
        require_positive("section coverage", self.section_coverage)?;
        require_in_range(
            "cluster tip scale",
            self.cluster_tip_scale,
            0.0,
            1.0,
            "0..=1 (tip radius / root radius)",
        )?;
        require_in_range(
            "root lift",
            self.root_lift_degrees,
            0.0,
            90.0,
            "0..=90 degrees",
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid_and_paper_curly_has_the_papers_strand_count() {
        for name in PRESET_NAMES {
            GroomParams::preset(name).unwrap().validate().unwrap();
        }
        let paper = GroomParams::paper_curly();
        assert_eq!(paper.section_count * 5 * paper.strands_per_group, 37_765);
        let error = GroomParams::preset("afro").unwrap_err().to_string();
        assert!(error.contains("paper-curly"), "{error}");
    }

    #[test]
    fn invalid_params_name_themselves() {
        let mut params = GroomParams::curly();
        params.strands_per_group = 0;
        assert!(
            params
                .validate()
                .unwrap_err()
                .to_string()
                .contains("strands per group")
        );
        let mut params = GroomParams::curly();
        params.hair_length = f32::NAN;
        assert!(
            params
                .validate()
                .unwrap_err()
                .to_string()
                .contains("hair length")
        );
        let mut params = GroomParams::curly();
        params.section_width = Some(-0.01);
        assert!(
            params
                .validate()
                .unwrap_err()
                .to_string()
                .contains("section width")
        );
    }
}
