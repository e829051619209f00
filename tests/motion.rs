//! How the meadow moves: each behaviour the wind and the grass should
//! show, as a measurement that fails when the physics behind it is wrong.
//! Measured on the CPU reference (`trace_on_cpu`: src/model's wind solver,
//! blade dynamics, canopy drag), which the GPU's kernels are held to step
//! by step (tests/wind_gpu.rs, tests/grass_gpu.rs, tests/canopy.rs) and
//! the GPU's trace to sample for sample
//! (`the_gpu_trace_follows_the_cpu_reference` below): the physics proven
//! once, without lavapipe running it. docs/physics.md gives the figures
//! and the breaks each test was seen to catch.

use crate::common;

use common::binary::temp_out;
use common::{finish, mean_spread, strict_gpu};
use meadow::analysis::stats::best_lag;
use meadow::analysis::trace::Trace;
use meadow::commands::render::{render_pictures, render_pictures_traced, Picture};
use meadow::commands::trace::{trace, trace_on_cpu, BladePick, TraceRequest};
use meadow::gpu::{GpuOptions, ValidationOptions};
use meadow::model::wind::Coupling;
use meadow::scene::Scene;

fn strict_options() -> GpuOptions {
    GpuOptions {
        validation: ValidationOptions::strict(),
        device_name: std::env::var("MEADOW_TEST_DEVICE").ok(),
        ..Default::default()
    }
}

/// The tests below measure the CPU reference; this holds the GPU's trace
/// to it, sample for sample: gust-strip in its gusts and turbulence, 300
/// blades traced 1.5 s (90 steps) with the wind at their tips, one-way
/// (the CPU steps only the traced blades) and two-way (every blade, the
/// canopy's drag on the wind). Tips within 1e-4 m and the tips' wind
/// within 1e-3 m/s of the GPU's, while the tips have moved centimetres
/// (a trace that sampled the wrong step, the wrong blade or a wind
/// without its turbulence is off by that much).
#[test]
fn the_gpu_trace_follows_the_cpu_reference() {
    let gpu = strict_gpu();
    for coupling in [Coupling::OneWay, Coupling::TwoWay] {
        let mut scene = Scene::builtin("gust-strip").unwrap();
        scene.wind.coupling = coupling;
        let request = TraceRequest {
            scene,
            seconds: 1.5,
            every: 6,
            blades: BladePick::Count(300),
            wind: true,
            diagram_from: 0.0,
            gpu: strict_options(),
        };
        let on_gpu = trace(&gpu, &request, &mut |_, _| true).unwrap();
        let on_cpu = trace_on_cpu(&request, &mut |_, _| true).unwrap();
        assert_eq!(on_gpu.blades, on_cpu.blades);
        assert_eq!(on_gpu.times, on_cpu.times);
        assert_eq!((on_gpu.dt, on_gpu.substeps), (on_cpu.dt, on_cpu.substeps));
        let worst = |a: &[[f32; 3]], b: &[[f32; 3]]| {
            assert_eq!(a.len(), b.len());
            a.iter()
                .zip(b)
                .flat_map(|(x, y)| (0..3).map(move |i| (x[i] - y[i]).abs()))
                .fold(0.0f32, f32::max)
        };
        let tips = worst(&on_gpu.tips, &on_cpu.tips);
        let wind = worst(&on_gpu.wind, &on_cpu.wind);
        let n = on_cpu.blades.len();
        let last = on_cpu.times.len() - 1;
        let moved = (0..n)
            .map(|b| (on_cpu.tip(last, b)[0] - on_cpu.tip(0, b)[0]).abs())
            .fold(0.0f32, f32::max);
        eprintln!(
            "{}: tips differ by {tips:e} m, their wind by {wind:e} m/s; the tips moved up to {moved:.3} m",
            coupling.name()
        );
        assert!(
            moved > 0.02,
            "the tips hardly moved ({moved} m): nothing to compare"
        );
        assert!(tips < 1e-4, "tips differ by {tips} m");
        assert!(wind < 1e-3, "the tips' wind differs by {wind} m/s");
    }
    finish(gpu);
}

/// A render that also traces its simulation (`render_pictures_traced`,
/// what `reproduce` draws the gust strip and the turbulent field with)
/// takes the samples `trace` takes, bit for bit, though it steps in other
/// submissions (to its frames, then on to the trace's end); and its frames
/// are a plain render's. gust-strip, 200 blades traced every 6 steps over
/// 1 s, frames at 0.25 and 0.5 s.
#[test]
fn a_traced_render_samples_as_the_trace_does_and_draws_as_a_render_does() {
    let scene = Scene::builtin("gust-strip").unwrap();
    let request = TraceRequest {
        scene: scene.clone(),
        seconds: 1.0,
        every: 6,
        blades: BladePick::Count(200),
        wind: true,
        diagram_from: 0.0,
        gpu: strict_options(),
    };
    let gpu = strict_gpu();
    let alone = trace(&gpu, &request, &mut |_, _| true).unwrap();
    finish(gpu);
    let mut render = common::strict_request(scene, 96, 64, 2, 4.0);
    render.animation.start = 0.25;
    let (traced_dir, plain_dir) = (temp_out("traced-render"), temp_out("plain-render"));
    let picture = |dir: &std::path::Path| Picture {
        view: render.view,
        dir: dir.to_path_buf(),
    };
    let (_, traced) =
        render_pictures_traced(&render, &[picture(&traced_dir)], &request, &mut |_| true).unwrap();
    render_pictures(&render, &[picture(&plain_dir)], &mut |_| true).unwrap();
    assert_eq!(traced.times, alone.times);
    assert_eq!(traced.blades, alone.blades);
    assert_eq!(traced.tips, alone.tips, "the tips differ");
    assert_eq!(traced.angles, alone.angles);
    assert_eq!(traced.wind, alone.wind);
    let last = alone.times.len() - 1;
    let moved = (0..alone.blades.len())
        .map(|b| (alone.tip(last, b)[0] - alone.tip(0, b)[0]).abs())
        .fold(0.0f32, f32::max);
    assert!(moved > 0.01, "the tips hardly moved ({moved} m)");
    for frame in ["frame_0000.png", "frame_0001.png", "animation.gif"] {
        assert_eq!(
            std::fs::read(traced_dir.join(frame)).unwrap(),
            std::fs::read(plain_dir.join(frame)).unwrap(),
            "{frame} differs from a plain render's"
        );
    }
    let _ = std::fs::remove_dir_all(traced_dir);
    let _ = std::fs::remove_dir_all(plain_dir);
}

/// Gusts travel: on the 36 m strip of `gust-strip` in gusts from the left,
/// each 3 m band of blades moves like the band upwind of it, later by the
/// time the wind takes between them. The phase speed (3 m over the best
/// lag) lies within 0.5-2x the mean wind at the tips, neighbours correlate
/// at least 0.5 at that lag, and the best lag from the first band grows
/// with distance (within one period of the gusts). A gust that scaled the whole inflow at once would move
/// every band together: best lag 0, which fails.
/// A trace reads "downwind" along the inflow's heading: a square meadow
/// in a steady wind from heading 0 and from heading 90 (along z) bends its
/// tips downwind alike in the trace's bands and spectra, where reading x
/// at heading 90 would see almost nothing; against the heading (a negative
/// speed) the tips still move downwind, forward.
#[test]
fn a_trace_reads_the_tips_along_the_winds_heading() {
    let run = |heading: f32, speed: f32| {
        let text = format!(
            "name = \"heading\"\nseed = 3\n[camera]\nposition = [0.0, 1.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y = 45.0\n\
             [[grass.meadow]]\ncenter = [0.0, 0.0]\nsize = [6.0, 6.0]\ncount = 400\n\
             [wind]\ncells = [24, 10, 24]\nheight = 2.0\n[wind.inflow]\nspeed = {speed:?}\nheading = {heading:?}\n"
        );
        let request = TraceRequest {
            scene: meadow::scene::file::parse(&text, "heading.toml").unwrap(),
            seconds: 1.5,
            every: 6,
            blades: BladePick::Count(100),
            wind: false,
            diagram_from: 0.0,
            gpu: GpuOptions::default(),
        };
        trace_on_cpu(&request, &mut |_, _| true).unwrap()
    };
    let downwind = |t: &Trace| *t.band_displacement(-10.0, 20.0, 1)[0].last().unwrap();
    let across_x = |t: &Trace| {
        let last = t.times.len() - 1;
        (0..t.blades.len())
            .map(|b| (t.tip(last, b)[0] - t.tip(0, b)[0]) as f64)
            .sum::<f64>()
            / t.blades.len() as f64
    };
    let (east, north, back) = (run(0.0, 4.0), run(90.0, 4.0), run(90.0, -4.0));
    assert_eq!(north.frame.downwind, [0.0, 1.0]);
    assert_eq!(back.frame.downwind, [0.0, -1.0]);
    let (e, n, b) = (downwind(&east), downwind(&north), downwind(&back));
    eprintln!(
        "mean downwind tip displacement: heading 0 {e:.4} m, heading 90 {n:.4} m (along x {:.4} m), against heading 90 {b:.4} m",
        across_x(&north)
    );
    assert!(e > 0.01, "the tips hardly moved: {e} m");
    for (what, d) in [("heading 90", n), ("against heading 90", b)] {
        assert!(
            (d / e - 1.0).abs() < 0.25,
            "{what}: {d} m downwind against {e} m at heading 0"
        );
    }
    assert!(across_x(&north).abs() < 0.25 * e);
    let (pe, pn) = (
        east.tip_spectrum(0.0).unwrap().power.iter().sum::<f64>(),
        north.tip_spectrum(0.0).unwrap().power.iter().sum::<f64>(),
    );
    assert!(
        (pn / pe - 1.0).abs() < 0.5,
        "the tips' spectra: heading 90 {pn:e} against heading 0 {pe:e}"
    );
}

#[test]
fn gusts_travel_down_a_strip_at_the_speed_of_the_wind() {
    // The inflow's gusts alone: the scene's turbulence left out.
    let mut scene = Scene::builtin("gust-strip").unwrap();
    scene.wind.turbulence = None;
    let request = TraceRequest {
        scene,
        seconds: 20.0,
        every: 6,
        blades: BladePick::Count(1500),
        wind: true,
        diagram_from: 0.0,
        gpu: GpuOptions::default(),
    };
    let run = trace_on_cpu(&request, &mut |_, _| true).unwrap();

    let sample_s = run.times[1] - run.times[0];
    // The first 13 s: the first gusts cross the 39 m of the wind grid at
    // 3 m/s and the grass leans into the wind.
    let skip = (13.0 / sample_s).round() as usize;
    let bands = run.band_displacement(-18.0, 3.0, 12);
    let bands: Vec<&[f64]> = bands.iter().map(|b| &b[skip..]).collect();
    let n = run.blades.len();
    let tip_wind: Vec<f64> = run.wind[skip * n..].iter().map(|w| w[0] as f64).collect();
    let mean_wind = tip_wind.iter().sum::<f64>() / tip_wind.len() as f64;
    eprintln!("mean downwind wind at the tips {mean_wind:.2} m/s");

    let within_2_s = (2.0 / sample_s).round() as usize;
    for k in 1..bands.len() {
        let (lag, r) = best_lag(bands[k - 1], bands[k], within_2_s);
        let speed = 3.0 / (lag as f64 * sample_s);
        eprintln!(
            "band {k} follows band {} by {:.2} s (phase speed {speed:.2} m/s, {:.2}x the wind), r = {r:.2}",
            k - 1,
            lag as f64 * sample_s,
            speed / mean_wind
        );
        assert!(
            lag > 0 && (0.5..=2.0).contains(&(speed / mean_wind)),
            "band {k}: phase speed {speed} m/s against a mean wind of {mean_wind} m/s"
        );
        assert!(
            r >= 0.5,
            "band {k}: neighbour correlation {r} at the best lag"
        );
    }
    // Within one period of the gusts' first harmonic (the strongest that
    // survives the trip): beyond it the best lag repeats.
    let period = 1.0 / request.scene.wind.inflow.as_ref().unwrap().gust.frequency as f64;
    let within_period = (period / sample_s).floor() as usize;
    let lags: Vec<usize> = (1..=3)
        .map(|k| best_lag(bands[0], bands[k], within_period).0)
        .collect();
    eprintln!("best lags from band 0 to bands 1-3 (samples of {sample_s:.2} s): {lags:?}");
    assert!(
        lags[0] > 0 && lags.windows(2).all(|w| w[1] > w[0]),
        "the lag does not grow with distance: {lags:?}"
    );
}

/// Issue 39, turbulence alive all along a strip: gust-strip's 36 m in its
/// turbulence alone (intensity 0.3, length scale 4 m; the inflow's gusts
/// left out), 1,500 blades traced 16 s with the wind at their tips, the
/// first 6 s left out (the grass leaning into the wind).
///
/// One-way (the scene's coupling): the spread in time of each 3 m band's
/// mean downwind tip displacement is at least 4% of that band's mean
/// displacement (measured 11.7-20.7%), and in the last three bands at least
/// 70% of the first three's (measured 1.27): the turbulence is as alive
/// 30 m downwind as at the inflow. Each blade's own spread, averaged over
/// a band's blades, is at least 25% of the band's mean displacement
/// (measured 27-41%). A band's relative spread is its wind's: over each
/// band, the spread of the blades' mean displacement over its mean is
/// 0.7-1.4 times the spread of the mean wind at their tips over its mean
/// (measured 0.84-1.10; the paper's drag is linear in the wind: made
/// quadratic by hand, |v| / 3 m/s times it, 1.57 in the first band, which
/// fails), and the band's mean averages away the eddies smaller than its
/// 3 x 4 m: the tips' wind spreads 30% about its mean, a band's mean wind
/// 14-20%.
///
/// Two-way (the canopy's drag slows the air at the tips, as in a real
/// canopy, where the turbulence at the top keeps its strength): the bands
/// from 18 m on spread by at least 30% of their mean in the median
/// (measured 42%; the one-way run's 17%, which fails the bound): issue
/// 39's 30%, reached where the canopy has slowed the mean wind at its top
/// to less than half (2.6 m/s in the first band, 1.0-1.4 from 18 m on)
/// while the turbulence keeps its strength (docs/physics.md).
///
/// Without the turbulence (the same steady inflow) every band and every
/// blade holds still, its spread under 1% of its mean, which fails the
/// first and third bounds.
#[test]
fn turbulence_moves_the_grass_all_along_a_strip() {
    let bands = |turbulent: bool, coupling: Coupling| -> Vec<Band> {
        let mut scene = Scene::builtin("gust-strip").unwrap();
        scene.wind.inflow.as_mut().unwrap().gust.amplitude = 0.0;
        scene.wind.coupling = coupling;
        if !turbulent {
            scene.wind.turbulence = None;
        }
        assert!(!turbulent || scene.wind.turbulence.is_some());
        let request = TraceRequest {
            scene,
            seconds: 16.0,
            every: 6,
            blades: BladePick::Count(1500),
            wind: true,
            diagram_from: 0.0,
            gpu: GpuOptions::default(),
        };
        let run = trace_on_cpu(&request, &mut |_, _| true).unwrap();
        let skip = (6.0 / (run.times[1] - run.times[0])).round() as usize;
        let n = run.blades.len();
        let in_band = |band: usize| -> Vec<usize> {
            let x0 = -18.0 + 3.0 * band as f32;
            (0..n)
                .filter(|&b| (x0..x0 + 3.0).contains(&run.roots[b][0]))
                .collect()
        };
        let own_spread = |band: usize| {
            let spreads: Vec<f64> = in_band(band)
                .into_iter()
                .map(|b| {
                    let tip_x: Vec<f64> = (skip..run.times.len())
                        .map(|s| (run.tip(s, b)[0] - run.tip(0, b)[0]) as f64)
                        .collect();
                    mean_spread(&tip_x).1
                })
                .collect();
            spreads.iter().sum::<f64>() / spreads.len().max(1) as f64
        };
        let wind = |band: usize| {
            let blades = in_band(band);
            let mean_wind: Vec<f64> = (skip..run.times.len())
                .map(|s| {
                    blades
                        .iter()
                        .map(|&b| run.wind[s * n + b][0] as f64)
                        .sum::<f64>()
                        / blades.len().max(1) as f64
                })
                .collect();
            mean_spread(&mean_wind)
        };
        run.band_displacement(-18.0, 3.0, 12)
            .iter()
            .enumerate()
            .map(|(band, b)| {
                let (mean, spread) = mean_spread(&b[skip..]);
                Band {
                    mean,
                    spread,
                    own: own_spread(band),
                    wind: wind(band),
                }
            })
            .collect()
    };
    let turbulent = bands(true, Coupling::OneWay);
    let steady = bands(false, Coupling::OneWay);
    let canopy = bands(true, Coupling::TwoWay);
    let show = |bands: &[Band]| {
        bands
            .iter()
            .map(|b| {
                format!(
                    "{:.1}+-{:.1} ({:.1}; wind {:.2}+-{:.2})",
                    1e3 * b.mean,
                    1e3 * b.spread,
                    1e3 * b.own,
                    b.wind.0,
                    b.wind.1
                )
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    eprintln!("mm by 3 m band (each blade's own spread; the band's mean wind, m/s):");
    eprintln!("turbulent, one-way: {}", show(&turbulent));
    eprintln!("steady, one-way:    {}", show(&steady));
    eprintln!("turbulent, two-way: {}", show(&canopy));
    for (k, b) in turbulent.iter().enumerate() {
        assert!(
            b.spread >= 0.04 * b.mean.abs(),
            "band {k}: spread {} against mean {}",
            b.spread,
            b.mean
        );
        assert!(
            b.own >= 0.25 * b.mean.abs(),
            "band {k}: the blades' own spread {} against mean {}",
            b.own,
            b.mean
        );
        let passed_on = b.relative() / (b.wind.1 / b.wind.0);
        eprintln!("band {k}: relative spread over its wind's {passed_on:.2}");
        assert!(
            (0.7..1.4).contains(&passed_on),
            "band {k}: relative spread {:.3} against its wind's {:.3}",
            b.relative(),
            b.wind.1 / b.wind.0
        );
    }
    let spread = |b: &[Band]| b.iter().map(|b| b.spread).sum::<f64>() / b.len() as f64;
    let (near, far) = (spread(&turbulent[..3]), spread(&turbulent[9..]));
    eprintln!(
        "spread in the last three bands over the first three: {:.2}",
        far / near
    );
    assert!(far >= 0.7 * near, "{far} against {near}");
    for (k, b) in steady.iter().enumerate() {
        assert!(
            b.spread < 0.01 * b.mean.abs() && b.own < 0.01 * b.mean.abs(),
            "steady band {k}: {} and {} against {}",
            b.spread,
            b.own,
            b.mean
        );
    }
    let median = |b: &[Band]| {
        let mut r: Vec<f64> = b.iter().map(Band::relative).collect();
        r.sort_by(f64::total_cmp);
        (r[(r.len() - 1) / 2] + r[r.len() / 2]) / 2.0
    };
    let (one_way, two_way) = (median(&turbulent[6..]), median(&canopy[6..]));
    eprintln!(
        "from 18 m on, the bands' spread over their mean, median: {:.1}% one-way, {:.1}% two-way",
        100.0 * one_way,
        100.0 * two_way
    );
    assert!(two_way >= 0.3, "two-way: {two_way:.3} of the mean");
}

/// One 3 m band of a strip: its mean downwind tip displacement and that
/// mean's spread in time (m), its blades' own spread averaged (m), and
/// the mean and spread of its mean downwind wind at the tips (m/s).
struct Band {
    mean: f64,
    spread: f64,
    own: f64,
    wind: (f64, f64),
}

impl Band {
    fn relative(&self) -> f64 {
        self.spread / self.mean.abs()
    }
}

/// The blades ring at their natural frequency under the turbulence: on
/// gust-strip in turbulence alone (the inflow's gusts left out), 300
/// blades traced 40 s with the wind at their tips, the first 6 s left
/// out. In quarter-octave bands from 0.1 to 3 Hz, the gain from the wind
/// to the tip (the band's downwind tip power over its wind power, both
/// averaged over the blades) averaged over the bands within 30% of the
/// median of the blades' bending natural frequencies (the model's closed
/// form, `GrassBlade::natural_frequency_hz`) is at least twice the median
/// gain below a third of that frequency: the resonance (issue 39, after
/// Py, de Langre and Moulia 2006). Measured 3.64 times (2.95 before the
/// tips felt the modes finer than the grid); with the GPU's damping 5
/// times higher by hand, 0.49 (fails). The renewed modes make
/// the wind broadband, and the gain is a plateau of 2.7-3.6 times from
/// 0.6 to 1.7 Hz, largest at 1.47 Hz: the downwind tip moves by bending
/// (0.65-1.40 Hz, 5-95%) in blades facing the wind and by swinging
/// (1.42-4.50 Hz) in blades across it, so it is the band the test reads,
/// not where the gain is largest. The tips' own spectrum in hertz, and
/// where it is largest above a third of the natural frequency, are
/// printed, not held: it falls all the way (docs/physics.md says why).
/// Per unit log frequency and each blade against its own bending
/// frequency (`Trace::scaled_tip_spectrum`) it peaks: its largest band
/// within 30% of f_bend and at least 1.3 times the median band at
/// 0.25-0.6 f_bend (measured: at 1.00 f_bend, 1.87 times, 1.62 before the
/// modes finer than the grid; with the damping 5 times higher by hand,
/// at 0.30 f_bend, 1.12 times: fails).
#[test]
fn blades_ring_at_their_natural_frequency_in_turbulence() {
    let mut scene = Scene::builtin("gust-strip").unwrap();
    scene.wind.inflow.as_mut().unwrap().gust.amplitude = 0.0;
    let request = TraceRequest {
        scene,
        seconds: 40.0,
        every: 6,
        blades: BladePick::Count(300),
        wind: true,
        diagram_from: 6.0,
        gpu: GpuOptions::default(),
    };
    let run = trace_on_cpu(&request, &mut |_, _| true).unwrap();
    let natural = run.bend_natural_hz().unwrap().median;
    let spectrum = run.tip_spectrum(6.0).unwrap();
    // The wind's own spectrum at the tips, the same way.
    let n = run.blades.len();
    let wind = run
        .mean_spectrum(6.0, |s, b| run.wind[s * n + b][0] as f64)
        .unwrap()
        .power;
    // Quarter-octave bands from 0.1 to 3 Hz: each band's tip power over
    // its wind power (the gain), and its tip power per hertz.
    let edges: Vec<f64> = (0..=20).map(|i| 0.1 * 2f64.powf(i as f64 / 4.0)).collect();
    let bands: Vec<(f64, f64, f64)> = edges
        .windows(2)
        .filter_map(|e| {
            let (mut tip, mut air, mut bins) = (0.0, 0.0, 0);
            for (i, &f) in spectrum.frequency_hz.iter().enumerate() {
                if f >= e[0] && f < e[1] {
                    tip += spectrum.power[i];
                    air += wind[i];
                    bins += 1;
                }
            }
            (bins > 0 && air > 0.0).then(|| ((e[0] * e[1]).sqrt(), tip / air, tip / bins as f64))
        })
        .collect();
    let slow = {
        let mut g: Vec<f64> = bands
            .iter()
            .filter(|b| b.0 < natural / 3.0)
            .map(|b| b.1)
            .collect();
        g.sort_by(f64::total_cmp);
        g[g.len() / 2]
    };
    let &(ringing_hz, ringing, _) = bands.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    // The mean gain over the bands within 30% of the natural frequency.
    let near: Vec<f64> = bands
        .iter()
        .filter(|b| (b.0 / natural - 1.0).abs() < 0.3)
        .map(|b| b.1)
        .collect();
    let resonant = near.iter().sum::<f64>() / near.len() as f64;
    // The tips' own spectrum: its largest band above a third of the
    // natural frequency, a local peak when the bands either side are lower.
    let fast: Vec<&(f64, f64, f64)> = bands.iter().filter(|b| b.0 > natural / 3.0).collect();
    let top = (1..fast.len() - 1)
        .max_by(|&a, &b| fast[a].2.total_cmp(&fast[b].2))
        .unwrap();
    let (tip_peak_hz, local) = (
        fast[top].0,
        fast[top].2 > fast[top - 1].2 && fast[top].2 > fast[top + 1].2,
    );
    eprintln!(
        "gain within 30% of the natural frequency {natural:.3} Hz: {:.2}x the slow bands'; largest at {ringing_hz:.3} Hz ({:.2} of it), {:.2}x; \
         the tips' spectrum: largest at {:.3} Hz, above a third of the natural frequency largest at {tip_peak_hz:.3} Hz ({:.2} of it, {}a local peak)",
        resonant / slow,
        ringing_hz / natural,
        ringing / slow,
        spectrum.peak_hz,
        tip_peak_hz / natural,
        if local { "" } else { "not " }
    );
    for (f, gain, tip) in &bands {
        eprintln!(
            "  {f:.3} Hz: gain {:.2}x the slow bands', tips {tip:.3e}",
            gain / slow
        );
    }
    // The tips' own spectrum per unit log frequency, each blade against
    // its own bending frequency (`Trace::scaled_tip_spectrum`): its largest
    // band within 30% of f_bend, and at least 1.3 times the median band
    // from 0.25 to 0.6 of it (where the wind drives the tips
    // quasi-statically).
    let (peak_over_natural, over_driven) = scaled_peak(&run);
    assert!(
        resonant > 2.0 * slow,
        "gain within 30% of the natural frequency {resonant:.3e}, below a third of it {slow:.3e}"
    );
    assert!(
        (peak_over_natural - 1.0).abs() <= 0.3 && over_driven >= 1.3,
        "the tips' spectrum per unit log frequency is largest at {peak_over_natural:.2} f_bend, {over_driven:.2}x the bands at 0.25-0.6 f_bend",
    );
}

/// The tips' spectrum per unit log frequency, each blade against its own
/// bending frequency (`Trace::scaled_tip_spectrum`, from 6 s): where its
/// largest band lies (over f_bend) and how many times the median band
/// from 0.25 to 0.6 f_bend it is (where the wind drives the tips
/// quasi-statically). Printed band by band.
fn scaled_peak(run: &Trace) -> (f64, f64) {
    let scaled = run.scaled_tip_spectrum(6.0).unwrap();
    let mut driven: Vec<f64> = scaled
        .frequency_over_natural
        .iter()
        .zip(&scaled.power_per_log_f)
        .filter(|(r, _)| (0.25..=0.6).contains(*r))
        .map(|(_, p)| *p)
        .collect();
    driven.sort_by(f64::total_cmp);
    let driven = driven[driven.len() / 2];
    let peak = scaled.power_per_log_f.iter().cloned().fold(0.0, f64::max);
    eprintln!(
        "per unit log frequency, against each blade's own f_bend: largest at {:.2} f_bend, {:.2}x the median band at 0.25-0.6 f_bend",
        scaled.peak_over_natural,
        peak / driven
    );
    for (r, p) in scaled
        .frequency_over_natural
        .iter()
        .zip(&scaled.power_per_log_f)
    {
        eprintln!("  {r:.3} f_bend: {p:.4}");
    }
    (scaled.peak_over_natural, peak / driven)
}

/// On a wind grid too coarse for the eddies that reach the blades'
/// resonance, the turbulence finer than the grid, summed at each tip,
/// makes them ring: a 20 x 20 m field (1.5 blades per m^2, 300 traced 40
/// s) in a 3 m/s wind of intensity 0.3 and L = 4 m on 2.3 m wind cells,
/// whose shortest wave (4.6 m) is longer than U / f_bend (3.4 m). With the
/// modes down to 0.5 m waves (the default) the tips' spectrum per unit log
/// frequency against each blade's own f_bend is largest within 30% of it
/// and at least 1.3 times the median band at 0.25-0.6 f_bend (measured:
/// at 1.00 f_bend, 1.75 times); with the finest wavelength longer than
/// the grid's shortest wave (none finer), the same field's is not largest
/// there (the control: the grid alone leaves the resonance undriven;
/// measured at 0.35 f_bend, 1.05 times).
#[test]
fn turbulence_finer_than_a_coarse_grid_makes_the_blades_ring() {
    let mut scene = Scene::builtin("gust-strip").unwrap();
    scene.wind.inflow.as_mut().unwrap().gust.amplitude = 0.0;
    scene.grass.meadow[0].size = [20.0, 20.0];
    scene.grass.meadow[0].density = Some(1.5);
    scene.wind.cells = [10, 8, 10];
    let mut measured = Vec::new();
    for finest in [None, Some(8.0)] {
        scene.wind.turbulence.as_mut().unwrap().finest_wavelength = finest;
        let request = TraceRequest {
            scene: scene.clone(),
            seconds: 40.0,
            every: 6,
            blades: BladePick::Count(300),
            wind: false,
            diagram_from: 6.0,
            gpu: GpuOptions::default(),
        };
        let run = trace_on_cpu(&request, &mut |_, _| true).unwrap();
        let cell = scene.wind_grid().unwrap().cell;
        eprintln!("finest wavelength {finest:?} on {cell} m cells:");
        measured.push(scaled_peak(&run));
    }
    let [(with, over), (without, _)] = measured[..] else {
        unreachable!()
    };
    assert!(
        (with - 1.0).abs() <= 0.3 && over >= 1.3,
        "with the modes finer than the grid the tips' spectrum is largest at {with:.2} f_bend, {over:.2}x the bands at 0.25-0.6 f_bend"
    );
    assert!(
        (without - 1.0).abs() > 0.3,
        "the grid alone already drives the resonance ({without:.2} f_bend): the field no longer tests the sub-grid modes"
    );
}

/// The lee is calmer, in the grass: on Fig. 13's meadow the blades just
/// downwind of the wall bend less than blades at the same distance from the
/// inflow but clear of every obstacle, and with the obstacles removed the
/// same two patches move alike (so the calm is the wall's doing, not the
/// patch's place in the field).
#[test]
fn blades_in_the_lee_of_a_wall_move_less_than_blades_beside_it() {
    let scene = Scene::builtin("fig13-obstacles").unwrap();
    let mut open = scene.clone();
    open.wind.obstacles.clear();
    // The wall stands at x -2.4..-2.0, z -2.6..-0.6; the boulder's
    // footprint is z 0.4..2.0 and the post stands at z 2.4.
    let lee = |x: f32, z: f32| (-1.8..-0.8).contains(&x) && (-2.2..-1.0).contains(&z);
    let beside = |x: f32, z: f32| (-1.8..-0.8).contains(&x) && (-3.0..-2.8).contains(&z);
    let mut ratios = Vec::new();
    for scene in [scene, open] {
        let request = TraceRequest {
            scene,
            seconds: 4.0,
            every: 30,
            blades: BladePick::All,
            wind: false,
            diagram_from: 0.0,
            gpu: GpuOptions::default(),
        };
        let run = trace_on_cpu(&request, &mut |_, _| true).unwrap();
        // Mean horizontal tip travel from rest over the last two seconds.
        let n = run.blades.len();
        let travel = |inside: &dyn Fn(f32, f32) -> bool| {
            let mut sum = 0.0f64;
            let mut count = 0usize;
            for (s, &t) in run.times.iter().enumerate() {
                if t < 2.0 {
                    continue;
                }
                for b in 0..n {
                    let [x, z] = run.roots[b];
                    if inside(x, z) {
                        let (now, rest) = (run.tip(s, b), run.tip(0, b));
                        sum +=
                            ((now[0] - rest[0]).powi(2) + (now[2] - rest[2]).powi(2)).sqrt() as f64;
                        count += 1;
                    }
                }
            }
            assert!(count > 50, "too few blades sampled: {count}");
            sum / count as f64
        };
        let (calm, windy) = (travel(&lee), travel(&beside));
        eprintln!(
            "{}: lee {calm:.3} m, beside {windy:.3} m",
            request.scene.name
        );
        ratios.push(calm / windy);
    }
    eprintln!(
        "lee / beside: with the obstacles {:.2}, without {:.2}",
        ratios[0], ratios[1]
    );
    assert!(ratios[0] < 0.6, "the lee is not calmer: {ratios:?}");
    assert!(
        ratios[1] > 0.8,
        "the patches differ without the wall: {ratios:?}"
    );
}

// The rotating wind followed, in the grass: measured on the run that
// bounds the rotating meadow's angle caps (tests/soak.rs), one simulation
// for both.
