//! `hairlod render`: render a groom to a PNG image sequence on the headless wgpu renderer (§6),
//! from a preset or a `SCENE.toml` file (see [`scene_file`]), at one fixed level of detail,
//! shaded, colour-coded by level or both side by side, with an orbiting, zooming or fixed camera.
//!
//! Frames are either the rest pose (`--motion still`) or simulated with the skeleton dynamics
//! (`hairlod::core::dynamics`, position-based integrator at 60 Hz) while the head shakes or nods
//! gently (`--motion shake|nod`, the default is `shake`). There are no collisions yet, so strongly
//! moving hair may pass through the head.

mod scene_file;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use glam::Vec3;
use hairlod::core::dynamics::{
    DynamicsModel, DynamicsParams, Environment, HeadMotion, IntegratorKind, Simulation,
    SimulationSettings,
};
use hairlod::core::{Frame, GroomParams, HeadParams, Level, RigidTransform, Scene, TriangleMesh};
use hairlod::render::{
    ActiveSkeletons, BackendChoice, Camera, DeviceOptions, FrameSettings, LineShading, Renderer,
    RendererOptions, ShadingMode, output,
};
use indicatif::{ProgressBar, ProgressStyle};

use scene_file::SceneFile;

/// Arguments of `hairlod render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML: preset, groom overrides, camera, frames; see docs/render.md). Flags given
    /// on the command line override it.
    #[arg(value_name = "SCENE.toml")]
    scene: Option<PathBuf>,
    /// Preset groom: paper-curly, straight, wavy or curly [default: paper-curly].
    #[arg(long)]
    preset: Option<String>,
    /// Number of frames [default: 12].
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Output folder (created if missing); frames are frame_00000.png, frame_00001.png, …
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Level of detail: strands, clusters or patches (auto: not yet) [default: strands].
    #[arg(long)]
    level: Option<String>,
    /// Colour-code by level (strands yellow, clusters red, patches blue) instead of shading.
    #[arg(long)]
    color_code: bool,
    /// Write shaded | colour-coded pairs side by side (twice as wide).
    #[arg(long)]
    side_by_side: bool,
    /// Image size WIDTHxHEIGHT in pixels [default: 1280x720].
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Camera path: orbit (once around), zoom-out (distance ×4) or fixed [default: orbit].
    #[arg(long)]
    camera: Option<String>,
    /// Head motion: still (rest pose, no simulation), shake or nod (simulated) [default: shake].
    #[arg(long)]
    motion: Option<String>,
    /// Also write contact_sheet.png with every frame scaled down.
    #[arg(long)]
    contact_sheet: bool,
    /// Shade 1-pixel strand lines per fragment instead of at their curve points (about 1.8× the
    /// strand render time on a CPU rasterizer; see docs/render.md for the difference it makes).
    #[arg(long)]
    per_fragment_lines: bool,
    /// Graphics backend: auto, vulkan or gl [default: $HAIRLOD_BACKEND, else auto].
    #[arg(long)]
    backend: Option<String>,
}

/// How the camera moves over the sequence.
#[derive(Debug, Clone, Copy, PartialEq)]
enum CameraPath {
    Orbit,
    ZoomOut,
    Fixed,
}

/// Everything the run needs, resolved from the file, the flags and the defaults.
#[derive(Debug, Clone)]
struct Plan {
    preset: String,
    groom: GroomParams,
    frames: u32,
    fps: f32,
    width: u32,
    height: u32,
    level: Level,
    mode: Mode,
    camera_path: CameraPath,
    distance: f32,
    end_distance: f32,
    azimuth: f32,
    elevation: f32,
    fov: f32,
    motion: Option<HeadMotion>,
    motion_name: String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Shaded,
    ColorCoded,
    SideBySide,
}

/// Parses `WIDTHxHEIGHT`.
fn parse_size(text: &str) -> Result<(u32, u32)> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Ok((w, h)),
        _ => bail!("size {text:?}: expected WIDTHxHEIGHT in pixels, each 1..=16384, e.g. 1280x720"),
    }
}

fn parse_level(text: &str) -> Result<Level> {
    if text.trim().eq_ignore_ascii_case("auto") {
        bail!(
            "--level auto needs the automatic level-of-detail selection, which is not built yet; \
             choose strands, clusters or patches"
        );
    }
    Ok(text.parse::<Level>()?)
}

fn parse_camera(text: &str) -> Result<CameraPath> {
    match text.trim().to_ascii_lowercase().as_str() {
        "orbit" => Ok(CameraPath::Orbit),
        "zoom-out" | "zoom" | "zoomout" => Ok(CameraPath::ZoomOut),
        "fixed" => Ok(CameraPath::Fixed),
        _ => bail!("camera {text:?}: expected orbit, zoom-out or fixed"),
    }
}

/// Gentle head motions: 0.25 rad (14°) at a peak of 1.2 rad/s (about 0.8 Hz).
fn parse_motion(text: &str) -> Result<Option<HeadMotion>> {
    match text.trim().to_ascii_lowercase().as_str() {
        "still" | "rest" | "static" => Ok(None),
        "shake" => Ok(Some(HeadMotion::shake(0.25, 1.2))),
        "nod" => Ok(Some(HeadMotion::nod(0.2, 1.0))),
        _ => bail!("motion {text:?}: expected still, shake or nod"),
    }
}

impl Plan {
    fn new(args: &RenderArgs) -> Result<Plan> {
        let file = match &args.scene {
            Some(path) => SceneFile::read(path)?,
            None => SceneFile::default(),
        };
        let preset = args
            .preset
            .clone()
            .or(file.preset.clone())
            .unwrap_or_else(|| "paper-curly".to_owned());
        let mut groom = GroomParams::preset(&preset)?;
        let overrides = &file.groom;
        if let Some(v) = overrides.section_count {
            groom.section_count = v;
        }
        if let Some(v) = overrides.strands_per_group {
            groom.strands_per_group = v;
        }
        if let Some(v) = overrides.hair_length {
            groom.hair_length = v;
        }
        if let Some(v) = overrides.seed {
            groom.seed = v;
        }
        let render = &file.render;
        let frames = args.frames.or(render.frames).unwrap_or(12);
        if frames == 0 {
            bail!("--frames 0: nothing to render; ask for at least 1 frame");
        }
        let size = args.size.as_deref().or(render.size.as_deref());
        let (width, height) = size.map_or(Ok((1280, 720)), parse_size)?;
        let level = parse_level(
            args.level
                .as_deref()
                .or(render.level.as_deref())
                .unwrap_or("strands"),
        )?;
        let side_by_side = args.side_by_side || render.side_by_side.unwrap_or(false);
        let color_code = args.color_code || render.color_code.unwrap_or(false);
        let mode = match (side_by_side, color_code) {
            (true, _) => Mode::SideBySide,
            (false, true) => Mode::ColorCoded,
            (false, false) => Mode::Shaded,
        };
        let camera = &file.camera;
        let camera_path = parse_camera(
            args.camera
                .as_deref()
                .or(camera.path.as_deref())
                .unwrap_or("orbit"),
        )?;
        let motion_name = args
            .motion
            .clone()
            .or(render.motion.clone())
            .unwrap_or_else(|| "shake".to_owned());
        let distance = camera.distance.unwrap_or(0.8);
        Ok(Plan {
            preset,
            groom,
            frames,
            fps: render.fps.unwrap_or(24.0),
            width,
            height,
            level,
            mode,
            camera_path,
            distance,
            end_distance: camera.end_distance.unwrap_or(4.0 * distance),
            azimuth: camera.azimuth_degrees.unwrap_or(150.0).to_radians(),
            elevation: camera.elevation_degrees.unwrap_or(8.0).to_radians(),
            fov: camera.fov_degrees.unwrap_or(35.0).to_radians(),
            motion: parse_motion(&motion_name)?,
            motion_name,
        })
    }

    /// The camera of frame `index`, looking at `target`.
    fn camera(&self, index: u32, target: Vec3) -> Camera {
        let t = if self.frames > 1 {
            index as f32 / (self.frames - 1) as f32
        } else {
            0.0
        };
        let (azimuth, distance) = match self.camera_path {
            CameraPath::Orbit => (
                self.azimuth + std::f32::consts::TAU * index as f32 / self.frames as f32,
                self.distance,
            ),
            CameraPath::ZoomOut => (
                self.azimuth,
                self.distance * (self.end_distance / self.distance).powf(t),
            ),
            CameraPath::Fixed => (self.azimuth, self.distance),
        };
        Camera::orbit(target, distance, azimuth, self.elevation, self.fov)
    }
}

/// Wall time per stage, summed over frames.
#[derive(Debug, Default)]
struct StageTimes {
    simulate: Duration,
    gather: Duration,
    render: Duration,
    write: Duration,
}

fn timed<T>(total: &mut Duration, work: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let value = work();
    *total += start.elapsed();
    value
}

/// The head mesh moved rigidly by `pose`.
fn posed_mesh(mesh: &TriangleMesh, pose: &RigidTransform) -> TriangleMesh {
    TriangleMesh {
        positions: mesh
            .positions
            .iter()
            .map(|&p| pose.transform_point(p))
            .collect(),
        normals: mesh
            .normals
            .iter()
            .map(|&n| pose.transform_vector(n))
            .collect(),
        triangles: mesh.triangles.clone(),
    }
}

/// Runs `hairlod render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let plan = Plan::new(args)?;
    let setup_start = Instant::now();
    let scene = Scene::new(&HeadParams::default(), &plan.groom)
        .with_context(|| format!("could not build the `{}` groom", plan.preset))?;
    let groom = &scene.groom;
    let counts = groom.counts();

    let mut device = DeviceOptions::from_env()?;
    if let Some(backend) = &args.backend {
        device.backend = backend.parse::<BackendChoice>()?;
    }
    let mut renderer = Renderer::new(&RendererOptions { device })?;
    renderer.upload_groom(groom)?;
    renderer.set_head_mesh(Some(&scene.head.mesh))?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output folder {}", args.out.display()))?;

    let (low, high) = scene.head.mesh.bounds().context("the head mesh is empty")?;
    let target = (low + high) * 0.5 + Vec3::new(0.0, 0.03, 0.0);

    let mut simulation = match &plan.motion {
        None => None,
        Some(motion) => {
            let model = DynamicsModel::new(
                groom.skeletons.clone(),
                DynamicsParams::for_style(&groom.params.style),
            )?;
            let settings = SimulationSettings::recommended(IntegratorKind::PositionBased);
            let environment = Environment {
                head: motion.clone(),
                ..Environment::default()
            };
            Some((Simulation::new(model, settings)?, environment))
        }
    };
    let mut state = match &simulation {
        Some((simulation, environment)) => simulation.rest_state(environment, 0.0),
        None => hairlod::core::dynamics::SimulationState::at_rest(
            &groom.skeletons,
            &RigidTransform::IDENTITY,
            0.0,
        ),
    };
    let steps_per_frame = simulation.as_ref().map_or(0, |(simulation, _)| {
        let step = f64::from(simulation.settings().time_step);
        ((1.0 / f64::from(plan.fps)) / step).round().max(1.0) as usize
    });
    let setup = setup_start.elapsed();

    let level_items = match plan.level {
        Level::StrandGroup => format!("{} strands", counts.strands),
        Level::Cluster => format!("{} clusters", counts.clusters),
        Level::Patch => format!("{} patches", counts.patches),
    };
    eprintln!("adapter: {}", renderer.adapter_report());
    eprintln!(
        "rendering {} frame(s) of `{}` at {}x{}: {level_items}, {}, camera {:?}, motion {}",
        plan.frames,
        plan.preset,
        plan.width,
        plan.height,
        match plan.mode {
            Mode::Shaded => "shaded",
            Mode::ColorCoded => "colour-coded",
            Mode::SideBySide => "shaded | colour-coded",
        },
        plan.camera_path,
        plan.motion_name,
    );

    let progress = ProgressBar::new(u64::from(plan.frames));
    progress.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {elapsed} elapsed, eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut times = StageTimes::default();
    let mut frames_buffer = vec![Frame::default(); state.node_count()];
    let mut active = ActiveSkeletons::new();
    let mut thumbnails = Vec::new();
    let mut head_pose = RigidTransform::IDENTITY;
    for index in 0..plan.frames {
        if let Some((simulation, environment)) = &mut simulation {
            if index > 0 {
                timed(&mut times.simulate, || {
                    simulation.run(&mut state, environment, steps_per_frame)
                })
                .with_context(|| format!("the simulation failed before frame {index}"))?;
            }
            head_pose = environment.head.transform_at(state.time);
            renderer.set_head_mesh(Some(&posed_mesh(&scene.head.mesh, &head_pose)))?;
        }
        timed(&mut times.gather, || {
            groom
                .skeletons
                .node_frames_into(&head_pose, &state.node_positions, &mut frames_buffer);
            active.gather_level(groom, plan.level, &state.node_positions, &frames_buffer)
        })?;
        let target = head_pose.transform_point(target);
        let mut settings = FrameSettings::new(plan.width, plan.height, plan.camera(index, target));
        settings.light.direction =
            (settings.camera.position - target).normalize() + Vec3::new(0.4, 0.8, 0.0);
        if args.per_fragment_lines {
            settings.line_shading = LineShading::PerFragment;
        }
        let image = timed(&mut times.render, || match plan.mode {
            Mode::Shaded => renderer.render(&active.frame(), &settings),
            Mode::ColorCoded => renderer.render(
                &active.frame(),
                &FrameSettings {
                    mode: ShadingMode::LevelColors,
                    ..settings
                },
            ),
            Mode::SideBySide => renderer.render_side_by_side(&active.frame(), &settings),
        })
        .with_context(|| format!("could not render frame {index}"))?;
        let path = output::frame_path(&args.out, u64::from(index), u64::from(plan.frames));
        timed(&mut times.write, || output::write_png_atomic(&image, &path))?;
        if args.contact_sheet {
            let width = 320.min(image.width());
            let height = (image.height() * width / image.width()).max(1);
            thumbnails.push((
                image::imageops::thumbnail(&image, width, height),
                width,
                height,
            ));
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    if let Some(&(_, width, height)) = thumbnails.first() {
        let images: Vec<_> = thumbnails.into_iter().map(|(image, _, _)| image).collect();
        let sheet = output::contact_sheet(&images, (images.len() as u32).min(6), width, height)?;
        let path = args.out.join("contact_sheet.png");
        output::write_png_atomic(&sheet, &path)?;
        eprintln!("wrote {}", path.display());
    }
    print_summary(&args.out, &plan, &times, setup);
    Ok(())
}

fn print_summary(out: &Path, plan: &Plan, times: &StageTimes, setup: Duration) {
    let frames = f64::from(plan.frames);
    let per_frame = |d: Duration| d.as_secs_f64() * 1e3 / frames;
    eprintln!(
        "wrote {} frame(s) to {} (setup {:.2} s: groom, device, upload)",
        plan.frames,
        out.display(),
        setup.as_secs_f64()
    );
    eprintln!("  stage        total [s]   per frame [ms]");
    for (name, time) in [
        ("simulate", times.simulate),
        ("gather", times.gather),
        ("render", times.render),
        ("write png", times.write),
    ] {
        eprintln!(
            "  {name:<10} {:>10.3} {:>15.1}",
            time.as_secs_f64(),
            per_frame(time)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_levels_and_paths_parse_or_explain() {
        assert_eq!(parse_size("1280x720").unwrap(), (1280, 720));
        assert!(
            parse_size("0x10")
                .unwrap_err()
                .to_string()
                .contains("WIDTHxHEIGHT")
        );
        assert!(parse_size("big").is_err());
        assert_eq!(parse_level("clusters").unwrap(), Level::Cluster);
        assert!(
            parse_level("auto")
                .unwrap_err()
                .to_string()
                .contains("not built yet")
        );
        assert!(parse_level("voxels").is_err());
        assert_eq!(parse_camera("zoom-out").unwrap(), CameraPath::ZoomOut);
        assert!(
            parse_camera("dolly")
                .unwrap_err()
                .to_string()
                .contains("orbit")
        );
        assert!(parse_motion("still").unwrap().is_none());
        assert!(parse_motion("dance").is_err());
    }
}
