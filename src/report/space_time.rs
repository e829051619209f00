//! A space-time diagram of the grass's motion: position along the wind
//! across, time up, each cell coloured by how far the blades of that band
//! are bent downwind at that time beyond their own average. Gusts that
//! travel draw diagonal stripes whose slope is their speed; a meadow that
//! sways in unison draws horizontal ones.

use plotters::prelude::*;

use crate::error::{Error, Result};

/// What to draw: `values[band][sample]`, band b covering
/// [x0 + b w, x0 + (b + 1) w) metres, sample s at `times[s]` seconds.
pub struct SpaceTime<'a> {
    pub title: &'a str,
    pub values: &'a [Vec<f64>],
    pub x0: f64,
    pub band_width: f64,
    pub times: &'a [f64],
}

/// Each band's values minus their mean, over their standard deviation (0
/// where a band does not move): the waves show at every distance even as
/// they weaken downwind.
pub fn standardised(values: &[Vec<f64>]) -> Vec<Vec<f64>> {
    values
        .iter()
        .map(|band| {
            let n = band.len().max(1) as f64;
            let mean = band.iter().sum::<f64>() / n;
            let sd = (band.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
            band.iter()
                .map(|v| if sd > 0.0 { (v - mean) / sd } else { 0.0 })
                .collect()
        })
        .collect()
}

/// Blue (-2 sd and below) through white (0) to red (+2 sd and above).
pub(crate) fn diverging(z: f64) -> RGBColor {
    let t = (z / 2.0).clamp(-1.0, 1.0);
    let mix = |a: f64, b: f64, f: f64| (a + (b - a) * f).round() as u8;
    if t >= 0.0 {
        RGBColor(255, mix(255.0, 40.0, t), mix(255.0, 40.0, t))
    } else {
        RGBColor(mix(255.0, 40.0, -t), mix(255.0, 90.0, -t), 255)
    }
}

/// The colour key of `diverging` in `area`, -2 to +2 standard deviations,
/// its axis labelled `label` (the space-time diagram's and the plan
/// view's).
pub(crate) fn diverging_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    label: &str,
) -> std::result::Result<(), String> {
    let mut legend = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(50)
        .y_label_area_size(40)
        .build_cartesian_2d(0.0..1.0, -2.0..2.0)
        .map_err(|e| e.to_string())?;
    legend
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(label)
        .axis_desc_style(("sans-serif", 14))
        .draw()
        .map_err(|e| e.to_string())?;
    legend
        .draw_series((0..40).map(|i| {
            let v = -2.0 + i as f64 * 0.1;
            Rectangle::new([(0.0, v), (1.0, v + 0.1)], diverging(v).filled())
        }))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The diagram as SVG, with axes in metres and seconds and a colour key.
pub fn svg(d: &SpaceTime) -> Result<String> {
    let err = |e: String| Error::InvalidInput(format!("drawing the space-time diagram: {e}"));
    let z = standardised(d.values);
    let (Some(&t0), Some(&t1)) = (d.times.first(), d.times.last()) else {
        return Err(err("no samples".into()));
    };
    let step = if d.times.len() > 1 {
        (t1 - t0) / (d.times.len() - 1) as f64
    } else {
        1.0
    };
    let x1 = d.x0 + d.band_width * z.len() as f64;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (760, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let (plot, key) = root.split_horizontally(660);
        let mut chart = ChartBuilder::on(&plot)
            .caption(d.title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(d.x0..x1, t0..t1 + step)
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("position along the wind (m)")
            .y_desc("time (s)")
            .draw()
            .map_err(|e| err(e.to_string()))?;
        let cells = z.iter().enumerate().flat_map(|(b, band)| {
            band.iter().enumerate().map(move |(s, &v)| {
                let x = d.x0 + b as f64 * d.band_width;
                let t = d.times[s];
                Rectangle::new(
                    [(x, t), (x + d.band_width, t + step)],
                    diverging(v).filled(),
                )
            })
        });
        chart.draw_series(cells).map_err(|e| err(e.to_string()))?;
        // The key: -2 to +2 standard deviations of the band's own motion.
        diverging_key(&key, "bent downwind (sd of the band)").map_err(err)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_band_is_scaled_by_its_own_spread() {
        let z = standardised(&[vec![1.0, 3.0], vec![10.0, 10.0]]);
        assert_eq!(z, [vec![-1.0, 1.0], vec![0.0, 0.0]]);
    }

    #[test]
    fn the_diagram_is_svg_with_one_cell_per_band_and_sample() {
        let values = vec![vec![0.0, 1.0, 0.5]; 4];
        let times = [0.0, 0.1, 0.2];
        let svg = svg(&SpaceTime {
            title: "test",
            values: &values,
            x0: -2.0,
            band_width: 1.0,
            times: &times,
        })
        .unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        assert!(svg.contains("time (s)") && svg.contains("position along the wind (m)"));
        // 12 cells and 40 key steps, plus the backgrounds.
        assert!(
            svg.matches("<rect").count() >= 52,
            "{}",
            svg.matches("<rect").count()
        );
    }
}
