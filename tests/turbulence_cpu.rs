//! The turbulence's CPU reference (src/model/turbulence.rs) against what
//! docs/method.md asks of it and of the wind it rides on: a field free of
//! divergence cell by cell and beside the ground, its intensity, spectrum
//! and seed, patches carried at the wind's speed and renewed without a
//! jump, and the patches it makes in a field's wind. (The GPU's
//! turbulence is held to this reference in tests/wind_gpu.rs.)

use crate::common;
use common::mean_spread;
use common::wind_scenes::{self, downwind_wind};
use glam::{DVec3, UVec3, Vec3};
use meadow::analysis::stats::{lagged_correlation, rms_over_fluid};
use meadow::interface::TurbulenceMode;
use meadow::model::turbulence::{Turbulence, TurbulenceField};
use meadow::model::wind::{Gust, Inflow, PressureSolver, WindField, WindGrid, WindSettings};

// The turbulence's field (src/model/turbulence.rs) on the faces.

fn turbulence_grid() -> WindGrid {
    WindGrid::new(
        UVec3::new(40, 8, 40),
        Vec3::new(-20.0, 0.0, -20.0),
        Vec3::new(40.0, 4.0, 40.0),
    )
    .unwrap()
}

/// sigma 0.9 m/s, advanced by `seconds` in a 3 m/s wind along x.
fn turbulence_records(seed: u32, seconds: f32) -> (TurbulenceField, Vec<TurbulenceMode>) {
    let t = Turbulence {
        intensity: 0.3,
        length_scale: 4.0,
        seed,
        speed: Some(3.0),
        finest_wavelength: None,
    };
    let g = turbulence_grid();
    // The ground, the top and the sides along a wind from +x are walls.
    let mut field = TurbulenceField::new(&t, g.cells, g.cell, [false, true, true]);
    field.advance(Vec3::new(3.0, 0.0, 0.0), 0.9, seconds);
    let records = field.records(0.9);
    (field, records)
}

/// The wind step's field on every face (`TurbulenceField::on_faces`, the
/// modes' phasors multiplied along each lattice line) is the per-face sum
/// `at` takes, as glsl/wind/turbulence.comp does: within 1e-4 of the
/// field's largest face value on every face of each axis, on walls both
/// mirrored (y, z) and free (x). A phasor taken along the wrong axis, or
/// the sine and cosine of a mirrored factor swapped, is off by the
/// field's own size.
#[test]
fn the_separated_sum_on_the_faces_is_the_per_face_sum() {
    let g = turbulence_grid();
    let (field, modes) = turbulence_records(5, 2.3);
    assert!(modes.iter().any(|m| m.mirrored != 0) && modes.iter().any(|m| m.mirrored & 1 == 0));
    for axis in 0..3 {
        let fast = field.on_faces(&modes, axis, g.face_dims(axis));
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for (idx, f) in g.each_face(axis) {
            let slow = field.at(&modes, axis, TurbulenceField::face_point(axis, f)) as f64;
            worst = worst.max((fast[idx] - slow).abs());
            scale = scale.max(slow.abs());
        }
        eprintln!("axis {axis}: worst {worst:e} m/s against {scale:.3} m/s");
        assert!(scale > 0.1, "axis {axis}: no field to compare ({scale})");
        assert!(worst < 1e-4 * scale, "axis {axis}: {worst} against {scale}");
    }
}

/// The faces' field has no divergence in any cell: the sum over a
/// cell's faces of (out - in) / h, against the faces' own size; and no
/// flow through the walls (the ground, the top, the sides along the wind).
#[test]
fn the_faces_field_is_divergence_free_cell_by_cell() {
    let g = turbulence_grid();
    let (field, modes) = turbulence_records(3, 1.7);
    let face = |axis: usize, i: u32, j: u32, k: u32| {
        field.at(&modes, axis, TurbulenceField::face_point(axis, [i, j, k]))
    };
    let (mut worst, mut scale) = (0.0f32, 0.0f32);
    for (_, [i, j, k]) in g.each_cell() {
        let mut div = 0.0;
        for axis in 0..3 {
            let mut hi = [i, j, k];
            hi[axis] += 1;
            let (a, b) = (face(axis, i, j, k), face(axis, hi[0], hi[1], hi[2]));
            div += (b - a) / g.cell[axis];
            scale = scale.max(a.abs() / g.cell[axis]);
        }
        worst = worst.max(div.abs());
    }
    // f32 sums of 64 terms: rounding, not truncation error (the
    // continuous field's faces would leave about 10% of `scale`).
    assert!(worst < 1e-4 * scale, "divergence {worst} against {scale}");
    let n = g.cells;
    let mut through_walls = 0.0f32;
    for (axis, end) in [(1, 0), (1, n.y), (2, 0), (2, n.z)] {
        for (_, f) in g.each_face(axis).filter(|(_, f)| f[axis] == end) {
            through_walls = through_walls.max(face(axis, f[0], f[1], f[2]).abs());
        }
    }
    let along = (0..n.x).map(|i| face(0, i, 3, 7).abs()).fold(0.0, f32::max);
    eprintln!("through the walls at most {through_walls} m/s; along x up to {along} m/s");
    assert!(
        through_walls < 1e-4 * along,
        "{through_walls} against {along}"
    );
}

/// Turbulence over terrain, 20 steps of 3 m/s with turbulence (intensity
/// 0.3, 4 m) over `terrain` on `grid`: the projection's rms divergence
/// before and after the step (1/s), f32's floor for the field's fastest
/// face, and the horizontal wind's rms in the first cells of air over the
/// ground's staircase (a cell under them solid).
struct TurbulentGround {
    before: f32,
    after: f32,
    floor: f32,
    near_ground: f32,
    /// The fastest horizontal wind in those cells (m/s).
    fastest_near_ground: f32,
}

fn turbulent_ground(terrain: meadow::model::terrain::Terrain, grid: WindGrid) -> TurbulentGround {
    let settings = WindSettings {
        inflow: Some(Inflow {
            speed: 3.0,
            heading: 0.0,
            gust: Gust::default(),
        }),
        turbulence: Some(Turbulence {
            intensity: 0.3,
            length_scale: 4.0,
            seed: 3,
            speed: None,
            finest_wavelength: None,
        }),
        terrain,
        solver: PressureSolver::Multigrid,
        v_cycles: 7,
        ..Default::default()
    };
    let mut field = WindField::new(grid, &settings);
    let under = field.ground.iter().filter(|&&g| g).count();
    assert!(under > 500, "{under} cells under the ground");
    for _ in 0..20 {
        field.step(&settings, 1.0 / 30.0);
    }
    let speed = field
        .vel
        .iter()
        .flatten()
        .fold(0.0f32, |m, v| m.max(v.abs()));
    let (mut sum, mut count, mut fastest) = (0.0f64, 0, 0.0f32);
    for (c, [i, j, k]) in grid.each_cell() {
        if field.solid[c] || j == 0 || !field.solid[grid.cell_index(i, j - 1, k)] {
            continue;
        }
        let v = field.cell_velocity(i, j, k);
        sum += (v.x * v.x + v.z * v.z) as f64;
        fastest = fastest.max(v.x.hypot(v.z));
        count += 1;
    }
    assert!(count > 50, "{count} cells over the ground");
    let report = TurbulentGround {
        before: rms_over_fluid(&field.divergence, &field.solid) as f32,
        after: field.rms_divergence(),
        floor: grid.divergence_floor(speed),
        near_ground: (sum / count as f64).sqrt() as f32,
        fastest_near_ground: fastest,
    };
    eprintln!(
        "rms divergence before the projection {:.3e} 1/s, after the step {:.3e} ({:.2e} of before, {:.2} of f32's floor); \
         over the ground ({count} cells) the horizontal wind's rms {:.2} m/s, at most {:.2}, in a 3 m/s inflow",
        report.before,
        report.after,
        report.after / report.before,
        report.after / report.floor,
        report.near_ground,
        report.fastest_near_ground
    );
    assert!(
        report.before > 1e-3,
        "nothing to project: {}",
        report.before
    );
    report
}

/// Turbulence over a hill standing on the grid's floor is projected as
/// over flat ground: among solid cells the modes are added before the
/// projection, which turns their flow around the ground as it turns the
/// mean wind's, and the step leaves at most 1e-4 of the divergence the
/// projection began with (2.1e-5). Added after the projection, as over
/// flat ground, the step ended with 9.25 times it.
#[test]
fn turbulence_over_a_hill_leaves_no_divergence_beside_the_ground() {
    let hill = meadow::model::terrain::Terrain {
        hills: vec![meadow::model::terrain::Hill {
            center: [0.0, 0.0],
            height: 2.0,
            half_width: 5.0,
        }],
        ..Default::default()
    };
    let r = turbulent_ground(hill, turbulence_grid());
    assert!(
        r.after < 1e-4 * r.before,
        "{} left of {}",
        r.after,
        r.before
    );
}

/// Where the ground stands above the grid's floor (a hollow sets the
/// floor, the hill and the flat 2 m over it), the air beside the ground
/// moves no faster than the inflow: the first cells of air over the
/// staircase keep an rms horizontal wind under 1.2 times the inflow's
/// (3.44 m/s, at most 6.6, the hill's speed-up and the turbulence). The
/// modes' potential held at zero on the edges touching the ground (the
/// previous way) cut the long modes' potential within a cell there, a jet
/// along the ground: 4.07 m/s rms, at most 8.8, and the test fails. The
/// divergence left is f32's rounding (1.2 times its floor; 1.7e-4 of the
/// projection's start).
#[test]
fn turbulence_over_raised_ground_makes_no_jet_along_it() {
    use meadow::model::terrain::{Hill, Terrain};
    let ground = Terrain {
        hills: vec![
            Hill {
                center: [5.0, 0.0],
                height: 2.0,
                half_width: 5.0,
            },
            Hill {
                center: [-12.0, 8.0],
                height: -2.0,
                half_width: 4.0,
            },
        ],
        ..Default::default()
    };
    let grid = WindGrid::new(
        UVec3::new(40, 12, 40),
        Vec3::new(-20.0, -2.0, -20.0),
        Vec3::new(40.0, 6.0, 40.0),
    )
    .unwrap();
    let r = turbulent_ground(ground, grid);
    assert!(
        r.near_ground < 1.2 * 3.0,
        "{} m/s beside the ground",
        r.near_ground
    );
    assert!(
        r.after < 2.0 * r.floor,
        "{} of the floor",
        r.after / r.floor
    );
}

/// Its statistics over the grid: each horizontal component's standard
/// deviation near sigma, and the same seed the same field, another
/// seed another.
#[test]
fn the_field_has_the_set_intensity_and_follows_its_seed() {
    let g = turbulence_grid();
    let (field, modes) = turbulence_records(3, 0.0);
    for axis in [0, 2] {
        let values: Vec<f32> = g
            .each_face(axis)
            .map(|(_, [i, j, k])| {
                field.at(&modes, axis, TurbulenceField::face_point(axis, [i, j, k]))
            })
            .collect();
        let n = values.len() as f32;
        let mean = values.iter().sum::<f32>() / n;
        let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / n).sqrt();
        assert!((0.6..1.3).contains(&(sd / 0.9)), "axis {axis}: sd {sd}");
    }
    assert_eq!(turbulence_records(3, 2.0).1, turbulence_records(3, 2.0).1);
    assert_ne!(turbulence_records(3, 2.0).1, turbulence_records(4, 2.0).1);
}

/// The modes finer than the grid carry the spectrum's share of the
/// energy: on a 60 x 60 m grid of 2 m cells (shortest wave 4 m) with the
/// tips feeling waves down to 0.5 m, the von Karman spectrum of L = 4 m
/// holds 29% of the energy between 4 m and 0.5 m waves (of all of it
/// above 0.5 m), a little less of the horizontal variance (the grid's
/// eddies deeper than the air are flattened into horizontal ones); over
/// twelve seeds the downwind component's variance over the grid's x
/// faces, the sub-grid modes summed at the same points, takes 0.12-0.4 of
/// the sum's, and the sum's standard deviation is within 20% of sigma.
/// With the finest wavelength the grid's own (4 m) there are none, and
/// the grid's modes carry sigma alone.
#[test]
fn the_modes_finer_than_the_grid_carry_their_share_of_the_spectrum() {
    let g = grid_60_m();
    let variance = |v: &[f64]| spread(v).powi(2);
    let field = |seed: u32, finest: Option<f32>| {
        let t = Turbulence {
            intensity: 0.3,
            length_scale: 4.0,
            seed,
            speed: Some(3.0),
            finest_wavelength: finest,
        };
        TurbulenceField::new(&t, g.cells, g.cell, [false, true, true])
    };
    let (mut grid_var, mut subgrid_var, mut total_var) = (0.0, 0.0, 0.0);
    for seed in 1..=12 {
        let modes = field(seed, None);
        let (records, subgrid) = (modes.records(0.9), modes.subgrid_records(0.9));
        assert_eq!(subgrid.len(), meadow::model::turbulence::SUBGRID_MODES);
        let (mut resolved, mut finer, mut sum) = (Vec::new(), Vec::new(), Vec::new());
        for (_, f) in g.each_face(0) {
            let q = TurbulenceField::face_point(0, f);
            let on_grid = modes.at(&records, 0, q) as f64;
            let x = q.as_vec3() * 0.5 * g.cell;
            let below = meadow::model::turbulence::velocity_at(&subgrid, x).x as f64;
            resolved.push(on_grid);
            finer.push(below);
            sum.push(on_grid + below);
        }
        grid_var += variance(&resolved) / 12.0;
        subgrid_var += variance(&finer) / 12.0;
        total_var += variance(&sum) / 12.0;
    }
    let share = subgrid_var / total_var;
    let sd = total_var.sqrt();
    eprintln!(
        "sub-grid share of the downwind variance {share:.3}; the grid's alone {:.3} m/s, with the sub-grid {sd:.3} m/s (sigma 0.9)",
        grid_var.sqrt()
    );
    assert!((0.12..0.4).contains(&share), "sub-grid share {share}");
    assert!((sd / 0.9 - 1.0).abs() < 0.2, "sd {sd}");
    let own = field(1, Some(4.0));
    assert!(own.subgrid_records(0.9).is_empty());
    let records = own.records(0.9);
    let alone: Vec<f64> = g
        .each_face(0)
        .map(|(_, f)| own.at(&records, 0, TurbulenceField::face_point(0, f)) as f64)
        .collect();
    let sd_alone = spread(&alone);
    eprintln!("finest wavelength the grid's: its modes alone {sd_alone:.3} m/s");
    assert!((sd_alone / 0.9 - 1.0).abs() < 0.3, "sd {sd_alone}");
}

/// The downwind turbulence on a 60 x 60 m grid of 2 m cells (walls at
/// the ground, the top and the sides along a 3 m/s wind from +x; sigma 0.9
/// m/s), sampled every `dt` for `seconds`: at each sample `probe` reads
/// the field through `at` (face indices of axis x).
fn sample_field_60_m(
    seed: u32,
    dt: f32,
    seconds: f32,
    mut probe: impl FnMut(&dyn Fn([u32; 3]) -> f32),
) {
    let g = grid_60_m();
    let t = Turbulence {
        intensity: 0.3,
        length_scale: 4.0,
        seed,
        speed: Some(3.0),
        finest_wavelength: None,
    };
    let mut field = TurbulenceField::new(&t, g.cells, g.cell, [false, true, true]);
    for _ in 0..(seconds / dt).round() as u32 {
        field.advance(Vec3::new(3.0, 0.0, 0.0), 0.9, dt);
        let records = field.records(0.9);
        probe(&|f| field.at(&records, 0, TurbulenceField::face_point(0, f)));
    }
}

/// A 60 x 60 m field's wind grid, 4 m of air, in 2 m cells (0.5 m up).
fn grid_60_m() -> WindGrid {
    WindGrid::new(
        UVec3::new(30, 8, 30),
        Vec3::new(-30.0, 0.0, -30.0),
        Vec3::new(60.0, 4.0, 60.0),
    )
    .unwrap()
}

/// Issue 39, patches carried by the wind: the downwind turbulence on 21
/// points 2 m apart along a 3 m/s wind (x faces 5..=25 of the 60 x 60 m
/// grid's lowest layer, 0.25 m up, mid-field), sampled every 0.05 s for
/// 20 s, for each of six seeds. The mean correlation of points d apart at
/// a lag tau, averaged over the pairs and the seeds, peaks along a ridge
/// d = U_c tau (the moving-frame estimate: at a fixed lag every
/// separation shares the eddies' decay in time, so the peak over d is not
/// pulled towards zero lag as the peak over the lag at a fixed d is); its
/// least-squares slope through the peaks at 0.5, 1 and 1.5 s (parabolic
/// between the points; beyond 1.5 s the ridge falls under 0.2 and is
/// noise) is 0.8-1.5 times the wind the modes are carried with (measured
/// 1.21: the ridge's decay still leans it a little towards short lags;
/// the issue allows 0.8-2.2 for the tips, canopy eddies travelling at
/// 1.5-2 U(h)). With the modes carried at twice the wind by hand it reads
/// 2.08 times the wind (fails); carried against it, the ridge downwind is
/// lost (2.32, fails). The peak over
/// the lag at 8 m, one seed's record, is not a measure: over twelve seeds
/// it read 0.5 to 53 times the wind (the eddies of a few metres live about
/// a second, under the 2.7 s they take to cross 8 m).
#[test]
fn patches_are_carried_at_the_speed_of_the_wind() {
    const LAGS_S: [f64; 3] = [0.5, 1.0, 1.5];
    const SEEDS: u32 = 6;
    let mut rho = [[0.0f64; 12]; 3];
    for seed in 1..=SEEDS {
        let mut series = vec![Vec::new(); 21];
        sample_field_60_m(seed, 0.05, 20.0, |u| {
            for (i, s) in series.iter_mut().enumerate() {
                s.push(u([5 + i as u32, 0, 15]) as f64);
            }
        });
        for (l, lag_s) in LAGS_S.iter().enumerate() {
            let lag = (lag_s / 0.05).round() as usize;
            for (d, r) in rho[l].iter_mut().enumerate() {
                let pairs = 21 - d;
                *r += (0..pairs)
                    .map(|i| lagged_correlation(&series[i], &series[i + d], lag))
                    .sum::<f64>()
                    / (pairs as u32 * SEEDS) as f64;
            }
        }
    }
    let (mut dt, mut tt) = (0.0, 0.0);
    for (l, lag_s) in LAGS_S.iter().enumerate() {
        let d = wind_scenes::ridge(&rho[l], 2.0);
        eprintln!("lag {lag_s} s: correlation peaks at {d:.2} m");
        dt += d * lag_s;
        tt += lag_s * lag_s;
    }
    let speed = dt / tt;
    eprintln!(
        "the ridge's speed {speed:.2} m/s, {:.2} times the wind",
        speed / 3.0
    );
    assert!((0.8..=1.5).contains(&(speed / 3.0)), "{speed} m/s");
}

/// The standard deviation of a series about its mean.
fn spread(v: &[f64]) -> f64 {
    mean_spread(v).1
}

/// Issue 39, patches and not fronts, settled: the downwind wind averaged
/// along the whole field (60 m) in two bands 20 m apart across the wind
/// correlates within +-0.4 over 300 s for each of six seeds (each band's
/// mean moving by over 0.1 m/s: measured 0.40-0.49). A band's mean
/// keeps only the modes with hardly a wave along it, a handful of a draw,
/// so with modes drawn once and carried (no renewal, their life set
/// infinite by hand) the same measure reads 0.87, -0.62, -0.61 and 0.95 for
/// four of these seeds: one draw's chance lay-out, not the spectrum's; the
/// renewed modes give the spectrum's answer, near 0.
#[test]
fn renewed_modes_leave_bands_20_m_apart_uncorrelated() {
    for seed in 1..=6 {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        sample_field_60_m(seed, 0.1, 300.0, |u| {
            let band = |k: u32| (0..30).map(|i| u([i, 0, k]) as f64).sum::<f64>() / 30.0;
            a.push(band(5));
            b.push(band(15));
        });
        let r = lagged_correlation(&a, &b, 0);
        eprintln!(
            "seed {seed}: bands 20 m apart correlate {r:.2} over 300 s (their means move {:.3} and {:.3} m/s)",
            spread(&a),
            spread(&b)
        );
        assert!(
            spread(&a) > 0.1 && spread(&b) > 0.1,
            "seed {seed}: still bands"
        );
        assert!(r.abs() < 0.4, "seed {seed}: {r}");
    }
}

/// A mode is renewed without a jump: it fades out before it is drawn
/// again (its weight sin(pi s) is 0 there) and its partner in the shell
/// fades in as it fades out, so the field at a point moves by a step's
/// worth at each step (stepped at 10 ms for 60 s, every mode renewed at
/// least five times: 0.077 m/s at most; redrawn at full weight, 1.50 m/s),
/// and its variance stays (the point's standard deviation over each 15 s
/// within 0.5-1.4 times sigma's; measured 0.82-1.04).
#[test]
fn modes_are_renewed_without_a_jump_and_keep_the_energy() {
    let (mut series, mut jump, mut last) = (Vec::new(), 0.0f32, None::<f32>);
    sample_field_60_m(3, 0.01, 60.0, |u| {
        let now = u([15, 0, 15]);
        if let Some(last) = last {
            jump = jump.max((now - last).abs());
        }
        last = Some(now);
        series.push(now as f64);
    });
    let sds: Vec<f64> = series.chunks(1500).map(spread).collect();
    eprintln!("largest change in 10 ms: {jump:.4} m/s; standard deviation over each 15 s: {sds:.2?} (sigma 0.9)");
    assert!(jump < 0.15, "{jump} m/s in one step");
    for sd in sds {
        assert!((0.5..1.4).contains(&(sd / 0.9)), "{sd}");
    }
}

/// Issue 39's band of grass, in closed form: the mean of the downwind
/// wind over a lattice of tips 3 m along by 4 m across and 0.4 m deep
/// (gust-strip's 3 m bands on its 4 m width, 7 x 9 x 3 points) spreads
/// as the von Karman spectrum of the set integral length scale says. For
/// an isotropic field the lattice mean's variance over a point's is
/// int E(k) <(1 - k_x^2 / k^2) D_x^2 D_y^2 D_z^2> dk / int E(k) dk, the
/// angle brackets a mean over the directions of k and D the lattice's
/// Dirichlet kernel sin(n k d / 2) / (n sin(k d / 2)) along each axis;
/// the test sums it (400 log-spaced wavenumbers over the drawn range,
/// 2,000 directions). The modes (no walls; 0.5 m cells, finest
/// wavelength 0.5 m, so the grid's 48 and 16 finer ones), 24 seeds, 81
/// lattices each, must give a standard deviation ratio within 6% of it:
/// measured 0.727 against 0.726 for L = 4 m. With the field's length
/// scale twice the set one by hand (its k_e halved in
/// `TurbulenceField::new`) the modes give 0.824 (fails), half of it 0.590
/// (fails).
///
/// What it says about the grass (docs/physics.md): one-way, a band's
/// displacement spreads as its mean wind does (tests/motion.rs), and
/// that is 0.73 of a point's, so at intensity 0.3 a 3 x 4 m band's
/// displacement spreads about 0.73 x 0.3 x 0.9 = 20% of its mean (d ~
/// U^0.9), and no length scale can lift it to the 30%: the ratio
/// is under 1 for any L. Only a canopy's top, whose air the grass slows
/// while the turbulence keeps its strength, reaches it (two-way).
#[test]
fn a_band_of_grass_averages_the_turbulence_as_the_von_karman_spectrum_says() {
    const L: f64 = 4.0;
    const FINEST: f64 = 0.5;
    // Lattice points along x (downwind), y (up) and z (across).
    const N: [usize; 3] = [7, 3, 9];
    const D: [f64; 3] = [0.5, 0.2, 0.5];
    let points = N.iter().product::<usize>();
    let dirichlet = |k: f64, axis: usize| -> f64 {
        let half = 0.5 * k * D[axis];
        if half.sin().abs() < 1e-12 {
            return 1.0;
        }
        (N[axis] as f64 * half).sin() / (N[axis] as f64 * half.sin())
    };
    // The closed form, on the modes' wavenumber range (k_e L = 0.746834,
    // from 0.1 k_e to 2 pi / FINEST).
    let k_e = 0.746_834 / L;
    let (k_lo, k_hi) = (0.1 * k_e, std::f64::consts::TAU / FINEST);
    let shape = |k: f64| (k / k_e).powi(4) / (1.0 + (k / k_e).powi(2)).powf(17.0 / 6.0);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let directions: Vec<[f64; 3]> = (0..2000)
        .map(|i| {
            let x = 1.0 - 2.0 * (i as f64 + 0.5) / 2000.0;
            let r = (1.0 - x * x).sqrt();
            let a = golden * i as f64;
            [x, r * a.cos(), r * a.sin()]
        })
        .collect();
    let (mut lattice, mut point) = (0.0, 0.0);
    let span = (k_hi / k_lo).ln();
    for n in 0..400 {
        let k = k_lo * (span * (n as f64 + 0.5) / 400.0).exp();
        let weight = shape(k) * k * span / 400.0;
        let mut mean = 0.0;
        for d in &directions {
            let h: f64 = (0..3).map(|a| dirichlet(k * d[a], a).powi(2)).product();
            mean += (1.0 - d[0] * d[0]) * h;
        }
        lattice += weight * mean / directions.len() as f64;
        point += weight * 2.0 / 3.0;
    }
    let closed = (lattice / point).sqrt();

    let cells = UVec3::new(120, 16, 120);
    let cell = Vec3::splat(0.5);
    let (mut lattice_sq, mut point_sq, mut count) = (0.0f64, 0.0f64, 0usize);
    for seed in 1..=24 {
        let t = Turbulence {
            intensity: 0.3,
            length_scale: L as f32,
            seed,
            speed: Some(3.0),
            finest_wavelength: Some(FINEST as f32),
        };
        let field = TurbulenceField::new(&t, cells, cell, [false; 3]);
        let (grid, finer) = (field.records(0.9), field.subgrid_records(0.9));
        assert_eq!(finer.len(), meadow::model::turbulence::SUBGRID_MODES);
        for (bi, bk) in (0..9).flat_map(|i| (0..9).map(move |k| (i, k))) {
            let corner = Vec3::new(3.0 + 6.0 * bi as f32, 3.0, 3.0 + 6.0 * bk as f32);
            let mut sum = 0.0f64;
            for (i, j, k) in (0..N[0])
                .flat_map(|i| (0..N[1]).flat_map(move |j| (0..N[2]).map(move |k| (i, j, k))))
            {
                let x = corner + Vec3::new(i as f32, j as f32, k as f32) * DVec3::from(D).as_vec3();
                let u = meadow::model::turbulence::component_at(&grid, 0, x)
                    + meadow::model::turbulence::component_at(&finer, 0, x);
                sum += u as f64;
                point_sq += (u as f64).powi(2);
            }
            let mean = sum / points as f64;
            lattice_sq += mean * mean;
            count += 1;
        }
    }
    let point_variance = point_sq / (count * points) as f64;
    let measured = (lattice_sq / count as f64 / point_variance).sqrt();
    eprintln!(
        "a 3 x 4 m band's mean downwind wind over a point's, standard deviations: {measured:.3} (closed form {closed:.3}; a point's {:.3} m/s for sigma 0.9)",
        point_variance.sqrt()
    );
    assert!(
        (measured / closed - 1.0).abs() < 0.06,
        "{measured:.3} against the closed form's {closed:.3}"
    );
}

/// The downwind wind at 0.4 m, sampled every third step over `seconds`
/// after 4 s, at `points` of a 60 x 60 m field (wind grid 30 x 6 x 30 cells
/// of 2 x 0.5 x 2 m, 3 m/s from -x) with `turbulence` and inflow gusts of
/// `gust_amplitude`: [point][sample].
fn field_wind(
    turbulence: Option<Turbulence>,
    gust_amplitude: f32,
    points: &[Vec3],
    seconds: f32,
) -> Vec<Vec<f64>> {
    let grid = WindGrid::new(
        UVec3::new(30, 6, 30),
        Vec3::new(-30.0, 0.0, -30.0),
        Vec3::new(60.0, 3.0, 60.0),
    )
    .unwrap();
    let settings = WindSettings {
        inflow: Some(Inflow {
            speed: 3.0,
            heading: 0.0,
            gust: Gust {
                amplitude: gust_amplitude,
                frequency: 0.3,
                seed: 4,
            },
        }),
        turbulence,
        ..Default::default()
    };
    downwind_wind(grid, &settings, 1.0 / 60.0, 4.0, seconds, points)
}

/// Issue 39, patches and not fronts: on a 60 x 60 m field in a 3 m/s wind,
/// the downwind wind at 0.4 m at two points 20 m apart across the wind
/// correlates below 0.5 with turbulence (intensity 0.3, length scale 4 m,
/// no inflow gusts), where the inflow's gusts alone (amplitude 0.5) give
/// fronts that correlate above 0.8 (so the test fails without the
/// turbulence; measured 0.06 and 0.99). And the patches are carried
/// downwind: half a second on, the points' mean correlation over the
/// pairs d apart on the line along the wind peaks (parabolic between the
/// points) at d = U_c 0.5 s with U_c 0.8 to 1.5 times the mean wind there
/// (the moving-frame estimate of
/// `patches_are_carried_at_the_speed_of_the_wind`, which holds it over
/// three lags and six seeds; at 0.5 s one seed's record suffices: twelve
/// seeds of the modes alone read 0.87-1.33). The best lag at a fixed 8 m,
/// which this test read before, is not a measure: one seed read 1.01,
/// others 0.5 to 53 times the wind. The patches' integral length, along the wind and across
/// it (the mean correlation of points r apart on lines of 21 points 2 m
/// apart, summed to its first zero), is 0.5 to 2 times the length scale
/// set (measured 4.73 m along, 2.67 m across for 4 m). The measure
/// saturates on this field and record: set to 12 m, the lengths read 6.8
/// and 6.4 m (with the modes drawn once), so it holds the length to a
/// factor, not finely.
#[test]
fn turbulence_makes_patches_carried_by_the_wind() {
    let turbulence = Turbulence {
        intensity: 0.3,
        length_scale: 4.0,
        seed: 9,
        speed: None,
        finest_wavelength: None,
    };
    // Two points 20 m apart across the wind, then 21 along the wind (x)
    // and 21 across it (z), 2 m apart, for the correlation lengths and the
    // patches' travel.
    let mut points = vec![Vec3::new(-4.0, 0.4, -10.0), Vec3::new(-4.0, 0.4, 10.0)];
    let line = |along: bool| {
        (-10..=10).map(move |i| {
            let r = 2.0 * i as f32;
            if along {
                Vec3::new(r, 0.4, 0.0)
            } else {
                Vec3::new(0.0, 0.4, r)
            }
        })
    };
    points.extend(line(true).chain(line(false)));
    let turbulent = field_wind(Some(turbulence), 0.0, &points, 20.0);
    let fronts = field_wind(None, 0.5, &points, 20.0);
    // The integral length along each line: the mean correlation of the
    // points r apart, summed over r (trapezoids of 2 m) to its first zero.
    let integral_length = |series: &[Vec<f64>]| {
        let rho: Vec<f64> = (0..series.len())
            .map(|m| {
                let pairs = series.len() - m;
                (0..pairs)
                    .map(|i| lagged_correlation(&series[i], &series[i + m], 0))
                    .sum::<f64>()
                    / pairs as f64
            })
            .collect();
        let mut length = 0.0;
        for pair in rho.windows(2) {
            if pair[1] <= 0.0 {
                // The last piece up to the zero crossing.
                length += 2.0 * pair[0] * pair[0] / (pair[0] - pair[1]) / 2.0;
                break;
            }
            length += 2.0 * (pair[0] + pair[1]) / 2.0;
        }
        (length, rho)
    };
    let (along, rho_along) = integral_length(&turbulent[2..23]);
    let (across_length, rho_across) = integral_length(&turbulent[23..44]);
    let show = |rho: &[f64]| {
        rho.iter()
            .take(8)
            .map(|r| format!("{r:.2}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    eprintln!(
        "integral length of the downwind wind at 0.4 m: along the wind {along:.2} m (correlation every 2 m: {}), across {across_length:.2} m ({}); the length scale set: 4 m",
        show(&rho_along),
        show(&rho_across)
    );
    // Within 0.5 to 2 times the length scale both ways (issue 39); the
    // inflow's fronts alone correlate right across the field.
    for (name, length) in [("along", along), ("across", across_length)] {
        assert!(
            (2.0..=8.0).contains(&length),
            "{name} the wind: integral length {length} m against 4 m"
        );
    }

    let (across, across_fronts) = (
        lagged_correlation(&turbulent[0], &turbulent[1], 0),
        lagged_correlation(&fronts[0], &fronts[1], 0),
    );
    // Samples every 3 steps of 1/60 s: half a second is 10 samples. The
    // mean correlation of the points d apart on the line along the wind,
    // the second 0.5 s later, for d = 0, 2, ... 22 m.
    let along_line = &turbulent[2..23];
    let rho: Vec<f64> = (0..12)
        .map(|d| {
            let pairs = 21 - d;
            (0..pairs)
                .map(|i| lagged_correlation(&along_line[i], &along_line[i + d], 10))
                .sum::<f64>()
                / pairs as f64
        })
        .collect();
    let ridge = wind_scenes::ridge(&rho, 2.0);
    let mean_wind = along_line.iter().flatten().sum::<f64>()
        / along_line.iter().map(Vec::len).sum::<usize>() as f64;
    let speed = ridge / 0.5;
    eprintln!(
        "20 m across the wind: correlation {across:.2} with turbulence, {across_fronts:.2} with the inflow's gusts alone; \
         0.5 s on, the correlation along the wind peaks {ridge:.2} m downwind: convection {speed:.2} m/s against a mean wind of {mean_wind:.2} m/s ({:.2}x)",
        speed / mean_wind
    );
    assert!(across < 0.5, "{across}");
    assert!(across_fronts > 0.8, "{across_fronts}");
    assert!(
        (0.8..=1.5).contains(&(speed / mean_wind)),
        "{speed} against {mean_wind}"
    );
}
