//! docs/bench/<device>.md: the report's figures as tables, the targets
//! first.

use super::*;

fn ms(v: Option<f64>) -> String {
    v.map_or("n/a".to_string(), |v| {
        if v < 1.0 {
            format!("{v:.3}")
        } else {
            format!("{v:.2}")
        }
    })
}

/// docs/bench/<device>.md: the targets first, then each part's table.
pub(super) fn markdown(r: &GpuReport, p: &Plan) -> String {
    let mut md = format!("# meadow GPU report: {}\n\n", r.device);
    md += &format!(
        "Device: {} ({}), driver {}, Vulkan {}. meadow {} built from commit {}; run ended {} \
         and took {:.0} s{}.\n\n",
        r.device,
        r.device_type,
        r.driver,
        r.api_version,
        r.meadow_version,
        r.commit,
        r.date,
        r.wall_seconds,
        if r.quick {
            "; **--quick**: reduced sizes, not the targets' (a check that the report runs, not figures to quote)"
        } else {
            ""
        }
    );
    md += "## Targets (docs/perf.md)\n\n| target | measured | met |\n|---|---|---|\n";
    for t in &r.targets {
        let measured = t.measured.map_or(format!("not measured: {}", t.note), |v| {
            format!("{v:.3} {} ({})", t.unit, t.note)
        });
        let met = match t.met {
            Some(true) => "yes",
            Some(false) => "**no**",
            None => "-",
        };
        md += &format!("| {} | {measured} | {met} |\n", t.target);
    }
    md += &frame_section(&r.bench, p);
    md += "\n## The grass step and its memory floor (`bench-grass`, table1)\n\n";
    md += &grass_table(&r.grass);
    md += "\n## The grass step with colliders (`bench-grass --colliders`)\n\n";
    md += &grass_table(&r.colliders);
    md += &wind_section(r);
    md += &frames_section(&r.frames);
    md += "\n## Under validation (core and synchronization)\n\n| command | errors | warnings |\n|---|---|---|\n";
    for v in &r.validation {
        match &v.outcome {
            Outcome::Ran(c) => {
                md += &format!("| `{}` | {} | {} |\n", v.command, c.errors, c.warnings)
            }
            Outcome::Failed(e) => md += &format!("| `{}` | failed: {e} | |\n", v.command),
        }
    }
    md
}

/// The frame's section: `bench`'s rows on table1.
fn frame_section(bench: &Outcome<Bench>, p: &Plan) -> String {
    let mut md = String::new();
    md += "\n## The frame (`bench`, table1)\n\n";
    match bench {
        Outcome::Ran(b) => {
            md += &format!(
                "{}x{}, MSAA {}x used ({}x asked), shadow map {}; {} warm-up and {} timed frames \
                 per row, one simulation step each; GPU ms are medians of timestamp queries.\n\n",
                b.width,
                b.height,
                b.msaa_used,
                b.msaa_requested,
                b.shadow_map,
                p.bench_warmup,
                p.bench_frames
            );
            md += "| blades | LOD | culling | wind | grass | cull | shadow | colour | GPU frame ms | FPS (GPU) | FPS (wall) | triangles |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
            for row in &b.rows {
                let frame = row.timing.gpu_ms.as_ref().and_then(|g| g.frame);
                let frame = frame.map(|s| s.median);
                md += &format!(
                    "| {} | {} | {} | {} | {} | {} | {} |\n",
                    row.blades,
                    on_off(row.lod),
                    on_off(row.cull),
                    phase_medians(&row.timing),
                    frame.map_or("n/a".into(), |f| format!("{:.1}", 1000.0 / f)),
                    row.timing.fps.map_or("n/a".into(), |f| format!("{f:.1}")),
                    row.triangles.map_or("n/a".into(), |t| t.to_string())
                );
            }
        }
        Outcome::Failed(e) => md += &format!("Failed: {e}\n"),
    }
    md
}

/// The wind step's section: each solver, one-way and two-way.
fn wind_section(r: &GpuReport) -> String {
    let mut md = String::new();
    md += "\n## The wind step (`wind`, table1's 60x20x60 grid)\n\n";
    md += "| coupling | solver | per step | median ms | p95 ms | steps | RMS divergence after |\n|---|---|---|---|---|---|---|\n";
    for (coupling, w) in [("one-way", &r.wind), ("two-way", &r.wind_two_way)] {
        match w {
            Outcome::Ran(w) => {
                for s in &w.solvers {
                    md += &format!(
                        "| {coupling} | {:?} | {} | {} | {} | {} | {:.2e} |\n",
                        s.solver,
                        s.iterations,
                        ms(s.step_ms_median),
                        ms(s.step_ms_p95),
                        s.steps,
                        s.rms_divergence_after
                    );
                }
            }
            Outcome::Failed(e) => md += &format!("| {coupling} | failed: {e} | | | | | |\n"),
        }
    }
    md
}

/// The shipped scenes' frames through `render`.
fn frames_section(frames: &[Outcome<SceneFrames>]) -> String {
    let mut md = String::new();
    md += "\n## Frames of shipped scenes (`render`)\n\n";
    md += "| scene | blades | size | MSAA | frames | wind | grass | cull | shadow | colour | GPU frame ms | FPS (wall) |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for f in frames {
        match f {
            Outcome::Ran(f) => {
                md += &format!(
                    "| {} | {} | {}x{} | {}x | {} | {} | {} |\n",
                    f.scene,
                    f.blades,
                    f.width,
                    f.height,
                    f.msaa_used,
                    f.frames,
                    phase_medians(&f.timing),
                    f.timing.fps.map_or("n/a".into(), |v| format!("{v:.1}"))
                );
            }
            Outcome::Failed(e) => md += &format!("| failed: {e} | | | | | | | | | | | |\n"),
        }
    }
    md
}

/// "wind | grass | cull | shadow | colour | frame": each phase's median GPU
/// ms, or n/a.
fn phase_medians(timing: &TimingSummary) -> String {
    let g = timing.gpu_ms.as_ref();
    [
        g.and_then(|g| g.wind),
        g.and_then(|g| g.grass),
        g.and_then(|g| g.cull),
    ]
    .into_iter()
    .chain([
        g.and_then(|g| g.shadow),
        g.and_then(|g| g.color),
        g.and_then(|g| g.frame),
    ])
    .map(|s| ms(s.map(|s| s.median)))
    .collect::<Vec<_>>()
    .join(" | ")
}

fn on_off(v: bool) -> &'static str {
    if v {
        "on"
    } else {
        "off"
    }
}

fn grass_table(g: &Outcome<GrassBench>) -> String {
    let g = match g {
        Outcome::Ran(g) => g,
        Outcome::Failed(e) => return format!("Failed: {e}\n"),
    };
    let mut md = match &g.copy_bandwidth {
        Some(c) => format!(
            "Memory floor: the bytes a step must read and write at this device's copy bandwidth, \
             {:.1} GB/s (median of {} copies of {} MiB).\n\n",
            c.gb_per_s,
            c.copies,
            c.bytes >> 20
        ),
        None => "Memory floor: n/a (no timestamps on this device).\n\n".to_string(),
    };
    md += "| blades | colliders | median ms | p95 ms | MB / step | floor ms | step / floor | x collider-free |\n|---|---|---|---|---|---|---|---|\n";
    for r in &g.rows {
        md += &format!(
            "| {} | {} | {} | {} | {:.1} | {} | {} | {} |\n",
            r.blades,
            r.colliders,
            ms(r.step_ms_median),
            ms(r.step_ms_p95),
            r.bytes_per_step as f64 / 1e6,
            ms(r.floor_ms),
            r.over_floor.map_or("n/a".into(), |v| format!("{v:.2}x")),
            r.over_collider_free
                .map_or("-".into(), |v| format!("{v:.2}x"))
        );
    }
    md
}
