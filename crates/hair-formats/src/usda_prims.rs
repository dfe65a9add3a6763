//! What the USD text parser (`usda_parse.rs`) collects: the prims of one type that a reader asks
//! for ([`PrimKind`]: `def BasisCurves` or `def Mesh`), each attribute read into its slot
//! ([`Field`], [`Slot`]), and the layer's axes and units ([`Layer`]).

use glam::Vec3;

use super::options::UpAxis;
use super::usda_values::{Array, Attr};

/// The prims a parse collects; every other prim is skipped by its brackets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PrimKind {
    /// `def BasisCurves` prims.
    Curves,
    /// `def Mesh` prims.
    Mesh,
}

impl PrimKind {
    /// The prim type's name in USD (`BasisCurves`, `Mesh`).
    pub(crate) fn type_name(self) -> &'static str {
        match self {
            PrimKind::Curves => "BasisCurves",
            PrimKind::Mesh => "Mesh",
        }
    }
}

/// The attributes of one `def BasisCurves` prim.
#[derive(Debug)]
pub(crate) struct CurvesPrim {
    /// The prim's name (quotes included) and line.
    pub(crate) name: String,
    pub(crate) line: usize,
    pub(crate) curve_type: Option<Attr<String>>,
    pub(crate) basis: Option<Attr<String>>,
    pub(crate) wrap: Option<Attr<String>>,
    pub(crate) counts: Option<Attr<Array<i64>>>,
    pub(crate) points: Option<Attr<Array<Vec3>>>,
    pub(crate) widths: Option<Attr<Array<f32>>>,
    pub(crate) primvar_widths: Option<Attr<Array<f32>>>,
    pub(crate) width_indices: Option<Attr<Array<i64>>>,
    pub(crate) colors: Option<Attr<Array<Vec3>>>,
    pub(crate) color_indices: Option<Attr<Array<i64>>>,
}

/// The attributes of one `def Mesh` prim.
#[derive(Debug)]
pub(crate) struct MeshPrim {
    /// The prim's path in the layer (`/body/head`) and the line of its name.
    pub(crate) path: String,
    pub(crate) line: usize,
    /// Where the prim starts among all the prims of the file (namespace order: parents first).
    pub(crate) order: usize,
    pub(crate) points: Option<Attr<Array<Vec3>>>,
    pub(crate) face_vertex_counts: Option<Attr<Array<i64>>>,
    pub(crate) face_vertex_indices: Option<Attr<Array<i64>>>,
    pub(crate) orientation: Option<Attr<String>>,
}

/// A prim being collected: what its properties are read into.
#[derive(Debug)]
pub(crate) enum Collected {
    Curves(Box<CurvesPrim>),
    Mesh(Box<MeshPrim>),
}

impl Collected {
    /// An empty prim of `kind`, named `name` (quotes included) at `line`, with path `path`.
    pub(crate) fn new(
        kind: PrimKind,
        name: String,
        path: String,
        line: usize,
        order: usize,
    ) -> Self {
        match kind {
            PrimKind::Curves => Collected::Curves(Box::new(CurvesPrim {
                name,
                line,
                curve_type: None,
                basis: None,
                wrap: None,
                counts: None,
                points: None,
                widths: None,
                primvar_widths: None,
                width_indices: None,
                colors: None,
                color_indices: None,
            })),
            PrimKind::Mesh => Collected::Mesh(Box::new(MeshPrim {
                path,
                line,
                order,
                points: None,
                face_vertex_counts: None,
                face_vertex_indices: None,
                orientation: None,
            })),
        }
    }

    pub(crate) fn kind(&self) -> PrimKind {
        match self {
            Collected::Curves(_) => PrimKind::Curves,
            Collected::Mesh(_) => PrimKind::Mesh,
        }
    }

    /// The prim as messages name it: its name in quotes (curves) or its path (meshes).
    pub(crate) fn shown(&self) -> String {
        match self {
            Collected::Curves(curves) => curves.name.clone(),
            Collected::Mesh(mesh) => mesh.path.clone(),
        }
    }

    /// Where the value of `field` goes; `None` for a field of the other prim type.
    pub(crate) fn slot(&mut self, field: Field) -> Option<Slot<'_>> {
        Some(match (self, field) {
            (Collected::Curves(c), Field::Type) => Slot::Token(&mut c.curve_type),
            (Collected::Curves(c), Field::Basis) => Slot::Token(&mut c.basis),
            (Collected::Curves(c), Field::Wrap) => Slot::Token(&mut c.wrap),
            (Collected::Curves(c), Field::Counts) => Slot::Ints(&mut c.counts),
            (Collected::Curves(c), Field::WidthIndices) => Slot::Ints(&mut c.width_indices),
            (Collected::Curves(c), Field::ColorIndices) => Slot::Ints(&mut c.color_indices),
            (Collected::Curves(c), Field::Points) => Slot::Vec3s(&mut c.points),
            (Collected::Curves(c), Field::Colors) => Slot::Vec3s(&mut c.colors),
            (Collected::Curves(c), Field::Widths) => Slot::Floats(&mut c.widths),
            (Collected::Curves(c), Field::PrimvarWidths) => Slot::Floats(&mut c.primvar_widths),
            (Collected::Mesh(m), Field::Points) => Slot::Vec3s(&mut m.points),
            (Collected::Mesh(m), Field::FaceVertexCounts) => Slot::Ints(&mut m.face_vertex_counts),
            (Collected::Mesh(m), Field::FaceVertexIndices) => {
                Slot::Ints(&mut m.face_vertex_indices)
            }
            (Collected::Mesh(m), Field::Orientation) => Slot::Token(&mut m.orientation),
            _ => return None,
        })
    }
}

/// Where one attribute's value is read into, by its value type.
pub(crate) enum Slot<'p> {
    Token(&'p mut Option<Attr<String>>),
    Ints(&'p mut Option<Attr<Array<i64>>>),
    Floats(&'p mut Option<Attr<Array<f32>>>),
    Vec3s(&'p mut Option<Attr<Array<Vec3>>>),
}

/// What a layer holds: its axes and units and the prims asked for, in file order (meshes) or in
/// the order their bodies close (curves, children before their parents).
#[derive(Debug)]
pub(crate) struct Layer {
    /// `upAxis` and its line (`Y` when not authored).
    pub(crate) up: UpAxis,
    /// `metersPerUnit` (0.01 when not authored, as in USD).
    pub(crate) meters_per_unit: f64,
    pub(crate) meters_per_unit_line: usize,
    /// The `def BasisCurves` prims (when they were asked for).
    pub(crate) curves: Vec<CurvesPrim>,
    /// The `def Mesh` prims (when they were asked for).
    pub(crate) meshes: Vec<MeshPrim>,
    /// `timeCodesPerSecond` and `framesPerSecond`, when authored.
    pub(crate) time_codes_per_second: Option<f64>,
    pub(crate) frames_per_second: Option<f64>,
    /// The transform ops of every `def` prim that has an `xformOpOrder` (only when a sequence is
    /// read), in file order.
    pub(crate) xforms: Vec<XformPrim>,
}

/// The transform of one prim as authored: `xformOpOrder` and the `xformOp:` attributes, each
/// value flattened to its numbers (a `double3` is 3, a `quatf` 4 as `(w, x, y, z)`, a `matrix4d`
/// 16, row by row).
#[derive(Debug)]
pub(crate) struct XformPrim {
    /// The prim's path and the line of its name.
    pub(crate) path: String,
    pub(crate) line: usize,
    pub(crate) order: Option<Attr<Array<String>>>,
    pub(crate) ops: Vec<(String, Option<Attr<Array<f64>>>)>,
}

/// The attributes of a `BasisCurves` or `Mesh` prim that are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Field {
    Type,
    Basis,
    Wrap,
    Counts,
    Points,
    Widths,
    PrimvarWidths,
    WidthIndices,
    Colors,
    ColorIndices,
    FaceVertexCounts,
    FaceVertexIndices,
    Orientation,
}

impl Field {
    /// The field an attribute named `name` of a prim of `kind` is read into, if any.
    pub(crate) fn from_name(kind: PrimKind, name: &str) -> Option<Field> {
        Some(match (kind, name) {
            (_, "points") => Field::Points,
            (PrimKind::Curves, "type") => Field::Type,
            (PrimKind::Curves, "basis") => Field::Basis,
            (PrimKind::Curves, "wrap") => Field::Wrap,
            (PrimKind::Curves, "curveVertexCounts") => Field::Counts,
            (PrimKind::Curves, "widths") => Field::Widths,
            (PrimKind::Curves, "primvars:widths") => Field::PrimvarWidths,
            (PrimKind::Curves, "primvars:widths:indices") => Field::WidthIndices,
            (PrimKind::Curves, "primvars:displayColor") => Field::Colors,
            (PrimKind::Curves, "primvars:displayColor:indices") => Field::ColorIndices,
            (PrimKind::Mesh, "faceVertexCounts") => Field::FaceVertexCounts,
            (PrimKind::Mesh, "faceVertexIndices") => Field::FaceVertexIndices,
            (PrimKind::Mesh, "orientation") => Field::Orientation,
            _ => return None,
        })
    }

    /// Whether `type_name` (`[]` included) fits, and the type expected, in words.
    pub(crate) fn accepts(self, type_name: &str) -> (bool, &'static str) {
        let vec3 = |t: &str| {
            t.strip_suffix("[]").is_some_and(|e| {
                ["3f", "3d", "3h", "float3", "double3", "half3"]
                    .iter()
                    .any(|s| e.ends_with(s))
            })
        };
        match self {
            Field::Type | Field::Basis | Field::Wrap | Field::Orientation => {
                (type_name == "token", "token")
            }
            Field::Counts
            | Field::WidthIndices
            | Field::ColorIndices
            | Field::FaceVertexCounts
            | Field::FaceVertexIndices => (
                matches!(type_name, "int[]" | "int64[]" | "uint[]" | "uint64[]"),
                "int[]",
            ),
            Field::Points => (vec3(type_name), "point3f[]"),
            Field::Colors => (vec3(type_name), "color3f[]"),
            Field::Widths | Field::PrimvarWidths => (
                matches!(type_name, "float[]" | "double[]" | "half[]"),
                "float[]",
            ),
        }
    }
}
