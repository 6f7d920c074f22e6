//! Plots of a benchmark: error against time on log–log axes with the ideal 1/√t slope, and a
//! bar chart of rays per second. PNG or SVG by extension (plotters; DejaVu Sans embedded, so no
//! system fonts are needed).

use super::BenchError;
use super::BenchPoint;
use plotters::coord::combinators::WithKeyPoints;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
    });
}

const SIZE: (u32, u32) = (900, 600);
/// Width of the key beside the error chart: curves of an error–time chart fill the corners a key
/// would sit in (slow methods the top right, biased ones the bottom right), so it sits outside.
const KEY_WIDTH: u32 = 220;
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// The (backend, sampler) curves in first-seen order.
fn series(points: &[BenchPoint]) -> Vec<(String, Vec<&BenchPoint>)> {
    let mut out: Vec<(String, Vec<&BenchPoint>)> = Vec::new();
    for p in points {
        let key = format!("{} / {}", p.accel, p.sampler);
        match out.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(p),
            None => out.push((key, vec![p])),
        }
    }
    out
}

fn with_backend(
    path: &Path,
    size: (u32, u32),
    draw: impl Fn(DrawingArea<SVGBackend, Shift>) -> Result<(), BenchError>,
    draw_png: impl Fn(DrawingArea<BitMapBackend, Shift>) -> Result<(), BenchError>,
) -> Result<(), BenchError> {
    register_font();
    // Draw into a temporary file and rename, like every other output.
    let temp = crate::io::TempFile::create(path)?;
    if path.extension().is_some_and(|e| e == "svg") {
        draw(SVGBackend::new(temp.path(), size).into_drawing_area())?;
    } else {
        draw_png(BitMapBackend::new(temp.path(), size).into_drawing_area())?;
    }
    Ok(temp.commit()?)
}

fn error_chart<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, points: &[BenchPoint]) -> Result<(), BenchError>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| BenchError::Plot(format!("{e:?}"));
    root.fill(&WHITE).map_err(err)?;
    let pts: Vec<&BenchPoint> = points.iter().filter(|p| p.time_s > 0.0 && p.rmse > 0.0).collect();
    if pts.is_empty() {
        return Ok(());
    }
    let (tmin, tmax) = pts.iter().fold((f64::MAX, 0f64), |(a, b), p| (a.min(p.time_s), b.max(p.time_s)));
    let (emin, emax) = pts.iter().fold((f64::MAX, 0f64), |(a, b), p| (a.min(p.rmse), b.max(p.rmse)));
    let (plot, key) = root.split_horizontally(SIZE.0);
    let mut chart = ChartBuilder::on(&plot)
        .caption("RMSE against render time (log–log)", ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(log_axis(tmin / 1.5, tmax * 1.5), log_axis(emin / 1.5, emax * 1.5))
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("RMSE vs reference (linear RGB)")
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    let (mut entries, mut ideal_entry) = (Vec::new(), None);
    for (i, (name, s)) in series(points).into_iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        let data: Vec<(f64, f64)> =
            s.iter().filter(|p| p.time_s > 0.0 && p.rmse > 0.0).map(|p| (p.time_s, p.rmse)).collect();
        let line = c.stroke_width(2);
        chart.draw_series(LineSeries::new(data.iter().copied(), line)).map_err(err)?;
        chart.draw_series(data.iter().map(|&p| Circle::new(p, 4, c.filled()))).map_err(err)?;
        entries.push((name, line));
        // Ideal Monte Carlo convergence through the first plotted point: RMSE ∝ 1/√t.
        if let (None, Some(&(t0, e0))) = (&ideal_entry, data.first()) {
            let ideal: Vec<(f64, f64)> = [tmin / 1.5, tmax * 1.5].iter().map(|&t| (t, e0 * (t0 / t).sqrt())).collect();
            let style = BLACK.mix(0.5).stroke_width(1);
            chart.draw_series(LineSeries::new(ideal, style)).map_err(err)?;
            ideal_entry = Some(("ideal 1/√t".to_string(), style));
        }
    }
    entries.extend(ideal_entry);
    // The key, top-aligned with the plotting area.
    for (i, (name, style)) in entries.into_iter().enumerate() {
        let y = 60 + 24 * i as i32;
        key.draw(&PathElement::new(vec![(0, y), (24, y)], style)).map_err(err)?;
        key.draw(&Text::new(name, (32, y - 8), ("sans-serif", 14))).map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// A log axis over [lo, hi] (lo > 0) labelled at 1, 2 and 5 × 10^k with a mesh line at every
/// m × 10^k. plotters' own log ticks start at the first power of ten inside the range, so a
/// range such as 0.15–5 would get no label below 1.
fn log_axis(lo: f64, hi: f64) -> WithKeyPoints<LogCoord<f64>> {
    let (mut bold, mut light) = (Vec::new(), Vec::new());
    for k in lo.log10().floor() as i32..=hi.log10().ceil() as i32 {
        for m in 1..10 {
            // Divided for k < 0 so that e.g. 0.3 is the double nearest 3/10, not 3 × 0.1.
            let v = if k < 0 { m as f64 / 10f64.powi(-k) } else { m as f64 * 10f64.powi(k) };
            if (lo..=hi).contains(&v) {
                if matches!(m, 1 | 2 | 5) {
                    bold.push(v);
                }
                light.push(v);
            }
        }
    }
    // A narrow range (e.g. 0.21–0.47) may hold no 1, 2 or 5: label every mesh line instead.
    if bold.len() < 2 {
        bold.clone_from(&light);
    }
    (lo..hi).log_scale().with_key_points(bold).with_light_points(light)
}

/// A tick value with as many decimals as its leading digit needs (0.002, 0.5, 20).
fn tick_label(v: f64) -> String {
    let decimals = (-(v.log10() + 1e-9).floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

fn rays_chart<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, points: &[BenchPoint]) -> Result<(), BenchError>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| BenchError::Plot(format!("{e:?}"));
    root.fill(&WHITE).map_err(err)?;
    // Throughput of each curve at its largest sample count (the steadiest figure).
    let bars: Vec<(String, f64)> = series(points)
        .into_iter()
        .filter_map(|(k, s)| s.iter().max_by_key(|p| p.spp).map(|p| (k, p.rays_per_s / 1e6)))
        .collect();
    let ymax = bars.iter().map(|b| b.1).fold(0.0, f64::max).max(1e-3) * 1.2;
    let n = bars.len() as u32;
    let mut chart = ChartBuilder::on(&root)
        .caption("Rays per second in the path tracer", ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d((0u32..n).into_segmented(), 0.0..ymax)
        .map_err(err)?;
    let names: Vec<String> = bars.iter().map(|b| b.0.clone()).collect();
    chart
        .configure_mesh()
        .y_desc("M rays/s")
        .x_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => names.get(*i as usize).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(bars.iter().enumerate().map(|(i, b)| {
            let c = PALETTE[i % PALETTE.len()];
            let mut r = Rectangle::new(
                [(SegmentValue::Exact(i as u32), 0.0), (SegmentValue::Exact(i as u32 + 1), b.1)],
                c.filled(),
            );
            r.set_margin(0, 0, 20, 20);
            r
        }))
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// Error against time, one curve per backend/sampler, with the ideal 1/√t slope.
pub fn plot_error_vs_time(points: &[BenchPoint], path: &Path) -> Result<(), BenchError> {
    with_backend(path, (SIZE.0 + KEY_WIDTH, SIZE.1), |a| error_chart(a, points), |a| error_chart(a, points))
}

/// Rays per second per backend/sampler.
pub fn plot_rays_per_s(points: &[BenchPoint], path: &Path) -> Result<(), BenchError> {
    with_backend(path, SIZE, |a| rays_chart(a, points), |a| rays_chart(a, points))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axes_are_labelled_in_every_decade_they_cover() {
        // 0.15–5 holds no power of ten but 1: plotters' own ticks label only 1 … 5 there.
        let axis = log_axis(0.15, 5.0);
        assert_eq!(axis.bold_points(), [0.2, 0.5, 1.0, 2.0, 5.0]);
        assert_eq!(axis.light_points().len(), 8 + 5); // 0.2 … 0.9, then 1 … 5
        let labels: Vec<String> = log_axis(0.0015, 0.06).bold_points().iter().map(|&v| tick_label(v)).collect();
        assert_eq!(labels, ["0.002", "0.005", "0.01", "0.02", "0.05"]);
        assert_eq!(tick_label(20.0), "20");
        // No 1, 2 or 5 inside: every m × 10^k is labelled.
        assert_eq!(log_axis(0.21, 0.47).bold_points(), [0.3, 0.4]);
    }

    fn point(accel: &str, spp: u64, time_s: f64, rmse: f64) -> BenchPoint {
        BenchPoint {
            accel: accel.into(),
            sampler: "sobol".into(),
            spp,
            time_s,
            samples_per_s: 1e6,
            rays_per_s: 4e6,
            rmse,
            ..Default::default()
        }
    }

    #[test]
    fn a_first_curve_with_nothing_to_plot_still_gives_a_chart() {
        // The first backend's images equal the reference (RMSE 0 has no place on a log axis):
        // the ideal slope goes through the next curve instead of indexing an empty one.
        let points = [point("embree", 4, 0.1, 0.0), point("obvhs", 4, 0.1, 0.2), point("obvhs", 16, 0.4, 0.1)];
        let dir = std::env::temp_dir().join(format!("prism-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["error.png", "error.svg"] {
            let path = dir.join(name);
            plot_error_vs_time(&points, &path).unwrap();
            assert!(std::fs::metadata(&path).unwrap().len() > 1000, "{name}");
        }
        let svg = std::fs::read_to_string(dir.join("error.svg")).unwrap();
        assert!(svg.contains("ideal 1/√t") && svg.contains("embree / sobol") && svg.contains("obvhs / sobol"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
