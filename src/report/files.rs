//! Writing results so that nothing half-written ever looks complete: each
//! file is written under a temporary name in the same folder, flushed, and
//! renamed into place.

use std::io::Write;

use image::ImageEncoder;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::frame::Frame;

/// Creates `dir` (and parents) and checks that a file can be made in it,
/// so that a folder the user cannot write (permissions, a read-only file
/// system) is refused before any work, not at the first frame; the error
/// names the folder.
pub fn ensure_dir(dir: &Path) -> Result<()> {
    writable(
        dir,
        &format!(
            "output directory {} (pass --out a directory you can write)",
            dir.display()
        ),
    )
}

/// As `ensure_dir`, for the folder of a file named by a flag (`--video
/// FILE`): refused naming the flag and the file.
pub fn ensure_dir_of(file: &Path, flag: &str) -> Result<()> {
    let dir = match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    writable(
        dir,
        &format!(
            "folder of {flag} {} (give a path you can write)",
            file.display()
        ),
    )
}

/// Makes `dir` and a file in it (removed at once); an error is `what`.
fn writable(dir: &Path, what: &str) -> Result<()> {
    let refused = |e: std::io::Error| Error::Io {
        path: what.to_string(),
        source: e,
    };
    std::fs::create_dir_all(dir).map_err(refused)?;
    // A hidden name of this process's own, made new and removed at once.
    let probe = dir.join(format!(".meadow-write-check-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(refused)?;
    std::fs::remove_file(&probe).map_err(refused)
}

/// Refuses, before the work, a folder whose file system has less free
/// room than `bytes` (what the run will write there, at least): `what`
/// says what needs it and how the size was reckoned. Where the free room
/// cannot be read (an unusual file system), the run goes on; a disk that
/// fills up later is still one line naming the file.
pub fn ensure_space(dir: &Path, bytes: u64, what: &str) -> Result<()> {
    let Ok(free) = fs4::available_space(dir) else {
        return Ok(());
    };
    if free >= bytes {
        return Ok(());
    }
    Err(Error::InvalidInput(format!(
        "{} has {} free and {what} would take at least about {}; free some space or pass --out a folder on another disk",
        dir.display(),
        human_bytes(free),
        human_bytes(bytes)
    )))
}

/// A byte count in the unit that reads best: B, KiB, MiB or GiB.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["B", "KiB", "MiB", "GiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// The least a PNG frame of `width` x `height` takes: an eighth of its
/// RGBA bytes. meadow's frames (soil texture, grass, sky) compress 3.4x
/// (640 x 360) to 4.6x (320 x 180); a frame compressing 8x would be
/// nearly all sky.
pub fn least_png_bytes(width: u32, height: u32) -> u64 {
    width as u64 * height as u64 * 4 / 8
}

/// The temporary name `path` is written under until it is complete.
pub(crate) fn temp_name(path: &Path) -> PathBuf {
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
        .map_err(|source| Error::image(path, source))?;
    write_atomic(path, &encoded)
}

/// An animated GIF written frame by frame under a temporary name, renamed
/// into place by `finish`; `abandon` (or dropping it) removes the partial
/// file, so a GIF under its real name is always complete.
pub struct GifWriter {
    path: PathBuf,
    tmp: PathBuf,
    encoder: Option<image::codecs::gif::GifEncoder<SharedFile>>,
    file: SharedFile,
    delay: image::Delay,
    frames: u32,
}

impl GifWriter {
    /// `frame_seconds`: how long each frame shows (GIF delays are in
    /// hundredths of a second, so 30 fps plays at about 33 fps).
    pub fn create(path: &Path, frame_seconds: f32) -> Result<Self> {
        let tmp = temp_name(path);
        let file = std::fs::File::create(&tmp).map_err(|e| Error::io(path, e))?;
        let file = SharedFile(std::rc::Rc::new(std::cell::RefCell::new(
            std::io::BufWriter::new(file),
        )));
        // Speed 10 of 1..=30: NeuQuant's default trade of colour for time.
        let mut encoder = image::codecs::gif::GifEncoder::new_with_speed(file.clone(), 10);
        encoder
            .set_repeat(image::codecs::gif::Repeat::Infinite)
            .map_err(|source| Error::image(path, source))?;
        let centis = (frame_seconds * 100.0).round().clamp(2.0, 65535.0) as u32;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            encoder: Some(encoder),
            file,
            delay: image::Delay::from_numer_denom_ms(centis * 10, 1),
            frames: 0,
        })
    }

    pub fn add(&mut self, frame: &Frame) -> Result<()> {
        let image = image::RgbaImage::from_raw(frame.width, frame.height, frame.rgba.clone())
            .expect("a frame holds width x height RGBA pixels");
        let encoder = self.encoder.as_mut().expect("GIF writer used after finish");
        encoder
            .encode_frame(image::Frame::from_parts(image, 0, 0, self.delay))
            .map_err(|source| Error::image(&self.path, source))?;
        self.frames += 1;
        Ok(())
    }

    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Ends the GIF (trailer, flush, sync) and renames it into place.
    pub fn finish(mut self) -> Result<()> {
        // Dropping the encoder writes the GIF trailer into the buffer.
        drop(self.encoder.take());
        let result = (|| {
            let mut w = self.file.0.borrow_mut();
            w.flush()?;
            w.get_ref().sync_all()?;
            std::fs::rename(&self.tmp, &self.path)
        })();
        result.map_err(|e| {
            let _ = std::fs::remove_file(&self.tmp);
            Error::io(&self.path, e)
        })
    }
}

impl Drop for GifWriter {
    fn drop(&mut self) {
        if self.encoder.is_some() {
            // Not finished: never leave a partial GIF behind.
            self.encoder = None;
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The GIF's file, shared between the encoder (which writes into it and
/// finishes it on drop) and the writer (which flushes and syncs it after).
#[derive(Clone)]
struct SharedFile(std::rc::Rc<std::cell::RefCell<std::io::BufWriter<std::fs::File>>>);

impl Write for SharedFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.0.borrow_mut().flush()
    }
}
