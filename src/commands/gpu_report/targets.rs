//! The GPU targets of docs/perf.md against what a run measured: each met,
//! missed, or not measured and why.

use super::*;

/// The targets of docs/perf.md (issue 41) against this run's figures; a
/// target whose configuration this run did not measure (`--quick`, a part
/// that failed, a device without timestamps) says so and is neither met
/// nor missed.
pub(super) fn targets(
    p: &Plan,
    bench: &Outcome<Bench>,
    grass: &Outcome<GrassBench>,
    colliders: &Outcome<GrassBench>,
    wind: &Outcome<WindReport>,
) -> Vec<Target> {
    let (ms_200k, note_200k) = frame_ms(bench, 200_000);
    let (ms_1m, note_1m) = frame_ms(bench, 1_000_000);
    vec![
        target(
            "frame_200k",
            "200K blades, 1280x720, 8x MSAA, 8192 shadow map, LOD and culling on: a frame in at most 9 ms",
            ms_200k,
            "ms",
            |v| v <= 9.0,
            note_200k,
        ),
        target(
            "fps_1m",
            "1M blades, the same settings: at least 60 frames a second (GPU frame)",
            ms_1m.map(|ms| 1000.0 / ms),
            "FPS",
            |v| v >= 60.0,
            note_1m,
        ),
        wind_target(p, wind),
        floor_target(p, grass),
        colliders_target(p, colliders),
    ]
}

/// Why `b` was not run at the frame targets' size, if it was not.
fn off_size(b: &Bench) -> Option<String> {
    if (b.width, b.height, b.shadow_map) != (1280, 720, 8192) {
        Some(format!(
            "run at {}x{} with a {} shadow map, not the target's 1280x720 and 8192",
            b.width, b.height, b.shadow_map
        ))
    } else if b.msaa_used != 8 {
        Some(format!("the device gives {}x MSAA, not 8x", b.msaa_used))
    } else {
        None
    }
}

/// The GPU frame's median at `blades` with LOD and culling on, and where
/// it comes from (or why there is none).
fn frame_ms(bench: &Outcome<Bench>, blades: usize) -> (Option<f64>, String) {
    let Some(b) = bench.ran() else {
        return (None, "bench failed".into());
    };
    let row = b
        .rows
        .iter()
        .find(|r| r.blades == blades && r.lod && r.cull);
    // Beside the drawing the frame's span is the drawing's: the steps on
    // their queue bound the frame too, so the frame is the longer of the two.
    let ms = row.and_then(|r| {
        let gpu = r.timing.gpu_ms.as_ref()?;
        let frame = gpu.frame?.median;
        Some(match r.overlap {
            "off" => frame,
            _ => frame.max(gpu.wind?.median + gpu.grass?.median),
        })
    });
    let how = match row.map(|r| r.overlap) {
        Some("off") | None => "GPU frame".to_string(),
        Some(queues) => {
            format!("the longer of the drawing's span and the steps beside it ({queues})")
        }
    };
    match (row, ms, off_size(b)) {
        (None, _, _) => (None, format!("not run at {blades} blades")),
        (_, None, _) => (None, "no GPU timestamps".into()),
        (_, Some(ms), None) => (
            Some(ms),
            format!("bench: {how}, median of {} frames", b.rows[0].frames),
        ),
        (_, Some(_), Some(why)) => (None, why),
    }
}

/// The multigrid wind step on table1's grid.
fn wind_target(p: &Plan, wind: &Outcome<WindReport>) -> Target {
    let mg = wind.ran().and_then(|w| {
        w.solvers
            .iter()
            .find(|s| s.solver == PressureSolver::Multigrid)
    });
    target(
        "wind_multigrid_ms",
        "the multigrid wind step (table1's 60x20x60 grid): at most 0.15 ms",
        mg.and_then(|s| s.step_ms_median).filter(|_| !p.quick),
        "ms",
        |v| v <= 0.15,
        match mg {
            None => "wind failed".into(),
            Some(_) if p.quick => format!("{} steps only (--quick)", p.wind_steps),
            Some(s) => format!(
                "wind: median of {} steps, {} V-cycles",
                s.steps, s.iterations
            ),
        },
    )
}

/// The grass step against its memory floor, at its worst count.
fn floor_target(p: &Plan, grass: &Outcome<GrassBench>) -> Target {
    let worst_floor = grass.ran().and_then(|g| {
        g.rows
            .iter()
            .filter_map(|r| r.over_floor.map(|f| (r.blades, f)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    });
    target(
        "grass_over_floor",
        "the grass step within 3x its memory floor at every count",
        worst_floor.map(|(_, f)| f).filter(|_| !p.quick),
        "x",
        |v| v <= 3.0,
        match worst_floor {
            None => "bench-grass failed or has no floor (no timestamps)".into(),
            Some(_) if p.quick => "small counts only (--quick)".into(),
            Some((n, _)) => format!("bench-grass: the largest ratio, at {n} blades"),
        },
    )
}

/// The grass step with 128 colliders against the collider-free one.
fn colliders_target(p: &Plan, colliders: &Outcome<GrassBench>) -> Target {
    let with_128 = colliders.ran().and_then(|g| {
        g.rows
            .iter()
            .filter(|r| r.colliders == 128)
            .max_by_key(|r| r.blades)
    });
    target(
        "colliders_128",
        "128 colliders: a grass step at most 1.5x the collider-free one",
        with_128
            .and_then(|r| r.over_collider_free)
            .filter(|_| !p.quick),
        "x",
        |v| v <= 1.5,
        match with_128 {
            None => "not run with 128 colliders".into(),
            Some(_) if p.quick => "small counts only (--quick)".into(),
            Some(r) => format!("bench-grass --colliders: at {} blades", r.blades),
        },
    )
}

fn target(
    name: &str,
    wording: &str,
    measured: Option<f64>,
    unit: &str,
    meets: impl Fn(f64) -> bool,
    note: String,
) -> Target {
    Target {
        name: name.to_string(),
        target: wording.to_string(),
        measured,
        unit: unit.to_string(),
        met: measured.map(meets),
        note,
    }
}
