//! `hairlod view`: an interactive window on the running frame pipeline. The viewer is one more
//! front end of [`hairlod::pipeline::Pipeline`], like `render`: each drawn frame steps the
//! pipeline once (unless paused) and renders it with the same renderer, into a window instead of
//! a PNG file, with an egui heads-up display over it.
//!
//! - [`controls`]: the keys and mouse gestures and what they do;
//! - [`script`]: timed inputs from a file (tests, CI);
//! - [`orbit`]: the mouse camera;
//! - [`session`]: the pipeline and the controls' state, without a window;
//! - [`display`]: the window's surface and the composed image;
//! - [`hud`]: the heads-up display;
//! - [`app`]: the event loop.

pub mod app;
pub mod controls;
pub mod display;
pub mod hud;
pub mod orbit;
pub mod script;
pub mod session;
