//! Grooms and bodies read from files, as a scene file names them (`[groom] file`, `[body] file`):
//! the curves read in the file's units and axes ([`hair_formats`]), the paper's hierarchy
//! fitted to them ([`hair_core::fit`]), the groom built from the fit
//! ([`Groom::from_fit`](hair_core::Groom::from_fit)), and the body mesh in the procedural head's
//! place (drawn, collided with, and hiding hair behind occluder boxes found inside it,
//! [`occluder_boxes`]).
//!
//! [`load_scene`] does it all and measures it ([`LoadReport`]): the strand roots' distances from
//! the body, and the fit's errors. A groom whose roots lie far from the body, or whose size is
//! no head of hair's, is refused with the field to check (its scale or axes). The rest pose
//! (the loaded shape made an equilibrium) is [`Shot::build_scene`](crate::Shot::build_scene)'s
//! work. [`rest_errors`] measures a built groom against its file's curves.

mod occluders;
mod rest_error;
mod sparse;

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use hair_collide::{AttachmentReport, CollisionBody, attach_roots};
use hair_core::fit::{
    FitReport, FitSettings, FittedHierarchy, NodeCountScope, SectionCount, Smoothness,
    bind_profiles, fit_hierarchy,
};
use hair_core::groom::ChildStrands;
use hair_core::{
    Groom, GroomParams, HairError, Head, HeadParams, MeshSequence, Scene, TriangleMesh,
};
use hair_formats::{
    Curves, ImportAxes, ImportOptions, SequenceLimits, UpAxis, read_curves_file, read_mesh_file,
    read_mesh_sequence_file,
};
use serde::Serialize;

pub use occluders::{OccluderSettings, occluder_boxes};
pub use rest_error::{LevelRestErrors, rest_errors};
pub use sparse::{
    CHILD_TARGET_STRANDS_PER_M2, DENSE_STRAND_COUNT, GrownChildren, MAX_GROWN_STRANDS,
    SPARSE_STRANDS_PER_M2, auto_children, root_density,
};

use crate::pipeline::Result;

/// A file's units and axes, as a scene gives them: converted to the scene's metres, +Y up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FileAxes {
    /// Metres per file unit (0.01 for centimetres), a finite number > 0.
    pub scale_to_metres: f32,
    /// The file's up axis is +Z (turned to +Y); otherwise +Y.
    pub z_up: bool,
    /// Negate x (a file from a left-handed tool).
    pub mirror_x: bool,
}

impl Default for FileAxes {
    /// Metres, +Y up, not mirrored.
    fn default() -> Self {
        FileAxes {
            scale_to_metres: 1.0,
            z_up: false,
            mirror_x: false,
        }
    }
}

impl FileAxes {
    /// The readers' options for these axes (degenerate curves skipped, not refused).
    pub fn import_options(&self) -> ImportOptions {
        ImportOptions {
            axes: ImportAxes {
                scale_to_metres: self.scale_to_metres,
                up: if self.z_up { UpAxis::Z } else { UpAxis::Y },
                mirror_x: self.mirror_x,
            },
            strict: false,
            sequence: Default::default(),
        }
    }
}

/// A groom read from a file (`[groom] file`) and fitted with the paper's hierarchy.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroomFile {
    /// The files (a scene file's relative paths resolved against the scene file's folder), at
    /// least one, read one after the other as one groom (the parts of a hairstyle); each file's
    /// extension picks its reader ([`read_curves_file`]).
    pub paths: Vec<PathBuf>,
    /// Its units and axes.
    pub axes: FileAxes,
    /// How many sections the fit makes.
    #[serde(skip)]
    pub sections: SectionCount,
    /// The longest skeleton segment [m] (the smoothness rule's, [`Smoothness`]).
    pub max_segment_length: f32,
    /// How much larger than the mean a section may grow, as a fraction
    /// ([`FitSettings::section_size_slack`]; 0: sizes within one strand, so that at 5 strands
    /// per section each strand group holds one file strand).
    pub section_size_slack: f32,
    /// Seed of the fit's clustering.
    pub seed: u64,
    /// Child strands grown around each file strand. With [`GroomFile::auto_children`] its count
    /// (and, with [`GroomFile::auto_child_spread`], its spread) is chosen at load time instead.
    #[serde(skip)]
    pub children: ChildStrands,
    /// Grow children around a sparse groom's strands by [`auto_children`] (the default). A
    /// scene's `groom.children_per_strand` sets `children.per_strand` and turns this off (0: the
    /// file's strands only).
    pub auto_children: bool,
    /// With [`GroomFile::auto_children`], spread the children over the disc each guide stands
    /// for (the default); `groom.child_spread` sets `children.spread` and turns this off.
    pub auto_child_spread: bool,
}

impl GroomFile {
    /// The groom in `paths`, in metres, +Y up, about 50 strands per section, 2.5 cm segments,
    /// seed 1.
    pub fn new(paths: Vec<PathBuf>) -> Self {
        let fit = FitSettings::default();
        GroomFile {
            paths,
            axes: FileAxes::default(),
            sections: fit.sections,
            max_segment_length: fit.smoothness.max_segment_length,
            section_size_slack: fit.section_size_slack,
            seed: fit.seed,
            children: ChildStrands::default(),
            auto_children: true,
            auto_child_spread: true,
        }
    }

    /// The fit's settings: these sections, segments and seed, one node count for the whole
    /// groom (every skeleton of a [`Groom`] has the same count), the rest the defaults.
    pub fn fit_settings(&self) -> FitSettings {
        FitSettings {
            sections: self.sections,
            smoothness: Smoothness {
                max_segment_length: self.max_segment_length,
                ..Smoothness::default()
            },
            node_counts: NodeCountScope::Uniform,
            section_size_slack: self.section_size_slack,
            seed: self.seed,
            ..FitSettings::default()
        }
    }
}

/// A body mesh read from a file (`[body] file`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BodyFile {
    /// The file; its extension picks the reader (`.tfxmesh`, `.obj`, `.usda`, `.usdc`, `.usd`: [`read_mesh_file`]).
    pub path: PathBuf,
    /// Its units and axes.
    pub axes: FileAxes,
    /// How long a run reads its animation [s from its first sample]: later samples are not
    /// read (but the first one after, so that the window plays as the file does), and the body
    /// holds its last pose read after that. `None` reads every sample; a shot sets its own
    /// length ([`Shot::build_loaded_scene`](crate::shot::Shot::build_loaded_scene)).
    pub seconds: Option<f64>,
}

/// What loading measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoadReport {
    /// Curves read (after degenerate ones were skipped).
    pub curves: usize,
    /// Curves the reader skipped (fewer than two points, a zero-length segment).
    pub skipped_curves: usize,
    /// Curves left out as shorter than [`MIN_CURVE_LENGTH`].
    pub short_curves: usize,
    /// The fit's counts and errors.
    pub fit: FitReport,
    /// How far the strand roots lie from the body's surface [m] (with a body file).
    pub roots: Option<AttachmentReport>,
    /// Occluder boxes found inside the body (with a body file).
    pub occluder_boxes: usize,
    /// The children grown by default around a sparse groom's strands ([`auto_children`]).
    pub grown_children: Option<GrownChildren>,
}

/// A scene loaded from files, with what was measured and the inputs kept for measuring it again.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The body and the fitted groom on it (in the loaded shape, not yet made an equilibrium).
    pub scene: Scene,
    /// The groom file's curves [m], scene axes.
    pub curves: Curves,
    /// The fit of those curves.
    pub fit: FittedHierarchy,
    /// What loading measured.
    pub report: LoadReport,
}

/// Curves shorter than this [m] are left out of a loaded groom: stubs that show as nothing, and
/// that would make skeletons whose segments (a skeleton's node count is the groom's) are too short
/// for the integrator (a 7.5 µm strand of the mohawk, as its strand group's only strand, made the
/// first step non-finite).
pub const MIN_CURVE_LENGTH: f32 = 0.005;

/// `curves` without those shorter than [`MIN_CURVE_LENGTH`], and how many were left out.
fn drop_short_curves(curves: Curves) -> (Curves, usize) {
    let keep: Vec<bool> = (0..curves.curve_count())
        .map(|c| {
            let range = curves.offsets[c] as usize..curves.offsets[c + 1] as usize;
            hair_core::fit::curve_length(&curves.points[range]) >= MIN_CURVE_LENGTH
        })
        .collect();
    let dropped = keep.iter().filter(|&&k| !k).count();
    if dropped == 0 {
        return (curves, 0);
    }
    let mut out = Curves {
        offsets: vec![0],
        widths: curves.widths.as_ref().map(|_| Vec::new()),
        colors: curves.colors.as_ref().map(|_| Vec::new()),
        skipped: curves.skipped.clone(),
        ..Curves::default()
    };
    for (c, _) in keep.iter().enumerate().filter(|(_, k)| **k) {
        let range = curves.offsets[c] as usize..curves.offsets[c + 1] as usize;
        out.points.extend_from_slice(&curves.points[range.clone()]);
        if let (Some(all), Some(kept)) = (&curves.widths, &mut out.widths) {
            kept.extend_from_slice(&all[range.clone()]);
        }
        if let (Some(all), Some(kept)) = (&curves.colors, &mut out.colors) {
            kept.extend_from_slice(&all[range]);
        }
        out.offsets.push(out.points.len() as u32);
    }
    (out, dropped)
}

/// Roots farther than this from the body [m] (the median over strands) mean the groom and the
/// body do not go together: wrong units or axes on one of them, most likely.
pub const MAX_MEDIAN_ROOT_DISTANCE: f32 = 0.05;

/// A groom's extent (its bounding box's diagonal) [m] must lie in this range: anything else is
/// no head of hair in metres (a file in centimetres read as metres is 100 times too large).
pub const GROOM_EXTENT_RANGE: (f32, f32) = (0.005, 10.0);

/// An error about a file named by a scene-file field: `reading <field> <path>: <message>`.
fn file_error(field: &'static str, path: &std::path::Path, message: impl ToString) -> HairError {
    HairError::Io {
        action: field,
        path: path.display().to_string(),
        message: message.to_string(),
    }
}

/// Reads the body mesh of `body` in scene axes. Errors name the field (`body.file`) and the file.
pub fn load_body_mesh(body: &BodyFile) -> Result<TriangleMesh> {
    read_mesh_file(&body.path, &body.axes.import_options())
        .map_err(|error| file_error("reading body.file", &body.path, error.kind).into())
}

/// Reads the body of `body` over time in scene axes ([`read_mesh_sequence_file`]: USD time
/// samples, an Alembic mesh sequence; one sample for the formats without animation), for
/// `body.seconds` from its first sample. Its positions may take at most half the memory the
/// machine has available ([`crate::host_memory`]): a sequence over that is refused with its
/// size instead of filling the memory. Errors name the field (`body.file`), the file and, for a
/// bad sample, the prim and time.
pub fn load_body_sequence(body: &BodyFile) -> Result<MeshSequence> {
    let options = ImportOptions {
        sequence: SequenceLimits {
            seconds: body.seconds,
            max_bytes: crate::host_memory::available_bytes().map(|bytes| bytes / 2),
        },
        ..body.axes.import_options()
    };
    read_mesh_sequence_file(&body.path, &options)
        .map_err(|error| file_error("reading body.file", &body.path, error.kind).into())
}

/// Reads `groom`'s curves, fits the paper's hierarchy to them and builds the groom with the
/// material of `params` (its style), on `body` when given (else on the procedural head). The
/// body takes the head's place: drawn, collided with, and hiding hair behind boxes found inside
/// it. Errors name the field and the file: a file that cannot be read, a groom of no plausible
/// size (check `groom.scale`), roots far from the body (check the scales and axes), or a fit
/// that fails.
pub fn load_scene(
    groom: &GroomFile,
    body: Option<&BodyFile>,
    params: &GroomParams,
) -> Result<LoadedScene> {
    let first = groom
        .paths
        .first()
        .ok_or_else(|| HairError::invalid("groom.file", "no file", "at least one groom file"))?;
    check_distinct_files(&groom.paths)?;
    let mut curves = Curves {
        offsets: vec![0],
        ..Curves::default()
    };
    for path in &groom.paths {
        let part = read_curves_file(path, &groom.axes.import_options())
            .map_err(|error| file_error("reading groom.file", path, error.kind))?;
        append_curves(&mut curves, part);
    }
    let (curves, short_curves) = drop_short_curves(curves);
    if curves.curve_count() == 0 {
        return Err(file_error(
            "reading groom.file",
            first,
            format!("every curve is shorter than {MIN_CURVE_LENGTH} m (check groom.scale)"),
        )
        .into());
    }
    check_extent(&curves, groom, first)?;
    check_section_count(&curves, groom, first)?;
    let fit = fit_hierarchy(&curves, &groom.fit_settings())
        .map_err(|error| file_error("fitting groom.file", first, error))?;
    let (children, grown_children) = children_of(groom, &curves);
    let mut groom_model = Groom::from_fit_with_children(&fit, &curves, params, &children)
        .map_err(|error| file_error("fitting groom.file", first, error))?;
    bind_profiles(&mut groom_model, &fit, &curves)
        .map_err(|error| file_error("fitting groom.file", first, error))?;
    let mut body_motion = None;
    let (head, roots, boxes) = match body {
        None => (Head::procedural(&HeadParams::default())?, None, 0),
        Some(body) => {
            // The body at its first sample is the rest shape the roots attach to; a body that
            // moves through its samples deforms (Scene::body_motion).
            let sequence = load_body_sequence(body)?;
            let mesh = sequence.mesh_at(sequence.times()[0]);
            if sequence.is_animated() {
                body_motion = Some(Arc::new(sequence));
            }
            let collision = CollisionBody::from_mesh(&mesh)
                .map_err(|error| file_error("reading body.file", &body.path, error))?;
            let strand_roots: Vec<Vec3> = curves.offsets[..curves.curve_count()]
                .iter()
                .map(|&start| curves.points[start as usize])
                .collect();
            let (_, report) = attach_roots(&collision, &strand_roots)?;
            if report.median > MAX_MEDIAN_ROOT_DISTANCE {
                return Err(file_error(
                    "attaching groom.file",
                    first,
                    format!(
                        "its strand roots lie {:.3} m (median) from the surface of body.file {}, \
                         more than {MAX_MEDIAN_ROOT_DISTANCE} m: check groom.scale, \
                         groom.up_axis and groom.mirror against body.scale, body.up_axis and \
                         body.mirror",
                        report.median,
                        body.path.display()
                    ),
                )
                .into());
            }
            let region = groom_bounds(&curves);
            let boxes = occluder_boxes(&collision, &mesh, region, &OccluderSettings::default());
            let count = boxes.len();
            (Head::from_mesh(mesh, boxes)?, Some(report), count)
        }
    };
    let report = LoadReport {
        curves: curves.curve_count(),
        skipped_curves: curves.skipped.len(),
        short_curves,
        fit: fit.report.clone(),
        roots,
        occluder_boxes: boxes,
        grown_children,
    };
    Ok(LoadedScene {
        scene: Scene {
            head,
            groom: groom_model,
            body_motion,
        },
        curves,
        fit,
        report,
    })
}

/// The children `groom` gets on `curves`: its own, or with [`GroomFile::auto_children`] those
/// [`auto_children`] grows on a sparse groom (none on a dense one).
fn children_of(groom: &GroomFile, curves: &Curves) -> (ChildStrands, Option<GrownChildren>) {
    if !groom.auto_children {
        return (groom.children, None);
    }
    let roots: Vec<Vec3> = curves.offsets[..curves.curve_count()]
        .iter()
        .map(|&start| curves.points[start as usize])
        .collect();
    let spread = (!groom.auto_child_spread).then_some(groom.children.spread);
    match auto_children(&roots, spread, &groom.children) {
        Some((children, grown)) => (children, Some(grown)),
        None => (
            ChildStrands {
                per_strand: 0,
                ..groom.children
            },
            None,
        ),
    }
}

/// The bounding box `(min, max)` of the curves' points [m].
fn groom_bounds(curves: &Curves) -> (Vec3, Vec3) {
    curves.points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(min, max), &p| (min.min(p), max.max(p)),
    )
}

/// Appends `part`'s curves to `all` (points, offsets; widths and colours are dropped unless
/// every part has them).
fn append_curves(all: &mut Curves, part: Curves) {
    let base_points = all.points.len() as u32;
    let base_curves = all.curve_count();
    let first_part = base_curves == 0 && all.points.is_empty();
    all.widths = match (first_part, all.widths.take(), part.widths) {
        (true, _, widths) => widths,
        (false, Some(mut a), Some(b)) => {
            a.extend(b);
            Some(a)
        }
        _ => None,
    };
    all.colors = match (first_part, all.colors.take(), part.colors) {
        (true, _, colors) => colors,
        (false, Some(mut a), Some(b)) => {
            a.extend(b);
            Some(a)
        }
        _ => None,
    };
    all.points.extend(part.points);
    all.offsets
        .extend(part.offsets[1..].iter().map(|&o| o + base_points));
    // Each skipped curve keeps its index in its own file.
    all.skipped.extend(part.skipped);
}

/// Refuses a list of groom files that names one file twice (by its canonical path, so `a.tfx`
/// and `./a.tfx` are the same): read twice, every strand of it would be doubled. The error names
/// both indices and both paths as given.
fn check_distinct_files(paths: &[PathBuf]) -> Result<()> {
    let canonical: Vec<PathBuf> = paths
        .iter()
        .map(|path| std::fs::canonicalize(path).unwrap_or_else(|_| path.clone()))
        .collect();
    for (j, later) in canonical.iter().enumerate() {
        if let Some(i) = canonical[..j].iter().position(|earlier| earlier == later) {
            return Err(file_error(
                "reading groom.file",
                &paths[j],
                format!(
                    "groom.file[{j}] ({}) is the same file as groom.file[{i}] ({}): list each \
                     part of the groom once (read twice, every strand of it would be doubled)",
                    paths[j].display(),
                    paths[i].display()
                ),
            )
            .into());
        }
    }
    Ok(())
}

/// Refuses a fixed section count the curves cannot hold: a fitted section needs 5 strands (one
/// per strand group), so `N` curves make at most `N / 5` sections. Asking for more would build
/// fewer sections than asked, silently; a count up to that is kept, less the sections merged
/// because they would hold fewer than 5 strands
/// ([`FitReport::merged_sections`](hair_core::fit::FitReport::merged_sections), which
/// `hairlod groom --file` prints).
fn check_section_count(curves: &Curves, groom: &GroomFile, path: &std::path::Path) -> Result<()> {
    let SectionCount::Fixed(asked) = groom.sections else {
        return Ok(());
    };
    let strands = curves.curve_count();
    let most = (strands / STRANDS_PER_FITTED_SECTION).max(1);
    if asked <= most {
        return Ok(());
    }
    Err(file_error(
        "fitting groom.file",
        path,
        format!(
            "groom.section_count = {asked}: its {strands} strands make at most {most} sections \
             ({STRANDS_PER_FITTED_SECTION} strands each, one per strand group); ask for at most \
             {most}, or give groom.strands_per_section instead"
        ),
    )
    .into())
}

/// The fewest strands a fitted section holds: one per strand group.
const STRANDS_PER_FITTED_SECTION: usize = 5;

/// Refuses curves whose extent is outside [`GROOM_EXTENT_RANGE`], naming `groom.scale` and the
/// (first) file.
fn check_extent(curves: &Curves, groom: &GroomFile, path: &std::path::Path) -> Result<()> {
    let (min, max) = groom_bounds(curves);
    let extent = min.distance(max);
    let (low, high) = GROOM_EXTENT_RANGE;
    if (low..=high).contains(&extent) {
        return Ok(());
    }
    Err(file_error(
        "reading groom.file",
        path,
        format!(
            "the groom is {extent:.4} m across at groom.scale = {}, outside {low}..={high} m: \
             set groom.scale to the file's metres per unit (0.01 for centimetres)",
            groom.axes.scale_to_metres
        ),
    )
    .into())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An OBJ groom of `strands` straight strands, 10 cm long, rooted over the top of the head,
    /// written to a fresh folder `name`; its path.
    fn obj_groom(name: &str, strands: usize) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("hairlod-loaded-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let mut text = String::new();
        for k in 0..strands {
            let angle = k as f32 * 2.399;
            let (x, z) = (0.04 * angle.cos(), 0.04 * angle.sin());
            for j in 0..4 {
                let t = j as f32 / 3.0;
                text += &format!("v {} {} {}\n", x * (1.0 + t), 0.1 - 0.1 * t, z * (1.0 + t));
            }
            let base = 4 * k + 1;
            text += &format!("l {} {} {} {}\n", base, base + 1, base + 2, base + 3);
        }
        let path = dir.join("groom.obj");
        std::fs::write(&path, text).unwrap();
        path
    }

    /// One file listed twice would double every strand: refused, naming both entries.
    #[test]
    fn a_groom_file_listed_twice_is_refused() {
        let path = obj_groom("twice", 10);
        let again = path.parent().unwrap().join(".").join("groom.obj");
        let groom = GroomFile::new(vec![path.clone(), again]);
        let error = load_scene(&groom, None, &GroomParams::straight())
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("groom.file[1]") && error.contains("groom.file[0]"),
            "{error}"
        );
        assert!(error.contains("is the same file as"), "{error}");
        assert!(error.contains(&path.display().to_string()), "{error}");
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }

    /// More sections than the strands can hold (5 each) is an error naming the field and the
    /// most there can be, not fewer sections silently; that many builds.
    #[test]
    fn more_sections_than_the_strands_hold_are_refused() {
        let path = obj_groom("sections", 20);
        let mut groom = GroomFile::new(vec![path.clone()]);
        groom.sections = SectionCount::Fixed(10);
        let error = load_scene(&groom, None, &GroomParams::straight())
            .unwrap_err()
            .to_string();
        assert!(error.contains("groom.section_count = 10"), "{error}");
        assert!(
            error.contains("20 strands make at most 4 sections"),
            "{error}"
        );
        groom.sections = SectionCount::Fixed(4);
        let loaded = load_scene(&groom, None, &GroomParams::straight()).unwrap();
        assert!((1..=4).contains(&loaded.scene.groom.section_count()));
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }
}
