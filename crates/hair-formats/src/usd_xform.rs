//! USD transforms for the mesh sequence reader: attribute values over time ([`Timed`], USD's
//! value resolution: time samples win over the default, linear between samples, held before the
//! first and after the last), and a prim's `xformOpOrder` ([`OpStack`]) composed into a matrix
//! at a time code as `UsdGeomXformable` does: the ops multiply left to right in column-vector
//! form, so the last op of `xformOpOrder` acts on the points first, and a prim's matrix is applied
//! after its children's (`world = parent · local`).
//!
//! Ops read: `translate`, `scale`, `rotateX`, `rotateY`, `rotateZ`, the six Euler orders
//! (`rotateXYZ` rotates about X first, then Y, then Z), `orient` (a quaternion `(w, x, y, z)`,
//! slerped between samples as USD does) and `transform` (a `matrix4d`, row-vector rows as USD
//! writes them), each with any suffix (`xformOp:translate:pivot`) and `!invert!`; and
//! `!resetXformStack!`, which drops the ancestors' transforms. Anything else is refused.

use glam::{DMat4, DQuat, DVec3};

/// An attribute's value over time codes: its default, and its time samples sorted by time (a
/// sample may be blocked: `None`).
#[derive(Debug, Clone)]
pub(crate) struct Timed<T> {
    pub(crate) default: Option<T>,
    pub(crate) samples: Vec<(f64, Option<T>)>,
}

impl<T: Clone> Timed<T> {
    /// From the authored default and samples in any order; of two samples at one time code the
    /// later wins, as in a layer.
    pub(crate) fn new(default: Option<T>, mut samples: Vec<(f64, Option<T>)>) -> Self {
        samples.reverse();
        samples.sort_by(|a, b| a.0.total_cmp(&b.0));
        samples.dedup_by(|later, earlier| later.0 == earlier.0);
        Timed { default, samples }
    }

    /// The value at the default time: the default, or else the earliest sample.
    pub(crate) fn at_default(&self) -> Option<T> {
        match &self.default {
            Some(value) => Some(value.clone()),
            None => self.samples.first().and_then(|(_, v)| v.clone()),
        }
    }

    /// The time codes of the samples.
    pub(crate) fn codes(&self) -> impl Iterator<Item = f64> + '_ {
        self.samples.iter().map(|(t, _)| *t)
    }

    /// The value at time code `t`: the default when there are no samples, else the samples
    /// held outside and interpolated by `lerp` (weight of the second in `[0, 1]`) between.
    pub(crate) fn at(&self, t: f64, lerp: impl Fn(&T, &T, f64) -> T) -> Option<T> {
        let (Some(first), Some(last)) = (self.samples.first(), self.samples.last()) else {
            return self.default.clone();
        };
        if t <= first.0 {
            return first.1.clone();
        }
        if t >= last.0 {
            return last.1.clone();
        }
        let upper = self.samples.partition_point(|(code, _)| *code <= t);
        let (t0, a) = &self.samples[upper - 1];
        let (t1, b) = &self.samples[upper];
        match (a, b) {
            (Some(a), Some(b)) if t > *t0 => Some(lerp(a, b, (t - t0) / (t1 - t0))),
            (a, _) => a.clone(),
        }
    }
}

/// What an op does, from the type in its name.
#[derive(Debug, Clone, Copy, PartialEq)]
enum OpKind {
    Translate,
    Scale,
    /// About one axis (0, 1, 2), degrees.
    Rotate(usize),
    /// About three axes in order (`rotateXYZ`: X first), degrees.
    Euler([usize; 3]),
    Orient,
    Transform,
}

impl OpKind {
    /// The number of values the op has.
    fn arity(self) -> usize {
        match self {
            OpKind::Rotate(_) => 1,
            OpKind::Translate | OpKind::Scale | OpKind::Euler(_) => 3,
            OpKind::Orient => 4,
            OpKind::Transform => 16,
        }
    }
}

/// One op of an `xformOpOrder`: its attribute's name, whether it is inverted, and its values.
#[derive(Debug, Clone)]
pub(crate) struct Op {
    /// The attribute (`xformOp:translate:pivot`).
    pub(crate) attribute: String,
    invert: bool,
    kind: OpKind,
    pub(crate) values: Timed<Vec<f64>>,
}

/// The supported op types, for messages.
const SUPPORTED: &str = "translate, scale, rotateX, rotateY, rotateZ, rotateXYZ, rotateXZY, \
                         rotateYXZ, rotateYZX, rotateZXY, rotateZYX, orient, transform";

impl Op {
    /// The op an entry of `xformOpOrder` names (`!invert!xformOp:translate:pivot`), with the
    /// values of its attribute; an error (in words) for what is not supported.
    pub(crate) fn new(entry: &str, values: Timed<Vec<f64>>) -> Result<Self, String> {
        let (invert, attribute) = match entry.strip_prefix("!invert!") {
            Some(rest) => (true, rest),
            None => (false, entry),
        };
        let op_type = attribute
            .strip_prefix("xformOp:")
            .and_then(|rest| rest.split(':').next())
            .ok_or_else(|| format!("xformOpOrder entry \"{entry}\" is not an xformOp"))?;
        let axis = |c: u8| (c - b'X') as usize;
        let kind = match op_type {
            "translate" => OpKind::Translate,
            "scale" => OpKind::Scale,
            "orient" => OpKind::Orient,
            "transform" => OpKind::Transform,
            "rotateX" | "rotateY" | "rotateZ" => OpKind::Rotate(axis(op_type.as_bytes()[6])),
            _ => match op_type.strip_prefix("rotate").map(str::as_bytes) {
                Some(&[a, b, c])
                    if [a, b, c].iter().all(|x| (b'X'..=b'Z').contains(x))
                        && a != b
                        && b != c
                        && a != c =>
                {
                    OpKind::Euler([axis(a), axis(b), axis(c)])
                }
                _ => {
                    return Err(format!(
                        "xformOpOrder entry \"{entry}\": the op type \"{op_type}\" is not \
                         supported (supported: {SUPPORTED})"
                    ));
                }
            },
        };
        Ok(Op {
            attribute: attribute.to_owned(),
            invert,
            kind,
            values,
        })
    }

    /// The op's matrix at time code `t`, or at the default time when `None` (column vectors);
    /// an error in words for a missing or malformed value.
    pub(crate) fn matrix(&self, t: Option<f64>) -> Result<DMat4, String> {
        let orient = self.kind == OpKind::Orient;
        let value = match t {
            Some(t) => self.values.at(t, |a, b, w| lerp_values(a, b, w, orient)),
            None => self.values.at_default(),
        }
        .ok_or_else(|| "has no value".to_owned())?;
        if value.len() != self.kind.arity() {
            return Err(format!(
                "has {} numbers; expected {}",
                value.len(),
                self.kind.arity()
            ));
        }
        let v = &value;
        let matrix = match self.kind {
            OpKind::Translate => DMat4::from_translation(DVec3::new(v[0], v[1], v[2])),
            OpKind::Scale => DMat4::from_scale(DVec3::new(v[0], v[1], v[2])),
            OpKind::Rotate(axis) => rotation(axis, v[0]),
            OpKind::Euler([a, b, c]) => rotation(c, v[c]) * rotation(b, v[b]) * rotation(a, v[a]),
            OpKind::Orient => {
                let q = DQuat::from_xyzw(v[1], v[2], v[3], v[0]);
                if q.length() == 0.0 || q.length().is_nan() {
                    return Err("is not a rotation (a zero quaternion)".into());
                }
                DMat4::from_quat(q.normalize())
            }
            // USD's rows (row vectors) are glam's columns (column vectors).
            OpKind::Transform => DMat4::from_cols_slice(v),
        };
        if !self.invert {
            return Ok(matrix);
        }
        let inverse = matrix.inverse();
        if matrix.determinant() == 0.0 || !inverse.is_finite() {
            return Err("is inverted (!invert!) but cannot be".into());
        }
        Ok(inverse)
    }
}

/// A rotation of `degrees` about axis `axis` (0 = X).
fn rotation(axis: usize, degrees: f64) -> DMat4 {
    let radians = degrees.to_radians();
    match axis {
        0 => DMat4::from_rotation_x(radians),
        1 => DMat4::from_rotation_y(radians),
        _ => DMat4::from_rotation_z(radians),
    }
}

/// Values between two samples: a quaternion slerped, anything else component by component (held
/// when the counts differ).
fn lerp_values(a: &[f64], b: &[f64], w: f64, orient: bool) -> Vec<f64> {
    if a.len() != b.len() {
        return a.to_vec();
    }
    if orient && a.len() == 4 {
        let qa = DQuat::from_xyzw(a[1], a[2], a[3], a[0]).normalize();
        let qb = DQuat::from_xyzw(b[1], b[2], b[3], b[0]).normalize();
        if qa.is_finite() && qb.is_finite() {
            let q = qa.slerp(qb, w);
            return vec![q.w, q.x, q.y, q.z];
        }
    }
    a.iter().zip(b).map(|(x, y)| x + (y - x) * w).collect()
}

/// One prim's transform: its ops in `xformOpOrder` order, and whether it drops its ancestors'.
#[derive(Debug, Clone)]
pub(crate) struct OpStack {
    /// The prim's path (`/body`).
    pub(crate) path: String,
    /// The line of its `xformOpOrder` (text), for messages.
    pub(crate) line: Option<usize>,
    pub(crate) reset: bool,
    pub(crate) ops: Vec<Op>,
}

impl OpStack {
    /// The time codes of every op's samples.
    pub(crate) fn codes(&self) -> impl Iterator<Item = f64> + '_ {
        self.ops.iter().flat_map(|op| op.values.codes())
    }

    /// The prim's local matrix at time code `t` (`None`: the default time); an error names the
    /// op.
    pub(crate) fn local(&self, t: Option<f64>) -> Result<DMat4, (String, String)> {
        let mut matrix = DMat4::IDENTITY;
        for op in &self.ops {
            matrix *= op
                .matrix(t)
                .map_err(|message| (op.attribute.clone(), message))?;
        }
        Ok(matrix)
    }
}

/// What is wrong with a transform: the attribute, the problem, and the line of the prim's
/// `xformOpOrder` (text).
pub(crate) type XformError = (String, String, Option<usize>);

/// The world matrix at time code `t` (`None`: the default time) of a prim under `stacks`
/// (outermost first, its own last).
pub(crate) fn world(stacks: &[OpStack], t: Option<f64>) -> Result<DMat4, XformError> {
    let mut matrix = DMat4::IDENTITY;
    for stack in stacks {
        if stack.reset {
            matrix = DMat4::IDENTITY;
        }
        let local = stack
            .local(t)
            .map_err(|(op, message)| (format!("{}.{op}", stack.path), message, stack.line))?;
        matrix *= local;
    }
    Ok(matrix)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant(values: &[f64]) -> Timed<Vec<f64>> {
        Timed::new(Some(values.to_vec()), Vec::new())
    }

    /// `rotateXYZ (90, 0, 90)` rotates about X first: (0, 1, 0) → (0, 0, 1) about X, which Z
    /// leaves; (1, 0, 0) stays under X, then goes to (0, 1, 0) about Z.
    #[test]
    fn euler_orders_rotate_about_the_first_axis_first() {
        let op = Op::new("xformOp:rotateXYZ", constant(&[90.0, 0.0, 90.0])).unwrap();
        let m = op.matrix(Some(0.0)).unwrap();
        assert!((m.transform_point3(DVec3::Y) - DVec3::Z).length() < 1e-12);
        assert!((m.transform_point3(DVec3::X) - DVec3::Y).length() < 1e-12);
        let inverse = Op::new("!invert!xformOp:rotateXYZ", constant(&[90.0, 0.0, 90.0]));
        let back = inverse.unwrap().matrix(None).unwrap() * m;
        assert!(back.abs_diff_eq(DMat4::IDENTITY, 1e-12));
    }

    /// A `matrix4d` op is USD's rows: the translation in the last row; `orient` (w, x, y, z) =
    /// (cos 45°, 0, 0, sin 45°) is 90° about Z; a stack multiplies in `xformOpOrder` order, so
    /// its last op acts first; `!resetXformStack!` drops the ancestors.
    #[test]
    fn matrices_quaternions_and_stacks_compose_as_usd_does() {
        let mut rows = DMat4::IDENTITY.to_cols_array();
        rows[12..15].copy_from_slice(&[1.0, 2.0, 3.0]);
        let transform = Op::new("xformOp:transform", constant(&rows)).unwrap();
        let m = transform.matrix(None).unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(1.0, 2.0, 3.0));
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let orient = Op::new("xformOp:orient", constant(&[h, 0.0, 0.0, h])).unwrap();
        let stack = OpStack {
            path: "/p".into(),
            line: None,
            reset: false,
            ops: vec![transform, orient],
        };
        // (1, 0, 0) turned to (0, 1, 0) first, then moved by (1, 2, 3).
        let p = world(std::slice::from_ref(&stack), None)
            .unwrap()
            .transform_point3(DVec3::X);
        assert!((p - DVec3::new(1.0, 3.0, 3.0)).length() < 1e-12, "{p}");
        let reset = OpStack {
            path: "/p/c".into(),
            line: None,
            reset: true,
            ops: Vec::new(),
        };
        assert_eq!(world(&[stack, reset], None).unwrap(), DMat4::IDENTITY);
    }

    #[test]
    fn samples_are_held_outside_and_interpolated_between() {
        let timed = Timed::new(
            Some(vec![7.0]),
            vec![
                (4.0, Some(vec![1.0])),
                (2.0, Some(vec![0.0])),
                (4.0, Some(vec![3.0])),
            ],
        );
        let lerp = |a: &Vec<f64>, b: &Vec<f64>, w| lerp_values(a, b, w, false);
        assert_eq!(timed.at(0.0, lerp), Some(vec![0.0]));
        assert_eq!(timed.at(3.0, lerp), Some(vec![1.5]));
        assert_eq!(timed.at(9.0, lerp), Some(vec![3.0]));
        assert_eq!(timed.codes().collect::<Vec<_>>(), vec![2.0, 4.0]);
    }

    #[test]
    fn unsupported_ops_are_refused_by_name() {
        let error = Op::new("xformOp:shear", constant(&[1.0])).unwrap_err();
        assert!(error.contains("\"shear\" is not supported"), "{error}");
        assert!(Op::new("xformOp:rotateXXY", constant(&[1.0; 3])).is_err());
        let short = Op::new("xformOp:translate", constant(&[1.0])).unwrap();
        assert_eq!(short.matrix(None).unwrap_err(), "has 1 numbers; expected 3");
    }
}
