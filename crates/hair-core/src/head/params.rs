//! Parameters of the procedural head: tessellation, hairline and part line, with validation.

use serde::{Deserialize, Serialize};

use crate::error::{HairError, Result, require_in_range};

/// Parameters of [`Head::procedural`](super::Head::procedural).
///
/// Heights are y coordinates [m] of the head's frame (origin at the head's centre, about eye level;
/// the top of the head is at y ≈ 0.107 m, the chin at y ≈ -0.113 m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeadParams {
    /// Number of latitude bands of the mesh, top pole to bottom pole (8..=1024; default 64).
    /// Latitudes are spaced evenly in arc length along the surface, not in angle.
    pub latitude_bands: usize,
    /// Number of longitude bands (vertices per ring) of the mesh (8..=2048; default 96).
    pub longitude_bands: usize,
    /// Position of the part line [m]: its x coordinate (signed distance from the mid-line, +x is the
    /// head's left; -0.04..=0.04; default 0.025, a side part). 0 is a centre part.
    pub part_offset: f32,
    /// Height of the hairline at the middle of the forehead [m] (0.02..=0.09; default 0.07).
    pub hairline_front_height: f32,
    /// Height of the hairline above the ears [m] (-0.04..=0.08; default 0.025).
    pub hairline_ear_height: f32,
    /// Height of the hairline at the nape, the middle of the back [m] (-0.12..=0.02; default -0.07).
    pub hairline_nape_height: f32,
    /// A root is `near_face` when it lies within this distance [m] of the front hairline (the part in
    /// front of the ears) (0..=0.2; default 0.03).
    pub near_face_distance: f32,
}

impl Default for HeadParams {
    fn default() -> Self {
        HeadParams {
            latitude_bands: 64,
            longitude_bands: 96,
            part_offset: 0.025,
            hairline_front_height: 0.07,
            hairline_ear_height: 0.025,
            hairline_nape_height: -0.07,
            near_face_distance: 0.03,
        }
    }
}

impl HeadParams {
    /// Checks every parameter; the error names the first one out of range and its allowed range.
    pub fn validate(&self) -> Result<()> {
        if !(8..=1024).contains(&self.latitude_bands) {
            return Err(HairError::invalid(
                "latitude_bands",
                self.latitude_bands,
                "an integer in 8..=1024",
            ));
        }
        if !(8..=2048).contains(&self.longitude_bands) {
            return Err(HairError::invalid(
                "longitude_bands",
                self.longitude_bands,
                "an integer in 8..=2048",
            ));
        }
        require_in_range(
            "part_offset",
            self.part_offset,
            -0.04,
            0.04,
            "a finite number in -0.04..=0.04 m",
        )?;
        require_in_range(
            "hairline_front_height",
            self.hairline_front_height,
            0.02,
            0.09,
            "a finite number in 0.02..=0.09 m",
        )?;
        require_in_range(
            "hairline_ear_height",
            self.hairline_ear_height,
            -0.04,
            0.08,
            "a finite number in -0.04..=0.08 m",
        )?;
        require_in_range(
            "hairline_nape_height",
            self.hairline_nape_height,
            -0.12,
            0.02,
            "a finite number in -0.12..=0.02 m",
        )?;
        require_in_range(
            "near_face_distance",
            self.near_face_distance,
            0.0,
            0.2,
            "a finite number in 0..=0.2 m",
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert!(HeadParams::default().validate().is_ok());
        let cases: [(HeadParams, &str); 6] = [
            (
                HeadParams {
                    latitude_bands: 2,
                    ..HeadParams::default()
                },
                "latitude_bands",
            ),
            (
                HeadParams {
                    longitude_bands: 5000,
                    ..HeadParams::default()
                },
                "longitude_bands",
            ),
            (
                HeadParams {
                    part_offset: f32::NAN,
                    ..HeadParams::default()
                },
                "part_offset",
            ),
            (
                HeadParams {
                    hairline_front_height: 0.5,
                    ..HeadParams::default()
                },
                "hairline_front_height",
            ),
            (
                HeadParams {
                    hairline_nape_height: f32::INFINITY,
                    ..HeadParams::default()
                },
                "hairline_nape_height",
            ),
            (
                HeadParams {
                    near_face_distance: -0.01,
                    ..HeadParams::default()
                },
                "near_face_distance",
            ),
        ];
        for (params, name) in cases {
            let error = params.validate().unwrap_err();
            assert!(
                matches!(&error, HairError::InvalidParameter { name: n, .. } if *n == name),
                "{error}"
            );
            assert!(error.to_string().contains(name));
        }
    }

    #[test]
    fn params_read_from_toml_like_json_with_defaults() {
        let params: HeadParams = serde_json::from_str(r#"{ "part_offset": 0.0 }"#).unwrap();
        assert_eq!(params.part_offset, 0.0);
        assert_eq!(params.latitude_bands, 64);
        assert!(serde_json::from_str::<HeadParams>(r#"{ "part": 0.0 }"#).is_err());
    }
}
