//! Fits the paper's hierarchy to the TressFX samples (the Ratboy mohawk in metres, the ponytail
//! parts in centimetres) and prints counts, errors per level and fit times, for the default
//! settings and for the alternatives the defaults were chosen against.
//!
//! `cargo run --release -p hair-formats --example fit_tressfx [TRESSFX_DIR]` (default: the samples'
//! `tressfx/` folder, `hair_core::samples`: `HAIRLOD_DATA`, or `../shared/data` beside the
//! workspace). A missing or unreadable file is an error naming it, and the example exits 1.

use std::path::PathBuf;
use std::time::Instant;

use hair_core::Level;
use hair_core::fit::{FitSettings, GroupSplit, Representative, SectionCount, fit_hierarchy};
use hair_formats::{Curves, ImportAxes, ImportOptions, read_curves_file};

fn read(
    dir: &std::path::Path,
    name: &str,
    scale_to_metres: f32,
) -> Result<Curves, hair_formats::FormatError> {
    let options = ImportOptions::with_axes(ImportAxes {
        scale_to_metres,
        ..ImportAxes::default()
    });
    read_curves_file(dir.join(name), &options)
}

/// The best of `runs` fits: (seconds, report line of drawn mean errors per level).
fn time_fit(curves: &Curves, settings: &FitSettings, runs: usize) -> (f64, String) {
    let mut best = f64::INFINITY;
    let mut line = String::new();
    for _ in 0..runs {
        let start = Instant::now();
        let fit = fit_hierarchy(curves, settings).expect("fit");
        best = best.min(start.elapsed().as_secs_f64());
        let e = &fit.report.errors;
        line = format!(
            "drawn mean/p95 [mm]: patch {:.2}/{:.2}  cluster {:.2}/{:.2}  group {:.2}/{:.2}; per-node group {:.2}; nodes {}..={}",
            e[Level::Patch].drawn.mean * 1e3,
            e[Level::Patch].drawn.p95 * 1e3,
            e[Level::Cluster].drawn.mean * 1e3,
            e[Level::Cluster].drawn.p95 * 1e3,
            e[Level::StrandGroup].drawn.mean * 1e3,
            e[Level::StrandGroup].drawn.p95 * 1e3,
            e[Level::StrandGroup].per_node_offsets.mean * 1e3,
            fit.report.min_nodes,
            fit.report.max_nodes,
        );
    }
    (best, line)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = match std::env::args_os().nth(1) {
        Some(dir) => PathBuf::from(dir),
        None => hair_core::samples::tressfx_dir()?,
    };
    let files = [
        ("ratboy_mohawk.tfx", 1.0),
        ("ponytail_back.tfx", 0.01),
        ("ponytail_front_top.tfx", 0.01),
        ("ponytail_side.tfx", 0.01),
        ("ponytail_tail.tfx", 0.01),
    ];
    for (name, scale) in files {
        let curves = read(&dir, name, scale)?;
        let lengths: Vec<f32> = curves.iter().map(hair_core::fit::curve_length).collect();
        let (lo, hi) = lengths
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &l| (lo.min(l), hi.max(l)));
        let mean = lengths.iter().sum::<f32>() / lengths.len() as f32;
        println!(
            "\n{name}: {} strands, length {:.1}..{:.1} mm (mean {:.1})",
            curves.curve_count(),
            lo * 1e3,
            hi * 1e3,
            mean * 1e3
        );
        let settings = FitSettings::default();
        let fit = fit_hierarchy(&curves, &settings).expect("fit");
        println!("{}", fit.report);
        let (seconds, line) = time_fit(&curves, &settings, 5);
        println!("default: {:.1} ms  {line}", seconds * 1e3);
        let mut alternatives: Vec<(String, FitSettings)> = Vec::new();
        for representative in [Representative::Mean, Representative::Medoid] {
            alternatives.push((
                format!("{representative:?}"),
                FitSettings {
                    representative,
                    ..settings.clone()
                },
            ));
        }
        alternatives.push((
            "slab groups".to_owned(),
            FitSettings {
                group_split: GroupSplit::Slabs,
                ..settings.clone()
            },
        ));
        for shape_weight in [0.0, 1.0, 2.0, 4.0] {
            alternatives.push((
                format!("shape weight {shape_weight}"),
                FitSettings {
                    shape_weight,
                    ..settings.clone()
                },
            ));
        }
        for slack in [0.0, 1.0] {
            alternatives.push((
                format!("slack {slack}"),
                FitSettings {
                    section_size_slack: slack,
                    ..settings.clone()
                },
            ));
        }
        for per in [25, 100] {
            alternatives.push((
                format!("{per} strands per section"),
                FitSettings {
                    sections: SectionCount::StrandsPerSection(per),
                    ..settings.clone()
                },
            ));
        }
        for (label, alternative) in alternatives {
            let (seconds, line) = time_fit(&curves, &alternative, 1);
            println!("{label:>24}: {:.1} ms  {line}", seconds * 1e3);
        }
    }
    Ok(())
}
