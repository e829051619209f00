//! The pressure solvers side by side, as `wind` and `bench` report them.

use crate::model::wind::PressureSolver;

/// One pressure solver timed on a scene's wind: `bench` and `wind` report
/// both, side by side.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SolverTiming {
    pub solver: PressureSolver,
    /// V-cycles (multigrid) or iterations (Jacobi) per step.
    pub iterations: u32,
    pub steps: u32,
    /// GPU time of one whole wind step (forces, advection, projection), ms;
    /// None where the device has no timestamps.
    pub step_ms_median: Option<f64>,
    pub step_ms_p95: Option<f64>,
    /// RMS divergence of the last step, before and after projection (1/s).
    pub rms_divergence_before: f32,
    pub rms_divergence_after: f32,
}

/// The scene's wind step with its turbulence and without it, over the
/// same steps in one run: what the turbulence costs.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TurbulenceTiming {
    pub steps: u32,
    /// GPU time of one whole wind step, ms (median; None where the device
    /// has no timestamps).
    pub step_ms_median_with: Option<f64>,
    pub step_ms_median_without: Option<f64>,
    /// with / without.
    pub ratio: Option<f64>,
}

/// The scene's wind step with each advection over the same steps in one
/// run: what MacCormack's corrector (the default) costs over the paper's
/// semi-Lagrangian step.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdvectionTiming {
    pub steps: u32,
    /// GPU time of one whole wind step, ms (median; None where the device
    /// has no timestamps).
    pub step_ms_median_maccormack: Option<f64>,
    pub step_ms_median_semi_lagrangian: Option<f64>,
    /// maccormack / semi-lagrangian.
    pub ratio: Option<f64>,
}

impl AdvectionTiming {
    /// From the median step (ms) with each scheme.
    pub fn new(steps: u32, mac: Option<f64>, semi: Option<f64>) -> Self {
        AdvectionTiming {
            steps,
            step_ms_median_maccormack: mac,
            step_ms_median_semi_lagrangian: semi,
            ratio: mac.zip(semi).map(|(m, s)| m / s),
        }
    }
}

/// "multigrid, at most 6 V-cycles" or "30 Jacobi iterations": what one step's
/// projection runs.
pub fn describe(solver: PressureSolver, jacobi_iterations: u32, v_cycles: u32) -> String {
    match solver {
        PressureSolver::Multigrid => format!("multigrid, at most {v_cycles} V-cycles"),
        PressureSolver::Jacobi => format!("{jacobi_iterations} Jacobi iterations"),
    }
}

/// A markdown table of the solvers: cost and what each leaves.
pub fn markdown(timings: &[SolverTiming]) -> String {
    let mut md = String::from(
        "| solver | per step | wind step ms (median) | p95 | rms divergence before -> after (1/s) | left |\n\
         |---|---|---|---|---|---|\n",
    );
    for t in timings {
        let ms = |v: Option<f64>| v.map_or("n/a".to_string(), |v| format!("{v:.3}"));
        let per_step = match t.solver {
            PressureSolver::Multigrid => format!("{} V-cycles", t.iterations),
            PressureSolver::Jacobi => format!("{} iterations", t.iterations),
        };
        md += &format!(
            "| {} | {per_step} | {} | {} | {:.3e} -> {:.3e} | {:.2}% |\n",
            t.solver.name(),
            ms(t.step_ms_median),
            ms(t.step_ms_p95),
            t.rms_divergence_before,
            t.rms_divergence_after,
            t.share_left() * 100.0,
        );
    }
    md
}

impl SolverTiming {
    /// The share of the divergence the projection left on the last step.
    pub fn share_left(&self) -> f32 {
        self.rms_divergence_after / self.rms_divergence_before.max(f32::MIN_POSITIVE)
    }
}
