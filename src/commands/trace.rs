//! `meadow trace`: the grass's motion as data for analysis. The scene is
//! simulated on the GPU (wind and grass, no rendering) for a number of
//! seconds; every `every` steps the traced blades' roots, tips and angles
//! are read back (`trace_on_cpu`: the same on the CPU reference, which
//! the tests of the physics measure). What is measured of a trace is
//! src/analysis/trace.rs. Writes DIR/blades.csv (one row per traced blade per
//! sample), DIR/trace.json (what the columns are, in which units, and
//! where the numbers came from) and DIR/space_time.svg (the motion along
//! the wind over time). The files' formats and the diagrams are
//! src/report/trace.rs's (re-exported here).

use std::path::Path;

use crate::analysis::trace::{Percentiles, ScaledSpectrum, Spectrum, Trace, WindFrame};
use crate::commands::on_gpu;
use crate::compute::{Simulation, StepPace};
use crate::error::{Error, Result};
use crate::frame::BladeBuffer;
use crate::gpu::{CommandPool, Gpu, GpuOptions};
use crate::model::canopy;
use crate::model::grass::{self, pressed_pose, BEND_A, SWING, TWIST};
use crate::model::wind::WindField;
use crate::model::{Blade, BladeVertex, GrassBlade, GrassField};
use crate::report::claim::OutputClaim;
use crate::report::files;
pub use crate::report::trace::{
    columns, csv, plan_view_svg, space_time_svg, spectrum_svg, Column, TraceReport, COLUMNS,
    CSV_NAME, PLAN_VIEW_NAME, REPORT_NAME, SPACE_TIME_NAME, SPECTRUM_NAME, WIND_COLUMNS,
};
use crate::scene::{field, Scene};
use glam::Vec3;

/// Longest trace, simulated seconds.
pub const MAX_SECONDS: f64 = 3600.0;
/// Largest sampling interval, in steps.
pub const MAX_EVERY: u32 = 100_000;

/// Which blades to trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BladePick {
    /// This many, one from each of as many equal runs of the field's
    /// blades, where in its run picked by the scene's seed.
    Count(usize),
    All,
}

impl BladePick {
    /// `--blades`: a count or "all".
    pub fn parse(text: &str) -> Result<Self> {
        if text.trim() == "all" {
            return Ok(BladePick::All);
        }
        match text.trim().parse::<usize>() {
            Ok(n) if n >= 1 => Ok(BladePick::Count(n)),
            _ => Err(Error::InvalidInput(format!(
                "--blades {text} is not allowed, use a count of 1 or more, or all"
            ))),
        }
    }

    /// The traced blades' indices among `total`, ascending.
    /// How many blades of `total` it picks.
    pub fn count(self, total: usize) -> usize {
        match self {
            BladePick::All => total,
            BladePick::Count(n) => n.min(total),
        }
    }

    pub fn indices(self, total: usize, seed: u64) -> Vec<u32> {
        let count = self.count(total);
        if count == total {
            return (0..total as u32).collect();
        }
        (0..count)
            .map(|i| {
                let start = i * total / count;
                let end = (i + 1) * total / count;
                let u = unit_hash(seed, i as u64);
                (start + ((u * (end - start) as f64) as usize).min(end - start - 1)) as u32
            })
            .collect()
    }
}

/// A uniform number in [0, 1) from a seed and an index (splitmix64).
fn unit_hash(seed: u64, index: u64) -> f64 {
    let mut z = seed
        .wrapping_add(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[derive(Clone, Debug)]
pub struct TraceRequest {
    pub scene: Scene,
    /// Simulated seconds (whole steps of the scene's dt, rounded).
    pub seconds: f64,
    /// A sample every this many steps (1: every step).
    pub every: u32,
    pub blades: BladePick,
    /// Also the wind each traced tip feels (columns wind_x, wind_y, wind_z).
    pub wind: bool,
    /// space_time.svg starts here (s): the first seconds, the grass
    /// leaning into a wind that fills the field, can outweigh the waves.
    pub diagram_from: f64,
    pub gpu: GpuOptions,
}

impl TraceRequest {
    pub fn validate(&self) -> Result<()> {
        if !(self.seconds > 0.0 && self.seconds <= MAX_SECONDS) {
            return Err(Error::InvalidInput(format!(
                "--seconds {} is not allowed, use more than 0 and at most {MAX_SECONDS}",
                self.seconds
            )));
        }
        if !(0.0..self.seconds).contains(&self.diagram_from) {
            return Err(Error::InvalidInput(format!(
                "--diagram-from {} is not allowed, use 0 or more and less than --seconds {}",
                self.diagram_from, self.seconds
            )));
        }
        if !(1..=MAX_EVERY).contains(&self.every) {
            return Err(Error::InvalidInput(format!(
                "--every {} is not allowed, use 1..={MAX_EVERY}",
                self.every
            )));
        }
        self.scene.validate()?;
        has_blades(&self.scene)?;
        self.scene.wind_grid()?;
        Ok(())
    }

    /// Simulation steps the trace runs.
    pub fn steps(&self) -> u64 {
        (self.seconds / self.scene.wind.dt as f64).round().max(1.0) as u64
    }
}

/// A trace follows the patches' blades (bunches and meadows): a scene
/// without any is refused, saying why.
fn has_blades(scene: &Scene) -> Result<()> {
    if scene.blade_count() > 0 {
        return Ok(());
    }
    Err(Error::InvalidInput(format!(
        "trace follows the patches' blades and scene {:?} has none: a [grass.cover]'s blades are made and remade around the camera as it moves, none kept to follow; add a [[grass.meadow]] where to trace, or pick a scene with one",
        scene.name
    )))
}

/// Simulates `request`'s scene on `gpu`, sampling from t = 0. `observer`
/// is asked after each sample, and after each submission of steps between
/// samples, whether to go on (false: stop, the trace ending at its last
/// sample and marked interrupted).
pub fn trace(
    gpu: &Gpu,
    request: &TraceRequest,
    observer: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<Trace> {
    let scene = &request.scene;
    let rest = scene.field()?;
    let dynamic = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed)?;
    let commands = CommandPool::new(gpu, "trace commands")?;
    let vertices = BladeBuffer::new(gpu, &commands, &rest)?;
    let mut simulation = Simulation::new(gpu, &commands, scene, &dynamic, vertices.buffer())?;
    let mut sampler = TraceSampler::new(request, &rest, &dynamic, &simulation)?;
    let steps = request.steps();
    let mut done = 0u64;
    let mut pace = StepPace::default();
    'samples: loop {
        sampler.sample_if_due(gpu, &commands, &simulation, &vertices, done)?;
        if !sampler.trace.goes_on(done, steps, observer) {
            break;
        }
        // The steps to the next sample, in submissions paced to the
        // machine, a stop asked after each (the trace then ends at the
        // last sample).
        let mut left = (request.every as u64).min(steps - done);
        while left > 0 {
            left -= pace.run(left, |batch| {
                let rec = commands.begin()?;
                simulation.record_steps(&rec, batch);
                rec.submit_and_wait("simulating a trace")
            })?;
            if left > 0 && !observer(done, steps) {
                sampler.trace.interrupted = true;
                break 'samples;
            }
        }
        done += request.every as u64;
        done = done.min(steps);
    }
    drop(simulation);
    Ok(sampler.trace)
}

/// A trace's samples read from a simulation as it steps, whoever steps it
/// (`trace` above, or a render that draws a shot of the same simulation:
/// `commands::render::render_pictures_traced`): one at step 0, then every
/// `every` steps, the last at the request's end.
pub struct TraceSampler {
    trace: Trace,
    /// The CPU field that samples what the GPU's wind read back (None: the
    /// tips' wind is not traced).
    wind: Option<WindField>,
    every: u64,
    steps: u64,
    /// The step of the next sample; None once the last is taken.
    next: Option<u64>,
}

impl TraceSampler {
    /// A sampler of `request` over `simulation`, made of the scene's
    /// blades `rest` and their dynamics `dynamic`.
    pub fn new(
        request: &TraceRequest,
        rest: &[Blade],
        dynamic: &[GrassBlade],
        simulation: &Simulation,
    ) -> Result<Self> {
        let scene = &request.scene;
        let wind = request
            .wind
            .then(|| -> Result<WindField> {
                Ok(WindField::new(scene.wind_grid()?, &scene.wind_settings()))
            })
            .transpose()?;
        Ok(Self {
            trace: Trace::begun(
                request,
                rest,
                dynamic,
                simulation.dt(),
                simulation.substeps(),
            ),
            wind,
            every: request.every as u64,
            steps: request.steps(),
            next: Some(0),
        })
    }

    /// Steps from `done` to the next sample; None once the last is taken.
    pub fn steps_to_next(&self, done: u64) -> Option<u64> {
        self.next.map(|next| next.saturating_sub(done))
    }

    /// Reads a sample when the simulation, `done` steps in, is at the next
    /// sample's step.
    pub fn sample_if_due(
        &mut self,
        gpu: &Gpu,
        commands: &CommandPool,
        simulation: &Simulation,
        vertices: &BladeBuffer,
        done: u64,
    ) -> Result<()> {
        if self.next != Some(done) {
            return Ok(());
        }
        sample(
            gpu,
            commands,
            simulation,
            vertices,
            self.wind.as_mut(),
            &mut self.trace,
            done,
        )?;
        self.trace.steps_done = done;
        self.next = (done < self.steps).then(|| (done + self.every).min(self.steps));
        Ok(())
    }

    /// The trace, every sample taken (`steps_to_next` is None).
    pub fn finish(self) -> Trace {
        self.trace
    }
}

/// The same trace on the CPU reference (src/model: the wind solver, the
/// blade dynamics, the canopy's two-way drag, the colliders), which the
/// GPU's kernels are tested to follow step by step (tests/wind_gpu.rs,
/// tests/grass_gpu.rs, tests/canopy.rs): for measuring the physics
/// without a device. With one-way coupling only the traced blades step
/// (no blade changes another's wind), at the whole field's substeps; with
/// two-way every blade does. The cover's own dynamics have no CPU
/// reference here: a scene with a simulated `[grass.cover]` is refused.
pub fn trace_on_cpu(
    request: &TraceRequest,
    observer: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<Trace> {
    let scene = &request.scene;
    if scene
        .grass
        .cover
        .as_ref()
        .is_some_and(|c| c.simulate_radius() > 0.0)
    {
        return Err(Error::InvalidInput(
            "the CPU trace has no reference for a simulated [grass.cover]; trace on the GPU, or set its simulate_radius to 0".into(),
        ));
    }
    has_blades(scene)?;
    let rest = scene.field()?;
    let dynamic = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed)?;
    let settings = scene.wind_settings();
    let dt = scene.wind.dt;
    let mut wind = WindField::new(scene.wind_grid()?, &settings);
    wind.canopy_unit = canopy::unit(&dynamic);
    let substeps = grass::substeps(&dynamic, dt)?;
    let mut trace = Trace::begun(request, &rest, &dynamic, dt, substeps);
    let traced = &trace.blades;
    // The blades stepped, and where each traced one is among them.
    let (stepped, at): (Vec<GrassBlade>, Vec<usize>) = if wind.is_coupled(&settings) {
        (
            dynamic.clone(),
            traced.iter().map(|&b| b as usize).collect(),
        )
    } else {
        (
            traced.iter().map(|&b| dynamic[b as usize]).collect(),
            (0..traced.len()).collect(),
        )
    };
    let mut grass = GrassField::new(stepped, dt)?.with_colliders(scene.colliders.clone());
    grass.substeps = substeps;
    let steps = request.steps();
    let mut done = 0u64;
    loop {
        trace.times.push(done as f64 * dt as f64);
        for &i in &at {
            let pose = pressed_pose(
                &grass.blades[i],
                grass.states[i].angle,
                grass.pressed[i].pressed,
            );
            let tip = pose.points[3];
            trace.tips.push(tip.to_array());
            let a = grass.states[i].angle;
            trace.angles.push([a[SWING], a[BEND_A], a[TWIST]]);
            if request.wind {
                trace.wind.push(wind.felt(tip).to_array());
            }
        }
        if !trace.goes_on(done, steps, observer) {
            break;
        }
        let next = (done + request.every as u64).min(steps);
        while done < next {
            canopy::coupled_step(&mut wind, &settings, &mut grass);
            done += 1;
        }
    }
    Ok(trace)
}

/// The frame a trace of `scene` is measured in: downwind along the
/// inflow's heading (against it for a negative speed), or along x without
/// an inflow (sources alone, or still air).
pub fn wind_frame(scene: &Scene) -> WindFrame {
    let Some(inflow) = scene.wind.inflow.as_ref() else {
        return WindFrame::default();
    };
    let [c, s] = inflow.heading_vector();
    let sign = if inflow.speed < 0.0 { -1.0 } else { 1.0 };
    WindFrame {
        downwind: [sign * c, sign * s],
    }
}

impl Trace {
    /// After the sample at step `done` of `steps`: whether the run steps
    /// on to the next (not at the end, and `observer` not stopping it,
    /// which marks the trace interrupted).
    fn goes_on(
        &mut self,
        done: u64,
        steps: u64,
        observer: &mut dyn FnMut(u64, u64) -> bool,
    ) -> bool {
        self.steps_done = done;
        if done >= steps {
            return false;
        }
        if !observer(done, steps) {
            self.interrupted = true;
            return false;
        }
        true
    }

    /// A trace of `request`'s blades with no samples yet.
    fn begun(
        request: &TraceRequest,
        rest: &[Blade],
        dynamic: &[GrassBlade],
        dt: f32,
        substeps: u32,
    ) -> Self {
        let blades = request.blades.indices(rest.len(), request.scene.seed);
        Trace {
            dt,
            substeps,
            frame: wind_frame(&request.scene),
            roots: blades
                .iter()
                .map(|&b| {
                    let p = rest[b as usize].rest[0];
                    [p.x, p.z]
                })
                .collect(),
            bend_hz: blades
                .iter()
                .map(|&b| dynamic[b as usize].natural_frequency_hz(BEND_A))
                .collect(),
            swing_hz: blades
                .iter()
                .map(|&b| dynamic[b as usize].natural_frequency_hz(SWING))
                .collect(),
            blades,
            total_blades: rest.len(),
            ..Trace::default()
        }
    }
}

/// Reads the traced blades' tips and angles after `step` steps.
fn sample(
    gpu: &Gpu,
    commands: &CommandPool,
    simulation: &Simulation,
    vertices: &BladeBuffer,
    wind: Option<&mut WindField>,
    trace: &mut Trace,
    step: u64,
) -> Result<()> {
    let all: Vec<BladeVertex> =
        vertices
            .buffer()
            .read_back(gpu, commands, 4 * trace.total_blades)?;
    let states = simulation
        .grass()
        .ok_or_else(|| {
            Error::InvalidInput(
                "trace follows the patches' blades and this scene's only grass is a [grass.cover]; add a [[grass.meadow]] or pick another scene".into(),
            )
        })?
        .read_states(gpu, commands)?;
    trace.times.push(step as f64 * trace.dt as f64);
    for &b in &trace.blades {
        let tip = all[4 * b as usize + 3].position;
        trace.tips.push([tip[0], tip[1], tip[2]]);
        let a = states[b as usize].angle;
        trace.angles.push([a[SWING], a[BEND_A], a[TWIST]]);
    }
    if let Some(field) = wind {
        field.vel = simulation.wind().read_velocity(gpu, commands)?;
        field.subgrid_turbulence = simulation.wind().subgrid_records();
        let first = trace.tips.len() - trace.blades.len();
        for tip in &trace.tips[first..] {
            // What the tip feels: the grid's wind and the turbulence finer
            // than the grid there.
            trace.wind.push(field.felt(Vec3::from(*tip)).to_array());
        }
    }
    Ok(())
}

/// The tips' spectrum, scaled by each blade's bending frequency, and the
/// blades' bending and swinging natural frequencies, as a trace's report
/// has them.
type Spectra<'a> = (
    Option<&'a Spectrum>,
    Option<&'a ScaledSpectrum>,
    Option<&'a Percentiles>,
    Option<&'a Percentiles>,
);

/// Writes the space-time diagram (two samples and blades or more), the
/// plan view (three seconds past `diagram_from`) and the spectrum (where
/// there is one); says which were written.
fn write_diagrams(
    claim: &OutputClaim,
    trace: &Trace,
    request: &TraceRequest,
    spectra: Spectra,
) -> Result<[bool; 3]> {
    let title = format!(
        "{}: tip displacement along the wind over time",
        request.scene.name
    );
    let diagram = (trace.blades.len() > 1 && trace.times.len() > 1)
        .then(|| space_time_svg(trace, request.diagram_from, &title))
        .transpose()?;
    if let Some(svg) = &diagram {
        claim.write(SPACE_TIME_NAME, svg.as_bytes())?;
    }
    let title = format!(
        "{}: tips bent downwind from above, a second apart",
        request.scene.name
    );
    let plan_view = (trace.blades.len() > 1)
        .then(|| plan_view_svg(trace, request.diagram_from, &title))
        .transpose()?
        .flatten();
    if let Some(svg) = &plan_view {
        claim.write(PLAN_VIEW_NAME, svg.as_bytes())?;
    }
    let title = format!("{}: the tips' spectrum", request.scene.name);
    let (tip, scaled, bend, swing) = spectra;
    let spectrum = tip
        .map(|s| spectrum_svg(s, scaled, bend, swing, &title))
        .transpose()?;
    if let Some(svg) = &spectrum {
        claim.write(SPECTRUM_NAME, svg.as_bytes())?;
    }
    Ok([diagram.is_some(), plan_view.is_some(), spectrum.is_some()])
}

/// Every file a trace may write.
const OUTPUTS: [&str; 5] = [
    CSV_NAME,
    REPORT_NAME,
    SPACE_TIME_NAME,
    PLAN_VIEW_NAME,
    SPECTRUM_NAME,
];

/// Runs the trace and writes DIR/blades.csv, DIR/trace.json and (with two
/// samples and blades or more) DIR/space_time.svg, DIR/plan_view.svg (when
/// the trace lasts three seconds past `diagram_from`) and DIR/spectrum.svg
/// (when there is a spectrum), replacing only an
/// earlier run's (`overwrite`: any file of those names; `report::claim`).
pub fn trace_to_dir(
    request: &TraceRequest,
    out: &Path,
    overwrite: bool,
    observer: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<TraceReport> {
    request.validate()?;
    files::ensure_dir(out)?;
    let planned = OUTPUTS.map(String::from);
    let claim = OutputClaim::new(out, &planned, overwrite)?;
    // blades.csv: a row per traced blade and sample, at least 30 bytes
    // (ten numbers and their commas).
    let blades = request.blades.count(request.scene.blade_count()) as u64;
    let samples = request.steps().div_ceil(request.every as u64) + 1;
    claim.ensure_room(
        samples * blades * 30,
        &format!("{samples} samples of {blades} blades in {CSV_NAME}"),
    )?;
    let ((trace, device, device_memory), validation) = on_gpu(&request.gpu, |gpu| {
        Ok((
            trace(gpu, request, observer)?,
            gpu.info().name.clone(),
            gpu.device_memory(),
        ))
    })?;
    // The work is done: the last run's files go (its diagram too, which
    // would pass for this one's).
    claim.begin()?;
    claim.write(CSV_NAME, csv(&trace).as_bytes())?;
    let tip_spectrum = trace.tip_spectrum(request.diagram_from);
    let tip_spectrum_scaled = trace.scaled_tip_spectrum(request.diagram_from);
    let bend_natural_hz = trace.bend_natural_hz();
    let swing_natural_hz = trace.swing_natural_hz();
    let spectra = (
        tip_spectrum.as_ref(),
        tip_spectrum_scaled.as_ref(),
        bend_natural_hz.as_ref(),
        swing_natural_hz.as_ref(),
    );
    let [diagram, plan_view, spectrum] = write_diagrams(&claim, &trace, request, spectra)?;
    let report = TraceReport {
        scene: request.scene.name.clone(),
        seed: request.scene.seed,
        device,
        device_memory,
        dt: trace.dt,
        substeps: trace.substeps,
        seconds: if trace.interrupted {
            trace.steps_done as f64 * trace.dt as f64
        } else {
            request.seconds
        },
        every: request.every,
        steps: trace.steps_done,
        seconds_planned: request.seconds,
        steps_planned: request.steps(),
        samples: trace.times.len(),
        blades_traced: trace.blades.len(),
        blades_total: trace.total_blades,
        downwind: trace.frame.downwind,
        csv: CSV_NAME.into(),
        space_time: diagram.then(|| SPACE_TIME_NAME.into()),
        plan_view: plan_view.then(|| PLAN_VIEW_NAME.into()),
        spectrum: spectrum.then(|| SPECTRUM_NAME.into()),
        tip_spectrum,
        tip_spectrum_scaled,
        bend_natural_hz,
        swing_natural_hz,
        tip_correlation: trace.tip_correlation(request.diagram_from),
        columns: columns(request.wind),
        interrupted: trace.interrupted,
        validation,
    };
    claim.write_json(REPORT_NAME, &report)?;
    report.validation.check()?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_with_only_a_cover_is_refused_saying_why() {
        let request = TraceRequest {
            scene: Scene::builtin("steppe").unwrap(),
            seconds: 1.0,
            every: 1,
            blades: BladePick::All,
            wind: false,
            diagram_from: 0.0,
            gpu: GpuOptions::default(),
        };
        let e = request.validate().unwrap_err().to_string();
        assert!(
            e.contains("scene \"steppe\" has none") && e.contains("[[grass.meadow]]"),
            "{e}"
        );
        let e = trace_on_cpu(&request, &mut |_, _| true)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("has none") || e.contains("simulated [grass.cover]"),
            "{e}"
        );
    }

    #[test]
    fn a_pick_takes_one_blade_from_each_equal_run_and_depends_on_the_seed() {
        let picked = BladePick::Count(10).indices(1000, 7);
        assert_eq!(picked.len(), 10);
        for (i, &b) in picked.iter().enumerate() {
            assert!(
                (100 * i as u32..100 * (i as u32 + 1)).contains(&b),
                "{picked:?}"
            );
        }
        assert_eq!(picked, BladePick::Count(10).indices(1000, 7));
        assert_ne!(picked, BladePick::Count(10).indices(1000, 8));
        assert_eq!(BladePick::Count(5000).indices(30, 1).len(), 30);
        assert_eq!(BladePick::All.indices(4, 1), [0, 1, 2, 3]);
    }

    #[test]
    fn blades_are_a_count_or_all() {
        assert_eq!(BladePick::parse("all").unwrap(), BladePick::All);
        assert_eq!(BladePick::parse("12").unwrap(), BladePick::Count(12));
        let e = BladePick::parse("0").unwrap_err().to_string();
        assert!(e.contains("--blades 0 is not allowed"), "{e}");
        assert!(BladePick::parse("some").is_err());
    }
}
