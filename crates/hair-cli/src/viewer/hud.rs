//! The heads-up display, drawn with egui over the frame: per-stage milliseconds (LOD, dynamics,
//! collision, render), sections at each level, simulated nodes and drawn segments, frames per
//! second, the controls' state and the keys.

use egui::{Align2, Color32, Frame, RichText, Ui};

use super::controls::KEY_HELP;
use super::session::Status;

/// Draws the HUD (and, with `help`, the list of keys) in the top-left corner.
pub fn show(ui: &mut Ui, status: &Status, help: bool) {
    let ctx = ui.ctx().clone();
    egui::Area::new(egui::Id::unique("hairlod-hud"))
        .anchor(Align2::LEFT_TOP, [8.0, 8.0])
        .fade_in(false)
        .interactable(false)
        .show(&ctx, |ui| {
            Frame::new()
                .fill(Color32::from_black_alpha(170))
                .inner_margin(6.0)
                .corner_radius(4.0)
                .show(ui, |ui| body(ui, status, help));
        });
}

/// One line of the HUD, never wrapped.
fn line(ui: &mut Ui, text: String) {
    let text = RichText::new(text)
        .monospace()
        .size(11.0)
        .color(Color32::from_gray(235));
    ui.add(egui::Label::new(text).extend().selectable(false));
}

fn body(ui: &mut Ui, status: &Status, help: bool) {
    ui.spacing_mut().item_spacing.y = 1.0;
    let fps = status
        .fps
        .map_or_else(|| "–".to_string(), |fps| format!("{fps:.1}"));
    let state = if status.paused { "paused" } else { "playing" };
    match &status.report {
        Some(report) => {
            let times = &report.times;
            line(
                ui,
                format!(
                    "frame {} ({:.2} s)  {fps} fps  {state}",
                    report.frame, report.time
                ),
            );
            line(
                ui,
                format!(
                    "lod {:.1} dyn {:.1} coll {:.1} render {:.1} ms",
                    1e3 * times.lod,
                    1e3 * times.dynamics,
                    1e3 * times.collision,
                    1e3 * times.rendering
                ),
            );
            let [patches, clusters, strands] = report.sections_at;
            line(
                ui,
                format!("sections  strands {strands}  clusters {clusters}  patches {patches}"),
            );
            line(
                ui,
                format!(
                    "nodes {}  segments {}  visible {}  blending {}",
                    report.simulated_nodes,
                    report.drawn_segments,
                    report.visible_sections,
                    report.blending_sections
                ),
            );
        }
        None => line(ui, format!("no frame yet  {state}")),
    }
    let budget = status
        .budget
        .map_or_else(|| "off".to_string(), |b| format!("{:.0} ms", 1e3 * b));
    line(
        ui,
        format!(
            "level {}  tol {:.2} px  budget {budget}",
            status.level.name(),
            status.tolerance
        ),
    );
    line(
        ui,
        format!(
            "wind {}  motion {}",
            if status.wind_on { "on" } else { "off" },
            status.motion
        ),
    );
    line(
        ui,
        format!(
            "{}  {}",
            if status.color_coded {
                "level colours"
            } else {
                "shaded"
            },
            if status.following_path {
                "scene camera"
            } else {
                "free camera"
            }
        ),
    );
    if help {
        ui.add_space(4.0);
        for (keys, what) in KEY_HELP {
            line(ui, format!("{keys:<18} {what}"));
        }
    } else {
        line(ui, "h: keys".to_string());
    }
}
