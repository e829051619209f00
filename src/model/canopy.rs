//! Two-way coupling (ours; the paper's first item of future work;
//! docs/method.md section 3): the grass slows the air. After each grass step
//! every blade lays the frontal area of each of its edges in the wind cell
//! the edge's midpoint stands in; the next wind step takes the canopy drag
//!
//! ```text
//! du/dt = -C_d a |u| u      (a: frontal area per unit volume, 1/m)
//! ```
//!
//! implicitly in its advection, u' = u / (1 + dt C_d a |u|)
//! (`WindField::advect`), which slows the air but never turns it back.
//!
//! The area is summed in fixed point, `unit` square metres per count, so
//! the GPU's atomic adds give the same sum in any order and a run's frames
//! are the same every time. glsl/grass/step.glsl lays the area as
//! `deposit` does; glsl/wind/advect.comp takes the drag.

use glam::Vec3;

use super::grass::{guard_wind, pose, GrassBlade, Pose};
use super::grass_field::GrassField;
use super::wind::{WindField, WindGrid, WindSettings};

/// The smallest fixed-point unit (m^2): a thousandth of a square millimetre.
const MIN_UNIT: f64 = 1e-9;

/// Square metres per count for `blades`: fine, but coarse enough that
/// their whole area, every edge face-on in one cell, stays below 2^31
/// counts, so no cell's sum can wrap.
pub fn unit(blades: &[GrassBlade]) -> f32 {
    let total: f64 = blades
        .iter()
        .map(|b| (0..3).map(|i| plate_area(b, i) as f64).sum::<f64>())
        .sum();
    (total / 2f64.powi(31)).max(MIN_UNIT) as f32
}

/// Edge `i`'s plate: its length times the blade's full width (the S of
/// docs/method.md section 4).
fn plate_area(blade: &GrassBlade, i: usize) -> f32 {
    (blade.rest_point(i + 1) - blade.rest_point(i)).length() * 2.0 * blade.half_width
}

/// The frontal area of each edge at `pose` to the wind `wind`: the edge's
/// plate projected on the plane across the wind, l 2 hw |E_n_local . v / |v||
/// (E_n_local with the twist: a face turned edge-on shows the wind less).
/// Still air meets no area.
pub fn frontal_areas(blade: &GrassBlade, pose: &Pose, wind: Vec3) -> [f32; 3] {
    let speed = wind.length();
    if speed <= 1e-6 {
        return [0.0; 3];
    }
    let along = wind / speed;
    std::array::from_fn(|i| {
        let n = pose.w_local[i].cross(pose.e[i]);
        let n_len = n.length();
        let facing = if n_len > 1e-12 {
            (n.dot(along) / n_len).abs()
        } else {
            0.0
        };
        plate_area(blade, i) * facing
    })
}

/// The cell of `grid` holding `x`, if any.
pub fn cell_of(grid: &WindGrid, x: Vec3) -> Option<usize> {
    let g = ((x - grid.origin) / grid.cell).floor();
    let inside = g.cmpge(Vec3::ZERO).all() && g.cmplt(grid.cells.as_vec3()).all();
    inside.then(|| grid.cell_index(g.x as u32, g.y as u32, g.z as u32))
}

/// Adds a blade's frontal area (`frontal_areas`, at `pose` in the wind
/// `wind` it felt) to the cells `cell_at` finds its edges' midpoints in, in
/// counts of `unit` m^2 rounded to the nearest. Midpoints outside the grid
/// lay none.
pub fn deposit(
    counts: &mut [u32],
    cell_at: impl Fn(Vec3) -> Option<usize>,
    unit: f32,
    blade: &GrassBlade,
    pose: &Pose,
    wind: Vec3,
) {
    for (i, area) in frontal_areas(blade, pose, wind).into_iter().enumerate() {
        let mid = (pose.points[i] + pose.points[i + 1]) * 0.5;
        if let Some(c) = cell_at(mid) {
            counts[c] = counts[c].wrapping_add((area / unit + 0.5) as u32);
        }
    }
}

/// One simulation step on the CPU, as the GPU records it: the wind step,
/// then the grass step. With two-way coupling (and a canopy unit set) the
/// wind takes the drag of the area the grass laid last step, and each
/// blade lays its area anew.
pub fn coupled_step(wind: &mut WindField, settings: &WindSettings, grass: &mut GrassField) {
    wind.step(settings, grass.dt);
    if !wind.is_coupled(settings) {
        grass.step(|x| wind.felt(x));
        return;
    }
    let mut counts = std::mem::take(&mut wind.canopy);
    counts.fill(0);
    let (grid, unit) = (wind.grid, wind.canopy_unit);
    grass.step_each(
        |x| wind.felt(x),
        |blade, state, felt| {
            let pose = pose(blade, state.angle);
            let cell_at = |x| cell_of(&grid, x);
            deposit(&mut counts, cell_at, unit, blade, &pose, guard_wind(felt));
        },
    );
    wind.canopy = counts;
}
