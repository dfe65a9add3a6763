//! Where the wall-clock time of the last rendered frame went, stage by stage, for benchmarks
//! that attribute a frame's cost ([`crate::Renderer::last_timings`]).

/// Wall-clock time of each stage of one [`crate::Renderer::render`] call [s].
///
/// On a software rasterizer (lavapipe, llvmpipe) the passes run while the CPU waits in
/// [`RenderTimings::gpu`]; on a real GPU that wait overlaps nothing else either, since the image
/// is read back before `render` returns.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RenderTimings {
    /// Validating the frame and uploading its nodes, chain table and globals [s].
    pub upload: f64,
    /// Building the draw batches, recording the passes and submitting them [s].
    pub encode: f64,
    /// Waiting for the device to run the passes and copy the image into the readback buffer [s].
    pub gpu: f64,
    /// Copying the mapped image out of the readback buffer into the returned image [s].
    pub readback: f64,
}

impl RenderTimings {
    /// The sum of the stages [s].
    pub fn total(&self) -> f64 {
        self.upload + self.encode + self.gpu + self.readback
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn total_sums_the_stages() {
        let timings = RenderTimings {
            upload: 1.0,
            encode: 2.0,
            gpu: 4.0,
            readback: 8.0,
        };
        assert_eq!(timings.total(), 15.0);
    }
}
