//! Writing results so that nothing half-written ever looks complete: each
//! file is written under a temporary name in the same folder, flushed, and
//! renamed into place.

use std::io::Write;

use image::ImageEncoder;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::render::Frame;

/// Creates `dir` (and parents), with an error that names it.
pub fn ensure_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
}

fn temp_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.partial"))
}

/// Writes `bytes` to `path` atomically (temporary file + rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_name(path);
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

/// Encodes a frame as an RGB PNG and writes it atomically.
pub fn write_png(path: &Path, frame: &Frame) -> Result<()> {
    let rgb: Vec<u8> = frame
        .rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    write_rgb_png(path, frame.width, frame.height, &rgb)
}

/// Encodes RGB8 pixels as a PNG and writes it atomically.
pub fn write_rgb_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    let mut encoded = Vec::new();
    image::codecs::png::PngEncoder::new(&mut encoded)
        .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|source| Error::Image {
            path: path.display().to_string(),
            source,
        })?;
    write_atomic(path, &encoded)
}
