//! The grass from above at a few instants, as data: the field cut into
//! square cells, each coloured by how far its blades' tips are bent
//! downwind at that instant beyond the cell's own average, in the cell's
//! own standard deviations (the space-time diagram's colours). Patches of
//! turbulence are blobs that move downwind from one panel to the next;
//! fronts would be stripes across the whole field.

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::report::space_time::{diverging, diverging_key};

/// What to draw: the cells' standardised values at each instant,
/// `instants[k] = (time, values)` with `values[iz * nx + ix]` the cell
/// covering [x0 + ix cell, x0 + (ix + 1) cell) x [z0 + iz cell, ...); NaN
/// where a cell has no blades.
pub struct PlanView<'a> {
    pub title: &'a str,
    /// The axes' names: along the wind (across the panel), across it
    /// (down).
    pub axes: (&'a str, &'a str),
    pub x0: f64,
    pub z0: f64,
    pub cell: f64,
    pub nx: usize,
    pub nz: usize,
    pub instants: &'a [(f64, Vec<f64>)],
}

/// The panels side by side, the wind's axis across, the axis across the
/// wind down, with a colour key.
pub fn svg(p: &PlanView) -> Result<String> {
    let err = |e: String| Error::InvalidInput(format!("drawing the plan view: {e}"));
    if p.instants.is_empty() || p.nx == 0 || p.nz == 0 {
        return Err(err("nothing to draw".into()));
    }
    let panel = 320u32;
    let (x1, z1) = (p.x0 + p.cell * p.nx as f64, p.z0 + p.cell * p.nz as f64);
    let height = (panel as f64 * (z1 - p.z0) / (x1 - p.x0)).clamp(60.0, 640.0) as u32 + 110;
    let width = panel * p.instants.len() as u32 + 110;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let root = root
            .titled(p.title, ("sans-serif", 18))
            .map_err(|e| err(e.to_string()))?;
        let (panels, key) = root.split_horizontally(panel * p.instants.len() as u32);
        let areas = panels.split_evenly((1, p.instants.len()));
        for (area, (time, values)) in areas.iter().zip(p.instants) {
            let mut chart = ChartBuilder::on(area)
                .caption(format!("t = {time:.1} s"), ("sans-serif", 14))
                .margin(8)
                .x_label_area_size(34)
                .y_label_area_size(40)
                .build_cartesian_2d(p.x0..x1, z1..p.z0)
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc(p.axes.0)
                .y_desc(p.axes.1)
                .draw()
                .map_err(|e| err(e.to_string()))?;
            let cells = values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(i, &v)| {
                    let (ix, iz) = ((i % p.nx) as f64, (i / p.nx) as f64);
                    let (x, z) = (p.x0 + ix * p.cell, p.z0 + iz * p.cell);
                    Rectangle::new([(x, z), (x + p.cell, z + p.cell)], diverging(v).filled())
                });
            chart.draw_series(cells).map_err(|e| err(e.to_string()))?;
        }
        diverging_key(&key, "bent downwind (sd of the cell)").map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_view_draws_a_panel_per_instant_and_a_cell_per_value() {
        let values = vec![0.5, -1.0, f64::NAN, 2.0, 0.0, 1.0];
        let instants = [
            (10.0, values.clone()),
            (11.0, values.clone()),
            (12.0, values),
        ];
        let svg = svg(&PlanView {
            axes: ("x, along the wind (m)", "z (m)"),
            title: "test",
            x0: -3.0,
            z0: -2.0,
            cell: 2.0,
            nx: 3,
            nz: 2,
            instants: &instants,
        })
        .unwrap();
        assert!(svg.starts_with("<svg"));
        for t in ["t = 10.0 s", "t = 11.0 s", "t = 12.0 s"] {
            assert!(svg.contains(t), "{t}");
        }
        // 5 drawn cells in each of 3 panels (the empty one left out) and
        // 40 key steps, beside the backgrounds.
        assert!(svg.matches("<rect").count() >= 55);
        assert!(svg.matches("<rect").count() < 55 + 8);
    }
}
