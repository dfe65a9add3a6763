//! `hairlod view`: open a window on a scene (a `SCENE.toml` file, or the defaults with flags)
//! running through the frame pipeline, with mouse and keyboard controls and a heads-up display
//! (see `docs/viewer.md`). `--frames N --screenshot FILE` runs N frames and exits, `--script FILE`
//! drives the controls from timed events: the headless runs of tests and CI (under Xvfb).

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow};
use clap::Args;
use hairlod::pipeline::Checkpoint;
use hairlod::render::DeviceOptions;
use hairlod::scene_file::SceneFile;
use winit::event_loop::EventLoop;

use hairlod::core::GroomPreset;
use hairlod::scene_file::{CameraPathKind, LodModeKind, MotionKind};

use crate::cli_args::{BackendArg, ShotOverrides, choice};
use crate::viewer::app::{self, ViewOptions};
use crate::viewer::script::Script;
use crate::viewer::session::Session;

/// Arguments of `hairlod view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Scene file (TOML, version 2; see scenes/example.toml). Flags given on the command line
    /// override it. Without one: the paper-curly groom on the procedural head.
    #[arg(value_name = "SCENE.toml")]
    scene: Option<PathBuf>,
    /// Draw N frames, then close (headless runs: tests, CI, measurements); the shot is N frames
    /// long (its camera path spans them) [scene: frames.count].
    #[arg(long, value_name = "N")]
    frames: Option<u64>,
    /// Write the last of the --frames as a PNG (the window's image, HUD included).
    #[arg(long, value_name = "FILE", requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Timed key presses, mouse drags, wheel turns and screenshots (see docs/viewer.md).
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// Folder of the screenshot key's PNGs (hairlod_view_<frame>.png).
    #[arg(long, value_name = "DIR", default_value = ".")]
    screenshot_dir: PathBuf,
    /// Window size WIDTHxHEIGHT [pixels]; also the image size the levels of detail are chosen
    /// for [scene: frames.size; default 1280x720].
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Preset groom [scene: groom.preset; default paper-curly].
    #[arg(long, value_parser = choice::<GroomPreset>())]
    preset: Option<GroomPreset>,
    /// Level of detail at the start [scene: lod.mode; default auto].
    #[arg(long, value_parser = choice::<LodModeKind>())]
    level: Option<LodModeKind>,
    /// Screen-space error tolerance of automatic levels [pixels] [scene: lod.pixel_tolerance].
    #[arg(long, value_name = "PX")]
    pixel_tolerance: Option<f32>,
    /// Start colour-coded by level (strands yellow, clusters red, patches blue).
    #[arg(long)]
    color_code: bool,
    /// Camera path followed until the mouse moves the camera [scene: camera.path].
    #[arg(long, value_parser = choice::<CameraPathKind>())]
    camera: Option<CameraPathKind>,
    /// Head motion [scene: motion.kind; default still].
    #[arg(long, value_parser = choice::<MotionKind>())]
    motion: Option<MotionKind>,
    /// Graphics backend [default: $HAIRLOD_BACKEND, else auto].
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Write the simulation's state to FILE when the viewer closes (window closed, `q`, or the
    /// end of --frames): `hairlod render SCENE --resume FILE` goes on from it.
    #[arg(long, value_name = "FILE")]
    checkpoint_on_exit: Option<PathBuf>,
    /// Start from a checkpoint written by `render --checkpoint` or --checkpoint-on-exit (same
    /// scene and flags).
    #[arg(long, value_name = "FILE")]
    resume: Option<PathBuf>,
}

impl ViewArgs {
    /// The scene file with the flags applied over it.
    fn scene_file(&self) -> Result<SceneFile> {
        // The camera path spans the frames shown, as `render --frames N` makes the shot N frames
        // long.
        let mut file = ShotOverrides {
            preset: self.preset,
            frames: self
                .frames
                .map(|frames| usize::try_from(frames).unwrap_or(usize::MAX)),
            level: self.level,
            pixel_tolerance: self.pixel_tolerance,
            size: self.size.as_ref(),
            camera: self.camera,
            motion: self.motion,
        }
        .scene_file(self.scene.as_deref())?;
        if self.color_code {
            file.output.color_coded = Some(true);
            file.output.shaded = Some(false);
        }
        file.resolve()
            .context("the scene with the command-line flags")?;
        Ok(file)
    }
}

/// Runs `hairlod view`.
pub fn run(args: &ViewArgs) -> Result<()> {
    let file = args.scene_file()?;
    let mut shot = file.resolve()?;
    anyhow::ensure!(
        !shot.is_crowd(),
        "the viewer shows one character; crowd scenes ([[character]] tables) run in `hairlod \
         render` and `hairlod bench`"
    );
    let script = args.script.as_deref().map(Script::read).transpose()?;
    if let (Some(frames), Some(last)) = (args.frames, script.as_ref().and_then(Script::last_frame))
        && last >= frames
    {
        eprintln!(
            "warning: the script has events up to frame {last}, but --frames {frames} stops \
             after frame {}",
            frames - 1
        );
    }
    let resume = args.resume.as_deref().map(Checkpoint::read).transpose()?;
    if args.frames == Some(0) {
        return Err(anyhow!(
            "--frames 0: nothing to show; give at least 1 frame"
        ));
    }
    let mut device = DeviceOptions::from_env()?;
    if let Some(backend) = args.backend {
        device.backend = backend.into();
    }
    // The display first: without one there is no point building the groom.
    let event_loop = EventLoop::new().map_err(|error| {
        anyhow!(
            "cannot open a window: {error}\n`hairlod view` needs a display (X11 or Wayland); \
             without one, run it under `xvfb-run`, or use `hairlod render SCENE --out DIR`, \
             which writes the same frames as PNG files"
        )
    })?;
    let scene = crate::scene_build::build_scene(&mut shot)?;
    let counts = scene.groom.counts();
    eprintln!(
        "viewing `{}` ({} sections, {} strands) at {}x{}, {}",
        file.groom.preset.unwrap_or_default(),
        counts.sections,
        counts.strands,
        shot.width,
        shot.height,
        shot.settings.lod.column_name(),
    );
    let pipeline = shot.pipeline(&scene, shot.settings, resume)?;
    let title = format!(
        "hairlod view: {}",
        args.scene
            .as_ref()
            .map_or_else(|| "paper-curly".to_string(), |p| p.display().to_string())
    );
    let options = ViewOptions {
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        script,
        screenshot_dir: args.screenshot_dir.clone(),
        checkpoint_on_exit: args.checkpoint_on_exit.clone(),
        device,
        title,
        size: (shot.width, shot.height),
    };
    let session = Session::new(shot, pipeline)?;
    let summary = app::run(event_loop, session, options)?;
    let mean = summary.mean_times();
    eprintln!(
        "drew {} frame(s) on {}, {} stepped; {} frames per second (stepped frames after the \
         first)",
        summary.drawn,
        summary.adapter,
        summary.stepped.len(),
        summary
            .fps
            .map_or_else(|| "–".to_string(), |fps| format!("{fps:.1}"))
    );
    eprintln!(
        "  per stepped frame [ms]: lod {:.1}, dynamics {:.1}, collision {:.1}, render {:.1}",
        1e3 * mean.lod,
        1e3 * mean.dynamics,
        1e3 * mean.collision,
        1e3 * mean.rendering
    );
    Ok(())
}
