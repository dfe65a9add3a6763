//! `hairlod farm SCENE --out job.yaml`: an Open Job Description job template (specification
//! `jobtemplate-2023-09`, what AWS Deadline Cloud and `openjd run` take) that simulates a scene
//! in chained chunks into a cache and renders its frames from the cache in parallel chunks.
//!
//! OpenJD orders steps, not tasks, so the template has one step per simulation chunk,
//! `Simulate-k`, each depending on the one before (a chunk resumes from its predecessor's
//! checkpoint in the cache, so a lost chunk is rerun alone), and one render step per simulation
//! chunk, `Render-k`, depending on `Simulate-k` alone, whose tasks are the render chunks whose
//! last frame that simulation chunk makes (their earlier frames come from chunks before it).
//! Render tasks run in any order, on any number of workers. The chunk counts shape the steps,
//! so they are fixed when the template is written (job parameters pinned to their value, so a
//! scheduler shows them and refuses another); the paths and the executable are job parameters.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use hairlod::cache::Chunk;
use hairlod::scene_file::SceneFile;
use serde_json::{Value, json};

use crate::destinations::{writable_file, writable_folder};

/// Arguments of `hairlod farm`.
#[derive(Debug, Args)]
pub struct FarmArgs {
    /// Scene files (TOML): one job template each.
    #[arg(value_name = "SCENE.toml", required = true)]
    scenes: Vec<PathBuf>,
    /// The template's path (one scene), or a folder that gets SCENE.job.yaml for each scene.
    #[arg(long, value_name = "FILE|DIR")]
    out: PathBuf,
    /// Simulation chunks (each a step resuming from the one before).
    #[arg(long, default_value_t = 4, value_name = "N")]
    simulation_chunks: usize,
    /// Render chunks (tasks, run in any order once the frames they draw are simulated).
    #[arg(long, default_value_t = 6, value_name = "N")]
    render_chunks: usize,
    /// The cache folder the job parameter CacheDir defaults to [default: SCENE's folder,
    /// STEM.cache].
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
    /// The output folder the job parameter OutputDir defaults to [default: SCENE's folder,
    /// STEM.frames].
    #[arg(long, value_name = "DIR")]
    frames_out: Option<PathBuf>,
    /// The hairlod executable the job parameter Hairlod defaults to [default: this one].
    #[arg(long, value_name = "FILE")]
    hairlod: Option<PathBuf>,
}

/// Runs `hairlod farm`.
pub fn run(args: &FarmArgs) -> Result<()> {
    let several = args.scenes.len() > 1;
    if several {
        writable_folder(&args.out, "template folder")?;
        let mut stems: Vec<String> = args.scenes.iter().map(|s| stem(s)).collect();
        stems.sort();
        if let Some(pair) = stems.windows(2).find(|w| w[0] == w[1]) {
            bail!(
                "two scenes are named {}: their templates would share {}.job.yaml; rename one",
                pair[0],
                pair[0]
            );
        }
    } else {
        writable_file(&args.out, "job template")?;
    }
    let hairlod = match &args.hairlod {
        Some(path) => absolute(path)?,
        None => std::env::current_exe().context("cannot find this hairlod executable")?,
    };
    for scene in &args.scenes {
        let shot = SceneFile::read(scene)
            .map_err(anyhow::Error::from)
            .and_then(|file| Ok(file.resolve()?))
            .with_context(|| format!("the scene {}", scene.display()))?;
        let scene = absolute(scene)?;
        let folder = scene.parent().unwrap_or(Path::new(".")).to_path_buf();
        let path = if several {
            args.out.join(format!("{}.job.yaml", stem(&scene)))
        } else {
            args.out.clone()
        };
        // OpenJD takes a PATH parameter's default relative to the template's folder.
        let base = absolute(&path)?
            .parent()
            .map_or_else(|| PathBuf::from("/"), Path::to_path_buf);
        let cache = match (&args.cache, several) {
            (Some(cache), false) => absolute(cache)?,
            (Some(cache), true) => absolute(cache)?.join(stem(&scene)),
            (None, _) => folder.join(format!("{}.cache", stem(&scene))),
        };
        let frames = match (&args.frames_out, several) {
            (Some(out), false) => absolute(out)?,
            (Some(out), true) => absolute(out)?.join(stem(&scene)),
            (None, _) => folder.join(format!("{}.frames", stem(&scene))),
        };
        let paths = JobPaths {
            scene: relative_to(&scene, &base),
            cache: relative_to(&cache, &base),
            frames: relative_to(&frames, &base),
            hairlod: hairlod.clone(),
        };
        let template = job_template(
            &paths,
            shot.frames,
            args.simulation_chunks,
            args.render_chunks,
        )?;
        let text = yaml(&template);
        hairlod::core::atomic_file::write_file_atomically(&path, |file| {
            std::io::Write::write_all(file, text.as_bytes())
        })?;
        eprintln!(
            "wrote {} ({} frames: {} simulation chunks, {} render chunks); run it with `openjd \
             run {} --step Simulate-1` and so on, or submit it (docs/farm.md)",
            path.display(),
            shot.frames,
            args.simulation_chunks,
            args.render_chunks,
            path.display()
        );
    }
    Ok(())
}

/// The file name of `path` without its extension.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
}

fn absolute(path: &Path) -> Result<PathBuf> {
    std::path::absolute(path).with_context(|| format!("cannot make {} absolute", path.display()))
}

/// `path` relative to the folder `base` (both absolute): the components they share left out,
/// `..` for each of `base`'s that `path` does not share.
fn relative_to(path: &Path, base: &Path) -> PathBuf {
    let path: Vec<_> = path.components().collect();
    let base: Vec<_> = base.components().collect();
    let shared = path.iter().zip(&base).take_while(|(a, b)| a == b).count();
    let mut relative = PathBuf::new();
    for _ in shared..base.len() {
        relative.push("..");
    }
    for component in &path[shared..] {
        relative.push(component);
    }
    if relative.as_os_str().is_empty() {
        relative.push(".");
    }
    relative
}

/// The paths a job's parameters default to: the scene, cache and output folder relative to the
/// template's folder (OpenJD joins a PATH default to it), the executable as given.
struct JobPaths {
    scene: PathBuf,
    cache: PathBuf,
    frames: PathBuf,
    hairlod: PathBuf,
}

/// The job template of a scene of `frames` frames (see the module docs).
fn job_template(
    paths: &JobPaths,
    frames: usize,
    simulation_chunks: usize,
    render_chunks: usize,
) -> Result<Value> {
    for (count, what) in [(simulation_chunks, "simulation"), (render_chunks, "render")] {
        let first = Chunk::new(1, count).map_err(|why| anyhow::anyhow!("{what} chunks: {why}"))?;
        first
            .frames(frames)
            .map_err(|why| anyhow::anyhow!("{what} chunks: {why}"))?;
    }
    let path_parameter = |name: &str, path: &Path, object: &str, flow: &str, about: &str| {
        json!({
            "name": name,
            "type": "PATH",
            "objectType": object,
            "dataFlow": flow,
            "default": path.display().to_string(),
            "description": about,
        })
    };
    let count_parameter = |name: &str, count: usize, about: &str| {
        json!({
            "name": name,
            "type": "INT",
            "default": count,
            "minValue": count,
            "maxValue": count,
            "description": format!("{about} Fixed when the template was written (the steps follow it): write another with hairlod farm to change it."),
        })
    };
    let mut steps = Vec::new();
    for k in 1..=simulation_chunks {
        let chunk = Chunk::new(k, simulation_chunks).map_err(anyhow::Error::msg)?;
        let range = chunk.frames(frames).map_err(anyhow::Error::msg)?;
        let mut step = json!({
            "name": format!("Simulate-{k}"),
            "description": format!("Simulate frames {}..{} into the cache{}.", range.start, range.end,
                if k > 1 { format!(", resuming from Simulate-{}'s checkpoint", k - 1) } else { String::new() }),
            "script": script(json!([
                "simulate", "{{Param.SceneFile}}", "--cache", "{{Param.CacheDir}}",
                "--chunk", format!("{k}/{{{{Param.SimulationChunks}}}}"),
            ])),
        });
        if k > 1 {
            step["dependencies"] = json!([{ "dependsOn": format!("Simulate-{}", k - 1) }]);
        }
        steps.push(step);
    }
    for k in 1..=simulation_chunks {
        // The render chunks whose last frame this simulation chunk makes.
        let tasks: Vec<usize> = (1..=render_chunks)
            .filter(|&j| {
                let range = Chunk {
                    index: j,
                    count: render_chunks,
                }
                .frames(frames)
                .unwrap_or(0..1);
                Chunk::holding(range.end - 1, simulation_chunks, frames).index == k
            })
            .collect();
        if tasks.is_empty() {
            continue;
        }
        steps.push(json!({
            "name": format!("Render-{k}"),
            "description": format!("Render chunks {tasks:?} of {render_chunks} from the cache (their frames are simulated once Simulate-{k} is done)."),
            "dependencies": [{ "dependsOn": format!("Simulate-{k}") }],
            "parameterSpace": {
                "taskParameterDefinitions": [{ "name": "Chunk", "type": "INT", "range": tasks }],
            },
            "script": script(json!([
                "render", "{{Param.SceneFile}}", "--from-cache", "{{Param.CacheDir}}",
                "--out", "{{Param.OutputDir}}",
                "--chunk", "{{Task.Param.Chunk}}/{{Param.RenderChunks}}",
            ])),
        }));
    }
    Ok(json!({
        "specificationVersion": "jobtemplate-2023-09",
        "name": format!("hairlod {}", stem(&paths.scene)),
        "description": format!("Simulate {} ({frames} frames) in {simulation_chunks} chained chunks, render it in {render_chunks} chunks from the cache. Written by hairlod farm {}.", paths.scene.display(), env!("CARGO_PKG_VERSION")),
        "parameterDefinitions": [
            path_parameter("SceneFile", &paths.scene, "FILE", "IN", "The scene file (TOML); a relative path is the template folder's."),
            path_parameter("CacheDir", &paths.cache, "DIRECTORY", "OUT", "The simulation cache: a record per frame and the chunks' checkpoints."),
            path_parameter("OutputDir", &paths.frames, "DIRECTORY", "OUT", "Where the frames (PNG) go."),
            json!({
                "name": "Hairlod",
                "type": "STRING",
                "default": paths.hairlod.display().to_string(),
                "description": "The hairlod executable on the workers (a path, or a name on their PATH).",
            }),
            count_parameter("SimulationChunks", simulation_chunks, "Simulation chunks."),
            count_parameter("RenderChunks", render_chunks, "Render chunks."),
        ],
        "steps": steps,
    }))
}

/// A step script that runs hairlod with `args`.
fn script(args: Value) -> Value {
    json!({ "actions": { "onRun": { "command": "{{Param.Hairlod}}", "args": args } } })
}

/// `value` as block-style YAML, every string double-quoted the JSON way (a subset of YAML's
/// double-quoted scalars), keys in their order.
fn yaml(value: &Value) -> String {
    let mut out = String::new();
    write_yaml(value, 0, &mut out);
    out
}

fn scalar(value: &Value) -> String {
    match value {
        Value::Array(items) if items.is_empty() => "[]".into(),
        Value::Object(map) if map.is_empty() => "{}".into(),
        other => other.to_string(),
    }
}

fn is_block(value: &Value) -> bool {
    match value {
        Value::Array(items) => !items.is_empty(),
        Value::Object(map) => !map.is_empty(),
        _ => false,
    }
}

fn write_yaml(value: &Value, indent: usize, out: &mut String) {
    let pad = " ".repeat(indent);
    match value {
        Value::Object(map) => {
            for (key, item) in map {
                if is_block(item) {
                    out.push_str(&format!("{pad}{key}:\n"));
                    let child = if item.is_array() { indent } else { indent + 2 };
                    write_yaml(item, child, out);
                } else {
                    out.push_str(&format!("{pad}{key}: {}\n", scalar(item)));
                }
            }
        }
        Value::Array(items) => {
            for item in items {
                if is_block(item) {
                    let mut inner = String::new();
                    write_yaml(item, indent + 2, &mut inner);
                    // The item's first line goes on the dash.
                    out.push_str(&format!("{pad}- {}", &inner[indent + 2..]));
                } else {
                    out.push_str(&format!("{pad}- {}\n", scalar(item)));
                }
            }
        }
        other => out.push_str(&format!("{pad}{}\n", scalar(other))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths() -> JobPaths {
        JobPaths {
            scene: "/shots/a b.toml".into(),
            cache: "/shots/a b.cache".into(),
            frames: "/shots/a b.frames".into(),
            hairlod: "/bin/hairlod".into(),
        }
    }

    fn step<'a>(template: &'a Value, name: &str) -> &'a Value {
        template["steps"]
            .as_array()
            .unwrap()
            .iter()
            .find(|s| s["name"] == name)
            .unwrap_or_else(|| panic!("no step {name}"))
    }

    #[test]
    fn render_chunks_wait_only_for_the_simulation_chunk_that_ends_their_frames() {
        // 60 frames: simulation chunks end at 15, 30, 45, 60; render chunks at 10, 20, …, 60.
        let template = job_template(&paths(), 60, 4, 6).unwrap();
        let tasks = |k: usize| {
            step(&template, &format!("Render-{k}"))["parameterSpace"]["taskParameterDefinitions"][0]
                ["range"]
                .clone()
        };
        assert_eq!(tasks(1), json!([1]));
        assert_eq!(tasks(2), json!([2, 3]));
        assert_eq!(tasks(3), json!([4]));
        assert_eq!(tasks(4), json!([5, 6]));
        assert_eq!(
            step(&template, "Render-2")["dependencies"],
            json!([{ "dependsOn": "Simulate-2" }])
        );
        assert_eq!(
            step(&template, "Simulate-3")["dependencies"],
            json!([{ "dependsOn": "Simulate-2" }])
        );
        assert!(step(&template, "Simulate-1").get("dependencies").is_none());
        assert!(template["steps"].as_array().unwrap().len() == 8);
        // More chunks than frames is refused, naming the chunks.
        let error = job_template(&paths(), 5, 4, 6).unwrap_err().to_string();
        assert!(
            error.contains("render chunks") && error.contains("6 chunks"),
            "{error}"
        );
    }

    #[test]
    fn defaults_are_relative_to_the_template_folder() {
        let base = Path::new("/shots/jobs");
        assert_eq!(
            relative_to(Path::new("/shots/jobs/a.toml"), base),
            PathBuf::from("a.toml")
        );
        assert_eq!(
            relative_to(Path::new("/shots/a.cache"), base),
            PathBuf::from("../a.cache")
        );
        assert_eq!(
            relative_to(Path::new("/data/x/a.toml"), base),
            PathBuf::from("../../data/x/a.toml")
        );
        assert_eq!(relative_to(base, base), PathBuf::from("."));
    }

    #[test]
    fn the_yaml_reads_back_as_the_template() {
        let template = job_template(&paths(), 60, 4, 6).unwrap();
        let text = yaml(&template);
        assert!(text.contains("specificationVersion: \"jobtemplate-2023-09\"\n"));
        // Block YAML whose scalars are JSON: turned back into JSON line by line it must give
        // the template again (a check of the indentation and the dashes).
        let back = yaml_to_json(&text);
        assert_eq!(back, template);
    }

    /// A reader of exactly the YAML [`yaml`] writes (for the test).
    fn yaml_to_json(text: &str) -> Value {
        let lines: Vec<(usize, &str)> = text
            .lines()
            .map(|l| (l.len() - l.trim_start().len(), l.trim_start()))
            .collect();
        let mut at = 0;
        parse_block(&lines, &mut at, 0)
    }

    fn parse_block(lines: &[(usize, &str)], at: &mut usize, indent: usize) -> Value {
        if lines[*at].1.starts_with("- ") {
            let mut items = Vec::new();
            while *at < lines.len() && lines[*at].0 == indent && lines[*at].1.starts_with("- ") {
                let rest = &lines[*at].1[2..];
                if rest.contains(": ") || rest.ends_with(':') {
                    // An object item: its first key on the dash line.
                    let mut item_lines = vec![(indent + 2, rest)];
                    let mut end = *at + 1;
                    while end < lines.len() && lines[end].0 > indent {
                        item_lines.push(lines[end]);
                        end += 1;
                    }
                    let mut inner = 0;
                    items.push(parse_block(&item_lines, &mut inner, indent + 2));
                    *at = end;
                } else {
                    items.push(serde_json::from_str(rest).unwrap());
                    *at += 1;
                }
            }
            return Value::Array(items);
        }
        let mut map = serde_json::Map::new();
        while *at < lines.len() && lines[*at].0 == indent && !lines[*at].1.starts_with("- ") {
            let line = lines[*at].1;
            *at += 1;
            if let Some(key) = line.strip_suffix(':') {
                let child = lines[*at].0;
                map.insert(key.into(), parse_block(lines, at, child));
            } else {
                let (key, value) = line.split_once(": ").unwrap();
                map.insert(key.into(), serde_json::from_str(value).unwrap());
            }
        }
        Value::Object(map)
    }
}
