//! The scene file's fixed choices that name a kind of thing whose details come from other fields
//! (a motion's keyframes, a camera path's keyframes, a body's file): [`BodyKind`],
//! [`MotionKind`], [`CameraPathKind`] and [`LodModeKind`]. The command line's `--motion`,
//! `--camera` and `--level` take the same names.

use hair_core::Level;

hair_core::named_enum! {
    /// `body.kind`: what the hair grows on and collides with.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum BodyKind {
        /// The procedural head (the default without `body.file`).
        ProceduralHead = "procedural-head",
        /// The mesh of `body.file` (the default with it).
        Mesh = "mesh",
    }
}

hair_core::named_enum! {
    /// `motion.kind`: how the head moves.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum MotionKind {
        /// The head holds still (the default).
        #[default]
        Still = "still",
        /// The head shakes about the vertical axis.
        Shake = "shake",
        /// The head nods about the ear-to-ear axis.
        Nod = "nod",
        /// The head follows `motion.keyframes`.
        Keyframes = "keyframes",
    }
}

hair_core::named_enum! {
    /// `camera.path`: how the camera moves.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum CameraPathKind {
        /// Once around the target (the default).
        #[default]
        Orbit = "orbit",
        /// From the start distance to `camera.end_distance` (4× by default), geometrically.
        ZoomOut = "zoom-out",
        /// Still.
        Fixed = "fixed",
        /// Through `camera.keyframes`.
        Keyframes = "keyframes",
    }
}

hair_core::named_enum! {
    /// `lod.mode`: levels chosen per section every frame, or one fixed level.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub enum LodModeKind {
        /// Chosen per section from visibility, screen size and motion (§7; the default).
        #[default]
        Auto = "auto",
        /// Every section as five strand groups.
        Strands = "strands",
        /// Every section as three clusters.
        Clusters = "clusters",
        /// Every section as one patch.
        Patches = "patches",
    }
}

impl LodModeKind {
    /// The fixed level, or `None` for automatic levels.
    pub fn level(self) -> Option<Level> {
        match self {
            LodModeKind::Auto => None,
            LodModeKind::Strands => Some(Level::StrandGroup),
            LodModeKind::Clusters => Some(Level::Cluster),
            LodModeKind::Patches => Some(Level::Patch),
        }
    }
}
