//! Attribute values of USD's text format as the parser (`usda_parse.rs`) keeps them: arrays with
//! the line of each element ([`Array`]), and each attribute's default and the time samples that
//! can matter at the time read ([`Attr`]), resolved as USD does: time samples win over the
//! default at a numeric time (held before the first and after the last sample, linear in
//! between, the sample itself at its time); with no time, the default wins, else the earliest
//! sample. Only the samples that can matter are kept, so an animation costs the memory of one or
//! two frames.

use glam::Vec3;

/// Values of one array attribute with the line of each element.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Array<T> {
    pub(crate) values: Vec<T>,
    /// The line of each value (saturated at `u32::MAX`).
    pub(crate) lines: Vec<u32>,
}

impl<T> Array<T> {
    pub(crate) fn new() -> Self {
        Array {
            values: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// Values without lines (read from a binary crate file, which names none).
    pub(crate) fn from_values(values: Vec<T>) -> Self {
        Array {
            values,
            lines: Vec::new(),
        }
    }

    pub(crate) fn push(&mut self, value: T, line: usize) {
        self.values.push(value);
        self.lines.push(u32::try_from(line).unwrap_or(u32::MAX));
    }

    pub(crate) fn len(&self) -> usize {
        self.values.len()
    }

    /// The line of value `i` (the attribute's when out of range).
    pub(crate) fn line(&self, i: usize, fallback: usize) -> usize {
        self.lines.get(i).map_or(fallback, |&l| l as usize)
    }
}

/// A value type that time samples interpolate.
pub(crate) trait Sample: Clone {
    /// `a` to `b` at `alpha` in `[0, 1]`.
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self;
}

impl Sample for Vec3 {
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        a.lerp(*b, alpha as f32)
    }
}

impl Sample for f32 {
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        (f64::from(*a) + (f64::from(*b) - f64::from(*a)) * alpha) as f32
    }
}

impl Sample for f64 {
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        a + (b - a) * alpha
    }
}

impl Sample for i64 {
    /// Integers are held, not interpolated (as in USD).
    fn lerp(a: &Self, _: &Self, _: f64) -> Self {
        *a
    }
}

impl Sample for String {
    fn lerp(a: &Self, _: &Self, _: f64) -> Self {
        a.clone()
    }
}

impl<T: Sample> Sample for Array<T> {
    /// Element by element when the sizes agree, else held (as in USD).
    fn lerp(a: &Self, b: &Self, alpha: f64) -> Self {
        if a.len() != b.len() {
            return a.clone();
        }
        Array {
            values: a
                .values
                .iter()
                .zip(&b.values)
                .map(|(x, y)| T::lerp(x, y, alpha))
                .collect(),
            lines: a.lines.clone(),
        }
    }
}

/// An authored value: `None` when blocked (`= None`).
pub(crate) type Authored<T> = Option<T>;

/// One attribute as authored: its default and the time samples that matter at the time read.
#[derive(Debug)]
pub(crate) struct Attr<T> {
    /// Line of the first declaration.
    pub(crate) line: usize,
    pub(crate) default: Option<Authored<T>>,
    /// The latest sample at or before the time (the earliest sample when reading with no time).
    lower: Option<(f64, Authored<T>)>,
    /// The earliest sample after the time.
    upper: Option<(f64, Authored<T>)>,
    /// The `interpolation` metadata and its line.
    pub(crate) interpolation: Option<(String, usize)>,
    /// Every time sample in file order, kept only when the parser reads a sequence (then
    /// `lower` and `upper` stay empty).
    pub(crate) samples: Vec<(f64, Authored<T>)>,
}

impl<T: Sample> Attr<T> {
    pub(crate) fn new(line: usize) -> Self {
        Attr {
            line,
            default: None,
            lower: None,
            upper: None,
            interpolation: None,
            samples: Vec::new(),
        }
    }

    /// Keeps a sample at `t` if it can matter when reading at `time`.
    pub(crate) fn offer(&mut self, time: Option<f64>, t: f64, value: Authored<T>) {
        match time {
            None => {
                if self.lower.as_ref().is_none_or(|(lt, _)| t < *lt) {
                    self.lower = Some((t, value));
                }
            }
            Some(time) if t <= time => {
                if self.lower.as_ref().is_none_or(|(lt, _)| t >= *lt) {
                    self.lower = Some((t, value));
                }
            }
            Some(_) => {
                if self.upper.as_ref().is_none_or(|(ut, _)| t < *ut) {
                    self.upper = Some((t, value));
                }
            }
        }
    }

    /// The time samples kept: every one when the parser reads a sequence, else the one or two
    /// that matter at the time read.
    pub(crate) fn kept_samples(&self) -> Vec<(f64, Authored<T>)> {
        if !self.samples.is_empty() {
            return self.samples.clone();
        }
        self.lower.iter().chain(&self.upper).cloned().collect()
    }

    /// The value at `time` (see the module's documentation); `None` when not authored or blocked.
    pub(crate) fn resolve(self, time: Option<f64>) -> Option<T> {
        let Some(time) = time else {
            return match self.default {
                Some(value) => value,
                None => self.lower.and_then(|(_, v)| v),
            };
        };
        match (self.lower, self.upper) {
            (None, None) => self.default.flatten(),
            (Some((_, value)), None) | (None, Some((_, value))) => value,
            (Some((lt, lower)), Some((ut, upper))) => match (lower, upper) {
                (Some(a), Some(b)) => Some(T::lerp(&a, &b, (time - lt) / (ut - lt))),
                (lower, _) => lower,
            },
        }
    }
}
