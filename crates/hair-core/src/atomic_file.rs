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
