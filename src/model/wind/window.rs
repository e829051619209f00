//! The wind window that follows the camera (`[grass.cover]`'s
//! `wind.window`, docs/method.md): a grid of the scene's cells centred
//! under the camera that moves in whole cells. A move shifts the air with
//! it, so that a point of the world keeps its wind, and fills the cells
//! that come in from the inflow's mean velocity and the turbulence there;
//! glsl/wind/shift.comp does the same on the GPU. Over terrain the window
//! stands in the world's heights, its floor and lid fixed (`Scene::
//! wind_grid`), and carries the ground's staircase with it: the cells
//! that come in are voxelised and every face classified again.

use glam::{IVec2, Vec2, Vec3};

use super::{voxelised, FaceKind, WindField, WindGrid, WindSettings};

impl WindGrid {
    /// The whole cells (x, z) the window must move by to stay under a
    /// camera at `eye` (x, z): none while the eye is less than a cell from
    /// the window's centre along each axis, so an eye that hovers on a
    /// cell's edge does not shift the air back and forth.
    pub fn window_shift(&self, eye: Vec2) -> IVec2 {
        let centre = Vec2::new(
            self.origin.x + 0.5 * self.size().x,
            self.origin.z + 0.5 * self.size().z,
        );
        let cells = (eye - centre) / Vec2::new(self.cell.x, self.cell.z);
        if !cells.is_finite() {
            return IVec2::ZERO;
        }
        // Beyond the grid's width every cell is new: a larger shift moves
        // the same air (none) and only risks overflow.
        let most = self.cells.x.max(self.cells.z) as f32 + 1.0;
        cells
            .trunc()
            .clamp(Vec2::splat(-most), Vec2::splat(most))
            .as_ivec2()
    }

    /// The grid moved by `by` whole cells (x, z).
    pub fn shifted(&self, by: IVec2) -> WindGrid {
        let mut grid = *self;
        grid.origin += Vec3::new(by.x as f32 * self.cell.x, 0.0, by.y as f32 * self.cell.z);
        grid
    }
}

/// The face a face `f` of the grid moved by `by` held before the move, if
/// the old grid had it.
fn source_face(grid: &WindGrid, axis: usize, f: [u32; 3], by: IVec2) -> Option<usize> {
    let dims = grid.face_dims(axis);
    let (i, k) = (f[0] as i64 + by.x as i64, f[2] as i64 + by.y as i64);
    ((0..dims.x as i64).contains(&i) && (0..dims.z as i64).contains(&k))
        .then(|| grid.face_index(axis, i as u32, f[1], k as u32))
}

impl WindField {
    /// Moves the window by `by` whole cells (x, z) between two steps.
    ///
    /// Every face takes what the face at its world position held, the
    /// turbulence the last step added taken off; a face with none there
    /// (new, or where the old grid had a wall) takes the inflow's mean
    /// velocity (zero without an inflow); walls hold zero. The turbulence
    /// is a field of the world: its modes' reference moves with the
    /// corner, and every face not a wall gains it where the face now is,
    /// as a step's end does. The canopy the grass laid moves with the
    /// cells; the pressure restarts from zero (the last steps' pressures,
    /// the multigrid's start, belong to the cells left behind). Over terrain the moved grid's cells are
    /// voxelised and its faces classified again (the multigrid's levels
    /// with them): a point of the world keeps its kind, the sides' faces
    /// take theirs where they now are. Obstacles, fixed in the window,
    /// are refused with a cover (`scene::check`).
    pub fn shift_window(&mut self, settings: &WindSettings, by: IVec2) {
        if by == IVec2::ZERO {
            return;
        }
        let grid = self.grid;
        let before = self.faces.clone();
        if !settings.terrain.is_flat() {
            let moved = grid.shifted(by);
            (self.ground, self.solid) = voxelised(&moved, settings);
            self.grid = moved;
            self.classify_faces(settings.inflow.as_ref());
        }
        let fill = settings.inflow.map_or(Vec3::ZERO, |i| i.mean_velocity());
        for axis in 0..3 {
            let (was, kinds) = (&before[axis], &self.faces[axis]);
            let (vel, added) = (&self.vel[axis], &self.turbulence_added[axis]);
            let moved: Vec<f32> = grid
                .each_face(axis)
                .map(|(idx, f)| {
                    if kinds[idx] == FaceKind::Wall {
                        return 0.0;
                    }
                    match source_face(&grid, axis, f, by) {
                        Some(src) if was[src] != FaceKind::Wall => vel[src] - added[src],
                        _ => fill[axis],
                    }
                })
                .collect();
            self.vel[axis] = moved;
            self.turbulence_added[axis].fill(0.0);
        }
        let n = grid.cells;
        self.canopy = grid
            .each_cell()
            .map(|(_, [i, j, k])| {
                let (si, sk) = (i as i64 + by.x as i64, k as i64 + by.y as i64);
                let inside = (0..n.x as i64).contains(&si) && (0..n.z as i64).contains(&sk);
                if inside {
                    self.canopy[grid.cell_index(si as u32, j, sk as u32)]
                } else {
                    0
                }
            })
            .collect();
        self.pressure.fill(0.0);
        self.pressure_before.fill(0.0);
        self.grid = grid.shifted(by);
        if let Some(turbulence) = &mut self.turbulence {
            turbulence.move_corner(self.grid.origin - grid.origin);
        }
        self.add_turbulence_now(settings);
    }
}

#[cfg(test)]
mod tests {
    use glam::{IVec2, UVec3, Vec2, Vec3};

    use crate::model::turbulence::Turbulence;
    use crate::model::wind::{FaceKind, Inflow, WindField, WindGrid, WindSettings};

    /// A 16 x 4 x 16 m window of 1 x 0.5 x 1 m cells in a 4 m/s wind
    /// towards 30 degrees (entering by two sides) with turbulence.
    fn window() -> (WindGrid, WindSettings) {
        let grid = WindGrid::new(
            UVec3::new(16, 8, 16),
            Vec3::new(-8.0, 0.0, -8.0),
            Vec3::new(16.0, 4.0, 16.0),
        )
        .unwrap();
        let settings = WindSettings {
            inflow: Some(Inflow {
                speed: 4.0,
                heading: 30.0,
                gust: Default::default(),
            }),
            turbulence: Some(Turbulence {
                intensity: 0.3,
                length_scale: 3.0,
                seed: 4,
                speed: None,
                finest_wavelength: None,
            }),
            moving_window: true,
            ..Default::default()
        };
        (grid, settings)
    }

    #[test]
    fn the_window_moves_in_whole_cells_once_the_eye_is_a_cell_from_its_centre() {
        let (grid, _) = window();
        assert_eq!(grid.window_shift(Vec2::new(0.9, -0.9)), IVec2::ZERO);
        assert_eq!(grid.window_shift(Vec2::new(1.0, -2.5)), IVec2::new(1, -2));
        assert_eq!(grid.window_shift(Vec2::new(-7.2, 40.0)), IVec2::new(-7, 17));
        assert_eq!(grid.window_shift(Vec2::new(f32::NAN, 0.0)), IVec2::ZERO);
        let moved = grid.shifted(IVec2::new(1, -2));
        assert_eq!(moved.origin, Vec3::new(-7.0, 0.0, -10.0));
        assert_eq!(moved.window_shift(Vec2::new(1.0, -2.5)), IVec2::ZERO);
    }

    /// After a move every point of the world that both windows hold keeps
    /// its wind, the turbulence included (recomputed where the faces now
    /// are, to f32's rounding of the modes' phases); the faces that came
    /// in hold the inflow's mean velocity plus the turbulence there (to
    /// 1e-5 m/s of the per-face sum); the
    /// canopy moves with its cells. Fails with the turbulence's corner
    /// left where it was (1 m/s off), or the air shifted the wrong way.
    #[test]
    fn a_point_of_the_world_keeps_its_wind_when_the_window_moves() {
        let (grid, settings) = window();
        let mut field = WindField::new(grid, &settings);
        for _ in 0..20 {
            field.step(&settings, 1.0 / 60.0);
        }
        for (c, count) in field.canopy.iter_mut().enumerate() {
            *count = c as u32 % 97;
        }
        let before = field.clone();
        let by = IVec2::new(3, -2);
        field.shift_window(&settings, by);
        assert_eq!(field.grid, grid.shifted(by));
        // Points at least a cell inside both windows.
        let (lo, hi) = (
            before.grid.origin.max(field.grid.origin) + Vec3::new(1.0, 0.5, 1.0),
            (before.grid.origin + before.grid.size()).min(field.grid.origin + field.grid.size())
                - Vec3::new(1.0, 0.5, 1.0),
        );
        let mut worst = 0.0f32;
        let mut speed = 0.0f32;
        for i in 0..=8 {
            for j in 0..=4 {
                for k in 0..=8 {
                    let t = Vec3::new(i as f32 / 8.0, j as f32 / 4.0, k as f32 / 8.0);
                    let x = lo + (hi - lo) * t;
                    worst = worst.max((field.sample(x) - before.sample(x)).abs().max_element());
                    speed = speed.max(before.sample(x).length());
                }
            }
        }
        eprintln!(
            "largest change of the wind at a point: {worst:.2e} m/s (winds up to {speed:.1} m/s)"
        );
        assert!(speed > 3.0);
        assert!(worst < 1e-4, "the wind at a point changed by {worst} m/s");
        // A face that came in: the mean flow and the turbulence there.
        let turbulence = field.turbulence.as_ref().unwrap();
        let records = turbulence.records(settings.turbulence_sigma());
        let n = field.grid.face_dims(0);
        let mean = settings.inflow.unwrap().mean_velocity();
        let mut checked = 0;
        for (idx, [i, j, k]) in field.grid.each_face(0) {
            let new = i + 3 >= n.x || k < 2;
            if new && field.faces[0][idx] == FaceKind::Free {
                let q = crate::model::turbulence::TurbulenceField::face_point(0, [i, j, k]);
                let u = turbulence.at(&records, 0, q);
                // The step sums the modes separated along the lattice, the
                // same sum to f64's rounding (held to 4e-6 m/s elsewhere).
                let added = field.turbulence_added[0][idx];
                assert!(
                    (added - u).abs() < 1e-5,
                    "turbulence {added} here, {u} per face"
                );
                assert_eq!(field.vel[0][idx], mean.x + added);
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked} new faces");
        // The canopy moved with its cells; the cells that came in are bare.
        let cells = field.grid.cells;
        for (c, [i, j, k]) in field.grid.each_cell() {
            let (si, sk) = (i as i32 + by.x, k as i32 + by.y);
            let expected = if si < cells.x as i32 && sk >= 0 {
                before.canopy[before.grid.cell_index(si as u32, j, sk as u32)]
            } else {
                0
            };
            assert_eq!(field.canopy[c], expected);
        }
        assert!(field.pressure.iter().all(|&p| p == 0.0));
        // The moved window steps on.
        for _ in 0..5 {
            field.step(&settings, 1.0 / 60.0);
        }
        assert!(field.vel.iter().flatten().all(|v| v.is_finite()));
    }

    /// A wind along an axis leaves the window's two sides along it walls
    /// for the mean flow, and the turbulence, mirrored across no side on a
    /// moving window, crosses them: the air the blades see stays
    /// divergence-free to f32's rounding after steps and moves, at every
    /// heading (at most 0.12 of the floor here). With the turbulence held
    /// at zero on those walls, a layer of cells along each diverged: 6e4
    /// times the floor. The first step is left out: a wind along an axis
    /// starts from rest, and the multigrid leaves its share of that first
    /// projection (36 times the floor).
    #[test]
    fn the_turbulence_crosses_the_sides_along_an_axis_wind_without_diverging() {
        for heading in [0.0, 90.0, 30.0] {
            let (grid, mut settings) = window();
            settings.inflow.as_mut().unwrap().heading = heading;
            let mut field = WindField::new(grid, &settings);
            field.step(&settings, 1.0 / 60.0);
            let mut worst = 0.0f32;
            for n in 0..30 {
                if n % 10 == 9 {
                    field.shift_window(&settings, IVec2::new(2, -1));
                }
                field.step(&settings, 1.0 / 60.0);
                let speed = field
                    .vel
                    .iter()
                    .flatten()
                    .fold(0.0f32, |m, v| m.max(v.abs()));
                worst = worst.max(field.rms_divergence() / field.grid.divergence_floor(speed));
            }
            eprintln!(
                "towards {heading} degrees: rms divergence at most {worst:.2} of f32's floor"
            );
            assert!(
                worst < 1.0,
                "towards {heading} degrees: {worst} of the floor"
            );
        }
    }
}
