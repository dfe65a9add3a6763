//! Charts the CLI draws with plotters, each written as PNG and SVG: the speed-against-accuracy
//! scatter with its Pareto fronts (`hairlod accuracy --chart`) and the model size over the
//! zoom-out (`hairlod bench paper --chart`). The stability heat map lives with its command.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{Context, Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

/// The font the charts are drawn with.
const FONT_PATH: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Registers DejaVu Sans as "sans-serif" for plotters (once per process).
pub fn register_chart_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            let bytes = std::fs::read(FONT_PATH).map_err(|_| {
                format!(
                    "the chart needs the font {FONT_PATH} (Debian/Ubuntu package \
                     fonts-dejavu-core); install it or leave out --chart"
                )
            })?;
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            register_font("sans-serif", FontStyle::Normal, bytes)
                .map_err(|_| format!("{FONT_PATH} is not a usable font"))
        })
        .clone()
        .map_err(|message| anyhow!(message))
}

/// A scratch file beside `path` for a plotters backend that writes a file itself:
/// `.<name>.<process id>.<ext>` in the same folder (two runs into one folder never share it).
pub fn scratch_beside(path: &Path, ext: &str) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "chart".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}.{ext}", std::process::id()))
}

/// Draws a PNG through `draw` into a scratch file beside `path` ([`scratch_beside`]), then
/// re-encodes it with the best compression (plotters writes a fast, large one) into `path`
/// through the one atomic writer. The scratch file is removed whether drawing succeeds or not.
pub fn write_png_through(path: &Path, draw: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let scratch = scratch_beside(path, "png");
    let result = draw(&scratch).and_then(|()| {
        let picture = image::open(&scratch)
            .with_context(|| format!("reading back {}", scratch.display()))?
            .into_rgb8();
        let mut bytes = Vec::new();
        PngEncoder::new_with_quality(&mut bytes, CompressionType::Best, FilterType::Adaptive)
            .write_image(
                picture.as_raw(),
                picture.width(),
                picture.height(),
                image::ExtendedColorType::Rgb8,
            )
            .with_context(|| format!("encoding {}", path.display()))?;
        write_atomically(path, &bytes)
    });
    let _ = std::fs::remove_file(&scratch);
    result
}

/// Writes `bytes` to `path` through the one atomic writer
/// ([`hairlod::core::atomic_file::write_file_atomically`]: a temporary file with the process id, synced,
/// renamed, removed on error). Its error names the path.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    hairlod::core::atomic_file::write_file_atomically(path, |file| file.write_all(bytes))?;
    Ok(())
}

/// Turns a plotters error (generic over the backend) into an `anyhow` one.
fn plot_error(error: impl std::fmt::Display) -> anyhow::Error {
    anyhow!("drawing the chart: {error}")
}

/// A chart that can draw itself on any plotters backend.
pub trait Chart {
    /// Draws the chart on `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// Draws `chart` into `path` with the extension `png` and into the same path with the extension
/// `svg`; both go through the one atomic writer, so a stopped run leaves no half-written chart. Returns the two paths.
pub fn write_png_and_svg(
    path: &Path,
    size: (u32, u32),
    chart: &impl Chart,
) -> Result<(PathBuf, PathBuf)> {
    register_chart_font()?;
    let png = path.with_extension("png");
    let svg = path.with_extension("svg");
    write_png_through(&png, |scratch| {
        let root = BitMapBackend::new(scratch, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        chart.draw(&root)?;
        root.present()
            .with_context(|| format!("drawing {}", png.display()))
    })?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        chart.draw(&root)?;
        root.present()
            .with_context(|| format!("drawing {}", svg.display()))?;
    }
    write_atomically(&svg, text.as_bytes())?;
    Ok((png, svg))
}

/// One point of the speed-against-accuracy scatter.
#[derive(Debug, Clone)]
pub struct ScatterPoint {
    /// Label drawn beside the point.
    pub label: String,
    /// Median cost per frame [ms].
    pub cost_ms: f64,
    /// Errors, one per panel (SSIM loss, mean pixel error).
    pub errors: [f64; 2],
    /// On the Pareto front of each panel's error against cost.
    pub pareto: [bool; 2],
    /// Colour group, an index into [`ParetoChart::group_colours`] (`hairlod accuracy`: 0 fixed
    /// levels, 1 LODs, 2 integrators and steps, 3 budgets).
    pub group: usize,
}

/// Colours of the point groups of `hairlod accuracy`: fixed levels, LODs, integrators, budgets.
pub const GROUP_COLOURS: [RGBColor; 4] = [
    RGBColor(33, 102, 172),
    RGBColor(214, 96, 77),
    RGBColor(77, 146, 33),
    RGBColor(118, 42, 131),
];

/// Two panels side by side, SSIM loss and mean pixel error against the median cost per frame (both
/// axes log scale), each with its Pareto front as a step line through the front's points.
pub struct ParetoChart<'a> {
    /// Title over both panels.
    pub title: String,
    /// The y-axis description of each panel.
    pub panel_names: [&'a str; 2],
    /// Colour of each point group, in group order (the last one serves larger groups).
    pub group_colours: &'a [RGBColor],
    /// The points.
    pub points: &'a [ScatterPoint],
}

/// The panels of the speed-against-accuracy chart of `hairlod accuracy`.
pub const ACCURACY_PANELS: [&str; 2] = [
    "SSIM loss (1 − mean SSIM vs reference, log scale)",
    "mean pixel error vs reference [px] (log scale)",
];

impl Chart for ParetoChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_pareto(root, self)
    }
}

fn draw_pareto<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &ParetoChart<'_>,
) -> Result<()> {
    let ParetoChart {
        title,
        panel_names: names,
        group_colours,
        points,
    } = chart;
    let (header, body) = root.split_vertically(40);
    header
        .draw(&Text::new(
            title.to_string(),
            (12, 10),
            ("sans-serif", 18).into_font(),
        ))
        .map_err(plot_error)?;
    let panels = body.split_evenly((1, 2));
    let min_cost = points
        .iter()
        .map(|p| p.cost_ms)
        .fold(f64::INFINITY, f64::min);
    let max_cost = points.iter().map(|p| p.cost_ms).fold(0.0, f64::max);
    let (low, high) = (min_cost.max(1e-3) / 1.5, max_cost.max(1e-3) * 1.5);
    for (panel, area) in panels.iter().enumerate() {
        // Errors span two decades or more (a failing integrator against a fine level): log scale,
        // with errors of zero drawn at the floor.
        let max_error = points
            .iter()
            .map(|p| p.errors[panel])
            .fold(0.0, f64::max)
            .max(1e-6);
        let min_error = points
            .iter()
            .map(|p| p.errors[panel])
            .filter(|&e| e > 0.0)
            .fold(max_error, f64::min);
        let (bottom, top) = (min_error / 1.5, max_error * 1.5);
        let floor = |e: f64| e.max(bottom);
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(
                (low..high)
                    .log_scale()
                    .with_key_points(log_key_points(low, high)),
                (bottom..top)
                    .log_scale()
                    .with_key_points(log_key_points(bottom, top)),
            )
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_label_formatter(&|v| format!("{v}"))
            .x_desc("median cost per frame [ms] (log scale)")
            .y_desc(names[panel])
            .y_label_formatter(&|v| format!("{v}"))
            .label_style(("sans-serif", 12))
            .axis_desc_style(("sans-serif", 13))
            .draw()
            .map_err(plot_error)?;
        let mut front: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.pareto[panel])
            .map(|p| (p.cost_ms, floor(p.errors[panel])))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut steps = Vec::new();
        for (i, &(cost, error)) in front.iter().enumerate() {
            if i > 0 {
                steps.push((cost, front[i - 1].1));
            }
            steps.push((cost, error));
        }
        chart
            .draw_series(LineSeries::new(steps, BLACK.stroke_width(1)))
            .map_err(plot_error)?;
        for point in points.iter() {
            let colour = group_colours
                .get(point.group)
                .or(group_colours.last())
                .copied()
                .unwrap_or(BLACK);
            let at = (point.cost_ms, floor(point.errors[panel]));
            let marker: EmptyElement<(f64, f64), DB> = EmptyElement::at(at);
            let size = if point.pareto[panel] { 6 } else { 4 };
            let element = marker
                + Circle::new((0, 0), size, colour.filled())
                + Text::new(
                    point.label.clone(),
                    (7, -12),
                    ("sans-serif", 11).into_font().color(&colour),
                );
            chart
                .draw_series(std::iter::once(element))
                .map_err(plot_error)?;
        }
    }
    Ok(())
}

/// Axis labels 1, 2, 5 × 10ⁿ between `low` and `high` (positive).
fn log_key_points(low: f64, high: f64) -> Vec<f64> {
    let mut points = Vec::new();
    let mut decade = 10f64.powf(low.log10().floor());
    while decade <= high {
        for m in [1.0, 2.0, 5.0] {
            let v = m * decade;
            if (low..=high).contains(&v) {
                points.push(v);
            }
        }
        decade *= 10.0;
    }
    points
}

/// The model a run keeps per frame, for [`ModelSizeChart`].
#[derive(Debug, Clone)]
pub struct ModelSeries {
    /// `LODs`, `Strands`...
    pub label: String,
    /// Simulated skeleton nodes per frame.
    pub nodes: Vec<f64>,
    /// Drawn segments per frame.
    pub segments: Vec<f64>,
}

/// Simulated nodes and drawn segments per frame (log scale, left) for each run, and the camera
/// distance (right axis) over the frames.
pub struct ModelSizeChart<'a> {
    /// Title.
    pub title: String,
    /// Camera distance per frame [m].
    pub distances: &'a [f64],
    /// One series per run.
    pub series: &'a [ModelSeries],
}

impl Chart for ModelSizeChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        draw_model_size(root, &self.title, self.distances, self.series)
    }
}

fn draw_model_size<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    distances: &[f64],
    series: &[ModelSeries],
) -> Result<()> {
    let frames = distances.len().max(2);
    let all = series
        .iter()
        .flat_map(|s| s.nodes.iter().chain(&s.segments))
        .copied()
        .filter(|&v| v > 0.0);
    let (low, high) = all.fold((f64::INFINITY, 0.0f64), |(l, h), v| (l.min(v), h.max(v)));
    // Room above the highest line for the legend.
    let (low, high) = if low.is_finite() {
        (low / 2.0, high * 20.0)
    } else {
        (1.0, 10.0)
    };
    let far = distances.iter().copied().fold(0.0, f64::max).max(1e-3);
    let near = distances
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
        .min(far);
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 18))
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .right_y_label_area_size(60)
        .build_cartesian_2d(
            0..frames - 1,
            (low..high)
                .log_scale()
                .with_key_points(log_key_points(low, high)),
        )
        .map_err(plot_error)?
        .set_secondary_coord(0..frames - 1, (near / 1.2..far * 1.2).log_scale());
    chart
        .configure_mesh()
        .x_desc("frame")
        .y_desc("simulated nodes, drawn segments (log scale)")
        .y_label_formatter(&|v| format!("{v}"))
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .draw()
        .map_err(plot_error)?;
    chart
        .configure_secondary_axes()
        .y_desc("camera distance [m] (dashed)")
        .label_style(("sans-serif", 12))
        .axis_desc_style(("sans-serif", 13))
        .draw()
        .map_err(plot_error)?;
    let palette = [
        RGBColor(214, 96, 77),
        RGBColor(33, 102, 172),
        RGBColor(77, 146, 33),
    ];
    for (i, s) in series.iter().enumerate() {
        let colour = palette[i % palette.len()];
        for (values, what, width) in [
            (&s.nodes, "simulated nodes", 1),
            (&s.segments, "drawn segments", 3),
        ] {
            let line = values
                .iter()
                .enumerate()
                .filter(|(_, v)| **v > 0.0)
                .map(|(f, &v)| (f, v));
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(width)))
                .map_err(plot_error)?
                .label(format!("{}: {what}", s.label))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(width))
                });
        }
    }
    let dashes = distances
        .iter()
        .enumerate()
        .map(|(f, &d)| (f, d))
        .collect::<Vec<_>>();
    chart
        .draw_secondary_series(DashedLineSeries::new(dashes, 6, 4, BLACK.stroke_width(1)))
        .map_err(plot_error)?
        .label("camera distance")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(plot_error)?;
    Ok(())
}
