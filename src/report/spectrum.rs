//! The tips' power spectrum as a chart: power (log scale) against
//! frequency, with the blades' bending and swinging natural frequencies
//! marked, and beside it the same motion per unit log frequency against
//! each blade's own bending frequency, so that the blades' ringing at
//! their natural frequency reads at a glance.

use plotters::prelude::*;

use crate::error::{Error, Result};

/// What to draw: `power[i]` (m^2/Hz) at `frequency_hz[i]`, and the
/// bending and swinging natural frequencies' median and 5-95% range, if
/// known (a downwind tip moves by bending where its blade faces the wind,
/// by swinging where it stands across it). With `scaled`, a second panel
/// beside it: the same motion per unit log frequency, each blade's
/// frequencies over its own bending natural frequency.
pub struct SpectrumChart<'a> {
    pub title: &'a str,
    pub frequency_hz: &'a [f64],
    pub power: &'a [f64],
    pub bend_hz: Option<(f64, f64, f64)>,
    pub swing_hz: Option<(f64, f64, f64)>,
    pub scaled: Option<ScaledPanel<'a>>,
}

/// `power_per_log_f[i]` (f S(f) / variance) at `frequency_over_natural[i]`
/// (f / f_bend).
pub struct ScaledPanel<'a> {
    pub frequency_over_natural: &'a [f64],
    pub power_per_log_f: &'a [f64],
}

/// Width of the chart in hertz, and of the scaled panel beside it.
const HERTZ_WIDTH: u32 = 720;
const SCALED_WIDTH: u32 = 560;
const HEIGHT: u32 = 440;

/// The bending frequencies' colours, in both panels: their range's band
/// and their median's (or f_bend's) line.
const BEND_BAND: RGBColor = RGBColor(255, 228, 196);
const BEND_LINE: RGBColor = RGBColor(200, 90, 20);

/// The chart as SVG, from the lowest frequency to 4 Hz (or the highest
/// sampled, if lower): the blades' motion lives below it.
pub fn svg(c: &SpectrumChart) -> Result<String> {
    let points: Vec<(f64, f64)> = c
        .frequency_hz
        .iter()
        .zip(c.power)
        .filter(|(&f, &p)| f > 0.0 && f <= 4.0 && p > 0.0)
        .map(|(&f, &p)| (f, p))
        .collect();
    if points.is_empty() {
        return Err(err("no power to draw"));
    }
    let scaled: Option<Vec<(f64, f64)>> = c.scaled.as_ref().map(|s| {
        s.frequency_over_natural
            .iter()
            .zip(s.power_per_log_f)
            .filter(|(&r, &p)| r > 0.0 && r <= 4.0 && p > 0.0)
            .map(|(&r, &p)| (r, p))
            .collect::<Vec<_>>()
    });
    let scaled = scaled.filter(|s| s.len() >= 2);
    let width = HERTZ_WIDTH + scaled.as_ref().map_or(0, |_| SCALED_WIDTH);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(c.title, ("sans-serif", 18)).map_err(err)?;
        let (left, right) = root.split_horizontally(HERTZ_WIDTH);
        draw_hertz(&left, c, &points)?;
        if let Some(scaled) = &scaled {
            draw_scaled(&right, scaled)?;
        }
        root.present().map_err(err)?;
    }
    Ok(out)
}

fn err(e: impl std::fmt::Display) -> Error {
    Error::InvalidInput(format!("drawing the spectrum: {e}"))
}

/// The tips' power per hertz beside the natural frequencies' ranges.
fn draw_hertz<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    c: &SpectrumChart,
    points: &[(f64, f64)],
) -> Result<()> {
    let (first, last) = (points[0], points[points.len() - 1]);
    let (lo, hi) = points
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &(_, p)| {
            (lo.min(p), hi.max(p))
        });
    let (lo, hi) = (lo * 0.5, hi * 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption("per hertz, the blades' mean", ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(first.0..last.0, (lo..hi).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_desc("frequency (Hz)")
        .y_desc("tip power (m^2/Hz)")
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()
        .map_err(err)?;
    let motions = [
        ("bending", c.bend_hz, BEND_BAND, BEND_LINE),
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
                .map_err(err)?
                .label(format!(
                    "{motion} natural frequencies, 5-95% ({p5:.2}-{p95:.2} Hz)"
                ))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], band.filled()));
        }
        if median < last.0 {
            chart
                .draw_series(LineSeries::new(
                    [(median, lo), (median, hi)],
                    line.stroke_width(2),
                ))
                .map_err(err)?
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
        .map_err(err)?
        .label("the tips' downwind motion, mean of the blades' periodograms")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 14, y)], BLUE.stroke_width(2)));
    draw_legend(&mut chart)
}

/// The same motion per unit log frequency, f / f_bend on a log axis up to
/// 4 (the blades' motion lives below it), with f_bend itself and the 30%
/// either side of it marked.
fn draw_scaled<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    points: &[(f64, f64)],
) -> Result<()> {
    // Octaves on a linear axis, labelled as f / f_bend: ticks fall on
    // powers of two rather than crowding where a log axis packs them.
    let (first, last) = (points[0].0.log2(), points[points.len() - 1].0.log2());
    // Headroom over the largest band for the legend.
    let hi = points.iter().map(|p| p.1).fold(0.0, f64::max) * 1.6;
    let mut chart = ChartBuilder::on(area)
        .caption(
            "per unit log frequency, each blade against its own f_bend",
            ("sans-serif", 15),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(first..last, 0.0..hi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_desc("frequency / the blade's bending natural frequency")
        .y_desc("f S(f) / variance")
        .x_labels(8)
        .x_label_formatter(&|v| ratio_label(v.exp2()))
        .draw()
        .map_err(err)?;
    let (band, line) = (BEND_BAND, BEND_LINE);
    let (near_lo, near_hi) = (0.7f64.log2(), 1.3f64.log2());
    if first < near_hi && last > near_lo {
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(near_lo.max(first), 0.0), (near_hi.min(last), hi)],
                band.mix(0.8).filled(),
            )))
            .map_err(err)?
            .label("within 30% of f_bend")
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], band.filled()));
        chart
            .draw_series(LineSeries::new(
                [(0.0, 0.0), (0.0, hi)],
                line.stroke_width(2),
            ))
            .map_err(err)?
            .label("f_bend")
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 14, y)], line.stroke_width(2)));
    }
    chart
        .draw_series(LineSeries::new(
            points.iter().map(|&(r, p)| (r.log2(), p)),
            BLUE.stroke_width(2),
        ))
        .map_err(err)?
        .label("quarter-octave bands, mean of the blades")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 14, y)], BLUE.stroke_width(2)));
    draw_legend(&mut chart)
}

/// Both panels' legend, at the upper right.
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)
}

/// A ratio with at most three decimals and no trailing zeros: 0.125, 0.5,
/// 1, 4.
fn ratio_label(ratio: f64) -> String {
    let text = format!("{ratio:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
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
            scaled: None,
        })
        .unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("frequency (Hz)") && svg.contains("their median, 0.89 Hz"));
        assert!(svg.contains("bending natural frequencies, 5-95% (0.65-1.41 Hz)"));
        assert!(svg.contains("swinging natural frequencies, 5-95% (1.42-4.50 Hz)"));
        assert!(svg.contains("their median, 2.36 Hz"));
        // With the scaled panel beside it.
        let (r, q) = ([0.5, 0.71, 1.0, 1.41], [0.2, 0.3, 0.5, 0.2]);
        let both = super::svg(&SpectrumChart {
            title: "test",
            frequency_hz: &f,
            power: &p,
            bend_hz: Some((0.89, 0.65, 1.41)),
            swing_hz: None,
            scaled: Some(ScaledPanel {
                frequency_over_natural: &r,
                power_per_log_f: &q,
            }),
        })
        .unwrap();
        assert!(both.contains("each blade against its own f_bend"));
        assert!(both.contains("within 30% of f_bend") && both.contains("f S(f) / variance"));
        assert!(!svg.contains("f S(f)"));
        assert_eq!(
            [0.125, 0.5, 1.0, 4.0, 2f64.sqrt()].map(ratio_label),
            ["0.125", "0.5", "1", "4", "1.414"]
        );
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
            scaled: None,
        })
        .unwrap_err()
        .to_string()
    }
}
