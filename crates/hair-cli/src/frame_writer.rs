//! Where a render's images go ([`FrameWriter`]): one folder per view (the output folder itself
//! for one view), every PNG written atomically, and a contact sheet when asked. Before the first
//! frame, the temporary files that a killed earlier run left for this run's frames are removed,
//! so a rerun chunk leaves nothing behind.

use std::ops::Range;
use std::path::{Path, PathBuf};

use anyhow::Result;
use hairlod::render::output;
use hairlod::run::View;

use crate::destinations::writable_folder;

/// Writes the frames of a run (see the module docs).
pub struct FrameWriter {
    out: PathBuf,
    folders: Vec<PathBuf>,
    /// The shot's frame count (the width of the frame numbers in the file names).
    shot_frames: usize,
    contact_sheet: bool,
    thumbnails: Vec<image::RgbaImage>,
}

impl FrameWriter {
    /// A writer of `views` into `out` for `frames` of a shot of `shot_frames` frames, the folders
    /// created and checked, stale temporary files of those frames removed.
    pub fn new(
        out: &Path,
        views: &[View],
        frames: Range<usize>,
        shot_frames: usize,
        contact_sheet: bool,
    ) -> Result<Self> {
        let folders: Vec<PathBuf> = if views.len() == 1 {
            vec![out.to_path_buf()]
        } else {
            views.iter().map(|v| out.join(v.name())).collect()
        };
        for folder in &folders {
            writable_folder(folder, "output folder")?;
            let paths: Vec<PathBuf> = frames
                .clone()
                .map(|frame| output::frame_path(folder, frame as u64, shot_frames as u64))
                .collect();
            hairlod::core::atomic_file::remove_stale_temporaries(folder, &paths)?;
        }
        Ok(FrameWriter {
            out: out.to_path_buf(),
            folders,
            shot_frames,
            contact_sheet,
            thumbnails: Vec::new(),
        })
    }

    /// Writes frame `frame`'s images, one per view in the writer's order.
    pub fn write(
        &mut self,
        frame: usize,
        images: &[image::RgbaImage],
    ) -> hairlod::pipeline::Result<()> {
        for (image, folder) in images.iter().zip(&self.folders) {
            let path = output::frame_path(folder, frame as u64, self.shot_frames as u64);
            output::write_png_atomic(image, &path)?;
        }
        if self.contact_sheet
            && let Some(image) = images.first()
        {
            let width = 320.min(image.width());
            let height = (image.height() * width / image.width()).max(1);
            self.thumbnails
                .push(image::imageops::thumbnail(image, width, height));
        }
        Ok(())
    }

    /// Writes the contact sheet, when asked for and there were frames.
    pub fn finish(self) -> Result<()> {
        if let Some(first) = self.thumbnails.first() {
            let (width, height) = first.dimensions();
            let columns = (self.thumbnails.len() as u32).min(6);
            let sheet = output::contact_sheet(&self.thumbnails, columns, width, height)?;
            let path = self.out.join("contact_sheet.png");
            output::write_png_atomic(&sheet, &path)?;
            eprintln!("wrote {}", path.display());
        }
        Ok(())
    }
}
