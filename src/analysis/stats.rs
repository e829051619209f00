//! Correlations, quantiles and a masked rms of plain series, shared by
//! `meadow trace`'s analysis, the waves of light and `meadow wind`.

/// The root mean square of `values` where `solid` is false (a wind
/// field's cells of air), in f64; 0 with none.
pub fn rms_over_fluid(values: &[f32], solid: &[bool]) -> f64 {
    let fluid: Vec<f64> = values
        .iter()
        .zip(solid)
        .filter(|(_, &s)| !s)
        .map(|(v, _)| (*v as f64).powi(2))
        .collect();
    (fluid.iter().sum::<f64>() / fluid.len().max(1) as f64).sqrt()
}

/// Pearson correlation of a[i] with b[i + lag] over the samples both have;
/// 0 where either is constant or fewer than two samples overlap.
pub fn lagged_correlation(a: &[f64], b: &[f64], lag: usize) -> f64 {
    let n = a.len().min(b.len().saturating_sub(lag));
    if n < 2 {
        return 0.0;
    }
    let (a, b) = (&a[..n], &b[lag..lag + n]);
    let (ma, mb) = (mean(a), mean(b));
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    if aa == 0.0 || bb == 0.0 {
        return 0.0;
    }
    ab / (aa * bb).sqrt()
}

/// The lag in 0..=max_lag samples at which b follows a most closely, and
/// the correlation there.
pub fn best_lag(a: &[f64], b: &[f64], max_lag: usize) -> (usize, f64) {
    (0..=max_lag)
        .map(|lag| (lag, lagged_correlation(a, b, lag)))
        .fold(
            (0, f64::NEG_INFINITY),
            |best, x| if x.1 > best.1 { x } else { best },
        )
}

/// The mean; 0 of nothing.
pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// The population standard deviation; 0 of fewer than two values.
pub fn std_dev(v: &[f64]) -> f64 {
    if v.len() < 2 {
        return 0.0;
    }
    let m = mean(v);
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt()
}

/// The q-quantile (0..=1) by the nearest rank of the sorted values; None
/// of nothing.
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    Some(v[((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wave sin(w (t - x / c)) seen at two points d apart: the best lag
    /// is d / c, where the correlation is 1.
    #[test]
    fn the_best_lag_of_a_travelling_wave_is_its_travel_time() {
        let dt = 0.1;
        let wave = |x: f64| -> Vec<f64> {
            (0..400)
                .map(|i| {
                    let t = i as f64 * dt - x / 3.0;
                    (1.3 * t).sin() + 0.5 * (3.1 * t).sin()
                })
                .collect()
        };
        let (lag, r) = best_lag(&wave(0.0), &wave(3.0), 30);
        assert_eq!(lag, 10, "3 m at 3 m/s is 1 s, 10 samples");
        assert!(r > 0.999, "{r}");
        assert!(lagged_correlation(&wave(0.0), &wave(3.0), 0) < 0.9);
    }

    #[test]
    fn a_series_against_itself_shifted_correlates_at_its_lag() {
        let a: Vec<f64> = (0..50).map(|i| (i as f64 * 0.7).sin()).collect();
        let b: Vec<f64> = (0..50).map(|i| ((i as f64 - 3.0) * 0.7).sin()).collect();
        let (lag, r) = best_lag(&a, &b, 6);
        assert_eq!(lag, 3);
        assert!((r - 1.0).abs() < 1e-9, "{r}");
        let negated: Vec<f64> = a.iter().map(|x| -2.0 * x + 5.0).collect();
        assert!((lagged_correlation(&a, &negated, 0) + 1.0).abs() < 1e-9);
        assert_eq!(lagged_correlation(&a, &[1.0; 50], 0), 0.0);
    }

    #[test]
    fn quantiles_and_spread() {
        let v = [5.0, 1.0, 3.0, 2.0, 4.0];
        assert_eq!(quantile(&v, 0.5), Some(3.0));
        assert_eq!(quantile(&v, 0.0), Some(1.0));
        assert_eq!(quantile(&v, 1.0), Some(5.0));
        assert_eq!(quantile(&[], 0.5), None);
        assert!((std_dev(&[1.0, 3.0]) - 1.0).abs() < 1e-12);
        assert_eq!(std_dev(&[2.0]), 0.0);
    }
}
