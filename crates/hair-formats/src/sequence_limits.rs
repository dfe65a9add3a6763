//! How much of a mesh sequence (a body file's animation) a reader keeps ([`SequenceLimits`]):
//! the samples a run's time window needs, and a cap on the positions' memory, so that a long or
//! heavy file is trimmed to the shot or refused with its size instead of filling the memory
//! (every sample holds every point: a large static mesh under a transform sampled 1,000 times
//! is 1,000 copies).

use super::error::FormatErrorKind;

/// Bytes of one point of one sample.
const POINT_BYTES: u64 = 12;

/// Limits on the mesh sequences a reader builds. The default keeps every sample, uncapped.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SequenceLimits {
    /// Seconds from the first sample to keep [s]: later samples are not built, but the first
    /// one after the window is, so that every time inside the window interpolates as the whole
    /// file does. `None`: every sample. A finite number ≥ 0.
    pub seconds: Option<f64>,
    /// The most bytes the sequence's positions may take (samples × points × 12); a sequence
    /// over it is refused with its size. `None`: no cap.
    pub max_bytes: Option<u64>,
}

impl SequenceLimits {
    /// Checks that `seconds` is a finite number ≥ 0.
    pub fn validate(&self) -> Result<(), FormatErrorKind> {
        match self.seconds {
            Some(seconds) if !(seconds.is_finite() && seconds >= 0.0) => {
                Err(FormatErrorKind::InvalidOption {
                    name: "sequence.seconds",
                    value: seconds.to_string(),
                    allowed: "a finite number ≥ 0 (seconds from the first sample)",
                })
            }
            _ => Ok(()),
        }
    }

    /// Drops from `times` (ascending, in units of which `per_second` make a second) those past
    /// the window, all but the first after it.
    pub(crate) fn window(&self, times: &mut Vec<f64>, per_second: f64) {
        let (Some(seconds), Some(&first)) = (self.seconds, times.first()) else {
            return;
        };
        let end = first + seconds * per_second;
        let inside = times.iter().take_while(|&&t| t <= end).count();
        times.truncate((inside + 1).min(times.len()));
    }

    /// Refuses a sequence of `samples` samples of `points` points over the cap, naming its
    /// size.
    pub(crate) fn check(&self, samples: usize, points: usize) -> Result<(), FormatErrorKind> {
        let Some(cap) = self.max_bytes else {
            return Ok(());
        };
        let bytes = (samples as u64)
            .saturating_mul(points as u64)
            .saturating_mul(POINT_BYTES);
        if bytes <= cap {
            return Ok(());
        }
        let gib = |b: u64| b as f64 / f64::from(1u32 << 30);
        Err(FormatErrorKind::SequenceTooLarge {
            message: format!(
                "{samples} samples of {points} points take {:.2} GiB, over the cap of {:.2} GiB \
                 (half the memory available): read a shorter time range (a scene reads only its \
                 frames') or a lighter mesh",
                gib(bytes),
                gib(cap)
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window keeps the samples up to `first + seconds` and the one after; none past it.
    #[test]
    fn the_window_keeps_its_samples_and_the_one_after() {
        let limits = SequenceLimits {
            seconds: Some(1.0),
            max_bytes: None,
        };
        // Time codes at 24 per second from code 1001: the window ends at code 1025.
        let mut codes: Vec<f64> = (1001..=1100).map(f64::from).collect();
        limits.window(&mut codes, 24.0);
        assert_eq!(codes.first(), Some(&1001.0));
        assert_eq!(codes.last(), Some(&1026.0));
        assert_eq!(codes.len(), 26);
        // Fewer samples than the window: all kept.
        let mut short = vec![0.0, 0.5];
        limits.window(&mut short, 1.0);
        assert_eq!(short, [0.0, 0.5]);
        // No window: all kept.
        let mut all: Vec<f64> = (0..10).map(f64::from).collect();
        SequenceLimits::default().window(&mut all, 1.0);
        assert_eq!(all.len(), 10);
    }

    /// A sequence over the cap is refused with its counts and size; one at the cap is not.
    #[test]
    fn a_sequence_over_the_cap_is_refused_with_its_size() {
        let limits = SequenceLimits {
            seconds: None,
            max_bytes: Some(1000 * 100 * 12),
        };
        assert!(limits.check(1000, 100).is_ok());
        let error = limits.check(1001, 100).unwrap_err().to_string();
        assert!(
            error.contains("1001 samples of 100 points") && error.contains("GiB"),
            "{error}"
        );
        for seconds in [-1.0, f64::NAN, f64::INFINITY] {
            let bad = SequenceLimits {
                seconds: Some(seconds),
                max_bytes: None,
            };
            assert!(bad.validate().is_err(), "{seconds}");
        }
    }
}
