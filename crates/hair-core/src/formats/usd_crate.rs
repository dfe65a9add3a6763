//! USD `BasisCurves` and `Mesh`, text `.usda` and binary `.usdc`, through the `openusd` crate.
