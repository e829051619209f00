//! Pictures of the wind a person can read: a slice of the field as SVG,
//! speed as colour with a colour bar in m/s, direction as short streaks
//! (a dot at the foot of each), axes in metres, the slice's height or
//! depth in the title, obstacles outlined in white, the grass in green,
//! solid cells (obstacles, the ground's staircase) and the ground under
//! its surface in earth brown with the ground's line in black. Drawn on
//! the CPU from the velocity read back from the GPU.

use glam::{Vec2, Vec3, Vec3Swizzles};
use plotters::coord::types::RangedCoordf32;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::model::terrain::Terrain;
use crate::model::wind::{Obstacle, WindField};
use crate::scene::GrassPatch;

/// Which plane to cut.
#[derive(Clone, Copy, Debug)]
pub enum Slice {
    /// The surface `height` above the ground (a horizontal plane over
    /// flat ground; x right, z up the picture): where the grass is.
    Horizontal { height: f32 },
    /// The vertical plane z = depth (x right, y up).
    Vertical { depth: f32 },
}

/// What stands in the wind, outlined on a slice.
pub struct Outlines<'a> {
    /// The ground: the horizontal slice follows it, the vertical one
    /// draws its line.
    pub ground: &'a Terrain,
    pub obstacles: &'a [Obstacle],
    pub grass: &'a [GrassPatch],
    /// The tallest blade (m): the grass's outline on a vertical slice.
    pub grass_height: f32,
}

/// At most this many colour cells along either axis of the picture.
const MAX_CELLS_ACROSS: u32 = 160;
/// About this many streaks along the longer axis.
const STREAKS_ACROSS: f32 = 24.0;
const PLOT_WIDTH: u32 = 760;

/// Dark blue -> cyan -> yellow -> red over [0, 1].
fn ramp(t: f32) -> RGBColor {
    const STOPS: [[f32; 3]; 4] = [
        [0.05, 0.05, 0.35],
        [0.0, 0.75, 0.85],
        [0.95, 0.9, 0.1],
        [0.85, 0.1, 0.05],
    ];
    let t = t.clamp(0.0, 1.0) * 3.0;
    let i = (t.floor() as usize).min(2);
    let f = t - i as f32;
    let c: [u8; 3] = std::array::from_fn(|k| {
        ((STOPS[i][k] * (1.0 - f) + STOPS[i + 1][k] * f) * 255.0).round() as u8
    });
    RGBColor(c[0], c[1], c[2])
}

/// Solid cells and the ground under its surface.
const EARTH: RGBColor = RGBColor(110, 84, 60);

impl Slice {
    /// World position of picture point (u, v) in metres.
    fn world(self, p: Vec2, ground: &Terrain) -> Vec3 {
        match self {
            Slice::Horizontal { height } => Vec3::new(p.x, ground.height(p.x, p.y) + height, p.y),
            Slice::Vertical { depth } => Vec3::new(p.x, p.y, depth),
        }
    }

    /// A velocity's part in the picture's plane.
    fn planar(self, v: Vec3) -> Vec2 {
        match self {
            Slice::Horizontal { .. } => Vec2::new(v.x, v.z),
            Slice::Vertical { .. } => Vec2::new(v.x, v.y),
        }
    }

    /// The picture's axis names.
    fn axes(self) -> (&'static str, &'static str) {
        match self {
            Slice::Horizontal { .. } => ("x (m)", "z (m)"),
            Slice::Vertical { .. } => ("x (m)", "height y (m)"),
        }
    }
}

/// Closed polylines (picture coordinates) outlining what `outlines` puts
/// in the plane of `slice`: obstacles first, then grass patches.
fn outline_paths(slice: Slice, outlines: &Outlines) -> (Vec<Vec<Vec2>>, Vec<Vec<Vec2>>) {
    let solids = outlines
        .obstacles
        .iter()
        .filter_map(|o| obstacle_outline(slice, *o))
        .collect();
    let grass = outlines
        .grass
        .iter()
        .filter_map(|p| grass_outline(slice, *p, outlines))
        .collect();
    (solids, grass)
}

/// A circle of radius `r` about `c`, as 48 segments.
fn circle(c: Vec2, r: f32) -> Vec<Vec2> {
    (0..=48)
        .map(|i| c + Vec2::from_angle(i as f32 / 48.0 * std::f32::consts::TAU) * r)
        .collect()
}

/// The rectangle from `lo` to `hi`, closed.
fn rect(lo: Vec2, hi: Vec2) -> Vec<Vec2> {
    vec![lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y), lo]
}

/// Half the chord a circle of radius r cuts at distance d from its centre.
fn chord(r: f32, d: f32) -> f32 {
    (r * r - d * d).max(0.0).sqrt()
}

/// Where obstacle `o` meets the plane of `slice` (None: it does not).
fn obstacle_outline(slice: Slice, o: Obstacle) -> Option<Vec<Vec2>> {
    match (slice, o) {
        (Slice::Horizontal { height }, Obstacle::Box { min, max }) => (min.y..=max.y)
            .contains(&height)
            .then(|| rect(min.xz(), max.xz())),
        (Slice::Vertical { depth }, Obstacle::Box { min, max }) => (min.z..=max.z)
            .contains(&depth)
            .then(|| rect(min.xy(), max.xy())),
        (Slice::Horizontal { height }, Obstacle::Sphere { center, radius }) => {
            let r = chord(radius, height - center.y);
            (r > 0.0).then(|| circle(center.xz(), r))
        }
        (Slice::Vertical { depth }, Obstacle::Sphere { center, radius }) => {
            let r = chord(radius, depth - center.z);
            (r > 0.0).then(|| circle(center.xy(), r))
        }
        (
            Slice::Horizontal { height },
            Obstacle::Cylinder {
                base,
                radius,
                height: tall,
            },
        ) => (base.y..=base.y + tall)
            .contains(&height)
            .then(|| circle(base.xz(), radius)),
        (
            Slice::Vertical { depth },
            Obstacle::Cylinder {
                base,
                radius,
                height: tall,
            },
        ) => {
            let r = chord(radius, depth - base.z);
            (r > 0.0).then(|| {
                rect(
                    Vec2::new(base.x - r, base.y),
                    Vec2::new(base.x + r, base.y + tall),
                )
            })
        }
    }
}

/// Where grass patch `p` meets the plane of `slice`, up to the tallest
/// blade over the ground (None: it does not).
fn grass_outline(slice: Slice, p: GrassPatch, outlines: &Outlines) -> Option<Vec<Vec2>> {
    // The grass's layer over x0..x1 in the plane z = depth: from the
    // ground up to the tallest blade over it.
    let layer = |x0: f32, x1: f32, depth: f32| -> Vec<Vec2> {
        let xs = |n: u32| (0..=n).map(move |i| x0 + (x1 - x0) * i as f32 / n as f32);
        let n = 48;
        let ground = |x: f32| outlines.ground.height(x, depth);
        let mut path: Vec<Vec2> = xs(n).map(|x| Vec2::new(x, ground(x))).collect();
        path.extend(
            xs(n)
                .rev()
                .map(|x| Vec2::new(x, ground(x) + outlines.grass_height)),
        );
        path.push(path[0]);
        path
    };
    match (slice, p) {
        (Slice::Horizontal { height }, GrassPatch::Bunch { center, radius, .. }) => {
            (height <= outlines.grass_height).then(|| circle(Vec2::from(center), radius))
        }
        (Slice::Horizontal { height }, GrassPatch::Meadow { center, size, .. }) => {
            let (c, half) = (Vec2::from(center), Vec2::from(size) / 2.0);
            (height <= outlines.grass_height).then(|| rect(c - half, c + half))
        }
        (Slice::Vertical { depth }, GrassPatch::Bunch { center, radius, .. }) => {
            let r = chord(radius, depth - center[1]);
            (r > 0.0).then(|| layer(center[0] - r, center[0] + r, depth))
        }
        (Slice::Vertical { depth }, GrassPatch::Meadow { center, size, .. }) => {
            ((depth - center[1]).abs() <= size[1] / 2.0)
                .then(|| layer(center[0] - size[0] / 2.0, center[0] + size[0] / 2.0, depth))
        }
    }
}

/// `slice` of `field` as SVG, titled `title`; speed coloured from 0 to
/// `max_speed` m/s (the field's maximum gives the most contrast).
pub fn svg(
    field: &WindField,
    slice: Slice,
    max_speed: f32,
    outlines: &Outlines,
    title: &str,
) -> Result<String> {
    let err = |e: String| Error::InvalidInput(format!("drawing the wind slice: {e}"));
    let g = field.grid;
    let (lo, size, cells) = match slice {
        Slice::Horizontal { .. } => (g.origin.xz(), g.size().xz(), [g.cells.x, g.cells.z]),
        Slice::Vertical { .. } => (g.origin.xy(), g.size().xy(), [g.cells.x, g.cells.y]),
    };
    let hi = lo + size;
    let across = cells.map(|n| n.min(MAX_CELLS_ACROSS));
    let step = size / Vec2::new(across[0] as f32, across[1] as f32);
    let scale = if max_speed > 0.0 { max_speed } else { 1.0 };
    // The plot keeps the world's aspect within reason.
    let plot_height = ((PLOT_WIDTH as f32 * size.y / size.x) as u32).clamp(220, 760);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (PLOT_WIDTH + 130, plot_height + 90))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let (plot, key) = root.split_horizontally(PLOT_WIDTH);
        let (x_desc, y_desc) = slice.axes();
        let mut chart = ChartBuilder::on(&plot)
            .caption(title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(lo.x..hi.x, lo.y..hi.y)
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .draw()
            .map_err(|e| err(e.to_string()))?;
        let ground = outlines.ground;
        let solid = |x: Vec3| {
            x.y < ground.height(x.x, x.z) || field.cell_at(x).is_some_and(|c| field.solid[c])
        };
        let colour_cells = (0..across[1]).flat_map(|j| {
            (0..across[0]).map(move |i| {
                let a = lo + step * Vec2::new(i as f32, j as f32);
                let x = slice.world(a + step / 2.0, ground);
                let colour = if solid(x) {
                    EARTH
                } else {
                    ramp(field.sample(x).length() / scale)
                };
                Rectangle::new([(a.x, a.y), (a.x + step.x, a.y + step.y)], colour.filled())
            })
        });
        chart
            .draw_series(colour_cells)
            .map_err(|e| err(e.to_string()))?;
        // Streaks along the flow in the plane, longer when faster.
        let streaks = streaks(field, slice, ground, (lo, size), scale, &solid);
        chart
            .draw_series(streaks.iter().map(|&(a, b)| {
                PathElement::new(vec![(a.x, a.y), (b.x, b.y)], WHITE.stroke_width(1))
            }))
            .map_err(|e| err(e.to_string()))?;
        chart
            .draw_series(
                streaks
                    .iter()
                    .map(|&(a, _)| Circle::new((a.x, a.y), 2, BLACK.filled())),
            )
            .map_err(|e| err(e.to_string()))?;
        draw_outlines(&mut chart, slice, outlines, (lo, size), across[0]).map_err(err)?;

        colour_bar(&key, scale).map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(out)
}

/// The chart a slice is drawn in: world coordinates in the plane.
type SliceChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf32, RangedCoordf32>>;

/// Over the slice's colours: the ground's line across a vertical plane
/// (`across` samples to a cell), the solids' outlines in white, the
/// grass's in green.
fn draw_outlines(
    chart: &mut SliceChart,
    slice: Slice,
    outlines: &Outlines,
    (lo, size): (Vec2, Vec2),
    across: u32,
) -> std::result::Result<(), String> {
    let ground = outlines.ground;
    if let Slice::Vertical { depth } = slice {
        // The ground's line across the plane.
        let line = (0..=4 * across).map(|i| {
            let x = lo.x + size.x * i as f32 / (4 * across) as f32;
            (x, ground.height(x, depth))
        });
        chart
            .draw_series(std::iter::once(PathElement::new(
                line.collect::<Vec<_>>(),
                BLACK.stroke_width(2),
            )))
            .map_err(|e| e.to_string())?;
    }
    let (solids, grass) = outline_paths(slice, outlines);
    let path = |p: &Vec<Vec2>, style: ShapeStyle| {
        PathElement::new(p.iter().map(|q| (q.x, q.y)).collect::<Vec<_>>(), style)
    };
    chart
        .draw_series(solids.iter().map(|p| path(p, WHITE.stroke_width(2))))
        .map_err(|e| e.to_string())?;
    chart
        .draw_series(
            grass
                .iter()
                .map(|p| path(p, RGBColor(40, 200, 40).stroke_width(2))),
        )
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The colour bar beside a slice: speed in m/s, from 0 to `scale`.
fn colour_bar(
    key: &DrawingArea<SVGBackend<'_>, Shift>,
    scale: f32,
) -> std::result::Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut bar = ChartBuilder::on(key)
        .margin_top(40)
        .margin_bottom(50)
        .y_label_area_size(55)
        .build_cartesian_2d(0.0f32..1.0, 0.0f32..scale)
        .map_err(|e| err(&e))?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc("wind speed (m/s)")
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    bar.draw_series((0..50).map(|i| {
        let v = scale * i as f32 / 50.0;
        Rectangle::new(
            [(0.0, v), (1.0, v + scale / 50.0)],
            ramp(i as f32 / 49.0).filled(),
        )
    }))
    .map_err(|e| err(&e))?;
    Ok(())
}

/// Streaks along the flow in the plane of `slice` over the rectangle
/// (least corner, size): from a lattice of points off the solids, each
/// as long as its speed over `scale` allows (at most one spacing).
fn streaks(
    field: &WindField,
    slice: Slice,
    ground: &Terrain,
    (lo, size): (Vec2, Vec2),
    scale: f32,
    solid: &dyn Fn(Vec3) -> bool,
) -> Vec<(Vec2, Vec2)> {
    let spacing = size.max_element() / STREAKS_ACROSS;
    let counts = (size / spacing).floor().max(Vec2::ONE);
    let mut streaks = Vec::new();
    for j in 0..counts.y as u32 {
        for i in 0..counts.x as u32 {
            let p = lo + (Vec2::new(i as f32, j as f32) + 0.5) * (size / counts);
            let x = slice.world(p, ground);
            if solid(x) {
                continue;
            }
            let d = slice.planar(field.sample(x));
            if let Some(dir) = d.try_normalize() {
                let end = p + dir * (d.length() / scale).min(1.0) * spacing * 0.85;
                streaks.push((p, end));
            }
        }
    }
    streaks
}

/// The plane's name for a title: "y = 0.60 m" (over flat ground, else
/// "0.60 m above the ground") or "z = 0.00 m".
pub fn plane_name(slice: Slice, ground: &Terrain) -> String {
    match slice {
        Slice::Horizontal { height } if ground.is_flat() => {
            format!("horizontal slice at height y = {height:.2} m")
        }
        Slice::Horizontal { height } => format!("slice {height:.2} m above the ground"),
        Slice::Vertical { depth } => format!("vertical slice at z = {depth:.2} m"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::wind::{WindGrid, WindSettings};
    use glam::UVec3;

    #[test]
    fn a_slice_has_axes_a_colour_bar_and_the_outlines() {
        let grid = WindGrid::new(
            UVec3::new(8, 4, 6),
            Vec3::new(-2.0, 0.0, -1.5),
            Vec3::new(4.0, 2.0, 3.0),
        )
        .unwrap();
        let mut field = WindField::new(grid, &WindSettings::default());
        field.vel[0].fill(2.0);
        let obstacles = [Obstacle::Box {
            min: Vec3::new(-0.5, 0.0, -0.5),
            max: Vec3::new(0.5, 1.0, 0.5),
        }];
        let grass = [GrassPatch::Bunch {
            center: [1.0, 0.0],
            radius: 0.3,
            count: 10,
        }];
        let flat = Terrain::default();
        let outlines = Outlines {
            ground: &flat,
            obstacles: &obstacles,
            grass: &grass,
            grass_height: 0.7,
        };
        let slice = Slice::Horizontal { height: 0.5 };
        let svg = svg(&field, slice, 2.0, &outlines, &plane_name(slice, &flat)).unwrap();
        assert!(svg.starts_with("<svg"));
        for text in ["x (m)", "z (m)", "wind speed (m/s)", "height y = 0.50 m"] {
            assert!(svg.contains(text), "no {text:?}");
        }
        // 48 colour cells and 50 bar steps, plus backgrounds.
        assert!(svg.matches("<rect").count() >= 98);
        let (solids, green) = outline_paths(slice, &outlines);
        assert_eq!((solids.len(), green.len()), (1, 1));
        // Above the obstacle and the grass, neither is cut.
        let (solids, green) = outline_paths(Slice::Horizontal { height: 1.5 }, &outlines);
        assert_eq!((solids.len(), green.len()), (0, 0));
        // A vertical cut through the bunch outlines it up to the tallest blade.
        let (_, green) = outline_paths(Slice::Vertical { depth: 0.1 }, &outlines);
        assert_eq!(green.len(), 1);
        assert!(green[0].iter().any(|p| (p.y - 0.7).abs() < 1e-6));
    }

    /// Over a ridge the horizontal slice follows the ground (no cell of it
    /// solid, the wind's colour everywhere), and the vertical one draws the
    /// ground and its staircase in earth, about as much of the picture as
    /// lies under the ground, with the ground's line; the grass's layer
    /// rides on the ground.
    #[test]
    fn over_terrain_the_slices_draw_the_ground_as_ground() {
        use crate::model::terrain::Ridge;
        let grid = WindGrid::new(
            UVec3::new(40, 12, 8),
            Vec3::new(-10.0, 0.0, -2.0),
            Vec3::new(20.0, 3.0, 4.0),
        )
        .unwrap();
        let ground = Terrain {
            ridges: vec![Ridge {
                center: [0.0, 0.0],
                height: 1.5,
                half_width: 2.0,
                heading: 90.0,
            }],
            ..Terrain::default()
        };
        let settings = WindSettings {
            terrain: ground.clone(),
            ..WindSettings::default()
        };
        let mut field = WindField::new(grid, &settings);
        field.vel[0].fill(2.0);
        let grass = [GrassPatch::Meadow {
            center: [0.0, 0.0],
            size: [16.0, 4.0],
            count: 100,
        }];
        let outlines = Outlines {
            ground: &ground,
            obstacles: &[],
            grass: &grass,
            grass_height: 0.5,
        };
        let earth = |svg: &str| svg.matches("fill=\"#6E543C\"").count();
        let above = Slice::Horizontal { height: 0.3 };
        let name = plane_name(above, &ground);
        assert_eq!(name, "slice 0.30 m above the ground");
        let picture = svg(&field, above, 2.0, &outlines, &name).unwrap();
        assert_eq!(earth(&picture), 0);
        let cut = Slice::Vertical { depth: 0.0 };
        let picture = svg(&field, cut, 2.0, &outlines, &plane_name(cut, &ground)).unwrap();
        // The ground's area over the grid's 20 x 3 m: the ridge's profile
        // integrated, pi H L (less its tails beyond 10 m).
        let under = (0..400)
            .map(|i| ground.height(-10.0 + (i as f32 + 0.5) * 0.05, 0.0) * 0.05)
            .sum::<f32>();
        let share = earth(&picture) as f32 / (40.0 * 12.0);
        assert!(
            (share / (under / 60.0) - 1.0).abs() < 0.25,
            "{share} of the cells in earth, {} of the slice under the ground",
            under / 60.0
        );
        let (_, green) = outline_paths(cut, &outlines);
        let top = green[0].iter().map(|p| p.y).fold(f32::MIN, f32::max);
        assert!((top - 2.0).abs() < 1e-3, "the grass's layer tops at {top}");
    }
}
