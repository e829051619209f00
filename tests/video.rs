//! `meadow render --video`: what ffprobe reads back is the codec, size,
//! frame rate and frame count asked for, the video's first frame is the
//! PNG's within a measured limit, an interrupted render's video holds the
//! frames written, and a missing ffmpeg is refused before anything renders.
//! Needs ffmpeg and ffprobe (scripts/test installs them).

use crate::common;

use std::path::Path;
use std::process::Command;

use common::binary::{
    files_in, interrupted_render, meadow, read_json, temp_out, SMALL_SCENE, SMALL_SIZE,
};

/// ffprobe's view of the first video stream, frames counted by decoding.
fn probe(video: &Path) -> serde_json::Value {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-count_frames"])
        .args(["-show_entries"])
        .arg("stream=codec_name,width,height,pix_fmt,r_frame_rate,nb_read_frames")
        .args(["-of", "json"])
        .arg(video)
        .output()
        .expect("ffprobe runs (scripts/ensure-ffmpeg installs it)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    json["streams"][0].clone()
}

fn render_video(args: &[&str], out: &Path, video: &Path) -> serde_json::Value {
    let mut full = vec!["render", "--validation"];
    full.extend(SMALL_SCENE);
    full.extend(SMALL_SIZE);
    full.extend(args);
    full.extend([
        "--video",
        video.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let result = meadow(&full, &[]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let report = read_json(&out.join("report.json"));
    assert_eq!(report["validation"]["errors"], 0, "{report}");
    assert_eq!(report["video"], video.to_str().unwrap());
    report
}

fn ffmpeg(args: &[&str], input: &Path, output: &Path) {
    let status = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-i"])
        .arg(input)
        .args(args)
        .arg(output)
        .status()
        .unwrap();
    assert!(status.success(), "ffmpeg {args:?} {}", input.display());
}

/// The video's first frame (decoded by ffmpeg) against the PNG of the same
/// frame, as a ratio to what 4:2:0 colour alone loses (the PNG through
/// ffmpeg's RGB -> 4:2:0 -> RGB and no encoder). At 320 x 180 the grass's
/// thin blades lose much to the halved colour (mean FLIP 0.051); measured
/// on lavapipe: the H.264 frame (CRF 12) 1.04x that, VP9's (CRF 15) 1.03x,
/// H.264 at CRF 30 1.5x; RGBA fed to ffmpeg as BGRA 7.2x.
fn loss_over_4_2_0(video: &Path, png: &Path, scratch: &Path) -> f32 {
    let decoded = scratch.join("decoded.png");
    ffmpeg(&["-frames:v", "1"], video, &decoded);
    let subsampled = scratch.join("subsampled.png");
    ffmpeg(&["-vf", "format=yuv420p,format=rgb24"], png, &subsampled);
    common::mean_flip_of_files(png, &decoded) / common::mean_flip_of_files(png, &subsampled)
}

/// Near-lossless: the encoder adds at most a quarter to the loss of the
/// 4:2:0 colour that players need.
const ENCODER_LOSS_LIMIT: f32 = 1.25;

#[test]
fn an_mp4_is_h264_with_the_size_rate_and_frames_asked_for() {
    let dir = temp_out("video-mp4");
    let video = dir.join("clips/grass.mp4");
    let out = dir.join("frames");
    render_video(&["--frames", "12", "--fps", "24"], &out, &video);
    let stream = probe(&video);
    assert_eq!(stream["codec_name"], "h264", "{stream}");
    assert_eq!(stream["pix_fmt"], "yuv420p", "{stream}");
    assert_eq!(
        (stream["width"].as_u64(), stream["height"].as_u64()),
        (Some(320), Some(180))
    );
    assert_eq!(stream["r_frame_rate"], "24/1", "{stream}");
    assert_eq!(stream["nb_read_frames"], "12", "{stream}");
    let loss = loss_over_4_2_0(&video, &out.join("frame_0000.png"), &dir);
    assert!(loss < ENCODER_LOSS_LIMIT, "{loss}x the 4:2:0 loss");
    // Only the video under its own name: no temporary file left beside it.
    assert_eq!(files_in(&dir.join("clips")), ["grass.mp4"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_webm_is_vp9_at_the_rate_of_the_frames_written() {
    let dir = temp_out("video-webm");
    let video = dir.join("grass.webm");
    let out = dir.join("frames");
    render_video(
        &["--frames", "12", "--fps", "12.5", "--every", "2"],
        &out,
        &video,
    );
    let stream = probe(&video);
    assert_eq!(stream["codec_name"], "vp9", "{stream}");
    assert_eq!(stream["pix_fmt"], "yuv420p", "{stream}");
    // Every second frame of 12.5 a second: 6.25 a second, 6 frames.
    assert_eq!(stream["r_frame_rate"], "25/4", "{stream}");
    assert_eq!(stream["nb_read_frames"], "6", "{stream}");
    let loss = loss_over_4_2_0(&video, &out.join("frame_0000.png"), &dir);
    assert!(loss < ENCODER_LOSS_LIMIT, "{loss}x the 4:2:0 loss");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A video written inside the output folder is one of the run's outputs:
/// the next render there replaces it with the rest, so the folder never
/// holds two runs.
#[test]
fn a_video_inside_the_output_folder_goes_with_its_run() {
    let out = temp_out("video-inside");
    let video = out.join("run.mp4");
    render_video(&["--frames", "3"], &out, &video);
    assert!(video.exists());
    let mut full = vec!["render"];
    full.extend(SMALL_SCENE);
    full.extend(SMALL_SIZE);
    full.extend(["--frames", "1", "--out", out.to_str().unwrap()]);
    let result = meadow(&full, &[]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert_eq!(
        files_in(&out),
        ["frame_0000.png", "report.json", "scene.toml"]
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn without_ffmpeg_the_video_is_refused_before_anything_renders() {
    let dir = temp_out("video-no-ffmpeg");
    let out = dir.join("frames");
    let video = dir.join("grass.mp4");
    // A PATH with no ffmpeg on it (the binary is started by its full path).
    let empty = dir.join("empty-bin");
    std::fs::create_dir_all(&empty).unwrap();
    let result = meadow(
        &[
            "render",
            "--video",
            video.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &[("PATH", empty.to_str().unwrap())],
    );
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success());
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("--video needs ffmpeg, which is not on PATH")
            && stderr.contains("scripts/ensure-ffmpeg"),
        "{stderr}"
    );
    assert!(
        !out.exists(),
        "the output folder was made: {:?}",
        files_in(&out)
    );
    assert!(!video.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_video_that_cannot_be_is_one_line_and_no_file() {
    let dir = temp_out("video-refused");
    let out = dir.join("frames");
    for (video, size, says) in [
        ("grass.mkv", "320", ".mp4 (H.264) or .webm (VP9)"),
        ("grass.mp4", "321", "--width 322 --height 180"),
    ] {
        let video = dir.join(video);
        let result = meadow(
            &[
                "render",
                "--width",
                size,
                "--height",
                "180",
                "--video",
                video.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &[],
        );
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success());
        assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(says), "{stderr}");
        assert!(!out.exists() && !video.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_interrupted_render_finishes_its_video_with_the_frames_written() {
    let dir = temp_out("video-interrupted");
    let out = dir.join("frames");
    let video = dir.join("grass.mp4");
    let result = interrupted_render(&out, &["--no-gif", "--video", video.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(130), "{stderr}");
    let report = read_json(&out.join("report.json"));
    assert_eq!(report["interrupted"], true);
    let written = report["frames"].as_array().unwrap().len();
    assert!((4..2000).contains(&written), "{written}");
    assert_eq!(report["video"], video.to_str().unwrap());
    let stream = probe(&video);
    assert_eq!(stream["nb_read_frames"], written.to_string(), "{stream}");
    assert_eq!(files_in(&dir), ["frames", "grass.mp4"]);
    let _ = std::fs::remove_dir_all(&dir);
}
