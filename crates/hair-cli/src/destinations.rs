//! Where a command will write, checked before it simulates or renders anything: a run that
//! would fail to write its report, checkpoint or frames at the end fails in its first second
//! instead, naming the path and the reason.
//!
//! A folder is created (with its parents) and a probe file is written into it and removed; a
//! file's folder is checked the same way, and the file itself must not be a folder.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

/// Creates `dir` (and its parents) if needed and checks that files can be written in it;
/// `what` names it in errors ("output folder", "checkpoint folder").
pub fn writable_folder(dir: &Path, what: &str) -> Result<()> {
    if dir.is_file() {
        bail!("{what} {} is a file, not a folder", dir.display());
    }
    if let Err(error) = std::fs::create_dir_all(dir) {
        bail!("cannot create the {what} {}: {error}", dir.display());
    }
    let probe = dir.join(format!(".hairlod-probe.{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(file) => {
            drop(file);
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(error) => bail!("cannot write in the {what} {}: {error}", dir.display()),
    }
}

/// Checks that the file `path` can be written: it names a file (not `.`, `..`, a path ending in
/// a separator, or an existing folder), and its folder can be created and written in; `what`
/// names it in errors ("JSON report").
pub fn writable_file(path: &Path, what: &str) -> Result<()> {
    let names_a_file = path
        .file_name()
        .is_some_and(|name| name != "." && name != "..")
        && !path
            .as_os_str()
            .to_string_lossy()
            .ends_with(std::path::MAIN_SEPARATOR);
    if !names_a_file {
        bail!("the {what} path {} names no file", path.display());
    }
    if path.is_dir() {
        bail!("the {what} path {} is a folder, not a file", path.display());
    }
    let folder: PathBuf = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    writable_folder(&folder, &format!("folder of the {what} {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hairlod-dest-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn folders_are_created_and_probed_and_files_in_their_way_named() {
        let dir = scratch("folders");
        let nested = dir.join("a/b");
        writable_folder(&nested, "output folder").unwrap();
        assert!(nested.is_dir());
        // The probe is gone.
        assert_eq!(std::fs::read_dir(&nested).unwrap().count(), 0);
        let file = dir.join("file");
        std::fs::write(&file, "x").unwrap();
        let error = writable_folder(&file, "checkpoint folder")
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("checkpoint folder") && error.contains("is a file"),
            "{error}"
        );
        let error = writable_folder(&file.join("under"), "output folder")
            .unwrap_err()
            .to_string();
        assert!(error.contains("cannot create the output folder"), "{error}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn report_paths_that_name_no_file_or_a_folder_are_refused() {
        let dir = scratch("files");
        for (path, expected) in [
            (PathBuf::from("."), "names no file"),
            (dir.join(".."), "names no file"),
            (dir.clone(), "is a folder"),
            (dir.join("report.json/"), "names no file"),
        ] {
            let error = writable_file(&path, "JSON report").unwrap_err().to_string();
            assert!(
                error.contains("JSON report") && error.contains(expected),
                "{path:?}: {error}"
            );
        }
        std::fs::write(dir.join("file"), "x").unwrap();
        let error = writable_file(&dir.join("file/report.json"), "JSON report")
            .unwrap_err()
            .to_string();
        assert!(error.contains("is a file"), "{error}");
        writable_file(&dir.join("new/report.json"), "JSON report").unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_read_only_folder_is_refused_where_permissions_hold() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("read-only");
        let locked = dir.join("locked");
        std::fs::create_dir_all(&locked).unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Root writes anywhere: the probe then succeeds, as the real write would.
        let probe_denied = std::fs::write(locked.join("x"), "x").is_err();
        let result = writable_folder(&locked, "checkpoint folder");
        assert_eq!(result.is_err(), probe_denied, "{result:?}");
        if let Err(error) = result {
            assert!(
                error
                    .to_string()
                    .contains("cannot write in the checkpoint folder")
            );
        }
        let _ = std::fs::remove_file(locked.join("x"));
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
