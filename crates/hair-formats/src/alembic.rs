//! Alembic `.abc` curves (Ogawa archives) through the `ogawa-rs` crate.
//!
//! Read: every `Curves` object of the archive (schema `AbcGeom_Curve_v*`), at any depth, in the
//! order of the object tree, concatenated: its positions `P` and vertex counts `nVertices` at the
//! first time sample, and its widths (`width` at the first sample: one per point, per curve or one
//! for the object), kept only when every Curves object has plain (not indexed) `float32` widths.
//! Each object's points
//! go through its parent `Xform` chain (the `.ops` and `.vals` of each transform at its first
//! sample: translate, scale, rotate, rotate X/Y/Z and matrix operations, composed as Alembic
//! does), and widths are scaled by the chain's mean scale (the cube root of its determinant). Then
//! the [`ImportAxes`](super::ImportAxes) conversion and the degenerate-curve handling of every
//! reader (curve indices in errors and in [`Curves::skipped`] count every curve of the archive, in
//! that order).
//!
//! Not read: later time samples; `cubic` and variable-order (NURBS) curves and periodic curves,
//! which are refused (convert them to linear polylines first), as the USD reader does; indexed
//! widths (dropped); normals, uvs, velocities and other properties; an `Xform`'s `.inherits`
//! flag (every transform is taken to inherit its parent's, Alembic's default); HDF5 archives
//! (refused by their signature).
//!
//! Robustness: `ogawa-rs` trusts the file (it allocates from unchecked sizes and indexes and
//! asserts on header values), so the archive is checked before the crate sees it: the Ogawa
//! container by [`super::ogawa`] and the Alembic headers by [`super::alembic_layout`]. As a last
//! guard, the calls into the crate run under [`std::panic::catch_unwind`], which turns a panic
//! left in it into a [`FormatError`] (the panic's message is still printed by the panic hook).
//! Two faults of `ogawa-rs` 0.4.0 are worked around: it drops the archive's last indexed metadata
//! entry (objects whose `schema` it lost are recognised by their properties), and it maps the
//! first sample of an animated property to the wrong child (the first sample is read from the
//! property's first child directly).

use std::io::{Cursor, Read, Seek, SeekFrom};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use glam::{DMat4, DVec3};
use ogawa_rs::{
    Archive, ArchiveReader, DataType, F32_TYPE, F32X3_TYPE, GroupChunk, I32_TYPE, ObjectReader,
    PodArray, PropertyHeader, PropertyReader,
};

use super::alembic_curves::{CurvesObject, build};
use super::alembic_layout::check_layout;
use super::alembic_xform::compose;
use super::binary::Bytes;
use super::curves::Curves;
use super::error::{FormatError, FormatErrorKind, Location};
use super::ogawa::{check_container, check_header, structure};
use super::options::ImportOptions;
use super::read_file;

/// Reads the curves of an Alembic (Ogawa) `.abc` archive from its bytes: every `Curves` object at
/// its first time sample, through its parent transforms; see the module documentation for what is
/// read and what is not. Positions and widths are taken as metres before `options.axes` (Alembic
/// has no unit; set [`ImportAxes::scale_to_metres`](super::ImportAxes::scale_to_metres) for a file
/// in centimetres). Errors name the object and the byte offset; the data is called
/// [`FormatError::IN_MEMORY`].
pub fn read_alembic(bytes: &[u8], options: &ImportOptions) -> Result<Curves, FormatError> {
    read(bytes, options).map_err(FormatError::in_memory)
}

/// Reads an Alembic `.abc` archive's curves; errors name the file. See [`read_alembic`].
pub fn read_alembic_file(
    path: impl AsRef<Path>,
    options: &ImportOptions,
) -> Result<Curves, FormatError> {
    read_file(path.as_ref(), |bytes| read(bytes, options))
}

fn read(data: &[u8], options: &ImportOptions) -> Result<Curves, FormatErrorKind> {
    options.axes.validate()?;
    check_archive(data)?;
    let objects = guarded(|| collect(data))?;
    build(&objects, options)
}

/// Runs `f` (calls into `ogawa-rs` on an archive checked by [`check_layout`]), turning a panic
/// into an error.
pub(crate) fn guarded<T>(
    f: impl FnOnce() -> Result<T, FormatErrorKind>,
) -> Result<T, FormatErrorKind> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|panic| {
        let message = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        FormatErrorKind::Alembic {
            element: "archive".into(),
            message: format!("the ogawa-rs crate failed on this archive: {message}"),
            location: Location::Unknown,
        }
    })?
}

/// Checks an archive's bytes (the Ogawa container and the Alembic headers) before `ogawa-rs`
/// reads them.
pub(crate) fn check_archive(data: &[u8]) -> Result<(), FormatErrorKind> {
    let bytes = Bytes::new(data);
    let root = check_header(&bytes)?;
    check_container(&bytes, root)?;
    check_layout(&bytes, root)
}

/// The file's bytes as `ogawa-rs` reads them.
pub(crate) struct Memory<'a>(pub(crate) Cursor<&'a [u8]>);

impl Read for Memory<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0.read(buf)
    }
}

impl Seek for Memory<'_> {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.0.seek(pos)
    }
}

impl ArchiveReader for Memory<'_> {
    fn size(&self) -> u64 {
        self.0.get_ref().len() as u64
    }
}

/// The objects read: curves, transforms, and the rest (walked through for their children).
pub(crate) enum Kind {
    Curves,
    PolyMesh,
    Xform,
    Other,
}

/// The archive being read.
pub(crate) struct Reading<'a> {
    pub(crate) reader: Memory<'a>,
    pub(crate) archive: Archive,
    pub(crate) objects: Vec<CurvesObject>,
}

/// An array or scalar property found by [`Reading::sampled_property`].
pub(crate) struct SampledProperty {
    /// Its samples' group.
    pub(crate) group: GroupChunk,
    /// Its header (data type, sample counts, time sampling).
    pub(crate) header: PropertyHeader,
    /// An array property (each sample two children: data and dimensions), not a scalar one.
    pub(crate) array: bool,
}

/// An `ogawa-rs` error about `element` at byte `offset`.
pub(crate) fn crate_error(
    element: &str,
    offset: u64,
) -> impl FnOnce(ogawa_rs::OgawaError) -> FormatErrorKind {
    move |error| {
        let mut message = error.to_string();
        let mut source = std::error::Error::source(&error);
        while let Some(cause) = source {
            message = format!("{message}: {cause}");
            source = cause.source();
        }
        structure(element, format!("ogawa-rs: {message}"), offset)
    }
}

/// Reads every Curves object of the archive (checked by [`check_layout`]).
fn collect(data: &[u8]) -> Result<Vec<CurvesObject>, FormatErrorKind> {
    let mut reader = Memory(Cursor::new(data));
    let archive = Archive::new(&mut reader).map_err(crate_error("archive", 0))?;
    let root = archive
        .load_root_object(&mut reader)
        .map_err(crate_error("/", 0))?;
    let mut reading = Reading {
        reader,
        archive,
        objects: Vec::new(),
    };
    reading.object(&root, "", DMat4::IDENTITY)?;
    Ok(reading.objects)
}

impl Reading<'_> {
    /// Reads the children of `object` (at `path`, under the transform `world`).
    fn object(
        &mut self,
        object: &ObjectReader,
        path: &str,
        world: DMat4,
    ) -> Result<(), FormatErrorKind> {
        for index in 0..object.children.len() {
            let child_path = format!("{path}/{}", object.children[index].name);
            let child = object
                .load_child(
                    index,
                    &mut self.reader,
                    &self.archive.indexed_meta_data,
                    &self.archive.time_samplings,
                )
                .map_err(crate_error(&child_path, object.group.position))?;
            let mut child_world = world;
            match self.kind(&child, &child_path)? {
                Kind::Curves => self.curves(&child, &child_path, world)?,
                Kind::Xform => child_world = world * self.local_transform(&child, &child_path)?,
                Kind::PolyMesh | Kind::Other => {}
            }
            self.object(&child, &child_path, child_world)?;
        }
        Ok(())
    }

    /// What `object` is: by its metadata's `schema`, or where that is empty (`ogawa-rs` 0.4.0
    /// drops the last entry of the archive's indexed metadata) by its properties: an `.xform`
    /// compound, or a `.geom` compound with `nVertices` and `curveBasisAndType`.
    pub(crate) fn kind(
        &mut self,
        object: &ObjectReader,
        path: &str,
    ) -> Result<Kind, FormatErrorKind> {
        let schema = object.header.meta_data.tokens.get("schema");
        let schema = schema.map(String::as_str).unwrap_or_default();
        if schema.starts_with("AbcGeom_Curve_v") {
            return Ok(Kind::Curves);
        } else if schema.starts_with("AbcGeom_PolyMesh_v") {
            return Ok(Kind::PolyMesh);
        } else if schema.starts_with("AbcGeom_Xform_v") {
            return Ok(Kind::Xform);
        } else if !schema.is_empty() {
            return Ok(Kind::Other);
        }
        if self.compound(object, ".xform", path)?.is_some() {
            return Ok(Kind::Xform);
        }
        Ok(match self.compound(object, ".geom", path)? {
            Some(PropertyReader::Compound(geom))
                if geom.find_sub_property_index("nVertices").is_some()
                    && geom.find_sub_property_index("curveBasisAndType").is_some() =>
            {
                Kind::Curves
            }
            Some(PropertyReader::Compound(geom))
                if geom.find_sub_property_index(".faceCounts").is_some()
                    && geom.find_sub_property_index(".faceIndices").is_some() =>
            {
                Kind::PolyMesh
            }
            _ => Kind::Other,
        })
    }

    /// The compound property `name` of `object` (`.geom`, `.xform`), if it has one: a
    /// [`PropertyReader::Compound`] (the crate does not export the compound reader's type).
    pub(crate) fn compound(
        &mut self,
        object: &ObjectReader,
        name: &str,
        path: &str,
    ) -> Result<Option<PropertyReader>, FormatErrorKind> {
        let Some(properties) = object.properties() else {
            return Ok(None);
        };
        let property = properties
            .load_sub_property_by_name(name, &mut self.reader, &self.archive)
            .map_err(crate_error(
                &format!("{path} {name}"),
                object.group.position,
            ))?;
        match property {
            Some(compound @ PropertyReader::Compound(_)) => Ok(Some(compound)),
            Some(_) => Err(structure(
                format!("{path} {name}"),
                "not a compound property".into(),
                object.group.position,
            )),
            None => Ok(None),
        }
    }

    /// Property `name` of `compound`, an array or a scalar one, with its samples' group and its
    /// header; `None` when there is no such property. `data_type`, when given, is the type it
    /// must have. Errors name `element` (the property's own name included).
    pub(crate) fn sampled_property(
        &mut self,
        compound: &PropertyReader,
        name: &str,
        element: &str,
        data_type: Option<&DataType>,
    ) -> Result<Option<SampledProperty>, FormatErrorKind> {
        let PropertyReader::Compound(compound) = compound else {
            return Err(structure(element, "not in a compound property".into(), 0));
        };
        let at = compound.group.position;
        let property = compound
            .load_sub_property_by_name(name, &mut self.reader, &self.archive)
            .map_err(crate_error(element, at))?;
        let (group, header, array) = match property {
            None => return Ok(None),
            Some(PropertyReader::Array(array)) => (array.group, array.header, true),
            Some(PropertyReader::Scalar(scalar)) => (scalar.group, scalar.header, false),
            Some(PropertyReader::Compound(_)) => {
                return Err(structure(
                    element,
                    "a compound property (an indexed geometry parameter), not an array".into(),
                    at,
                ));
            }
        };
        if let Some(wanted) = data_type
            && header.data_type != *wanted
        {
            return Err(structure(
                element,
                format!("type {:?}, expected {wanted:?}", header.data_type),
                group.position,
            ));
        }
        Ok(Some(SampledProperty {
            group,
            header,
            array,
        }))
    }

    /// The first sample of property `name` of `compound`, and the byte offset of its first value;
    /// `None` when there is no such property. `data_type`, when given, is the type it must have.
    fn first_sample(
        &mut self,
        compound: &PropertyReader,
        name: &str,
        element: &str,
        data_type: Option<&DataType>,
    ) -> Result<Option<(PodArray, u64)>, FormatErrorKind> {
        let element = format!("{element} {name}");
        let Some(SampledProperty { group, header, .. }) =
            self.sampled_property(compound, name, &element, data_type)?
        else {
            return Ok(None);
        };
        if header.next_sample_index == 0 || group.children.is_empty() {
            return Err(structure(element, "no sample".into(), group.position));
        }
        // Sample 0 is always the group's first child (for an array, its data; the dimensions
        // follow).
        let sample = group
            .load_data(&mut self.reader, 0)
            .map_err(crate_error(&element, group.position))?;
        // Past the block's size and the sample's 16-byte key.
        let values_at = sample.position + 8 + 16;
        if sample.size == 0 {
            // Empty data: an empty array (ogawa-rs would subtract the key's 16 bytes from 0).
            return Ok(Some((PodArray::U8(Vec::new()), values_at)));
        }
        let values = sample
            .read_pod_array(&header.data_type, &mut self.reader)
            .map_err(crate_error(&element, sample.position))?;
        Ok(Some((values, values_at)))
    }

    /// The local matrix of an Xform object (column vectors: `p' = M p`).
    fn local_transform(
        &mut self,
        object: &ObjectReader,
        path: &str,
    ) -> Result<DMat4, FormatErrorKind> {
        let Some(xform) = self.compound(object, ".xform", path)? else {
            return Ok(DMat4::IDENTITY);
        };
        let element = format!("{path} .xform");
        let at = object.group.position;
        let ops = match self.first_sample(&xform, ".ops", &element, None)? {
            None => return Ok(DMat4::IDENTITY),
            Some((PodArray::U8(ops), _)) => ops,
            Some(_) => return Err(structure(element, ".ops is not uint8".into(), at)),
        };
        let (vals, vals_at) = match self.first_sample(&xform, ".vals", &element, None)? {
            None => (Vec::new(), at),
            Some((PodArray::F64(vals), at)) => (vals, at),
            Some((PodArray::U8(empty), at)) if empty.is_empty() => (Vec::new(), at),
            Some(_) => return Err(structure(element, ".vals is not float64".into(), at)),
        };
        compose(&ops, &vals).map_err(|message| structure(element, message, vals_at))
    }

    /// Reads a Curves object's first sample, with its points through `world`.
    fn curves(
        &mut self,
        object: &ObjectReader,
        path: &str,
        world: DMat4,
    ) -> Result<(), FormatErrorKind> {
        let at = object.group.position;
        let Some(geom) = self.compound(object, ".geom", path)? else {
            return Err(structure(path, "a Curves object without .geom".into(), at));
        };
        let element = format!("{path} .geom");
        let missing = |name: &str| structure(&element, format!("no {name} property"), at);
        match self.first_sample(&geom, "curveBasisAndType", &element, None)? {
            Some((PodArray::U8(kind), kind_at)) => {
                check_curve_type(&kind, &format!("{element} curveBasisAndType"), kind_at)?
            }
            Some(_) => return Err(missing("uint8 curveBasisAndType")),
            None => return Err(missing("curveBasisAndType")),
        }
        let (points, points_at) =
            match self.first_sample(&geom, "P", &element, Some(&F32X3_TYPE))? {
                Some((PodArray::F32(p), p_at)) => (p, p_at),
                Some((PodArray::U8(_), p_at)) => (Vec::new(), p_at),
                _ => return Err(missing("P")),
            };
        let (counts, counts_at) =
            match self.first_sample(&geom, "nVertices", &element, Some(&I32_TYPE))? {
                Some((PodArray::I32(n), n_at)) => (n, n_at),
                Some((PodArray::U8(_), n_at)) => (Vec::new(), n_at),
                _ => return Err(missing("nVertices")),
            };
        let widths = match self.first_sample(&geom, "width", &element, Some(&F32_TYPE)) {
            Ok(Some((PodArray::F32(w), w_at))) => Some((w, w_at)),
            // Indexed widths (a compound), widths of another type, and empty widths are left
            // aside.
            _ => None,
        };
        let (widths, widths_at) = match widths {
            Some((w, w_at)) => (Some(w), w_at),
            None => (None, 0),
        };
        let scale = world.determinant().abs().cbrt();
        let points = points
            .chunks_exact(3)
            .map(|p| {
                let p = DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
                if world == DMat4::IDENTITY {
                    p.as_vec3()
                } else {
                    world.transform_point3(p).as_vec3()
                }
            })
            .collect();
        let widths = widths.map(|w| {
            if world == DMat4::IDENTITY {
                w
            } else {
                w.iter().map(|&w| (f64::from(w) * scale) as f32).collect()
            }
        });
        self.objects.push(CurvesObject {
            path: path.to_owned(),
            points,
            points_at,
            counts,
            counts_at,
            widths,
            widths_at,
        });
        Ok(())
    }
}

/// Refuses all but linear, non-periodic curves (`curveBasisAndType`: type, periodicity, basis).
fn check_curve_type(kind: &[u8], element: &str, at: u64) -> Result<(), FormatErrorKind> {
    let basis = match kind.get(2) {
        Some(0) => "none",
        Some(1) => "bezier",
        Some(2) => "b-spline",
        Some(3) => "catmull-rom",
        Some(4) => "hermite",
        Some(5) => "power",
        _ => "unknown",
    };
    let problem = match (kind.first(), kind.get(1)) {
        (Some(1), Some(0)) => return Ok(()),
        (Some(1), Some(_)) => "periodic (closed) curves".to_owned(),
        (Some(0), _) => format!("type cubic (basis {basis})"),
        (Some(2), _) => "type variable order (NURBS)".to_owned(),
        (Some(other), _) => format!("unknown type {other}"),
        (None, _) => "an empty curveBasisAndType".to_owned(),
    };
    Err(structure(
        element,
        format!(
            "{problem}; only linear, non-periodic curves are read (convert the curves to linear \
             polylines first)"
        ),
        at,
    ))
}
