//! `meadow view` in a window on Xvfb, with lavapipe and the validation
//! layer (synchronization too): a script pauses, steps, switches views,
//! resizes and quits; what the window shows (overlay hidden) is what P
//! writes, and what P writes is what `render` writes for the same time and
//! camera; the overlay covers its corner and nothing else; the wind keys
//! and a click act; zero
//! validation errors, nothing leaked (the layer's teardown report). Needs
//! Xvfb and ffmpeg (scripts/test installs them).

use crate::common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

use common::binary::{meadow, send_sigint, temp_out, wait_for_file, SMALL_SCENE, SMALL_SIZE};

/// A virtual X display for one test, stopped when dropped.
struct Xvfb {
    server: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Self {
        // -displayfd: the server picks a free display and writes its number.
        let mut server = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb runs (scripts/ensure-xvfb installs it)");
        let mut line = String::new();
        BufReader::new(server.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let number: u32 = line.trim().parse().expect("Xvfb says its display");
        Self {
            server,
            display: format!(":{number}"),
        }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.server.kill();
        let _ = self.server.wait();
    }
}

fn view(x: &Xvfb, script: &str, out: &Path) -> Child {
    view_sized(x, script, out, (320, 180))
}

fn view_sized(x: &Xvfb, script: &str, out: &Path, (width, height): (u32, u32)) -> Child {
    std::fs::create_dir_all(out).unwrap();
    let script_path = out.join("script.txt");
    std::fs::write(&script_path, script).unwrap();
    let mut args = vec!["view", "--validation"];
    let (width, height) = (width.to_string(), height.to_string());
    args.extend(SMALL_SCENE);
    args.extend(["--width", &width, "--height", &height]);
    let (script_arg, out_arg) = (
        script_path.to_str().unwrap().to_string(),
        out.to_str().unwrap().to_string(),
    );
    args.extend(["--script", &script_arg, "--out", &out_arg]);
    Command::new(env!("CARGO_BIN_EXE_meadow"))
        .args(args)
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("MEADOW_QUIET_VALIDATION", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start meadow view")
}

fn finished(child: Child) -> (Output, String) {
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "exit {:?}: {stdout}{}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("validation: 0 errors"), "{stdout}");
    (output, stdout)
}

/// Stops a viewer whose script has no end with Ctrl-C, as a person
/// would; its stdout, checked as `finished` checks it but for the
/// signal's status.
fn interrupted(child: Child) -> String {
    send_sigint(&child);
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stdout}{stderr}");
    assert!(stdout.contains("validation: 0 errors"), "{stdout}");
    stdout
}

/// The window's pixels (at the screen's top left corner) from the X
/// screen, through ffmpeg's x11grab.
fn grab_window(x: &Xvfb, (width, height): (u32, u32), path: &Path) {
    let grab = Command::new("ffmpeg")
        .args(["-v", "error", "-y", "-f", "x11grab", "-draw_mouse", "0"])
        .arg("-video_size")
        .arg(format!("{width}x{height}"))
        .arg("-i")
        .arg(format!("{}+0,0", x.display))
        .args(["-frames:v", "1"])
        .arg(path)
        .status()
        .unwrap();
    assert!(grab.success());
}

/// The share of the pixels in the rectangle (x0, y0, x1, y1) where `a`
/// and `b` differ.
fn differing_share(
    a: &image::RgbImage,
    b: &image::RgbImage,
    (x0, y0, x1, y1): (u32, u32, u32, u32),
) -> f64 {
    let mut n = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            n += (a.get_pixel(x, y) != b.get_pixel(x, y)) as u32;
        }
    }
    n as f64 / ((x1 - x0) * (y1 - y0)) as f64
}

/// The window grabbed once it shows the paused frame `shot` (P's
/// screenshot) in `settled`, a rectangle the overlay leaves alone. The
/// window shows a presented frame once the X server has it: with the
/// machine busy (other tests beside this one) that can lag the
/// screenshot's file by more than a moment, so it grabs every 0.3 s
/// until then, or 20 times. The scripts that use it have no end: the
/// test stops the viewer once it has the window (`interrupted`). A
/// script's quit at a set time closed the window before the grab when
/// the frames before P were slow (one action a frame, at 1 to 1.5 frames
/// a second with validation: P came at 5 s, the quit at 6).
fn grab_paused_frame(
    x: &Xvfb,
    out: &Path,
    shot: &image::RgbImage,
    settled: (u32, u32, u32, u32),
) -> image::RgbImage {
    let grabbed = out.join("grabbed.png");
    let mut tries = 0;
    loop {
        std::thread::sleep(std::time::Duration::from_millis(300));
        grab_window(x, (shot.width(), shot.height()), &grabbed);
        let window = image::open(&grabbed).unwrap().to_rgb8();
        tries += 1;
        if differing_share(shot, &window, settled) == 0.0 || tries == 20 {
            return window;
        }
    }
}

/// The simulated times P printed, in order.
fn screenshot_times(stdout: &str) -> Vec<(PathBuf, f64)> {
    stdout
        .lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("wrote ")?;
            let (path, rest) = rest.split_once(" (simulated time ")?;
            let time = rest.split_once(' ')?.0.parse().ok()?;
            Some((PathBuf::from(path), time))
        })
        .collect()
}

/// The share of pixels that are strongly red (the LOD view's level 20).
fn red_share(path: &Path) -> f64 {
    let img = image::open(path).unwrap().to_rgb8();
    let red = img
        .pixels()
        .filter(|p| p[0] > 120 && p[0] as u32 > 2 * p[1] as u32 + 20)
        .count();
    red as f64 / (img.width() * img.height()) as f64
}

/// Whether two pictures are the same, pixel for pixel: the same frame on
/// the same device is (the window's blit is 1:1, sRGB to sRGB; the
/// screenshot and `render` run the same passes on the same blades).
fn same_pixels(a: &Path, b: &Path) -> bool {
    image::open(a).unwrap().to_rgb8() == image::open(b).unwrap().to_rgb8()
}

#[test]
fn a_scripted_session_pauses_steps_switches_views_resizes_and_quits() {
    let x = Xvfb::start();
    let out = temp_out("viewer-session");
    // Times after the first frame. While paused at 1.0 s the window shows
    // one frame again and again: the test grabs it from the X screen.
    // The overlay is hidden first: the window is then the frame alone.
    let script = "\
        0.1 key o\n\
        0.8 key space\n\
        1.0 key p\n\
        6.0 key .\n\
        6.2 key p\n\
        6.4 key v\n\
        6.6 key p\n\
        6.8 resize 480 270\n\
        8.0 key p\n\
        8.2 key esc\n";
    let mut child = view(&x, script, &out);
    // The first screenshot (paused) is on disk: grab the window now.
    wait_for_file(&out.join("view_0000.png"), &mut child);
    let shot = image::open(out.join("view_0000.png")).unwrap().to_rgb8();
    grab_paused_frame(&x, &out, &shot, (0, 0, 320, 180));
    let grabbed = out.join("grabbed.png");
    let (_, stdout) = finished(child);

    let shots = screenshot_times(&stdout);
    assert_eq!(shots.len(), 4, "{stdout}");
    // Paused: the time stands; `.` is one 1/60 s step.
    let step = shots[1].1 - shots[0].1;
    assert!((step - 1.0 / 60.0).abs() < 1e-3, "{shots:?}");
    assert_eq!(shots[2].1, shots[1].1, "{shots:?}");
    // The window shows what P wrote (a blit of the same image).
    let window = common::mean_flip_of_files(&shots[0].0, &grabbed);
    assert!(
        same_pixels(&shots[0].0, &grabbed),
        "window vs screenshot: FLIP {window}"
    );
    // V switched to the LOD view: near blades turn red (level 20), which
    // no shaded pixel is.
    let (shaded, lod) = (red_share(&shots[1].0), red_share(&shots[2].0));
    assert!(
        shaded < 0.001 && lod > 0.02,
        "red share {shaded} then {lod}"
    );
    // After the resize, frames have the window's new size.
    let resized = image::open(&shots[3].0).unwrap();
    assert_eq!((resized.width(), resized.height()), (480, 270));

    // P's picture is `render`'s for the same time and camera.
    let render_out = out.join("render");
    let start = format!("{:.4}", shots[0].1);
    let mut args = vec!["render", "--validation", "--start", &start, "--out"];
    let render_dir = render_out.to_str().unwrap().to_string();
    args.push(&render_dir);
    args.extend(SMALL_SCENE);
    args.extend(SMALL_SIZE);
    let rendered = meadow(&args, &[]);
    assert!(
        rendered.status.success(),
        "{}",
        String::from_utf8_lossy(&rendered.stderr)
    );
    let same = common::mean_flip_of_files(&shots[0].0, &render_out.join("frame_0000.png"));
    assert!(
        same_pixels(&shots[0].0, &render_out.join("frame_0000.png")),
        "screenshot vs render: FLIP {same}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A screenshot never replaces a file: with `view_0000.png` already in
/// the folder (an earlier session's, or the user's), P writes
/// `view_0001.png` and leaves it alone.
#[test]
fn screenshots_continue_the_numbering_of_the_folder() {
    let x = Xvfb::start();
    let out = temp_out("viewer-numbering");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("view_0000.png"), "mine").unwrap();
    let mut child = view(&x, "0.3 key p\n0.6 key esc\n", &out);
    wait_for_file(&out.join("view_0001.png"), &mut child);
    let (_, stdout) = finished(child);
    let shots = screenshot_times(&stdout);
    assert_eq!(shots.len(), 1, "{stdout}");
    assert!(shots[0].0.ends_with("view_0001.png"), "{stdout}");
    image::open(out.join("view_0001.png")).expect("the screenshot decodes");
    assert_eq!(
        std::fs::read_to_string(out.join("view_0000.png")).unwrap(),
        "mine"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_overlay_covers_its_corner_and_the_wind_keys_and_a_click_act() {
    let x = Xvfb::start();
    let out = temp_out("viewer-overlay");
    let (width, height) = (640, 360);
    // Stronger inflow, turned heading, a click in front of the bunches,
    // paused; the grab then shows the frame P writes with the overlay on it.
    let script = "\
        0.2 key up\n\
        0.3 key left\n\
        0.4 click 320 300\n\
        0.6 click 320 10\n\
        0.8 key space\n\
        1.0 key p\n";
    let mut child = view_sized(&x, script, &out, (width, height));
    wait_for_file(&out.join("view_0000.png"), &mut child);
    let shot = image::open(out.join("view_0000.png")).unwrap().to_rgb8();
    let differs = |window: &image::RgbImage, x0: u32, y0: u32, x1: u32, y1: u32| {
        differing_share(&shot, window, (x0, y0, x1, y1))
    };
    let window = grab_paused_frame(
        &x,
        &out,
        &shot,
        (width / 2 + 60, height / 2 + 60, width, height),
    );
    let stdout = interrupted(child);
    // The click on the ground dropped a gust along the turned heading;
    // the one at the sky did not.
    assert!(stdout.contains("along 15 degrees"), "{stdout}");
    assert!(
        stdout.contains("no gust: the pointer is above the horizon"),
        "{stdout}"
    );

    // The panel sits in the top left corner; the rest of the window is
    // the frame, pixel for pixel.
    let corner = differs(&window, 20, 20, 120, 80);
    let rest = differs(&window, width / 2 + 60, height / 2 + 60, width, height);
    assert!(
        corner > 0.5,
        "the overlay does not cover its corner: {corner}"
    );
    assert_eq!(rest, 0.0, "the overlay spills over the frame");
    let _ = std::fs::remove_dir_all(&out);
}

/// In a 320 x 180 window the overlay collapses to two lines and a narrow
/// colour key, and the frame stays in sight; the keys' panel (H) is only
/// printed there. The debug views say what their colours mean, on the
/// terminal when the view changes, and a screenshot too small for its
/// key says it left the key out. The full panel covered the whole
/// window at this size and the keys went unsaid.
#[test]
fn a_small_window_keeps_the_frame_in_sight_and_the_keys_said() {
    let x = Xvfb::start();
    let out = temp_out("viewer-small");
    let (width, height) = (320, 180);
    let script = "\
        0.3 key v\n\
        0.5 key v\n\
        0.8 key space\n\
        1.2 key p\n";
    let mut child = view_sized(&x, script, &out, (width, height));
    wait_for_file(&out.join("view_0000.png"), &mut child);
    let shot = image::open(out.join("view_0000.png")).unwrap().to_rgb8();
    let differs = |window: &image::RgbImage, x0: u32, y0: u32, x1: u32, y1: u32| {
        differing_share(&shot, window, (x0, y0, x1, y1))
    };
    let window = grab_paused_frame(&x, &out, &shot, (100, 60, 220, 130));
    let stdout = interrupted(child);
    let covered = differs(&window, 0, 0, width, height);
    let middle = differs(&window, 100, 60, 220, 130);
    let key = differs(&window, width - 50, height - 20, width - 10, height - 6);
    assert!(
        covered < 0.25,
        "the overlay covers {covered:.2} of the window"
    );
    assert_eq!(middle, 0.0, "the overlay hides the middle of the frame");
    assert!(
        key > 0.3,
        "no colour key in the bottom right corner: {key:.2}"
    );
    for said in [
        "view lod: colour is the blade's tessellation, red 20 segments (close)",
        "view motion: colour is the tip's bend from rest, blue at 0 rad to red at 0.6 rad",
        "the motion view's key is left out of 320 x 180 frames",
    ] {
        assert!(stdout.contains(said), "{said:?} not said: {stdout}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn closing_the_window_ends_the_viewer_cleanly() {
    let x = Xvfb::start();
    let out = temp_out("viewer-close");
    let (_, stdout) = finished(view(&x, "0.5 close\n", &out));
    assert!(stdout.contains("showed "), "{stdout}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn without_a_display_the_viewer_says_so_in_one_line() {
    let out = temp_out("viewer-no-display");
    let result = Command::new(env!("CARGO_BIN_EXE_meadow"))
        .args(["view", "--out", out.to_str().unwrap()])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success());
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("meadow view needs a display") && stderr.contains("meadow render"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn a_bad_script_is_refused_before_the_window_opens() {
    let out = temp_out("viewer-bad-script");
    std::fs::create_dir_all(&out).unwrap();
    let script = out.join("s.txt");
    std::fs::write(&script, "1 key space\n2 jump\n").unwrap();
    let result = meadow(
        &["view", "--script", script.to_str().unwrap()],
        &[("DISPLAY", ":12345")],
    );
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success());
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("s.txt line 2: unknown action"), "{stderr}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn ctrl_c_closes_the_window_cleanly_with_the_signals_status() {
    let x = Xvfb::start();
    let out = temp_out("viewer-sigint");
    // Without a script's end: only the signal stops it.
    let child = view(&x, "", &out);
    std::thread::sleep(std::time::Duration::from_secs(4));
    send_sigint(&child);
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stdout}{stderr}");
    assert!(stdout.contains("validation: 0 errors"), "{stdout}{stderr}");
    assert!(stderr.contains("interrupted by SIGINT"), "{stderr}");
    let _ = std::fs::remove_dir_all(&out);
}

/// The centre (x, y) of the strongly red pixels (the ball's red gores) and
/// their share of the picture.
fn red_centre(path: &Path) -> Option<((f64, f64), f64)> {
    let img = image::open(path).unwrap().to_rgb8();
    let (mut n, mut sx, mut sy) = (0u32, 0.0f64, 0.0f64);
    for (x, y, p) in img.enumerate_pixels() {
        if p[0] > 120 && p[0] as u32 > 2 * p[1] as u32 + 20 {
            n += 1;
            sx += x as f64;
            sy += y as f64;
        }
    }
    let share = n as f64 / (img.width() * img.height()) as f64;
    (n > 0).then(|| ((sx / n as f64, sy / n as f64), share))
}

/// A pair "(x, z) m" after `prefix` on a line of `stdout`.
fn ground_after(stdout: &str, prefix: &str) -> (f64, f64) {
    let line = stdout
        .lines()
        .find_map(|l| l.split_once(prefix).map(|(_, rest)| rest))
        .unwrap_or_else(|| panic!("no {prefix:?} in {stdout}"));
    let inside = &line[line.find('(').unwrap() + 1..line.find(')').unwrap()];
    let (x, z) = inside.split_once(", ").unwrap();
    (x.parse().unwrap(), z.parse().unwrap())
}

/// B brings the ball onto the ground the window's middle looks at, drawn
/// there; a right click rolls it towards the ground under the pointer,
/// speeding up as `ACCELERATION` says; B takes it away again (validation
/// clean, with the ball's collider changing every frame).
#[test]
fn b_brings_a_ball_a_right_click_rolls_it_and_b_takes_it_away() {
    use meadow::commands::view::ball::{ACCELERATION, BALL_RADIUS};
    let x = Xvfb::start();
    let out = temp_out("viewer-ball");
    // After the right click, 30 single steps (`.`, paused): at least half
    // a second of simulated time however slow the frames come.
    let mut script =
        String::from("0.2 key p\n0.3 key b\n0.4 resize 300 170\n0.5 key p\n0.6 roll 215 125\n");
    for i in 0..30 {
        script += &format!("{:.2} key .\n", 0.7 + 0.01 * i as f64);
    }
    script += "1.5 key p\n1.6 key b\n1.7 key p\n1.8 key esc\n";
    let (_, stdout) = finished(view(&x, &script, &out));
    let shots = screenshot_times(&stdout);
    assert_eq!(shots.len(), 4, "{stdout}");

    // Before B no red; after it the ball sits in the middle of the
    // picture (its centre a radius above the ground point there), drawn
    // still after the window was resized (the new renderer keeps it).
    assert!(
        red_centre(&shots[0].0).is_none(),
        "red before the ball came"
    );
    let ((cx, cy), share) = red_centre(&shots[1].0).expect("the ball is drawn");
    assert_eq!(image::image_dimensions(&shots[1].0).unwrap(), (300, 170));
    // Measured: 0.08% (about 48 pixels at 320 x 180, partly behind a bunch).
    assert!(
        share > 0.0003,
        "the ball covers only {share} of the picture"
    );
    assert!(
        (cx - 150.0).abs() < 8.0 && (55.0..87.0).contains(&cy),
        "the ball's red is centred at ({cx}, {cy}), not the window's middle"
    );
    let brought = ground_after(&stdout, "ball at ");
    let goal = ground_after(&stdout, "ball rolling to ");
    let from_time: f64 = stdout
        .lines()
        .find_map(|l| {
            l.split_once(" m from t ")
                .map(|(_, t)| t.trim_end_matches(" s"))
        })
        .unwrap()
        .parse()
        .unwrap();

    // Rolled: along the way to the goal, as far as speeding up from rest
    // at ACCELERATION goes in the simulated time since. Each frame's
    // stretch takes the velocity reached at its start, so it runs ahead of
    // a t^2 / 2 by a h t / 2 at most, for frames of h <= 0.1 s of
    // simulated time (MAX_CATCH_UP_S).
    let line = stdout
        .lines()
        .find(|l| l.contains(shots[2].0.to_str().unwrap()))
        .unwrap();
    let now = ground_after(line, "ball at ");
    let moved = ((now.0 - brought.0).powi(2) + (now.1 - brought.1).powi(2)).sqrt();
    let way = (goal.0 - brought.0, goal.1 - brought.1);
    let along = ((now.0 - brought.0) * way.0 + (now.1 - brought.1) * way.1)
        / (way.0.hypot(way.1) * moved.max(1e-9));
    let t = shots[2].1 - from_time;
    let free = 0.5 * ACCELERATION as f64 * t * t;
    eprintln!(
        "ball: brought to {brought:?}, goal {goal:?}; {moved} m in {t} s (speeding up \
         from rest: {free} m), direction cosine {along}"
    );
    assert!(
        t >= 0.49,
        "too little simulated time ({t} s) to see it roll"
    );
    assert!(along > 0.999, "it rolled off its way: cosine {along}");
    let ahead = 0.5 * ACCELERATION as f64 * meadow::commands::view::MAX_CATCH_UP_S * t;
    assert!(
        moved >= free - 1e-4 && moved <= free + ahead + 1e-4,
        "{moved} m in {t} s; speeding up at {ACCELERATION} m/s^2 from rest gives {free} m \
         (up to {ahead} m more in frames)"
    );
    assert!(moved < way.0.hypot(way.1) + 1e-3 && BALL_RADIUS > 0.0);

    // Taken away: no red again.
    assert!(stdout.contains("ball taken away"), "{stdout}");
    assert!(red_centre(&shots[3].0).is_none(), "the ball is still drawn");
    let _ = std::fs::remove_dir_all(&out);
}
