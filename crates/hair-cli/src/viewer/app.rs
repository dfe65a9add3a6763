//! The window: a winit event loop around a [`Session`]. Each redraw applies the inputs (from the
//! window and a script), steps the pipeline once unless paused, renders the frame with the same
//! renderer as `hairlod render` into the [`Display`]'s composed image, draws the HUD over it,
//! writes the screenshots asked for and presents it.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use hairlod::pipeline::{FrameReport, PipelineRenderer, StageTimes};
use hairlod::render::wgpu;
use hairlod::render::{DeviceOptions, Renderer, output};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key as WinitKey, NamedKey};
use winit::window::{Window, WindowId};

use super::controls::{Action, DragButton, Input, Key, action_of};
use super::display::Display;
use super::hud;
use super::script::{Script, ScriptEvent};
use super::session::Session;

/// Pixels of a wheel's pixel delta that count as one notch.
const PIXELS_PER_NOTCH: f32 = 40.0;

/// What a viewer run does besides showing the scene.
pub struct ViewOptions {
    /// Stop after this many drawn frames (`None`: until closed).
    pub frames: Option<u64>,
    /// Write the last drawn frame here (with `frames`).
    pub screenshot: Option<PathBuf>,
    /// Timed inputs.
    pub script: Option<Script>,
    /// Folder of the screenshot key's PNGs.
    pub screenshot_dir: PathBuf,
    /// Write the pipeline's state here when the viewer closes.
    pub checkpoint_on_exit: Option<PathBuf>,
    /// Adapter choice and MSAA.
    pub device: DeviceOptions,
    /// The window's title.
    pub title: String,
    /// The window's size [pixels].
    pub size: (u32, u32),
}

/// What a viewer run did: every stepped frame's report and the frame rate.
pub struct ViewSummary {
    /// Frames drawn (stepped or not).
    pub drawn: u64,
    /// Reports of the stepped frames.
    pub stepped: Vec<FrameReport>,
    /// Frames per second over the stepped frames after the first (wall clock, from the end of
    /// the first to the end of the last); `None` with fewer than two.
    pub fps: Option<f64>,
    /// The adapter the window was drawn with.
    pub adapter: String,
}

impl ViewSummary {
    /// Mean time per stepped frame of each stage [s].
    pub fn mean_times(&self) -> StageTimes {
        let mut total = StageTimes::default();
        for report in &self.stepped {
            total.add(&report.times);
        }
        let n = self.stepped.len().max(1) as f64;
        StageTimes {
            lod: total.lod / n,
            dynamics: total.dynamics / n,
            collision: total.collision / n,
            rendering: total.rendering / n,
        }
    }
}

/// Opens the window on `event_loop` and runs `session` until the window closes, the frames are
/// done or the script quits.
pub fn run(
    event_loop: EventLoop<()>,
    session: Session,
    options: ViewOptions,
) -> Result<ViewSummary> {
    let mut descriptor = wgpu::InstanceDescriptor::new_with_display_handle(Box::new(
        event_loop.owned_display_handle(),
    ));
    descriptor.backends = options.device.backend.backends();
    let instance = wgpu::Instance::new(descriptor);
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        instance,
        options,
        session,
        window: None,
        display: None,
        renderer: None,
        egui: None,
        help: false,
        buttons: [false; 3],
        cursor: None,
        pending: Vec::new(),
        screenshots: Vec::new(),
        drawn: 0,
        stepped: Vec::new(),
        first_stepped: None,
        last_stepped: None,
        adapter: String::new(),
        error: None,
        finished: false,
    };
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    if let Some(error) = app.error {
        return Err(error);
    }
    let fps = match (app.first_stepped, app.last_stepped) {
        (Some(first), Some(last)) if app.stepped.len() > 1 && last > first => {
            Some((app.stepped.len() - 1) as f64 / last.duration_since(first).as_secs_f64())
        }
        _ => None,
    };
    Ok(ViewSummary {
        drawn: app.drawn,
        stepped: app.stepped,
        fps,
        adapter: app.adapter,
    })
}

struct App {
    instance: wgpu::Instance,
    options: ViewOptions,
    session: Session,
    window: Option<Arc<Window>>,
    display: Option<Display>,
    renderer: Option<PipelineRenderer>,
    egui: Option<egui_winit::State>,
    /// The key list shown in the HUD.
    help: bool,
    /// Left, right, middle held.
    buttons: [bool; 3],
    /// The last cursor position [pixels].
    cursor: Option<(f64, f64)>,
    /// Inputs from the window since the last frame.
    pending: Vec<Input>,
    /// Screenshots asked for this frame.
    screenshots: Vec<PathBuf>,
    drawn: u64,
    stepped: Vec<FrameReport>,
    first_stepped: Option<Instant>,
    last_stepped: Option<Instant>,
    adapter: String,
    error: Option<anyhow::Error>,
    finished: bool,
}

impl App {
    /// Creates the window, its device, the renderer and egui.
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let (width, height) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(self.options.title.clone())
            .with_inner_size(PhysicalSize::new(width, height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot open a window")?,
        );
        let display = Display::new(&self.instance, window.clone(), &self.options.device).map_err(
            |error| {
                anyhow!(
                    "{error:#}\nno adapter can draw into the window; `hairlod render SCENE --out \
                     DIR` renders the same frames to PNG files without one"
                )
            },
        )?;
        let renderer =
            Renderer::with_context(display.gpu.clone(), self.options.device.sample_count)?;
        self.adapter = renderer.adapter_report().to_string();
        eprintln!("adapter: {}", self.adapter);
        let mut renderer =
            PipelineRenderer::with_renderer(renderer, self.session.pipeline().scene())?;
        renderer.set_style(self.session.draw_style());
        let context = egui::Context::default();
        let egui = egui_winit::State::new(
            context,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(display.gpu.device.limits().max_texture_dimension_2d as usize),
        );
        self.window = Some(window);
        self.display = Some(display);
        self.renderer = Some(renderer);
        self.egui = Some(egui);
        Ok(())
    }

    /// Turns a window event into the viewer's inputs.
    fn input(&mut self, event: &WindowEvent) {
        match event {
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed && !event.repeat =>
            {
                let key = match &event.logical_key {
                    WinitKey::Named(NamedKey::Space) => Some(Key::Space),
                    WinitKey::Named(NamedKey::Escape) => Some(Key::Escape),
                    WinitKey::Named(NamedKey::Home) => Some(Key::Home),
                    WinitKey::Named(NamedKey::F12) => Some(Key::F12),
                    WinitKey::Character(text) => text
                        .chars()
                        .next()
                        .map(|c| Key::Char(c.to_ascii_lowercase())),
                    _ => None,
                };
                if let Some(key) = key {
                    self.pending.push(Input::Key(key));
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let index = match button {
                    MouseButton::Left => 0,
                    MouseButton::Right => 1,
                    MouseButton::Middle => 2,
                    _ => return,
                };
                self.buttons[index] = *state == ElementState::Pressed;
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let Some(last) = self.cursor {
                    let (dx, dy) = ((now.0 - last.0) as f32, (now.1 - last.1) as f32);
                    let button = [DragButton::Left, DragButton::Right, DragButton::Middle]
                        .into_iter()
                        .zip(self.buttons)
                        .find_map(|(button, held)| held.then_some(button));
                    if let Some(button) = button
                        && (dx != 0.0 || dy != 0.0)
                    {
                        self.pending.push(Input::Drag { button, dx, dy });
                    }
                }
                self.cursor = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / PIXELS_PER_NOTCH,
                };
                self.pending.push(Input::Scroll(notches));
            }
            _ => {}
        }
    }

    /// Applies one input's action.
    fn act(&mut self, input: Input) -> Result<()> {
        let Some(action) = action_of(input) else {
            return Ok(());
        };
        match action {
            Action::Screenshot => {
                let path = self.options.screenshot_dir.join(format!(
                    "hairlod_view_{:05}.png",
                    self.session.pipeline().frame()
                ));
                self.screenshots.push(path);
            }
            Action::ToggleHud => {
                // HUD, HUD with the keys, nothing.
                if self.session.hud_visible() && !self.help {
                    self.help = true;
                } else {
                    self.help = false;
                    self.session.apply(action, 0)?;
                }
            }
            _ => {
                let height = self.display.as_ref().map_or(1, |d| d.size().1);
                self.session.apply(action, height)?;
            }
        }
        Ok(())
    }

    /// One frame: inputs, a pipeline step unless paused, render, HUD, screenshots, present.
    fn frame(&mut self) -> Result<()> {
        let mut quit = false;
        if let Some(script) = &mut self.options.script {
            for event in script.take_due(self.drawn) {
                match event {
                    ScriptEvent::Input(input) => self.pending.push(input),
                    ScriptEvent::Screenshot(path) => self.screenshots.push(path),
                    ScriptEvent::Quit => quit = true,
                }
            }
        }
        for input in std::mem::take(&mut self.pending) {
            self.act(input)?;
        }
        let camera = self.session.camera();
        let stepped = if self.session.wants_step() {
            Some(self.session.advance(&camera)?)
        } else {
            None
        };
        let (Some(display), Some(renderer), Some(window), Some(egui)) = (
            self.display.as_mut(),
            self.renderer.as_mut(),
            self.window.as_ref(),
            self.egui.as_mut(),
        ) else {
            return Err(anyhow!("the window is not open"));
        };
        let started = Instant::now();
        let shading = self.session.shading();
        renderer.render_to_texture(
            self.session.pipeline_mut(),
            &camera,
            shading,
            display.composed(),
        )?;
        display.wait_for_gpu()?;
        let rendering = started.elapsed().as_secs_f64();
        if let Some(report) = stepped {
            self.session.frame_drawn(report, rendering)?;
            let mut report = report;
            report.times.rendering = rendering;
            self.stepped.push(report);
        }
        let input = egui.take_egui_input(window);
        let status = self.session.status();
        let (visible, help) = (self.session.hud_visible(), self.help);
        let output = egui.egui_ctx().run_ui(input, |ui| {
            if visible {
                hud::show(ui, &status, help);
            }
        });
        egui.handle_platform_output(window, output.platform_output);
        let jobs = egui
            .egui_ctx()
            .tessellate(output.shapes, output.pixels_per_point);
        display.draw_hud(&jobs, output.textures_delta, output.pixels_per_point);
        let last = self.options.frames.is_some_and(|n| self.drawn + 1 >= n);
        if last && let Some(path) = &self.options.screenshot {
            self.screenshots.push(path.clone());
        }
        for path in std::mem::take(&mut self.screenshots) {
            let image = display.read_composed()?;
            if let Some(folder) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
                std::fs::create_dir_all(folder)
                    .with_context(|| format!("cannot create {}", folder.display()))?;
            }
            output::write_png_atomic(&image, &path)?;
            eprintln!("wrote {}", path.display());
        }
        display.present()?;
        if stepped.is_some() {
            let now = Instant::now();
            self.first_stepped.get_or_insert(now);
            self.last_stepped = Some(now);
        }
        self.drawn += 1;
        if last || quit || self.session.quit_requested() {
            self.finished = true;
        }
        Ok(())
    }

    /// Writes the checkpoint asked for, once, as the viewer closes.
    fn close(&mut self) -> Result<()> {
        let Some(path) = self.options.checkpoint_on_exit.take() else {
            return Ok(());
        };
        let pipeline = self.session.pipeline();
        pipeline.checkpoint()?.write(&path)?;
        eprintln!(
            "wrote {} at frame {} (resume with `hairlod render SCENE --resume {} --frames {}..`)",
            path.display(),
            pipeline.frame(),
            path.display(),
            pipeline.frame()
        );
        if self.session.differs_from_scene() {
            eprintln!(
                "note: the wind, head motion or level mode was changed in the viewer, so the \
                 checkpoint belongs to the changed run: `--resume` refuses it with a scene and \
                 flags that do not make the same changes"
            );
        }
        Ok(())
    }

    /// Records `result`'s error (the first one) and stops the event loop on any error.
    fn check(&mut self, event_loop: &ActiveEventLoop, result: Result<()>) {
        if let Err(error) = result {
            if self.error.is_none() {
                self.error = Some(error);
            }
            self.exit(event_loop);
        }
    }

    /// Closes the viewer: the checkpoint, then the event loop.
    fn exit(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(error) = self.close()
            && self.error.is_none()
        {
            self.error = Some(error);
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            let result = self.open(event_loop);
            self.check(event_loop, result);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let (Some(egui), Some(window)) = (self.egui.as_mut(), self.window.as_ref()) {
            let _ = egui.on_window_event(window, &event);
        }
        match event {
            WindowEvent::CloseRequested => self.exit(event_loop),
            WindowEvent::Resized(size) => {
                if let Some(display) = self.display.as_mut() {
                    display.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested => {
                if self.finished {
                    return;
                }
                let result = self.frame();
                self.check(event_loop, result);
                if self.finished {
                    self.exit(event_loop);
                }
            }
            other => self.input(&other),
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(window) = &self.window
            && !self.finished
        {
            window.request_redraw();
        }
    }
}
