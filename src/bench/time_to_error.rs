//! Time to a target error: for each (backend, sampler) curve of the ladder, when its RMSE falls
//! to the target. Read off the curve by log–log interpolation between the two neighbouring
//! points; outside the ladder, by the ideal Monte Carlo law RMSE ∝ 1/√t from the nearest point.

use super::BenchPoint;

/// How a time was read off its curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Reading {
    /// Between two ladder points that bracket the target.
    Interpolated,
    /// From the nearest ladder point by RMSE ∝ 1/√t (no two points bracket the target).
    Extrapolated,
}

/// The time one curve takes to reach one target RMSE.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TimeToRmse {
    /// Backend.
    pub accel: String,
    /// Sampler.
    pub sampler: String,
    /// Target RMSE (linear RGB, as [`BenchPoint::rmse`]).
    pub target_rmse: f64,
    /// Render time to reach it [s].
    pub time_s: f64,
    /// How it was read.
    pub reading: Reading,
}

/// The time at which a curve of (time [s], RMSE) points reaches `target`, or None if it has no
/// point with both positive. The first pair of points, in time order, whose RMSEs bracket the
/// target is interpolated on log–log axes; without one, the point whose RMSE is nearest the
/// target (in ratio) is extrapolated with slope −½.
pub fn time_to(curve: &[(f64, f64)], target: f64) -> Option<(f64, Reading)> {
    let mut pts: Vec<(f64, f64)> = curve.iter().copied().filter(|&(t, e)| t > 0.0 && e > 0.0).collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in pts.windows(2) {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        if e0 >= target && target >= e1 {
            if e0 == e1 || t0 == t1 {
                return Some((t0, Reading::Interpolated));
            }
            let slope = (e1 / e0).ln() / (t1 / t0).ln();
            return Some((t0 * (target / e0).powf(1.0 / slope), Reading::Interpolated));
        }
    }
    let &(t, e) = pts.iter().min_by(|a, b| (a.1 / target).ln().abs().total_cmp(&(b.1 / target).ln().abs()))?;
    Some((t * (e / target).powi(2), Reading::Extrapolated))
}

/// One (accel, sampler) curve of the ladder.
struct Curve {
    accel: String,
    sampler: String,
    /// (time [s], RMSE) per ladder point.
    points: Vec<(f64, f64)>,
}

/// The curves of `points`, in first-appearance order.
fn curves(points: &[BenchPoint]) -> Vec<Curve> {
    let mut out: Vec<Curve> = Vec::new();
    for p in points {
        match out.iter_mut().find(|c| c.accel == p.accel && c.sampler == p.sampler) {
            Some(c) => c.points.push((p.time_s, p.rmse)),
            None => {
                out.push(Curve { accel: p.accel.clone(), sampler: p.sampler.clone(), points: vec![(p.time_s, p.rmse)] })
            }
        }
    }
    out
}

/// The default target: the lowest RMSE every curve reaches within its ladder (the largest of
/// the curves' smallest RMSEs), to two significant digits, so every curve is read without
/// extrapolating far. None when no point has a positive RMSE.
pub fn default_target(points: &[BenchPoint]) -> Option<f64> {
    let worst_best = curves(points)
        .iter()
        .filter_map(|c| c.points.iter().map(|&(_, e)| e).filter(|&e| e > 0.0).min_by(f64::total_cmp))
        .max_by(f64::total_cmp)?;
    let scale = 10f64.powf(worst_best.log10().floor() - 1.0);
    Some((worst_best / scale).ceil() * scale)
}

/// Every curve's time to every target.
pub fn times_to_rmse(points: &[BenchPoint], targets: &[f64]) -> Vec<TimeToRmse> {
    let mut out = Vec::new();
    for &target in targets {
        for c in curves(points) {
            if let Some((time_s, reading)) = time_to(&c.points, target) {
                out.push(TimeToRmse { accel: c.accel, sampler: c.sampler, target_rmse: target, time_s, reading });
            }
        }
    }
    out
}

/// The times as a Markdown table: one row per curve, one column per target, each time with its
/// ratio to the fastest curve at that target.
pub fn markdown(times: &[TimeToRmse]) -> String {
    let mut targets: Vec<f64> = Vec::new();
    let mut rows: Vec<(&str, &str)> = Vec::new();
    for t in times {
        if !targets.contains(&t.target_rmse) {
            targets.push(t.target_rmse);
        }
        if !rows.contains(&(t.accel.as_str(), t.sampler.as_str())) {
            rows.push((&t.accel, &t.sampler));
        }
    }
    let mut s = String::from("| accel | sampler |");
    for t in &targets {
        s += &format!(" time to RMSE {t:.3e} [s] |");
    }
    s += &format!("\n|---|---|{}\n", "---|".repeat(targets.len()));
    for (accel, sampler) in &rows {
        s += &format!("| {accel} | {sampler} |");
        for &target in &targets {
            let at: Vec<&TimeToRmse> = times.iter().filter(|t| t.target_rmse == target).collect();
            let fastest = at.iter().map(|t| t.time_s).min_by(f64::total_cmp).unwrap_or(f64::NAN);
            match at.iter().find(|t| t.accel == *accel && t.sampler == *sampler) {
                Some(t) => {
                    let mark = if t.reading == Reading::Extrapolated { "¹" } else { "" };
                    s += &format!(" {:.3}{mark} ({:.2}×) |", t.time_s, t.time_s / fastest);
                }
                None => s += " – |",
            }
        }
        s += "\n";
    }
    if times.iter().any(|t| t.reading == Reading::Extrapolated) {
        s += "\n¹ extrapolated from the nearest ladder point as RMSE ∝ 1/√t; the others are interpolated.\n";
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curve of the ideal law RMSE = c/√t at the given times.
    fn ideal(c: f64, times: &[f64]) -> Vec<(f64, f64)> {
        times.iter().map(|&t| (t, c / t.sqrt())).collect()
    }

    #[test]
    fn reads_the_ideal_law_exactly_inside_and_outside_the_ladder() {
        let c = ideal(0.2, &[0.5, 2.0, 8.0]);
        for target in [0.2 / 1.0f64.sqrt(), 0.2 / 4.0f64.sqrt(), 0.2 / 8.0f64.sqrt()] {
            let (t, how) = time_to(&c, target).unwrap();
            assert_eq!(how, Reading::Interpolated);
            assert!((t - (0.2 / target).powi(2)).abs() < 1e-9 * t, "{target}: {t}");
        }
        // Beyond both ends the 1/√t law is extrapolated from the nearest point.
        for target in [0.2 / 100.0f64.sqrt(), 0.2 / 0.1f64.sqrt()] {
            let (t, how) = time_to(&c, target).unwrap();
            assert_eq!(how, Reading::Extrapolated);
            assert!((t - (0.2 / target).powi(2)).abs() < 1e-9 * t, "{target}: {t}");
        }
    }

    #[test]
    fn interpolates_log_log_between_the_first_bracketing_pair() {
        // Faster than 1/√t between the points (RMSE ∝ 1/t: a QMC-like slope of −1), and a noisy
        // bump afterwards that crosses the target again later: the first crossing counts.
        let c = [(1.0, 0.1), (4.0, 0.025), (2.0, 0.05), (8.0, 0.045), (16.0, 0.01)];
        let (t, how) = time_to(&c, 0.04).unwrap();
        assert_eq!(how, Reading::Interpolated);
        // Between 2 and 4 s the RMSE is 0.1/t, which is 0.04 at t = 2.5.
        assert!((t - 2.5).abs() < 1e-9, "{t}");
        // A target met exactly at a point, and a flat segment.
        assert!((time_to(&c, 0.05).unwrap().0 - 2.0).abs() < 1e-9);
        assert_eq!(time_to(&[(1.0, 0.02), (3.0, 0.02)], 0.02).unwrap(), (1.0, Reading::Interpolated));
    }

    #[test]
    fn ignores_points_without_a_positive_time_and_error() {
        assert_eq!(time_to(&[(0.0, 0.1), (1.0, 0.0)], 0.05), None);
        let (t, _) = time_to(&[(0.0, 0.1), (1.0, 0.0), (2.0, 0.04)], 0.02).unwrap();
        assert!((t - 8.0).abs() < 1e-9);
    }

    fn point(accel: &str, sampler: &str, time_s: f64, rmse: f64) -> BenchPoint {
        BenchPoint { accel: accel.into(), sampler: sampler.into(), time_s, rmse, ..Default::default() }
    }

    #[test]
    fn the_default_target_is_the_lowest_error_every_curve_reaches() {
        let pts = [
            point("embree", "sobol", 1.0, 0.02),
            point("embree", "sobol", 4.0, 0.00512),
            point("embree", "independent", 1.0, 0.05),
            point("embree", "independent", 4.0, 0.0251),
        ];
        assert!((default_target(&pts).unwrap() - 0.026).abs() < 1e-12);
        let times = times_to_rmse(&pts, &[0.026]);
        // Sobol is below the target from its first point on, so its time is read backwards.
        let how: Vec<(&str, Reading)> = times.iter().map(|t| (t.sampler.as_str(), t.reading)).collect();
        assert_eq!(how, [("sobol", Reading::Extrapolated), ("independent", Reading::Interpolated)]);
        let md = markdown(&times);
        assert!(md.contains("| embree | sobol | 0.592¹ (1.00×) |"), "{md}");
        assert!(md.contains("¹ extrapolated"), "{md}");
        assert_eq!(default_target(&[point("obvhs", "sobol", 1.0, 0.0)]), None);
    }
}
