//! Where the TressFX sample grooms live: AMD's TressFX samples (MIT) that the data tests, the
//! `ratboy` collision bench, the `fit_tressfx` example and the `scenes/tressfx-*.toml` scenes
//! read. They are not part of this repository.
//!
//! The samples' folder (the one holding `tressfx/ratboy_mohawk.tfx`) is the folder named by the
//! environment variable [`DATA_VAR`] (`HAIRLOD_DATA`), or, where it is unset, `../shared/data`
//! beside the workspace (the folder the example scenes point to). The files come from AMD's
//! TressFX repositories (GPUOpen), MIT-licensed: the Ratboy mohawk and body in TressFX 4.x
//! format, the ponytail parts and `testhair1.tfx` in 3.x; see the README's "The TressFX samples".
//!
//! Tests that read them are `#[ignore]`d with the reason, so that a clone of the repository alone
//! passes `cargo test --workspace`; `.ci/run` runs them with `-- --ignored`, and each one fails
//! naming the file it looked for when the data is missing (never passing without it).

use std::fmt;
use std::path::{Path, PathBuf};

/// The environment variable that names the samples' folder (the one holding `tressfx/`).
pub const DATA_VAR: &str = "HAIRLOD_DATA";

/// The files of the TressFX samples' `tressfx/` folder, as the data tests use them.
pub const TRESSFX_FILES: [&str; 7] = [
    "ratboy_mohawk.tfx",
    "ratboy_body.tfxmesh",
    "ponytail_back.tfx",
    "ponytail_front_top.tfx",
    "ponytail_side.tfx",
    "ponytail_tail.tfx",
    "testhair1.tfx",
];

/// A sample file that is not where it was looked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MissingSample {
    /// The path looked for.
    pub path: PathBuf,
    /// Whether the folder came from [`DATA_VAR`] (otherwise the default beside the workspace).
    pub from_variable: bool,
}

impl fmt::Display for MissingSample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let source = if self.from_variable {
            format!("the folder {DATA_VAR} names")
        } else {
            format!("the default folder ../shared/data beside the workspace; {DATA_VAR} unset")
        };
        write!(
            f,
            "the TressFX sample {} is missing (looked in {source}); the samples are AMD's TressFX \
             files (MIT): put them in <folder>/tressfx/ and set {DATA_VAR}=<folder>, or place \
             them in ../shared/data/tressfx beside the repository",
            self.path.display()
        )
    }
}

impl std::error::Error for MissingSample {}

/// The samples' folder: [`DATA_VAR`] where it is set and not empty, otherwise `../shared/data`
/// beside the workspace (this crate's sources are in `crates/hair-core` of it).
pub fn data_dir() -> PathBuf {
    data_dir_from(std::env::var_os(DATA_VAR).map(PathBuf::from)).0
}

/// The folder from the variable's value, and whether it came from the variable.
fn data_dir_from(variable: Option<PathBuf>) -> (PathBuf, bool) {
    match variable {
        Some(dir) if !dir.as_os_str().is_empty() => (dir, true),
        _ => (
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
            false,
        ),
    }
}

/// The path of `tressfx/<name>` in the samples' folder, or an error naming the path looked for
/// and where the samples come from when it is not a file.
pub fn tressfx_file(name: &str) -> Result<PathBuf, MissingSample> {
    let (dir, from_variable) = data_dir_from(std::env::var_os(DATA_VAR).map(PathBuf::from));
    let path = dir.join("tressfx").join(name);
    if path.is_file() {
        Ok(path)
    } else {
        Err(MissingSample {
            path,
            from_variable,
        })
    }
}

/// The `tressfx/` folder of the samples, or an error naming the first of [`TRESSFX_FILES`] that
/// is missing from it.
pub fn tressfx_dir() -> Result<PathBuf, MissingSample> {
    for name in TRESSFX_FILES {
        tressfx_file(name)?;
    }
    Ok(data_dir().join("tressfx"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variable_names_the_folder_and_an_empty_one_means_the_default() {
        let (dir, from_variable) = data_dir_from(Some(PathBuf::from("/somewhere")));
        assert_eq!((dir, from_variable), (PathBuf::from("/somewhere"), true));
        let (dir, from_variable) = data_dir_from(Some(PathBuf::new()));
        assert!(!from_variable && dir.ends_with("shared/data"), "{dir:?}");
        assert_eq!(data_dir_from(None).0, dir);
    }

    #[test]
    fn a_missing_sample_names_the_path_and_the_variable() {
        let error = MissingSample {
            path: PathBuf::from("/nowhere/tressfx/ratboy_mohawk.tfx"),
            from_variable: true,
        };
        let text = error.to_string();
        assert!(
            text.contains("/nowhere/tressfx/ratboy_mohawk.tfx") && text.contains(DATA_VAR),
            "{text}"
        );
    }
}
