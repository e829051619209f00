//! Every command line path through the `meadow` binary with the validation
//! layer's core, synchronization and best-practices checks on: no error,
//! and no best-practices warning that docs/validation.md does not accept
//! (its "Accepted" table is read here, so the document and the layer's
//! output cannot drift apart).

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::binary::{meadow, temp_out};
use meadow::scene::BUILTIN;

/// The message IDs docs/validation.md accepts: the first cell of each row
/// of its "### Accepted" table.
fn accepted_warnings() -> Vec<String> {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/validation.md"))
        .unwrap();
    let table = doc
        .split("### Accepted")
        .nth(1)
        .and_then(|rest| rest.split("\n### ").next())
        .expect("docs/validation.md has an Accepted section");
    let ids: Vec<String> = table
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .map(|l| l[..l.find('`').unwrap()].to_string())
        .collect();
    assert!(!ids.is_empty(), "no accepted IDs parsed");
    ids
}

/// Every warning ID seen, with where.
#[derive(Default)]
struct Seen(BTreeMap<String, Vec<String>>);

impl Seen {
    /// Checks one report's `validation`: enabled, no error; records the
    /// warning IDs.
    fn report(&mut self, case: &str, path: &Path) {
        let json: serde_json::Value = serde_json::from_slice(
            &std::fs::read(path).unwrap_or_else(|e| panic!("{case}: {}: {e}", path.display())),
        )
        .unwrap();
        let v = &json["validation"];
        assert_eq!(v["enabled"], true, "{case}: validation was off");
        assert_eq!(v["errors"], 0, "{case}: {:#}", v["messages"]);
        for m in v["messages"].as_array().unwrap() {
            let id = m["id"].as_str().unwrap().to_string();
            self.0.entry(id).or_default().push(case.to_string());
        }
    }

    /// Fails naming every warning ID seen that docs/validation.md does not
    /// accept, and where it was seen.
    fn assert_accepted(&self) {
        let accepted = accepted_warnings();
        let unaccepted: Vec<String> = self
            .0
            .iter()
            .filter(|(id, _)| !accepted.contains(id))
            .map(|(id, cases)| format!("{id} (in {})", cases.join(", ")))
            .collect();
        assert!(
            unaccepted.is_empty(),
            "best-practices warnings docs/validation.md does not accept: {unaccepted:#?}"
        );
    }
}

/// Runs `meadow args --validation --best-practices [--out DIR]`, asserting
/// success.
fn run(case: &str, args: &[&str], env: &[(&str, &str)], out: Option<&Path>) {
    let mut full: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    full.extend(["--validation".into(), "--best-practices".into()]);
    if let Ok(device) = std::env::var("MEADOW_TEST_DEVICE") {
        full.extend(["--device".into(), device]);
    }
    if let Some(out) = out {
        full.extend(["--out".into(), out.to_str().unwrap().into()]);
    }
    let full: Vec<&str> = full.iter().map(String::as_str).collect();
    let result = meadow(&full, env);
    assert!(
        result.status.success(),
        "{case}: {}",
        String::from_utf8_lossy(&result.stderr)
    );
}

fn scene_file(name: &str) -> String {
    format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_command_line_path_is_validation_clean_with_best_practices() {
    let base = temp_out("validation-matrix");
    let mut seen = Seen::default();
    let small = ["--width", "96", "--height", "64"];
    let mut case = 0;
    let mut render = |name: &str, args: &[&str], env: &[(&str, &str)], seen: &mut Seen| {
        case += 1;
        let out: PathBuf = base.join(format!("render-{case}"));
        let mut full = vec!["render"];
        full.extend(small);
        full.extend(args);
        run(name, &full, env, Some(&out));
        seen.report(name, &out.join("report.json"));
    };

    // Every shipped scene file, one frame (honami at its start: its own
    // 6 s of 216,000 blades take minutes on lavapipe, down the same path;
    // one frame measures no light waves). Each at its own blade count but
    // prairie: its 2 million blades are there to run the grass and cull
    // kernels in batches (more than lavapipe lets one binding reach), and
    // 60,000 blades with bindings held to 4.5 MiB (its wind grid's binding
    // is 4.3 MB) run them in two, down the same path in a seventh of the
    // time.
    for (scene, _) in BUILTIN {
        let path = scene_file(scene);
        let mut args = vec!["--scene", path.as_str(), "--frames", "1"];
        let mut env = Vec::new();
        if *scene == "honami" {
            args.extend(["--start", "0"]);
        }
        if *scene == "prairie" {
            args.extend(["--blades", "60000"]);
            env.push(("MEADOW_STORAGE_RANGE", "4718592"));
        }
        render(scene, &args, &env, &mut seen);
    }
    let few = scene_file("fig10-few-bunches");
    let lod = scene_file("fig12-lod");
    render(
        "animated, GIF",
        &["--scene", &few, "--frames", "3", "--fps", "10"],
        &[],
        &mut seen,
    );
    render(
        "every 2nd frame",
        &["--scene", &few, "--frames", "4", "--every", "2"],
        &[],
        &mut seen,
    );
    // fig12's 20 x 20 m at 4,000 blades (of its 100,000) still has blades
    // at every level of detail.
    for (lod_flag, view) in [
        ("on", "lod"),
        ("off", "lod"),
        ("on", "shaded"),
        ("off", "motion"),
    ] {
        render(
            &format!("--lod {lod_flag} --view {view}"),
            &[
                "--scene", &lod, "--blades", "4000", "--frames", "2", "--fps", "5", "--lod",
                lod_flag, "--view", view,
            ],
            &[],
            &mut seen,
        );
    }
    render(
        "--msaa 1",
        &["--scene", &few, "--msaa", "1"],
        &[],
        &mut seen,
    );
    render(
        "--shadow-map 0",
        &["--scene", &few, "--shadow-map", "0"],
        &[],
        &mut seen,
    );
    render(
        "--cull on",
        &["--scene", &few, "--frames", "2", "--cull", "on"],
        &[],
        &mut seen,
    );
    // Occlusion culling (off by default): the depth pyramid built from the
    // multisampled depth and, at 1x, from the single-sample one, and read
    // by the next frame's cull pass.
    for msaa in ["4", "1"] {
        render(
            &format!("--occlusion on --msaa {msaa}"),
            &[
                "--scene",
                &few,
                "--frames",
                "2",
                "--occlusion",
                "on",
                "--msaa",
                msaa,
            ],
            &[],
            &mut seen,
        );
    }
    render(
        "no timestamps or statistics",
        &["--scene", &few, "--frames", "2"],
        &[(
            "MEADOW_PRETEND_MISSING",
            "timestamps,pipelineStatisticsQuery",
        )],
        &mut seen,
    );

    let mut command = |name: &str, args: &[&str], report: &str| {
        let out = base.join(name);
        run(name, args, &[], Some(&out));
        seen.report(name, &out.join(report));
    };
    command(
        "wind",
        &["wind", "--scene", "fig13-obstacles", "--steps", "5"],
        "wind_report.json",
    );
    // Two-way: the grass steps with the wind, laying its frontal area.
    command(
        "wind-two-way",
        &[
            "wind",
            "--scene",
            "fig13-obstacles",
            "--steps",
            "5",
            "--coupling",
            "two-way",
            "--cells",
            "30,10,30",
        ],
        "wind_report.json",
    );
    command(
        "bench",
        &[
            "bench", "--blades", "1k,2k", "--lod", "both", "--frames", "2", "--warmup", "1",
            "--width", "96", "--height", "64", "--cells", "12,6,12",
        ],
        "bench.json",
    );
    command(
        "bench-grass",
        &[
            "bench-grass",
            "--blades",
            "1k",
            "--steps",
            "2",
            "--warmup",
            "1",
            "--wind-warmup",
            "2",
        ],
        "grass_bench.json",
    );
    run("devices", &["devices"], &[], None);

    seen.assert_accepted();
    for (id, cases) in &seen.0 {
        eprintln!("accepted {id}: {} cases", cases.len());
    }
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn reproduce_quick_renders_every_figure_validation_clean_with_both_indexes() {
    let out = temp_out("reproduce");
    run("reproduce", &["reproduce", "--quick"], &[], Some(&out));
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for title in [
        "Fig. 10 (left)",
        "Fig. 10 (right)",
        "Fig. 11",
        "Fig. 12",
        "Fig. 13",
        "Beyond the paper: gusts that travel",
        "Beyond the paper: turbulence everywhere",
        "Beyond the paper: waves of light",
        "Beyond the paper: touch",
        "Beyond the paper: a landscape",
        "Beyond the paper: grass without edges",
    ] {
        assert!(
            md.contains(&format!("## {title}")),
            "index.md lacks {title}"
        );
        assert!(
            html.contains(&format!("<h2>{title}")),
            "index.html lacks {title}"
        );
    }
    // Every image index.md links exists and decodes; index.html inlines
    // each one (it is self-contained: no file links).
    let links: Vec<&str> = md
        .split("](")
        .skip(1)
        .map(|rest| &rest[..rest.find(')').unwrap()])
        .collect();
    // 29 shots' frames (steppe's flight three of them, honami's two four
    // each), the GIFs of the four shots of several frames, the flight's
    // video (scripts/test installs ffmpeg), the gust strip's space-time
    // diagram and the turbulent field's plan view and spectrum.
    assert_eq!(links.len(), 37, "{links:?}");
    let (gifs, links): (Vec<&str>, Vec<&str>) = links.iter().partition(|l| l.ends_with(".gif"));
    assert_eq!(
        gifs,
        [
            "fig11/animation.gif",
            "honami/shaded/animation.gif",
            "honami/motion/animation.gif",
            "steppe/animation.gif"
        ]
    );
    for gif in &gifs {
        let frames = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
            std::fs::File::open(out.join(gif)).unwrap(),
        ))
        .map(|d| image::AnimationDecoder::into_frames(d).count())
        .unwrap_or_else(|e| panic!("{gif}: {e}"));
        assert!(frames >= 3, "{gif}: {frames} frames");
    }
    assert_eq!(html.matches("src=\"data:image/gif;base64,").count(), 4);
    // honami's shaded shot measures its waves of light.
    assert!(
        md.contains("light waves: over 4 frames"),
        "honami's light waves"
    );
    let (videos, links): (Vec<&str>, Vec<&str>) = links.iter().partition(|l| l.ends_with(".mp4"));
    assert_eq!(videos, ["steppe/flight.mp4"]);
    let mp4 = std::fs::read(out.join(videos[0])).unwrap();
    assert!(mp4.len() > 1000 && &mp4[4..8] == b"ftyp", "an MP4 file");
    assert_eq!(html.matches("src=\"data:video/mp4;base64,").count(), 1);
    let (svgs, pngs): (Vec<&str>, Vec<&str>) = links.iter().partition(|l| l.ends_with(".svg"));
    assert_eq!(
        svgs,
        [
            "gusts/space_time.svg",
            "turbulence/plan_view.svg",
            "turbulence/spectrum.svg"
        ]
    );
    for link in &pngs {
        image::open(out.join(link)).unwrap_or_else(|e| panic!("{link}: {e}"));
    }
    // Each diagram is XML with its axes labelled; the plan view has its
    // three instants.
    for (svg, axis) in svgs
        .iter()
        .zip(["time (s)", "x, along the wind (m)", "frequency (Hz)"])
    {
        let text = std::fs::read_to_string(out.join(svg)).unwrap();
        roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{svg}: {e}"));
        assert!(text.contains(axis), "{svg}: the axes are labelled");
    }
    let plan = std::fs::read_to_string(out.join(svgs[1])).unwrap();
    for t in ["t = 8.0 s", "t = 9.0 s", "t = 10.0 s"] {
        assert!(plan.contains(t), "{t}");
    }
    assert_eq!(
        html.matches("src=\"data:image/png;base64,").count(),
        pngs.len()
    );
    assert_eq!(html.matches("src=\"data:image/svg+xml;base64,").count(), 3);
    assert!(!html.contains(".png\""), "index.html links a file");
    assert!(md.contains("MSAA") && md.contains("V-cycles"));
    assert!(md.contains("angle caps"));

    // Each shot's own report: validation clean, warnings accepted.
    let mut seen = Seen::default();
    let mut shots = 0;
    let mut dirs = vec![out.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.file_name().unwrap() == "report.json" {
                seen.report(&path.display().to_string(), &path);
                shots += 1;
            }
        }
    }
    assert_eq!(shots, 19, "one report per shot");
    seen.assert_accepted();
    let _ = std::fs::remove_dir_all(&out);
}
