//! The hair's reflectance: its colours and coefficients ([`HairMaterial`]) and its model
//! ([`HairShading`], named by [`ShadingModel`]): Kajiya-Kay or Marschner's lobes.

use glam::Vec3;

use crate::marschner::Marschner;

hair_core::named_enum! {
    /// The reflectance model by name ([`HairShading::from`] gives it with its default
    /// parameters): scene files' `output.shading` and the command line's `--shading`.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum ShadingModel {
        /// Kajiya-Kay: a diffuse term and one specular lobe ([`HairShading::KajiyaKay`]).
        #[default]
        KajiyaKay = "kajiya-kay",
        /// Marschner's R, TT and TRT lobes with the paper's measured shift and width
        /// ([`HairShading::Marschner`] with [`Marschner::default`]).
        Marschner = "marschner",
    }
}

impl From<ShadingModel> for HairShading {
    fn from(model: ShadingModel) -> Self {
        match model {
            ShadingModel::KajiyaKay => HairShading::KajiyaKay,
            ShadingModel::Marschner => HairShading::Marschner(Marschner::default()),
        }
    }
}

impl HairShading {
    /// The model's name ([`ShadingModel`]), its parameters aside.
    pub fn model(&self) -> ShadingModel {
        match self {
            HairShading::KajiyaKay => ShadingModel::KajiyaKay,
            HairShading::Marschner(_) => ShadingModel::Marschner,
        }
    }
}

/// The reflectance model of strands, clusters and patches.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum HairShading {
    /// Kajiya-Kay in the Heidrich-Seidel form: a diffuse term `∝ sin(T, L)` and one specular lobe
    /// about the mirror cone ([`HairMaterial::specular`], [`HairMaterial::specular_exponent`]).
    #[default]
    KajiyaKay,
    /// Marschner's single-scattering lobes (R, TT, TRT; [`Marschner`]) in place of the specular
    /// lobe: the highlight shifted towards the root, a coloured secondary highlight and light
    /// transmitted through back-lit hair. The diffuse term stays (it stands for the light
    /// scattered many times); [`HairMaterial::specular`] and the exponent are not used.
    Marschner(Marschner),
}

/// Hair colour range and shading coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairMaterial {
    /// Colour of shade 0.
    pub dark_color: Vec3,
    /// Colour of shade 1.
    pub light_color: Vec3,
    /// Diffuse coefficient (multiplies sin(T, L)).
    pub diffuse: f32,
    /// Specular coefficient.
    pub specular: f32,
    /// Specular exponent (highlight sharpness).
    pub specular_exponent: f32,
    /// The reflectance model (Kajiya-Kay by default).
    pub shading: HairShading,
}

impl Default for HairMaterial {
    /// Medium brown hair.
    fn default() -> Self {
        HairMaterial {
            dark_color: Vec3::new(0.09, 0.045, 0.02),
            light_color: Vec3::new(0.35, 0.2, 0.09),
            diffuse: 1.0,
            specular: 0.2,
            specular_exponent: 40.0,
            shading: HairShading::KajiyaKay,
        }
    }
}
