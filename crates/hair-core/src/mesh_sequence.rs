//! Triangle meshes sampled in time ([`MeshSequence`]): a body that moves and deforms, as USD
//! time samples and Alembic mesh sequences hold one. One topology for every sample, positions
//! per sample, interpolated linearly in time between samples and held before the first and after
//! the last, so any frame rate reads it (a rate that differs from the file's is resampled).

use glam::Vec3;
use thiserror::Error;

use crate::mesh::{MeshError, TriangleMesh};

/// What makes a mesh sequence unusable, found by [`MeshSequence::new`]. Readers add the file
/// and the prim; the sample is named here.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshSequenceError {
    /// No samples at all.
    #[error("the mesh sequence has no samples")]
    NoSamples,
    /// Not one time per sample.
    #[error("the mesh sequence has {times} sample times for {samples} samples")]
    TimeCount {
        /// Number of times.
        times: usize,
        /// Number of samples.
        samples: usize,
    },
    /// A sample time is NaN or infinite.
    #[error("sample {sample} of the mesh sequence has a time that is not finite: {time}")]
    TimeNotFinite {
        /// Index of the sample.
        sample: usize,
        /// Its time [s].
        time: f64,
    },
    /// Sample times do not strictly increase.
    #[error(
        "sample {sample} of the mesh sequence is at {time} s, not after the sample before it \
         ({previous} s): sample times must strictly increase"
    )]
    TimesNotIncreasing {
        /// Index of the sample.
        sample: usize,
        /// Its time [s].
        time: f64,
        /// The time of the sample before it [s].
        previous: f64,
    },
    /// A sample has another number of points than the first (the topology changed).
    #[error(
        "sample {sample} of the mesh sequence has {count} points where the first has {expected}: \
         the topology must not change between samples"
    )]
    PointCount {
        /// Index of the sample.
        sample: usize,
        /// Its number of points.
        count: usize,
        /// The first sample's number of points.
        expected: usize,
    },
    /// A time code rate that is not finite and > 0.
    #[error("time codes per second {rate}: a finite number > 0 is needed")]
    TimeCodeRate {
        /// The rate given.
        rate: f64,
    },
    /// A sample's mesh is malformed (a point that is not finite, an index out of range, …).
    #[error("sample {sample} of the mesh sequence: {source}")]
    Mesh {
        /// Index of the sample.
        sample: usize,
        /// What is wrong with it.
        source: MeshError,
    },
}

/// A triangle mesh sampled in time [m, s]: one set of triangles, one set of positions per
/// sample. Between samples positions are interpolated linearly; before the first sample and after
/// the last they are held. A rigid mesh is the one-sample case ([`MeshSequence::still`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshSequence {
    /// Triangles as three indices into each sample's positions, counter-clockwise seen from
    /// outside.
    triangles: Vec<[u32; 3]>,
    /// Number of points of every sample.
    vertex_count: usize,
    /// Sample times [s], strictly increasing.
    times: Vec<f64>,
    /// Positions [m], sample-major: sample `s` owns `s·vertex_count .. (s+1)·vertex_count`.
    positions: Vec<Vec3>,
    /// Where the times came from.
    clock: SequenceClock,
}

/// How a sequence's times [s] map to its source's time line: a file's time codes per second,
/// and the source time of time 0 (a sequence moved in time by [`MeshSequence::retimed`] keeps
/// it, so that what is written out lines up with the file again).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SequenceClock {
    /// The source's time codes (frames) per second, where it has them (USD's
    /// `timeCodesPerSecond`); `None` for a source timed in seconds (Alembic, a procedural body).
    pub time_codes_per_second: Option<f64>,
    /// The source time [s] at the sequence's time 0.
    pub source_time_at_zero: f64,
}

impl Default for SequenceClock {
    fn default() -> Self {
        Self {
            time_codes_per_second: None,
            source_time_at_zero: 0.0,
        }
    }
}

impl SequenceClock {
    /// The source time code of sequence time `time` [s], at `codes_per_second` codes per second
    /// where the source has none; rounded to 1e-6 of a code, so that a source's whole codes
    /// read back whole.
    pub fn time_code(&self, time: f64, codes_per_second: f64) -> f64 {
        let rate = self.time_codes_per_second.unwrap_or(codes_per_second);
        ((time + self.source_time_at_zero) * rate * 1e6).round() / 1e6
    }
}

impl MeshSequence {
    /// A sequence from its triangles, sample times [s] and each sample's positions [m]. Checks
    /// that there is a sample, that times are finite and strictly increase, that every sample
    /// has the first's number of points, and that every sample is a valid mesh with those
    /// triangles ([`TriangleMesh::validate`]); the first problem is reported with its sample.
    pub fn new(
        triangles: Vec<[u32; 3]>,
        times: Vec<f64>,
        samples: Vec<Vec<Vec3>>,
    ) -> Result<Self, MeshSequenceError> {
        let Some(first) = samples.first() else {
            return Err(MeshSequenceError::NoSamples);
        };
        let vertex_count = first.len();
        if times.len() != samples.len() {
            return Err(MeshSequenceError::TimeCount {
                times: times.len(),
                samples: samples.len(),
            });
        }
        for (sample, &time) in times.iter().enumerate() {
            if !time.is_finite() {
                return Err(MeshSequenceError::TimeNotFinite { sample, time });
            }
            if sample > 0 && time <= times[sample - 1] {
                return Err(MeshSequenceError::TimesNotIncreasing {
                    sample,
                    time,
                    previous: times[sample - 1],
                });
            }
        }
        let mut positions = Vec::with_capacity(vertex_count * samples.len());
        let mut check = TriangleMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            triangles,
        };
        for (sample, points) in samples.into_iter().enumerate() {
            if points.len() != vertex_count {
                return Err(MeshSequenceError::PointCount {
                    sample,
                    count: points.len(),
                    expected: vertex_count,
                });
            }
            check.positions = points;
            check
                .validate()
                .map_err(|source| MeshSequenceError::Mesh { sample, source })?;
            positions.extend_from_slice(&check.positions);
        }
        Ok(Self {
            triangles: check.triangles,
            vertex_count,
            times,
            positions,
            clock: SequenceClock::default(),
        })
    }

    /// The sequence with its source's time codes per second (`None`: timed in seconds); a rate
    /// that is not finite and > 0 is refused.
    pub fn with_time_codes_per_second(
        mut self,
        rate: Option<f64>,
    ) -> Result<Self, MeshSequenceError> {
        if let Some(rate) = rate.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(MeshSequenceError::TimeCodeRate { rate });
        }
        self.clock.time_codes_per_second = rate;
        Ok(self)
    }

    /// The sequence moved in time so that its first sample is at `first` [s]; the clock keeps
    /// the source time of the new time 0. A `first` that is not finite is refused.
    pub fn retimed(mut self, first: f64) -> Result<Self, MeshSequenceError> {
        if !first.is_finite() {
            return Err(MeshSequenceError::TimeNotFinite {
                sample: 0,
                time: first,
            });
        }
        let shift = first - self.times[0];
        for time in &mut self.times {
            *time += shift;
        }
        self.clock.source_time_at_zero -= shift;
        Ok(self)
    }

    /// How the times map to the source's time line.
    pub fn clock(&self) -> SequenceClock {
        self.clock
    }

    /// A mesh that never moves: one sample at time 0.
    pub fn still(mesh: &TriangleMesh) -> Result<Self, MeshSequenceError> {
        Self::new(
            mesh.triangles.clone(),
            vec![0.0],
            vec![mesh.positions.clone()],
        )
    }

    /// The triangles, as indices into each sample's positions.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of points of every sample.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Number of samples (at least one).
    pub fn sample_count(&self) -> usize {
        self.times.len()
    }

    /// Sample times [s], strictly increasing.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The first and last sample times [s].
    pub fn time_range(&self) -> (f64, f64) {
        (self.times[0], self.times[self.times.len() - 1])
    }

    /// Whether the points ever move: more than one sample, and some sample differs from the
    /// first.
    pub fn is_animated(&self) -> bool {
        let first = self.sample_positions(0);
        (1..self.sample_count()).any(|s| self.sample_positions(s) != first)
    }

    /// The positions of sample `sample` [m]. Panics when `sample` is out of range.
    pub fn sample_positions(&self, sample: usize) -> &[Vec3] {
        &self.positions[sample * self.vertex_count..(sample + 1) * self.vertex_count]
    }

    /// The two samples around time `time` [s] and the weight of the second: positions at `time`
    /// are `(1 − w)·p[s0] + w·p[s1]`. Before the first sample it is `(0, 0, 0)`, after the last
    /// `(last, last, 0)`; a NaN time reads the first sample.
    pub fn bracket(&self, time: f64) -> (usize, usize, f32) {
        let last = self.times.len() - 1;
        if time.is_nan() || time <= self.times[0] {
            return (0, 0, 0.0);
        }
        if time >= self.times[last] {
            return (last, last, 0.0);
        }
        // times[s1 - 1] < time < times[s1]... or equal to times[s1 - 1].
        let s1 = self.times.partition_point(|&t| t <= time);
        let s0 = s1 - 1;
        let weight = (time - self.times[s0]) / (self.times[s1] - self.times[s0]);
        (s0, s1, weight as f32)
    }

    /// Point `vertex` at time `time` [m], interpolated between its samples. Panics when `vertex`
    /// is out of range.
    pub fn point_at(&self, vertex: usize, time: f64) -> Vec3 {
        let (s0, s1, weight) = self.bracket(time);
        let a = self.positions[s0 * self.vertex_count + vertex];
        let b = self.positions[s1 * self.vertex_count + vertex];
        a.lerp(b, weight)
    }

    /// Writes every point at time `time` [m] into `out` (resized to the vertex count; allocates
    /// nothing once `out` has grown).
    pub fn positions_at(&self, time: f64, out: &mut Vec<Vec3>) {
        let (s0, s1, weight) = self.bracket(time);
        let a = self.sample_positions(s0);
        let b = self.sample_positions(s1);
        out.clear();
        out.extend(a.iter().zip(b).map(|(a, b)| a.lerp(*b, weight)));
    }

    /// The mesh at time `time`, with vertex normals.
    pub fn mesh_at(&self, time: f64) -> TriangleMesh {
        let mut mesh = TriangleMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            triangles: self.triangles.clone(),
        };
        self.positions_at(time, &mut mesh.positions);
        mesh.compute_vertex_normals();
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle_at(offset: f32) -> Vec<Vec3> {
        vec![
            Vec3::new(offset, 0.0, 0.0),
            Vec3::new(offset + 1.0, 0.0, 0.0),
            Vec3::new(offset, 1.0, 0.0),
        ]
    }

    fn moving() -> MeshSequence {
        MeshSequence::new(
            vec![[0, 1, 2]],
            vec![0.0, 0.5, 1.5],
            vec![triangle_at(0.0), triangle_at(1.0), triangle_at(3.0)],
        )
        .unwrap()
    }

    #[test]
    fn interpolates_linearly_between_samples_and_holds_outside() {
        let sequence = moving();
        // x(t) is piecewise linear through (0, 0), (0.5, 1), (1.5, 3): x(0.25) = 0.5,
        // x(1.0) = 1 + (0.5/1.0)·2 = 2.
        assert_eq!(sequence.point_at(0, 0.25), Vec3::new(0.5, 0.0, 0.0));
        assert_eq!(sequence.point_at(0, 1.0), Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(sequence.point_at(0, 0.5), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(sequence.point_at(1, -3.0), Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(sequence.point_at(2, 9.0), Vec3::new(3.0, 1.0, 0.0));
        assert_eq!(sequence.point_at(0, f64::NAN), Vec3::ZERO);
        let mut out = Vec::new();
        sequence.positions_at(1.0, &mut out);
        assert_eq!(out, triangle_at(2.0));
        assert!(sequence.is_animated());
        assert_eq!(sequence.time_range(), (0.0, 1.5));
        let mesh = sequence.mesh_at(1.0);
        assert_eq!(mesh.normals, vec![Vec3::Z; 3]);
    }

    #[test]
    fn a_still_mesh_is_one_sample_that_never_moves() {
        let mesh = TriangleMesh {
            positions: triangle_at(0.0),
            normals: Vec::new(),
            triangles: vec![[0, 1, 2]],
        };
        let still = MeshSequence::still(&mesh).unwrap();
        assert_eq!(still.sample_count(), 1);
        assert!(!still.is_animated());
        assert_eq!(still.point_at(2, 7.0), Vec3::Y);
    }

    #[test]
    fn bad_sequences_are_refused_naming_the_sample() {
        let two = |a, b| vec![triangle_at(a), triangle_at(b)];
        assert_eq!(
            MeshSequence::new(vec![[0, 1, 2]], vec![], vec![]),
            Err(MeshSequenceError::NoSamples)
        );
        assert!(matches!(
            MeshSequence::new(vec![[0, 1, 2]], vec![0.0, f64::INFINITY], two(0.0, 1.0)),
            Err(MeshSequenceError::TimeNotFinite { sample: 1, .. })
        ));
        assert!(matches!(
            MeshSequence::new(vec![[0, 1, 2]], vec![1.0, 1.0], two(0.0, 1.0)),
            Err(MeshSequenceError::TimesNotIncreasing { sample: 1, .. })
        ));
        assert_eq!(
            MeshSequence::new(vec![[0, 1, 2]], vec![0.0], two(0.0, 1.0)),
            Err(MeshSequenceError::TimeCount {
                times: 1,
                samples: 2
            })
        );
        let mut short = two(0.0, 1.0);
        short[1].pop();
        assert_eq!(
            MeshSequence::new(vec![[0, 1, 2]], vec![0.0, 1.0], short),
            Err(MeshSequenceError::PointCount {
                sample: 1,
                count: 2,
                expected: 3
            })
        );
        let mut nan = two(0.0, 1.0);
        nan[1][2].y = f32::NAN;
        let error = MeshSequence::new(vec![[0, 1, 2]], vec![0.0, 1.0], nan).unwrap_err();
        assert!(matches!(error, MeshSequenceError::Mesh { sample: 1, .. }));
        assert!(error.to_string().contains("sample 1"), "{error}");
        assert!(matches!(
            MeshSequence::new(vec![[0, 1, 3]], vec![0.0], vec![triangle_at(0.0)]),
            Err(MeshSequenceError::Mesh { sample: 0, .. })
        ));
    }
}
