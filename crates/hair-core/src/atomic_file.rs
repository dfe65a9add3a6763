//! Replacing a file atomically ([`write_file_atomically`]): a temporary file beside it, synced,
//! then renamed over it, so an interrupted run never leaves a half-written file. Every writer of
//! the workspace (OBJ, USD, cyHair, PNG, checkpoints, charts) goes through it.

use std::fs::File;
use std::io::{self, BufWriter};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// Distinguishes temporary files of concurrent writes from one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes the file at `path` through `write`, atomically: `write` fills a temporary file beside
/// `path` (same directory, named `.<name>.<process>.<n>.tmp`), which is flushed, synced and then
/// renamed over `path`. If `write` or any step fails, the temporary file is removed and `path` is
/// left as it was (absent, or the previous complete file), so an interrupted run never leaves a
/// half-written file. Errors name the path.
pub fn write_file_atomically<F>(path: impl AsRef<Path>, write: F) -> io::Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    let path = path.as_ref();
    let context = |error: io::Error| {
        io::Error::new(error.kind(), format!("writing {}: {error}", path.display()))
    };
    let Some(name) = path.file_name() else {
        return Err(context(invalid_input("the path names no file".into())));
    };
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let counter = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary = directory.join(format!(
        ".{}.{}.{counter}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let file = File::create_new(&temporary).map_err(context)?;
    let result = (|| {
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        let file = writer
            .into_inner()
            .map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, path)
    })();
    if let Err(error) = result {
        // Best effort: the temporary file is ours, and the original error is the one to report.
        let _ = std::fs::remove_file(&temporary);
        return Err(context(error));
    }
    Ok(())
}

/// Removes, in `directory`, the temporary files that [`write_file_atomically`] leaves when its
/// process is killed mid-write (`.<name>.<process>.<n>.tmp`) for each file of `paths` (which lie
/// in `directory`): a rerun of a killed job leaves nothing of the earlier run behind. Other
/// files, and temporaries of other names, are left alone. Errors name the directory.
pub fn remove_stale_temporaries(directory: &Path, paths: &[impl AsRef<Path>]) -> io::Result<()> {
    let prefixes: std::collections::HashSet<String> = paths
        .iter()
        .filter_map(|path| path.as_ref().file_name())
        .map(|name| format!(".{}.", name.to_string_lossy()))
        .collect();
    if prefixes.is_empty() {
        return Ok(());
    }
    let context = |error: io::Error| {
        io::Error::new(
            error.kind(),
            format!(
                "removing stale temporary files in {}: {error}",
                directory.display()
            ),
        )
    };
    for entry in std::fs::read_dir(directory).map_err(context)? {
        let entry = entry.map_err(context)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_suffix(".tmp") else {
            continue;
        };
        // `.<name>.<process>.<n>`: the prefix up to the last two dot-separated numbers.
        let mut parts = stem.rsplitn(3, '.');
        let (Some(n), Some(process), Some(prefix)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        let numbers = [n, process]
            .iter()
            .all(|part| !part.is_empty() && part.bytes().all(|b| b.is_ascii_digit()));
        if numbers && prefixes.contains(&format!("{prefix}.")) {
            std::fs::remove_file(entry.path()).map_err(context)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_temporaries_of_the_given_files_are_removed_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("hairlod-stale-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let names = [
            ".frame_00003.png.4242.0.tmp", // a killed write of frame 3: removed
            ".frame_00004.png.4242.7.tmp", // frame 4 is not this run's: kept
            ".frame_00003.png.tmp",        // not the writer's pattern: kept
            "frame_00003.png",             // the frame itself: kept
            ".frame_00003.png.x.1.tmp",    // not a process number: kept
        ];
        for name in names {
            std::fs::write(dir.join(name), b"x").unwrap();
        }
        remove_stale_temporaries(&dir, &[dir.join("frame_00003.png")]).unwrap();
        let left: Vec<bool> = names.iter().map(|name| dir.join(name).exists()).collect();
        std::fs::remove_dir_all(&dir).ok();
        assert_eq!(left, [false, true, true, true, true]);
    }

    #[test]
    fn a_write_that_fails_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("hairlod-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("record.bin");
        write_file_atomically(&path, |file| std::io::Write::write_all(file, b"old")).unwrap();
        let failed = write_file_atomically(&path, |file| {
            std::io::Write::write_all(file, b"half")?;
            Err(io::Error::other("killed"))
        });
        let kept = std::fs::read(&path).unwrap();
        let entries = std::fs::read_dir(&dir).unwrap().count();
        std::fs::remove_dir_all(&dir).ok();
        assert!(failed.unwrap_err().to_string().contains("record.bin"));
        assert_eq!(kept, b"old");
        assert_eq!(entries, 1, "a temporary file was left");
    }
}
