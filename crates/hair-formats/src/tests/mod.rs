//! Tests of the readers as a whole: every error case with its message, the real TressFX files in
//! `shared/data` (read, and fitted: `fit_real_data.rs`), round trips through the writers, Alembic
//! `.abc` curves (`alembic.rs`), USD text `BasisCurves` (`usda.rs`), USD through the `openusd`
//! crate (`usd_crate.rs`), and fuzz-style tests under plain `cargo test`.

pub(crate) mod alembic;
mod errors;
mod fit_real_data;
mod fuzz;
mod mesh_sequence;
pub(crate) mod real_data;
mod round_trips;
pub(crate) mod usd_crate;
mod usda;

use std::path::PathBuf;

/// A fresh directory for this test's files (removed by the caller).
pub(crate) fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hairlod-formats-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
