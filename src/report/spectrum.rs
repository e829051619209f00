//! The tips' power spectrum as a chart: power (log scale) against
//! frequency, with the blades' bending and swinging natural frequencies
//! marked, so that a peak at a natural frequency (the lock-in of a canopy
//! to its wind) reads at a glance.

use plotters::prelude::*;

use crate::error::{Error, Result};

/// What to draw: `power[i]` (m^2/Hz) at `frequency_hz[i]`, and the
/// bending and swinging natural frequencies' median and 5-95% range, if
/// known (a downwind tip moves by bending where its blade faces the wind,
/// by swinging where it stands across it).
pub struct SpectrumChart<'a> {
    pub title: &'a str,
    pub frequency_hz: &'a [f64],
    pub power: &'a [f64],
    pub bend_hz: Option<(f64, f64, f64)>,
    pub swing_hz: Option<(f64, f64, f64)>,
}

/// The chart as SVG, from the lowest frequency to 4 Hz (or the highest
/// sampled, if lower): the blades' motion lives below it.
pub fn svg(c: &SpectrumChart) -> Result<String> {
    let err = |e: String| Error::InvalidInput(format!("drawing the spectrum: {e}"));
    let points: Vec<(f64, f64)> = c
        .frequency_hz
        .iter()
        .zip(c.power)
        .filter(|(&f, &p)| f > 0.0 && f <= 4.0 && p > 0.0)
        .map(|(&f, &p)| (f, p))
        .collect();
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Err(err("no power to draw".into()));
    };
    let (lo, hi) = points
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &(_, p)| {
            (lo.min(p), hi.max(p))
        });
    let (lo, hi) = (lo * 0.5, hi * 2.0);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (720, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(c.title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(first.0..last.0, (lo..hi).log_scale())
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .light_line_style(WHITE)
            .x_desc("frequency (Hz)")
            .y_desc("tip power (m^2/Hz)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        let motions = [
            (
                "bending",
                c.bend_hz,
                RGBColor(255, 228, 196),
                RGBColor(200, 90, 20),
            ),
            (
                "swinging",
                c.swing_hz,
                RGBColor(214, 236, 214),
                RGBColor(40, 130, 60),
            ),
        ];
        for (motion, hz, band, line) in motions {
            let Some((median, p5, p95)) = hz else {
                continue;
            };
            if p5 < last.0 {
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(p5.max(first.0), lo), (p95.min(last.0), hi)],
                        band.mix(0.8).filled(),
                    )))
                    .map_err(|e| err(e.to_string()))?
                    .label(format!(
                        "{motion} natural frequencies, 5-95% ({p5:.2}-{p95:.2} Hz)"
                    ))
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 14, y + 5)], band.filled())
                    });
            }
            if median < last.0 {
                chart
                    .draw_series(LineSeries::new(
                        [(median, lo), (median, hi)],
                        line.stroke_width(2),
                    ))
                    .map_err(|e| err(e.to_string()))?
                    .label(format!("their median, {median:.2} Hz"))
                    .legend(move |(x, y)| {
                        PathElement::new([(x, y), (x + 14, y)], line.stroke_width(2))
                    });
            }
        }
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                BLUE.stroke_width(2),
            ))
            .map_err(|e| err(e.to_string()))?
            .label("the tips' downwind motion, mean of the blades' periodograms")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 14, y)], BLUE.stroke_width(2)));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spectrum_is_drawn_with_the_natural_frequencies_marked() {
        let f: Vec<f64> = (1..200).map(|i| i as f64 * 0.05).collect();
        let p: Vec<f64> = f
            .iter()
            .map(|f| 1e-4 / (1.0 + (f - 0.8f64).powi(2) * 20.0))
            .collect();
        let svg = svg(&SpectrumChart {
            title: "test",
            frequency_hz: &f,
            power: &p,
            bend_hz: Some((0.89, 0.65, 1.41)),
            swing_hz: Some((2.36, 1.42, 4.50)),
        })
        .unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("frequency (Hz)") && svg.contains("their median, 0.89 Hz"));
        assert!(svg.contains("bending natural frequencies, 5-95% (0.65-1.41 Hz)"));
        assert!(svg.contains("swinging natural frequencies, 5-95% (1.42-4.50 Hz)"));
        assert!(svg.contains("their median, 2.36 Hz"));
        let none = svg_err(&[0.0], &[0.0]);
        assert!(none.contains("no power"), "{none}");
    }

    fn svg_err(f: &[f64], p: &[f64]) -> String {
        svg(&SpectrumChart {
            title: "t",
            frequency_hz: f,
            power: p,
            bend_hz: None,
            swing_hz: None,
        })
        .unwrap_err()
        .to_string()
    }
}
