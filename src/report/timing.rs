//! The per-phase timing table `meadow render` prints.

use crate::frame::timing::{Phase, TimingSummary};

/// A short table of `summary` for the terminal.
pub fn table(summary: &TimingSummary) -> String {
    let mut out = String::new();
    match &summary.gpu_ms {
        Some(g) => {
            out += &format!(
                "GPU ms per frame over {} frames (timestamps): phase, median, p95\n",
                summary.frames
            );
            for p in Phase::ALL {
                out += &match g.get(p) {
                    Some(s) => format!("  {:<11} {:>9.3} {:>9.3}\n", p.name(), s.median, s.p95),
                    None => format!(
                        "  {:<11} unavailable: {}\n",
                        p.name(),
                        summary
                            .phases_unavailable
                            .get(p.name())
                            .map_or("not timed", String::as_str)
                    ),
                };
            }
        }
        None => {
            out += &format!(
                "GPU time per phase: unavailable ({})\n",
                summary.gpu_unavailable.as_deref().unwrap_or("unknown")
            );
        }
    }
    if let (Some(w), Some(fps)) = (summary.wall_frame_ms, summary.fps) {
        out += &format!(
            "wall clock per frame: median {:.3} ms, p95 {:.3} ms ({fps:.2} FPS)\n",
            w.median, w.p95
        );
    }
    out
}
