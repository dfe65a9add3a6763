//! PNG output: atomic writes, frame names that sort, side-by-side and contact-sheet composition.

use std::io::Write;
use std::path::{Path, PathBuf};

use hair_core::atomic_file::write_file_atomically;

use crate::error::{RenderError, Result, invalid};

/// Digits in a frame number when the sequence is short enough (`frame_00001.png`).
pub const MIN_FRAME_DIGITS: usize = 5;

/// The file name of frame `index` in a sequence of `frame_count` frames: `frame_00001.png`.
///
/// Numbers are zero-padded to [`MIN_FRAME_DIGITS`] digits, or more when `frame_count` needs them,
/// so names sort in frame order.
pub fn frame_file_name(index: u64, frame_count: u64) -> String {
    let last = frame_count.saturating_sub(1).max(index);
    let digits = last.to_string().len().max(MIN_FRAME_DIGITS);
    format!("frame_{index:0digits$}.png")
}

/// The path of frame `index` of `frame_count` in `directory` (see [`frame_file_name`]).
pub fn frame_path(directory: &Path, index: u64, frame_count: u64) -> PathBuf {
    directory.join(frame_file_name(index, frame_count))
}

/// Writes `image` as a PNG at `path` atomically, through the project's one atomic writer
/// ([`hair_core::atomic_file::write_file_atomically`]): the bytes go to a temporary file beside `path`
/// named with the process id, are synced to disk, and the file is renamed over `path`; on any
/// error the temporary file is removed. A stopped run leaves either the old file or the complete
/// new one, never a half-written PNG, and two runs writing into one folder never share a
/// temporary file.
///
/// Errors name the path that failed.
pub fn write_png_atomic(image: &image::RgbaImage, path: &Path) -> Result<()> {
    if image.width() == 0 || image.height() == 0 {
        return Err(invalid(format!(
            "cannot write an empty {}x{} image to {}",
            image.width(),
            image.height(),
            path.display()
        )));
    }
    if path.file_name().is_none() {
        return Err(invalid(format!("{} does not name a file", path.display())));
    }
    write_file_atomically(path, |writer| {
        image
            .write_to(writer, image::ImageFormat::Png)
            .map_err(std::io::Error::other)?;
        writer.flush()
    })
    .map_err(|cause| RenderError::Io {
        path: path.to_owned(),
        cause,
    })
}

/// `left` and `right` next to each other (e.g. shaded | colour-coded); the shorter one is padded
/// with transparent black at the bottom.
pub fn side_by_side(left: &image::RgbaImage, right: &image::RgbaImage) -> image::RgbaImage {
    let width = left.width() + right.width();
    let height = left.height().max(right.height());
    let mut sheet = image::RgbaImage::new(width, height);
    image::imageops::replace(&mut sheet, left, 0, 0);
    image::imageops::replace(&mut sheet, right, i64::from(left.width()), 0);
    sheet
}

/// A contact sheet: `images` in rows of `columns`, each cell scaled down to `cell_width`×
/// `cell_height` pixels (aspect ratio not kept).
pub fn contact_sheet(
    images: &[image::RgbaImage],
    columns: u32,
    cell_width: u32,
    cell_height: u32,
) -> Result<image::RgbaImage> {
    if images.is_empty() || columns == 0 || cell_width == 0 || cell_height == 0 {
        return Err(invalid(format!(
            "contact sheet needs images, columns and a cell size \
             (got {} images, {columns} columns, {cell_width}x{cell_height} cells)",
            images.len()
        )));
    }
    let count = u32::try_from(images.len()).map_err(|_| invalid("too many images"))?;
    let rows = count.div_ceil(columns);
    let mut sheet = image::RgbaImage::new(columns.min(count) * cell_width, rows * cell_height);
    for (index, image) in (0..count).zip(images) {
        let cell = image::imageops::resize(
            image,
            cell_width,
            cell_height,
            image::imageops::FilterType::Triangle,
        );
        let x = (index % columns) * cell_width;
        let y = (index / columns) * cell_height;
        image::imageops::replace(&mut sheet, &cell, i64::from(x), i64::from(y));
    }
    Ok(sheet)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hair-render-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn frame_names_sort_in_frame_order() {
        assert_eq!(frame_file_name(1, 3), "frame_00001.png");
        assert_eq!(frame_file_name(123_456, 200_000), "frame_123456.png");
        assert_eq!(frame_file_name(7, 200_000), "frame_000007.png");
        let mut names: Vec<String> = (0..120).map(|i| frame_file_name(i, 120)).collect();
        let in_order = names.clone();
        names.sort();
        assert_eq!(names, in_order);
    }

    #[test]
    fn png_round_trips_and_leaves_no_temp_file() {
        let dir = temp_dir("png");
        let path = frame_path(&dir, 0, 1);
        let image =
            image::RgbaImage::from_fn(3, 2, |x, y| image::Rgba([x as u8 * 80, y as u8, 7, 255]));
        write_png_atomic(&image, &path).unwrap();
        let read = image::open(&path).unwrap().to_rgba8();
        assert_eq!(read, image);
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|entry| entry.ok())
            .filter(|entry| entry.path().extension().is_some_and(|e| e == "tmp"))
            .collect();
        assert!(leftovers.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn write_errors_name_the_path() {
        let path = Path::new("/nonexistent-hair-render-dir/frame_00000.png");
        let image = image::RgbaImage::new(1, 1);
        let message = write_png_atomic(&image, path).unwrap_err().to_string();
        assert!(
            message.contains("/nonexistent-hair-render-dir/frame_00000.png"),
            "{message}"
        );
        let empty = write_png_atomic(&image::RgbaImage::new(0, 0), path).unwrap_err();
        assert!(empty.to_string().contains("empty"));
    }

    #[test]
    fn side_by_side_and_contact_sheet_place_images() {
        let red = image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 0, 0, 255]));
        let blue = image::RgbaImage::from_pixel(3, 1, image::Rgba([0, 0, 255, 255]));
        let pair = side_by_side(&red, &blue);
        assert_eq!(pair.dimensions(), (5, 2));
        assert_eq!(pair.get_pixel(1, 1).0, [255, 0, 0, 255]);
        assert_eq!(pair.get_pixel(4, 0).0, [0, 0, 255, 255]);
        assert_eq!(pair.get_pixel(4, 1).0, [0, 0, 0, 0]);
        let sheet = contact_sheet(&[red.clone(), red.clone(), red], 2, 4, 4).unwrap();
        assert_eq!(sheet.dimensions(), (8, 8));
        assert_eq!(sheet.get_pixel(2, 6).0, [255, 0, 0, 255]);
        assert_eq!(sheet.get_pixel(6, 6).0, [0, 0, 0, 0]);
        assert!(contact_sheet(&[], 2, 4, 4).is_err());
    }
}
