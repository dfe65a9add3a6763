//! One binary USD layer (`PXR-USDC`) opened from bytes through the `openusd` crate, read field by
//! field: checked by `usdc_check.rs`, then decoded value by value on demand. Any panic inside the
//! crate becomes an error (`catch_unwind`); the crate's errors name no byte offset, so neither do
//! these. Text layers (`#usda`) never reach the crate: they go through the project's parser
//! (`usda_parse.rs`). [`sniff`] tells the two encodings apart.
//!
//! Only the layer is read: no composition (references, payloads, sublayers, variants), and no
//! fallback values but those the readers state.

use std::collections::{HashMap, HashSet};
use std::io::Cursor;
use std::panic::{AssertUnwindSafe, catch_unwind};

use glam::Vec3;
use openusd::sdf::{self, SpecType, Value};
use openusd::usdc::CrateFile;

use super::error::{FormatErrorKind, Location};
use super::usdc_check::{self, MAGIC, Version};

/// Which encoding a USD file uses, from its first bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Encoding {
    /// `#usda`: text.
    Text,
    /// `PXR-USDC`: a binary crate file.
    Crate,
}

/// The encoding of a USD file, or a wrong-magic error.
pub(crate) fn sniff(bytes: &[u8]) -> Result<Encoding, FormatErrorKind> {
    if bytes.starts_with(MAGIC) {
        Ok(Encoding::Crate)
    } else if bytes.starts_with(b"#usda ") {
        Ok(Encoding::Text)
    } else {
        let start = &bytes[..bytes.len().min(8)];
        Err(FormatErrorKind::WrongMagic {
            format: "USD",
            found: format!("\"{}\"", start.escape_ascii()),
            expected: "\"#usda 1.0\" (text) or \"PXR-USDC\" (binary)",
        })
    }
}

/// An error of the layer about `element` (a prim or attribute path).
pub(crate) fn usd_error(element: impl ToString, message: impl Into<String>) -> FormatErrorKind {
    FormatErrorKind::Usd {
        element: element.to_string(),
        message: message.into(),
        location: Location::Unknown,
    }
}

/// Runs `f` (a call into the crate), turning a panic into an error about `element`.
fn guarded<T>(element: &str, f: impl FnOnce() -> T) -> Result<T, FormatErrorKind> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        usd_error(
            element,
            format!("the openusd crate failed on malformed data ({what})"),
        )
    })
}

/// A binary crate file's fields, with its specs' fieldsets by path.
pub(crate) struct Layer<'a> {
    bytes: &'a [u8],
    version: Version,
    file: Box<CrateFile<Cursor<&'a [u8]>>>,
    specs: HashMap<sdf::Path, usize>,
}

impl<'a> Layer<'a> {
    /// Opens the layer of a binary crate file's bytes, after checking them (`usdc_check.rs`).
    pub(crate) fn open(bytes: &'a [u8]) -> Result<Self, FormatErrorKind> {
        open_crate(bytes)
    }

    /// The value of `field` of the spec at `path`; `None` when not authored.
    pub(crate) fn field(
        &mut self,
        path: &sdf::Path,
        field: &str,
    ) -> Result<Option<Value>, FormatErrorKind> {
        let element = path.as_str();
        let Layer {
            bytes,
            version,
            file,
            specs,
        } = self;
        let Some(&start) = specs.get(path) else {
            return Ok(None);
        };
        let file = &mut **file;
        let mut rep = None;
        for index in file.fieldsets.get(start..).unwrap_or_default() {
            let Some(index) = *index else { break };
            let Some(f) = file.fields.get(index) else {
                break;
            };
            if file.tokens.get(f.token_index).map(String::as_str) == Some(field) {
                rep = Some(f.value_rep);
                break;
            }
        }
        let Some(rep) = rep else { return Ok(None) };
        let what = format!("{element} {field}");
        usdc_check::check_value(bytes, *version, rep.0, &what)?;
        match guarded(&what, || file.value(rep))? {
            Ok(value) => Ok(Some(value)),
            Err(error) => Err(usd_error(&what, format!("{error:#}"))),
        }
    }

    /// Whether a spec exists at `path`.
    pub(crate) fn has_spec(&self, path: &sdf::Path) -> bool {
        self.specs.contains_key(path)
    }

    /// The prims of the layer in namespace order (parents first, children in authored order),
    /// following `primChildren` from the root.
    pub(crate) fn prims(&mut self) -> Result<Vec<sdf::Path>, FormatErrorKind> {
        let mut out = Vec::new();
        // A child listed twice is read once (and a malformed file cannot multiply the walk).
        let mut seen = HashSet::new();
        let mut pending = vec![sdf::Path::abs_root()];
        while let Some(parent) = pending.pop() {
            let children = match self.field(&parent, "primChildren")? {
                Some(Value::TokenVec(children)) => children,
                _ => Vec::new(),
            };
            // Reversed onto the stack, so the first child is read first.
            for child in children.iter().rev() {
                let path = parent
                    .append_path(child.as_str())
                    .map_err(|e| usd_error(&parent, format!("child {child}: {e:#}")))?;
                if self.has_spec(&path) && seen.insert(path.clone()) {
                    pending.push(path);
                }
            }
            if !parent.is_abs_root() {
                out.push(parent);
            }
        }
        Ok(out)
    }

    /// Whether the prim at `path` is defined (`def`) with type `type_name`.
    pub(crate) fn is_defined(
        &mut self,
        path: &sdf::Path,
        type_name: &str,
    ) -> Result<bool, FormatErrorKind> {
        let def = matches!(
            self.field(path, "specifier")?,
            Some(Value::Specifier(sdf::Specifier::Def))
        );
        let typed = match self.field(path, "typeName")? {
            Some(Value::Token(t)) => t.as_str() == type_name,
            Some(Value::String(t)) => t == type_name,
            _ => false,
        };
        Ok(def && typed)
    }

    /// The value of attribute `name` of `prim` at the default time: its default, or else its
    /// earliest time sample; `None` when not authored or blocked.
    pub(crate) fn attribute(
        &mut self,
        prim: &sdf::Path,
        name: &str,
    ) -> Result<Option<(sdf::Path, Value)>, FormatErrorKind> {
        let path = prim
            .append_property(name)
            .map_err(|e| usd_error(prim, format!("attribute {name}: {e:#}")))?;
        if !self.has_spec(&path) {
            return Ok(None);
        }
        let value = match self.field(&path, "default")? {
            Some(value) => Some(value),
            None => match self.field(&path, "timeSamples")? {
                Some(Value::TimeSamples(samples)) => samples
                    .into_iter()
                    .filter(|(t, _)| t.is_finite())
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, v)| v),
                _ => None,
            },
        };
        Ok(match value {
            None | Some(Value::ValueBlock) => None,
            Some(value) => Some((path, value)),
        })
    }

    /// Attribute `name` of `prim` as authored: its path, its default and its time samples in
    /// file order (a blocked value is a [`Value::ValueBlock`]); `None` when it has no spec.
    #[allow(clippy::type_complexity)]
    pub(crate) fn attribute_samples(
        &mut self,
        prim: &sdf::Path,
        name: &str,
    ) -> Result<Option<(sdf::Path, Option<Value>, Vec<(f64, Value)>)>, FormatErrorKind> {
        let path = prim
            .append_property(name)
            .map_err(|e| usd_error(prim, format!("attribute {name}: {e:#}")))?;
        if !self.has_spec(&path) {
            return Ok(None);
        }
        let default = self.field(&path, "default")?;
        let samples = match self.field(&path, "timeSamples")? {
            Some(Value::TimeSamples(samples)) => samples,
            _ => Vec::new(),
        };
        if let Some((t, _)) = samples.iter().find(|(t, _)| !t.is_finite()) {
            return Err(usd_error(
                &path,
                format!("has a time sample at time code {t}"),
            ));
        }
        Ok(Some((path, default, samples)))
    }

    /// The token metadata `field` of the spec at `path` (`interpolation`, `upAxis`).
    pub(crate) fn token(
        &mut self,
        path: &sdf::Path,
        field: &str,
    ) -> Result<Option<String>, FormatErrorKind> {
        Ok(match self.field(path, field)? {
            Some(Value::Token(t)) => Some(t.as_str().to_owned()),
            Some(Value::String(s)) => Some(s),
            _ => None,
        })
    }
}

fn open_crate(bytes: &[u8]) -> Result<Layer<'_>, FormatErrorKind> {
    let version = usdc_check::check_structure(bytes)?;
    let element = "crate file";
    let file = guarded(element, || {
        CrateFile::open(Cursor::new(bytes)).and_then(|file| file.validate().map(|()| file))
    })?
    .map_err(|error| usd_error(element, format!("{error:#}")))?;
    let mut specs = HashMap::with_capacity(file.specs.len());
    for spec in &file.specs {
        if !matches!(
            spec.spec_type,
            SpecType::Prim | SpecType::PseudoRoot | SpecType::Attribute
        ) {
            continue;
        }
        // In range: `validate` checked the path and fieldset indices.
        if let Some(path) = file.paths.get(spec.path_index) {
            specs.insert(path.clone(), spec.fieldset_index);
        }
    }
    Ok(Layer {
        bytes,
        version,
        file: Box::new(file),
        specs,
    })
}

/// A value as points, when it is a 3-vector array (`point3f[]`, `double3[]`, `half3[]`).
pub(crate) fn as_points(value: &Value) -> Option<Vec<Vec3>> {
    Some(match value {
        Value::Vec3fVec(v) => v.iter().map(|p| Vec3::new(p.x, p.y, p.z)).collect(),
        Value::Vec3dVec(v) => v
            .iter()
            .map(|p| Vec3::new(p.x as f32, p.y as f32, p.z as f32))
            .collect(),
        Value::Vec3hVec(v) => v
            .iter()
            .map(|p| Vec3::new(p.x.to_f32(), p.y.to_f32(), p.z.to_f32()))
            .collect(),
        _ => return None,
    })
}

/// A value as integers, when it is an integer array.
pub(crate) fn as_ints(value: &Value) -> Option<Vec<i64>> {
    Some(match value {
        Value::IntVec(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Value::Int64Vec(v) => v.clone(),
        Value::UintVec(v) => v.iter().map(|&i| i64::from(i)).collect(),
        Value::Uint64Vec(v) => v.iter().map(|&i| i64::try_from(i).unwrap_or(-1)).collect(),
        _ => return None,
    })
}

/// A transform op's value as its numbers: a scalar, a 3-vector, a quaternion `(w, x, y, z)` or
/// a `matrix4d` row by row.
pub(crate) fn as_numbers(value: &Value) -> Option<Vec<f64>> {
    Some(match value {
        Value::Double(x) => vec![*x],
        Value::Float(x) => vec![f64::from(*x)],
        Value::Half(x) => vec![f64::from(x.to_f32())],
        Value::Vec3d(v) => vec![v.x, v.y, v.z],
        Value::Vec3f(v) => vec![f64::from(v.x), f64::from(v.y), f64::from(v.z)],
        Value::Vec3h(v) => [v.x, v.y, v.z]
            .iter()
            .map(|c| f64::from(c.to_f32()))
            .collect(),
        Value::Quatd(q) => vec![q.w, q.x, q.y, q.z],
        Value::Quatf(q) => [q.w, q.x, q.y, q.z].map(f64::from).to_vec(),
        Value::Quath(q) => [q.w, q.x, q.y, q.z]
            .iter()
            .map(|c| f64::from(c.to_f32()))
            .collect(),
        Value::Matrix4d(m) => m.0.to_vec(),
        _ => return None,
    })
}

/// A value as floats, when it is a float array.
pub(crate) fn as_floats(value: &Value) -> Option<Vec<f32>> {
    Some(match value {
        Value::FloatVec(v) => v.clone(),
        Value::DoubleVec(v) => v.iter().map(|&x| x as f32).collect(),
        Value::HalfVec(v) => v.iter().map(|x| x.to_f32()).collect(),
        _ => return None,
    })
}

/// The name of a value's type for messages (`FloatVec`).
pub(crate) fn type_name(value: &Value) -> &'static str {
    value.into()
}
