//! The phases of a frame and their GPU times: what the frame recorder
//! brackets with timestamps, summed per frame and summarised over a run.
//! Plain data; the queries are `gpu::query`'s, the tables `report`'s.

/// The phases of a frame that are timed apart. `GrassDraw` lies inside
/// `Color` (the blade draw alone, without sky and ground, for the floor
/// comparison); `Frame` spans everything.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Wind solver steps (forces, advection, divergence, Jacobi, projection).
    Wind,
    /// Grass dynamics steps (swing, bend, twist).
    Grass,
    /// The cover's tiles made around the camera (`[grass.cover]`).
    Cover,
    /// The cull pass: which blades the shadow and colour passes draw.
    Cull,
    /// The depth-only pass from the sun into the shadow map.
    Shadow,
    /// Sky, ground and grass into the multisampled image, resolved at the
    /// end of the pass.
    Color,
    /// The blade draw alone (vert/tesc/tese/geom/frag), inside `Color`.
    GrassDraw,
    /// The copy of the resolved image into the host-visible buffer.
    Readback,
    /// From the first command of the frame to the last.
    Frame,
}

impl Phase {
    pub const ALL: [Phase; 9] = [
        Phase::Wind,
        Phase::Grass,
        Phase::Cover,
        Phase::Cull,
        Phase::Shadow,
        Phase::Color,
        Phase::GrassDraw,
        Phase::Readback,
        Phase::Frame,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Phase::Wind => "wind",
            Phase::Grass => "grass",
            Phase::Cover => "cover",
            Phase::Cull => "cull",
            Phase::Shadow => "shadow",
            Phase::Color => "colour",
            Phase::GrassDraw => "grass_draw",
            Phase::Readback => "readback",
            Phase::Frame => "frame",
        }
    }
}

/// One value per phase of a frame, named as the phases are in reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PerPhase<T> {
    pub wind: T,
    pub grass: T,
    pub cover: T,
    pub cull: T,
    pub shadow: T,
    #[serde(rename = "colour")]
    pub color: T,
    pub grass_draw: T,
    pub readback: T,
    pub frame: T,
}

impl<T> PerPhase<T> {
    /// Each phase's value from `f`.
    pub fn from_fn(mut f: impl FnMut(Phase) -> T) -> Self {
        Self {
            wind: f(Phase::Wind),
            grass: f(Phase::Grass),
            cover: f(Phase::Cover),
            cull: f(Phase::Cull),
            shadow: f(Phase::Shadow),
            color: f(Phase::Color),
            grass_draw: f(Phase::GrassDraw),
            readback: f(Phase::Readback),
            frame: f(Phase::Frame),
        }
    }

    pub fn get_mut(&mut self, phase: Phase) -> &mut T {
        match phase {
            Phase::Wind => &mut self.wind,
            Phase::Grass => &mut self.grass,
            Phase::Cover => &mut self.cover,
            Phase::Cull => &mut self.cull,
            Phase::Shadow => &mut self.shadow,
            Phase::Color => &mut self.color,
            Phase::GrassDraw => &mut self.grass_draw,
            Phase::Readback => &mut self.readback,
            Phase::Frame => &mut self.frame,
        }
    }
}

impl<T: Copy> PerPhase<T> {
    pub fn get(&self, phase: Phase) -> T {
        match phase {
            Phase::Wind => self.wind,
            Phase::Grass => self.grass,
            Phase::Cover => self.cover,
            Phase::Cull => self.cull,
            Phase::Shadow => self.shadow,
            Phase::Color => self.color,
            Phase::GrassDraw => self.grass_draw,
            Phase::Readback => self.readback,
            Phase::Frame => self.frame,
        }
    }
}

/// GPU milliseconds of one frame per phase (a phase recorded several times,
/// such as one wind step per simulation step, is summed; one not recorded
/// is 0: a frame with no simulation step has no wind work).
pub type FrameTimings = PerPhase<f64>;

/// Median and 95th percentile of one quantity over many frames.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spread {
    pub median: f64,
    pub p95: f64,
}

impl Spread {
    pub fn of(values: &[f64]) -> Option<Self> {
        median_p95(values).map(|(median, p95)| Self { median, p95 })
    }
}

/// Median and 95th percentile of a set of timings.
pub fn median_p95(values: &[f64]) -> Option<(f64, f64)> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    Some((at(0.5), at(0.95)))
}

/// Median and p95 GPU ms of each phase over a run of frames; None for a
/// phase this device cannot time (`TimingSummary::phases_unavailable`).
pub type PhaseSpreads = PerPhase<Option<Spread>>;

/// Timings of a run of frames, as `report.json` and `bench.json` hold them.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TimingSummary {
    /// Frames the figures cover.
    pub frames: usize,
    /// GPU ms per phase (timestamp queries); None when unavailable, with
    /// the reason in `gpu_unavailable` (never reported as zero).
    pub gpu_ms: Option<PhaseSpreads>,
    pub gpu_unavailable: Option<String>,
    /// Phases the device times none of, each with why (their `gpu_ms`
    /// entry is null, never zero).
    pub phases_unavailable: std::collections::BTreeMap<String, String>,
    /// Wall-clock ms per frame on the host: recording, submission, the GPU
    /// work and the wait for the read-back (not PNG encoding).
    pub wall_frame_ms: Option<Spread>,
    /// 1000 / the median wall-clock frame.
    pub fps: Option<f64>,
}

impl TimingSummary {
    /// From each frame's GPU timings (None: no timestamps on this device),
    /// wall-clock ms, and the phases the device could not time, with why.
    pub fn of(gpu: &[Option<FrameTimings>], wall_ms: &[f64], untimed: &[(Phase, String)]) -> Self {
        let all: Option<Vec<FrameTimings>> = gpu.iter().copied().collect();
        let gpu_ms = all.filter(|v| !v.is_empty()).map(|v| {
            PhaseSpreads::from_fn(|p| {
                if untimed.iter().any(|(u, _)| *u == p) {
                    return None;
                }
                Spread::of(&v.iter().map(|t| t.get(p)).collect::<Vec<_>>())
            })
        });
        let gpu_unavailable = match (&gpu_ms, gpu.is_empty()) {
            (Some(_), _) => None,
            (None, true) => Some("no frames were timed".to_string()),
            (None, false) => Some(
                "the device has no timestamp queries on its graphics+compute queue".to_string(),
            ),
        };
        let wall = Spread::of(wall_ms);
        Self {
            frames: wall_ms.len(),
            gpu_ms,
            gpu_unavailable,
            phases_unavailable: untimed
                .iter()
                .map(|(p, why)| (p.name().to_string(), why.clone()))
                .collect(),
            wall_frame_ms: wall,
            fps: wall.filter(|w| w.median > 0.0).map(|w| 1000.0 / w.median),
        }
    }
}
