//! The measurements of one `prism compat` scene, the rule that decides whether it matches
//! pbrt-v4, and the markdown report.

use super::compat_case::CompatCase;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Largest relative difference of a channel mean from pbrt-v4's that still matches.
pub const MEAN_TOLERANCE: f64 = 0.02;
/// Largest ratio of prism's error to pbrt-v4's own error at the same spp that still matches.
pub const ERROR_RATIO_LIMIT: f64 = 1.25;

/// prism against pbrt-v4 on one scene.
#[derive(Clone, Debug)]
pub struct SceneReport {
    /// Reference stem.
    pub name: String,
    /// Scene file.
    pub scene: PathBuf,
    /// Samples per pixel prism rendered.
    pub spp: u64,
    /// Exit code of `prism render` (`None`: killed by a signal).
    pub exit_code: Option<i32>,
    /// Warnings about features prism does not render (or parameters it ignored), with counts.
    pub unsupported: Vec<(String, usize)>,
    /// Other warnings, with counts.
    pub notes: Vec<(String, usize)>,
    /// The error message of a failed render.
    pub error: Option<String>,
    /// Channel means of pbrt-v4's high-spp image.
    pub ref_means: [f64; 3],
    /// Channel means of prism's image.
    pub prism_means: Option<[f64; 3]>,
    /// Error of pbrt-v4's second-seed image against its reference, and that image's spp.
    pub pbrt_error: Option<(f64, u64)>,
    /// Error of prism's image against pbrt-v4's reference.
    pub prism_error: Option<f64>,
    /// Wall time of the whole `prism render` process [s].
    pub wall_s: f64,
    /// Time of the render loop alone [s].
    pub render_s: Option<f64>,
    /// pbrt-v4's wall time for its second-seed image [s].
    pub pbrt_wall_s: Option<f64>,
    /// The side-by-side image (pbrt-v4 | prism | difference).
    pub panels: Option<PathBuf>,
}

/// Whether a warning reports something prism does not render: an unsupported feature or a
/// parameter it did not use.
fn is_unsupported(message: &str) -> bool {
    message.starts_with("unsupported feature") || message.contains("was not used")
}

/// Whether `s` is a scene location, "file:line:col".
fn is_location(s: &str) -> bool {
    let mut parts = s.rsplitn(3, ':');
    let digits = |p: Option<&str>| p.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
    digits(parts.next()) && digits(parts.next()) && parts.next().is_some_and(|f| !f.is_empty())
}

/// The message of a "prism: warning: [file:line:col: ]message[ (N more like it)]" line and how
/// many places it stands for.
fn warning_of(line: &str) -> Option<(&str, usize)> {
    let rest = line.strip_prefix("prism: warning: ")?;
    let msg = match rest.match_indices(": ").map(|(i, _)| i).find(|&i| is_location(&rest[..i])) {
        Some(i) => &rest[i + 2..],
        None => rest,
    };
    let repeated = msg.strip_suffix(" more like it)").and_then(|m| {
        let (m, n) = m.rsplit_once(" (")?;
        Some((m, n.parse::<usize>().ok()? + 1))
    });
    Some(repeated.unwrap_or((msg, 1)))
}

/// The distinct messages of the warning lines of a log, with counts, in first-seen order.
fn warnings(log: &str) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    for (msg, count) in log.lines().filter_map(warning_of) {
        match out.iter_mut().find(|(m, _)| m == msg) {
            Some((_, n)) => *n += count,
            None => out.push((msg.to_string(), count)),
        }
    }
    out
}

impl SceneReport {
    /// The report of `case` before its images are measured.
    pub fn new(case: &CompatCase, spp: u64, exit_code: Option<i32>, log: &str, wall_s: f64) -> Self {
        let (unsupported, notes) = warnings(log).into_iter().partition(|(m, _)| is_unsupported(m));
        let error = (exit_code != Some(0))
            .then(|| log.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("(no message)").to_string());
        Self {
            name: case.name.clone(),
            scene: case.scene.clone(),
            spp,
            exit_code,
            unsupported,
            notes,
            error,
            ref_means: [f64::NAN; 3],
            prism_means: None,
            pbrt_error: None,
            prism_error: None,
            wall_s,
            render_s: None,
            pbrt_wall_s: case.pbrt_wall_s,
            panels: None,
        }
    }

    /// Unsupported-feature warnings, counting repeats.
    pub fn unsupported_count(&self) -> usize {
        self.unsupported.iter().map(|w| w.1).sum()
    }

    /// prism's channel means over pbrt-v4's.
    pub fn mean_ratios(&self) -> Option<[f64; 3]> {
        self.prism_means.map(|m| [0, 1, 2].map(|k| m[k] / self.ref_means[k]))
    }

    /// prism's error over pbrt-v4's own at the same spp.
    pub fn error_ratio(&self) -> Option<f64> {
        Some(self.prism_error? / self.pbrt_error?.0)
    }

    /// The time prism needs to reach pbrt-v4's second-seed error [s], assuming its error falls
    /// as 1/√time (pure noise): wall time × (error / pbrt-v4's error)². Only meaningful for a
    /// scene that matches (no bias).
    pub fn time_to_pbrt_error(&self) -> Option<f64> {
        Some(self.wall_s * self.error_ratio()?.powi(2))
    }

    /// The harness rule: the render succeeded with no unsupported-feature warning, every
    /// channel mean is within [`MEAN_TOLERANCE`] of pbrt-v4's, and the error is at most
    /// [`ERROR_RATIO_LIMIT`] × pbrt-v4's own at the same spp.
    pub fn matches(&self) -> bool {
        self.exit_code == Some(0)
            && self.unsupported.is_empty()
            && self.mean_ratios().is_some_and(|r| r.iter().all(|x| (x - 1.0).abs() <= MEAN_TOLERANCE))
            && self.error_ratio().is_some_and(|r| r <= ERROR_RATIO_LIMIT)
    }

    /// "matches", "differs" or "fails".
    pub fn status(&self) -> &'static str {
        if self.exit_code != Some(0) {
            "fails"
        } else if self.matches() {
            "matches"
        } else {
            "differs"
        }
    }
}

fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |v| format!("{v:.digits$}"))
}

/// The mean ratios joined by `sep`, prism's error, pbrt-v4's, and their ratio, as text.
fn measured_cells(r: &SceneReport, sep: &str) -> [String; 4] {
    let ratios = r.mean_ratios().map_or("–".into(), |m| format!("{:.3}{sep}{:.3}{sep}{:.3}", m[0], m[1], m[2]));
    [ratios, fmt_opt(r.prism_error, 5), fmt_opt(r.pbrt_error.map(|e| e.0), 5), fmt_opt(r.error_ratio(), 2)]
}

/// One line for the terminal.
pub fn one_line(r: &SceneReport) -> String {
    let [ratios, error, pbrt, ratio] = measured_cells(r, "/");
    format!(
        "{:<22} {:<8} warnings {:>3}  means {ratios}  error {error} vs pbrt-v4 {pbrt} ({ratio}×)  {:.1} s",
        r.name,
        r.status(),
        r.unsupported_count(),
        r.wall_s
    )
}

/// The report: the rule, the table, per-scene images and warnings, and which unsupported
/// features affect which scenes.
/// `notes` (the per-feature status, kept in `compatibility-notes.md`) follow the table.
pub fn markdown(reports: &[SceneReport], command: &str, notes: Option<&str>) -> String {
    let mut s = String::new();
    let matched = reports.iter().filter(|r| r.matches()).count();
    let _ = writeln!(s, "# Compatibility with pbrt-v4\n");
    let _ = writeln!(s, "Generated by `{command}` (from the repository root; `make compat`). Do not edit by hand.\n");
    let _ = writeln!(
        s,
        "pbrt-v4's own 98 test scenes, the features each uses and whether prism renders it under \
         `--strict`: [census.md](census.md).\n"
    );
    let _ = writeln!(
        s,
        "Each scene is rendered by prism at the resolution of pbrt-v4's reference image and at the spp of \
         pbrt-v4's second-seed image, with 2 threads. **Error** is the RMSE of x/(1+x)-mapped RGB against \
         pbrt-v4's high-spp image; pbrt-v4's own error is that of its second-seed image at the same spp. \
         A scene **matches** when it renders with no unsupported-feature warning, every channel mean is \
         within {:.0}% of pbrt-v4's and the error is at most {ERROR_RATIO_LIMIT}× pbrt-v4's. **Time to \
         pbrt-v4's error** is prism's wall time (the median of `--repeat` runs, one by default) × (error ratio)², the time at which noise alone would fall \
         to pbrt-v4's error; it means something only for scenes that match. pbrt-v4's times are its \
         recorded wall times (a loaded 2-core machine of the same kind: an upper bound).\n",
        MEAN_TOLERANCE * 100.0
    );
    let _ = writeln!(s, "**{matched} of {} scenes match.**\n", reports.len());
    let _ = writeln!(
        s,
        "| scene | status | unsupported | mean ratio R / G / B | error | pbrt-v4 error | ratio | prism time [s] | \
         time to pbrt-v4's error [s] | pbrt-v4 time [s] | time ratio |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for r in reports {
        let [ratios, error, pbrt, ratio] = measured_cells(r, " / ");
        let t = r.time_to_pbrt_error();
        let time_ratio = t.zip(r.pbrt_wall_s).map(|(t, p)| t / p);
        let _ = writeln!(
            s,
            "| [{}](#{}) | {} | {} | {ratios} | {error} | {pbrt} | {ratio} | {:.2} | {} | {} | {} |",
            r.name,
            r.name,
            r.status(),
            r.unsupported_count(),
            r.wall_s,
            fmt_opt(t, 2),
            fmt_opt(r.pbrt_wall_s, 2),
            fmt_opt(time_ratio, 2),
        );
    }
    if let Some(notes) = notes {
        let _ = writeln!(s, "\n## Per-feature status\n\n(from `docs/compatibility-notes.md`)\n\n{}", notes.trim());
    }
    let _ = writeln!(s, "\n## Unsupported features, by scene\n");
    let mut by_feature: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for r in reports {
        for (m, _) in &r.unsupported {
            by_feature.entry(m).or_default().push(&r.name);
        }
    }
    if by_feature.is_empty() {
        let _ = writeln!(s, "None.");
    }
    for (m, scenes) in &by_feature {
        let _ = writeln!(s, "- {m}: {}", scenes.join(", "));
    }
    let _ = writeln!(s, "\n## Scenes\n");
    for r in reports {
        let _ = writeln!(s, "### {}\n", r.name);
        let _ = writeln!(s, "`{}`, {} spp: **{}**.\n", r.scene.display(), r.spp, r.status());
        if let Some(e) = &r.error {
            let _ = writeln!(s, "prism fails (exit code {}): `{}`\n", fmt_opt(r.exit_code.map(f64::from), 0), e);
        }
        if let Some(p) = &r.panels {
            let file = p.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
            let _ = writeln!(s, "pbrt-v4 | prism | difference\n\n![{}](images/compat/{file})\n", r.name);
        }
        for (m, n) in r.unsupported.iter().chain(&r.notes) {
            let _ = writeln!(s, "- {m}{}", if *n > 1 { format!(" (×{n})") } else { String::new() });
        }
        let _ = writeln!(s);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(log: &str) -> SceneReport {
        let case = CompatCase {
            name: "x".into(),
            scene: "x.pbrt".into(),
            reference: "ref/x.pbrt-v4.exr".into(),
            second: None,
            pbrt_wall_s: Some(10.0),
        };
        let mut r = SceneReport::new(&case, 256, Some(0), log, 2.0);
        r.ref_means = [1.0, 2.0, 4.0];
        r.prism_means = Some([1.01, 1.97, 4.0]);
        r.pbrt_error = Some((0.010, 256));
        r.prism_error = Some(0.012);
        r
    }

    #[test]
    fn the_rule_needs_means_error_and_no_unsupported_feature() {
        let r = report("prism: warning: a.pbrt:1:2: something deprecated\n");
        assert_eq!(r.notes, vec![("something deprecated".to_string(), 1)]);
        assert!(r.matches(), "{r:?}");
        // (0.012 / 0.010)² × 2 s.
        assert!((r.time_to_pbrt_error().unwrap() - 2.88).abs() < 1e-9);
        let mut far = r.clone();
        far.prism_means = Some([1.0, 2.0, 4.1]);
        assert!(!far.matches());
        let mut noisy = r.clone();
        noisy.prism_error = Some(0.0126);
        assert!(!noisy.matches());
        let w = report(
            "prism: warning: a.pbrt:1:2: unsupported feature: x; prism y (1 more like it)\n\
             prism: warning: C:\\s\\b.pbrt:4:2: parameter \"float q\" of Shape \"s\" was not used\n\
             prism: warning: a.pbrt:5:2: unsupported feature: x; prism y\n",
        );
        assert_eq!(w.unsupported.len(), 2);
        assert_eq!(w.unsupported[0], ("unsupported feature: x; prism y".to_string(), 3));
        assert_eq!(w.unsupported[1].0, "parameter \"float q\" of Shape \"s\" was not used");
        assert!(!w.matches());
        assert_eq!(w.status(), "differs");
    }

    #[test]
    fn a_failed_render_reports_its_last_line() {
        let case = CompatCase {
            name: "x".into(),
            scene: "x.pbrt".into(),
            reference: "r".into(),
            second: None,
            pbrt_wall_s: None,
        };
        let r = SceneReport::new(&case, 16, Some(1), "prism: error: x.pbrt:3:1: bad\n\n", 0.1);
        assert_eq!(r.error.as_deref(), Some("prism: error: x.pbrt:3:1: bad"));
        assert_eq!(r.status(), "fails");
        let md = markdown(&[r], "prism compat", Some("- notes here"));
        assert!(md.contains("prism fails (exit code 1)") && md.contains("- notes here"), "{md}");
    }
}
