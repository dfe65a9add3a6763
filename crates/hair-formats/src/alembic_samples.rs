//! The samples of one Alembic property, every one (the curves reader reads the first only), with
//! its time from the property's time sampling, for the mesh sequence reader (`alembic_mesh.rs`).
//!
//! `ogawa-rs` 0.4.0 maps an array property's samples to the wrong children (it forgets that each
//! array sample has two, its data and its dimensions, and takes the first changed sample as 0
//! where Alembic stores 1), so samples are located here as Alembic's `ReadUtil` does.

use ogawa_rs::{DataType, PodArray, PropertyReader};

use super::alembic::{Reading, SampledProperty, crate_error};
use super::error::FormatErrorKind;
use super::ogawa::structure;
use super::usd_xform::Timed;

/// One sample of a property: its time [s], its values, and the byte offset of its first value.
pub(crate) type PropertySample = (f64, PodArray, u64);

/// Every sample of property `name` of `compound`: its time [s], its values and the byte offset
/// of its first value; `None` when there is no such property.
pub(crate) fn samples(
    reading: &mut Reading,
    compound: &PropertyReader,
    name: &str,
    element: &str,
    data_type: Option<&DataType>,
) -> Result<Option<Vec<PropertySample>>, FormatErrorKind> {
    let element = format!("{element} {name}");
    let Some(SampledProperty {
        group,
        header,
        array,
    }) = reading.sampled_property(compound, name, &element, data_type)?
    else {
        return Ok(None);
    };
    let per_sample = if array { 2 } else { 1 };
    let count = header.next_sample_index;
    if count == 0 || group.children.is_empty() {
        return Err(structure(element, "no sample".into(), group.position));
    }
    let (first, last) = (header.first_changed_index, header.last_changed_index);
    let mut out = Vec::with_capacity(count as usize);
    for sample in 0..count {
        // Alembic's ReadUtil: samples before the first change are the first stored one, samples
        // after the last change the last one. `ogawa-rs` reads the header's implicit first
        // change as 0 where Alembic takes 1.
        let stored = if first == 0 && last == 0 {
            0
        } else {
            let first = first.max(1);
            if sample < first {
                0
            } else if sample >= last {
                last.saturating_sub(first) + 1
            } else {
                sample - first + 1
            }
        };
        let child = stored as usize * per_sample;
        if child >= group.children.len() {
            return Err(structure(
                element,
                format!(
                    "sample {sample} is stored at child {child}, but the property has {}",
                    group.children.len()
                ),
                group.position,
            ));
        }
        let time = sample_time(header.time_sampling.as_deref(), sample)
            .map_err(|message| structure(&element, message, group.position))?;
        let data = group
            .load_data(&mut reading.reader, child)
            .map_err(crate_error(&element, group.position))?;
        let values_at = data.position + 8 + 16;
        let values = if data.size == 0 {
            PodArray::U8(Vec::new())
        } else {
            data.read_pod_array(&header.data_type, &mut reading.reader)
                .map_err(crate_error(&element, data.position))?
        };
        out.push((time, values, values_at));
    }
    Ok(Some(out))
}

/// The time of sample `index` of a property with time sampling `sampling` [s] (none: Alembic's
/// identity sampling, one per second from 0).
fn sample_time(sampling: Option<&ogawa_rs::TimeSampling>, index: u32) -> Result<f64, String> {
    let Some(sampling) = sampling else {
        return Ok(f64::from(index));
    };
    let per_cycle = sampling.sampling_type.num_samples_per_cycle;
    let time = if per_cycle == u32::MAX {
        *sampling
            .samples
            .get(index as usize)
            .ok_or_else(|| format!("sample {index} has no time in its acyclic time sampling"))?
    } else {
        let n = per_cycle as usize;
        if n == 0 || sampling.samples.len() < n {
            return Err(format!(
                "its time sampling lists {} times for {n} samples per cycle",
                sampling.samples.len()
            ));
        }
        let cycle = index as usize / n;
        sampling.samples[index as usize % n] + cycle as f64 * sampling.sampling_type.time_per_cycle
    };
    if !time.is_finite() {
        return Err(format!("sample {index} is at time {time} s"));
    }
    Ok(time)
}

/// The samples of an array property as a [`Timed`] value, each converted by `convert`.
pub(crate) fn timed<T: Clone>(
    samples: Vec<PropertySample>,
    mut convert: impl FnMut(PodArray) -> Option<T>,
) -> Option<Timed<T>> {
    let mut out = Vec::with_capacity(samples.len());
    for (time, values, _) in samples {
        out.push((time, Some(convert(values)?)));
    }
    Some(Timed::new(None, out))
}

#[cfg(test)]
mod tests {
    use ogawa_rs::{TimeSampling, TimeSamplingType};

    use super::sample_time;

    fn sampling(per_cycle: u32, time_per_cycle: f64, samples: &[f64]) -> TimeSampling {
        TimeSampling {
            sampling_type: TimeSamplingType {
                num_samples_per_cycle: per_cycle,
                time_per_cycle,
            },
            samples: samples.to_vec(),
        }
    }

    /// Alembic's `TimeSampling::getSampleTime`: uniform `start + i · tpc`; cyclic, the cycle's
    /// times shifted by whole cycles; acyclic, the listed times; no sampling, index 0 (identity:
    /// one sample per second from 0).
    #[test]
    fn sample_times_follow_the_time_sampling() {
        let uniform = sampling(1, 0.25, &[1.0]);
        assert_eq!(sample_time(Some(&uniform), 3), Ok(1.75));
        let cyclic = sampling(2, 1.0, &[0.0, 0.1]);
        let times: Vec<f64> = (0..4)
            .map(|i| sample_time(Some(&cyclic), i).unwrap())
            .collect();
        assert_eq!(times, [0.0, 0.1, 1.0, 1.1]);
        let acyclic = sampling(u32::MAX, f64::MAX / 32.0, &[0.0, 0.5, 2.0]);
        assert_eq!(sample_time(Some(&acyclic), 2), Ok(2.0));
        assert!(sample_time(Some(&acyclic), 3).is_err());
        assert_eq!(sample_time(None, 2), Ok(2.0));
        assert!(sample_time(Some(&sampling(0, 1.0, &[])), 0).is_err());
    }
}
