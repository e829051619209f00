//! `--video FILE.mp4|.webm`: the frames piped to Debian's ffmpeg as they
//! are rendered. Like the GIF, the video is written under a temporary name
//! and renamed into place by `finish`, so a file under its real name is
//! always a whole video; an unfinished one is removed.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use crate::error::{Error, Result};
use crate::frame::Frame;

/// The containers meadow writes, chosen by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VideoFormat {
    /// H.264 in MP4: plays everywhere.
    Mp4,
    /// VP9 in WebM: for the web.
    Webm,
}

impl VideoFormat {
    pub fn of(path: &Path) -> Result<Self> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match extension.as_deref() {
            Some("mp4") => Ok(Self::Mp4),
            Some("webm") => Ok(Self::Webm),
            _ => Err(Error::InvalidInput(format!(
                "--video {}: the name must end in .mp4 (H.264) or .webm (VP9)",
                path.display()
            ))),
        }
    }

    /// ffmpeg's encoder, at a quality where the encoding's loss is under
    /// what the eye sees in the moving grass (constant-quality 12 of H.264's
    /// 0..=51, 15 of VP9's 0..=63), in 4:2:0, which every player decodes.
    fn encoder_args(self) -> &'static [&'static str] {
        match self {
            Self::Mp4 => &[
                "-c:v",
                "libx264",
                "-preset",
                "medium",
                "-crf",
                "12",
                "-pix_fmt",
                "yuv420p",
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ],
            Self::Webm => &[
                "-c:v",
                "libvpx-vp9",
                "-crf",
                "15",
                "-b:v",
                "0",
                "-row-mt",
                "1",
                "-pix_fmt",
                "yuv420p",
                "-f",
                "webm",
            ],
        }
    }
}

/// The ffmpeg on PATH, or one line saying how to get it.
pub fn find_ffmpeg() -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|dir| dir.join("ffmpeg"))
        .find(|candidate| candidate.is_file())
        .ok_or_else(|| {
            Error::InvalidInput(
                "--video needs ffmpeg, which is not on PATH; install it (scripts/ensure-ffmpeg does, \
                 or apt install ffmpeg) or leave out --video (the PNG frames and GIF need nothing)"
                    .into(),
            )
        })
}

/// Refuses what a 4:2:0 video cannot hold: an odd width or height.
pub fn check_size(width: u32, height: u32) -> Result<()> {
    if width % 2 == 1 || height % 2 == 1 {
        return Err(Error::InvalidInput(format!(
            "--video needs an even width and height (4:2:0 colour halves both), not {width} x {height}; \
             use --width {} --height {}",
            width + width % 2,
            height + height % 2
        )));
    }
    Ok(())
}

/// An ffmpeg process fed RGBA frames on its standard input.
pub struct VideoWriter {
    path: PathBuf,
    tmp: PathBuf,
    ffmpeg: Option<Child>,
    stdin: Option<ChildStdin>,
    /// ffmpeg's messages, read on a thread so it never blocks on a full pipe.
    messages: Option<std::thread::JoinHandle<String>>,
    width: u32,
    height: u32,
}

impl VideoWriter {
    /// Starts ffmpeg for `width` x `height` frames shown `fps` per second.
    /// A video already at `path` is removed first, so that a render that
    /// fails never leaves an older video looking like its own.
    pub fn create(path: &Path, width: u32, height: u32, fps: f32) -> Result<Self> {
        let format = VideoFormat::of(path)?;
        check_size(width, height)?;
        let ffmpeg = find_ffmpeg()?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::Io {
                path: format!(
                    "folder of --video {} (give a path you can write)",
                    path.display()
                ),
                source: e,
            })?;
        }
        match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(path, e)),
            _ => {}
        }
        let tmp = super::files::temp_name(path);
        let mut command = Command::new(ffmpeg);
        command
            .args(["-hide_banner", "-loglevel", "error", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{width}x{height}")])
            .args(["-framerate", &fps.to_string()])
            .args(["-i", "pipe:0"])
            .args(format.encoder_args())
            .arg(&tmp)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        // Its own process group: Ctrl-C at a terminal reaches meadow only,
        // which stops after the frame it is on and finishes the video with
        // the frames so far.
        std::os::unix::process::CommandExt::process_group(&mut command, 0);
        let mut child = command.spawn().map_err(|e| Error::Io {
            path: format!("starting ffmpeg for {}", path.display()),
            source: e,
        })?;
        let stdin = child.stdin.take();
        let mut stderr = child.stderr.take();
        let messages = std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(s) = stderr.as_mut() {
                let _ = s.read_to_string(&mut text);
            }
            text
        });
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            ffmpeg: Some(child),
            stdin,
            messages: Some(messages),
            width,
            height,
        })
    }

    pub fn add(&mut self, frame: &Frame) -> Result<()> {
        assert_eq!(
            (frame.width, frame.height),
            (self.width, self.height),
            "every frame of a video has the size it was created with"
        );
        let stdin = self.stdin.as_mut().expect("video writer used after finish");
        if let Err(e) = stdin.write_all(&frame.rgba) {
            // A broken pipe means ffmpeg stopped: its own words say why.
            return Err(self.failure(e));
        }
        Ok(())
    }

    /// Closes ffmpeg's input, waits for it to write the file's end and
    /// renames the video into place.
    pub fn finish(mut self) -> Result<()> {
        drop(self.stdin.take());
        let mut child = self.ffmpeg.take().expect("finished once");
        let status = child.wait().map_err(|e| Error::io(&self.path, e))?;
        let messages = self.messages();
        if !status.success() {
            let _ = std::fs::remove_file(&self.tmp);
            return Err(Error::InvalidInput(format!(
                "ffmpeg failed writing {} ({status}): {}",
                self.path.display(),
                last_line(&messages)
            )));
        }
        let result = std::fs::File::open(&self.tmp)
            .and_then(|f| f.sync_all())
            .and_then(|_| std::fs::rename(&self.tmp, &self.path));
        result.map_err(|e| {
            let _ = std::fs::remove_file(&self.tmp);
            Error::io(&self.path, e)
        })
    }

    /// ffmpeg's error after a failed write: it is stopped and its last
    /// message names the cause.
    fn failure(&mut self, e: std::io::Error) -> Error {
        drop(self.stdin.take());
        if let Some(mut child) = self.ffmpeg.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
        let _ = std::fs::remove_file(&self.tmp);
        let messages = self.messages();
        if messages.trim().is_empty() {
            Error::io(&self.path, e)
        } else {
            Error::InvalidInput(format!(
                "ffmpeg stopped writing {}: {}",
                self.path.display(),
                last_line(&messages)
            ))
        }
    }

    fn messages(&mut self) -> String {
        self.messages
            .take()
            .and_then(|t| t.join().ok())
            .unwrap_or_default()
    }
}

impl Drop for VideoWriter {
    fn drop(&mut self) {
        if let Some(mut child) = self.ffmpeg.take() {
            // Not finished: stop ffmpeg and leave no partial video behind.
            drop(self.stdin.take());
            let _ = child.kill();
            let _ = child.wait();
            let _ = self.messages();
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

fn last_line(text: &str) -> &str {
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("no message")
        .trim()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_format_is_the_extension_and_nothing_else_is_taken() {
        assert_eq!(
            VideoFormat::of(Path::new("a/b.mp4")).unwrap(),
            VideoFormat::Mp4
        );
        assert_eq!(
            VideoFormat::of(Path::new("b.WebM")).unwrap(),
            VideoFormat::Webm
        );
        for bad in ["b.mkv", "b", "mp4", "b.mp4.txt"] {
            let e = VideoFormat::of(Path::new(bad)).unwrap_err().to_string();
            assert!(e.contains(".mp4 (H.264) or .webm (VP9)"), "{bad}: {e}");
        }
    }

    #[test]
    fn odd_sizes_are_refused_with_the_next_even_one() {
        assert!(check_size(1280, 720).is_ok());
        let e = check_size(321, 180).unwrap_err().to_string();
        assert!(e.contains("--width 322 --height 180"), "{e}");
    }
}
