//! Where, when and how a benchmark ran. Times mean little without the machine, the thread count,
//! the build and the date, so `prism bench` writes them beside its figures (`run.json` and the
//! head of `bench.md`).

use super::BenchConfig;
use crate::integrator::UNBOUNDED_DEPTH;
use std::time::{SystemTime, UNIX_EPOCH};

/// The context of one `prism bench` run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunInfo {
    /// CPU model (`/proc/cpuinfo` "model name"), "unknown" where it cannot be read.
    pub cpu: String,
    /// Logical CPUs available to this process.
    pub logical_cpus: usize,
    /// Worker threads the renders ran on.
    pub threads: usize,
    /// Operating system and kernel release.
    pub os: String,
    /// prism's version and the C libraries it was built with.
    pub prism: String,
    /// When the run started, UTC (ISO 8601).
    pub started_utc: String,
    /// The scene (a file or a built-in name).
    pub scene: String,
    /// Image size [pixels].
    pub resolution: (u32, u32),
    /// Maximum path depth (-1: no limit).
    pub max_depth: i64,
    /// The reference image, or the spp of the rendered one.
    pub reference: String,
}

impl RunInfo {
    /// Gathers the context now, on the thread pool the renders will use.
    pub fn collect(cfg: &BenchConfig) -> Self {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let cpu = cpuinfo
            .lines()
            .find_map(|l| l.strip_prefix("model name")?.split_once(':').map(|(_, v)| v.trim().to_string()))
            .unwrap_or_else(|| "unknown".into());
        let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default();
        let libraries: Vec<&str> = [
            (cfg!(feature = "embree"), "Embree 3"),
            (cfg!(feature = "embree4"), "Embree 4"),
            (cfg!(feature = "oiio"), "OpenImageIO"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect();
        let since_epoch = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
        Self {
            cpu,
            logical_cpus: std::thread::available_parallelism().map_or(1, |n| n.get()),
            threads: rayon::current_num_threads(),
            os: format!("{} {}", std::env::consts::OS, kernel.trim()).trim().to_string(),
            prism: if libraries.is_empty() {
                format!("{} (pure Rust)", env!("CARGO_PKG_VERSION"))
            } else {
                format!("{} (with {})", env!("CARGO_PKG_VERSION"), libraries.join(", "))
            },
            started_utc: iso8601_utc(since_epoch),
            scene: cfg.scene.as_ref().map_or("builtin:cornell".into(), |p| p.display().to_string()),
            resolution: cfg.settings.resolution,
            max_depth: match cfg.settings.integrator.max_depth {
                UNBOUNDED_DEPTH => -1,
                d => d as i64,
            },
            reference: match &cfg.reference {
                Some(p) => p.display().to_string(),
                None => format!("rendered at {} spp (Sobol)", cfg.reference_spp),
            },
        }
    }

    /// Markdown lines for the head of `bench.md`.
    pub fn markdown(&self) -> String {
        format!(
            "- machine: {}, {} logical CPUs, {} worker threads; {}\n\
             - prism {}; run started {}\n\
             - scene {}, {}×{}, max depth {}; reference {}\n",
            self.cpu,
            self.logical_cpus,
            self.threads,
            self.os,
            self.prism,
            self.started_utc,
            self.scene,
            self.resolution.0,
            self.resolution.1,
            self.max_depth,
            self.reference
        )
    }
}

/// `secs` after the Unix epoch as an ISO 8601 UTC time, e.g. "2026-11-22T22:40:05Z" (the
/// proleptic Gregorian calendar by H. Hinnant's days-to-civil algorithm).
fn iso8601_utc(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Days since 0000-03-01, in 400-year eras of 146,097 days; the year starts in March so
    // that the leap day is its last.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let (h, m, s) = (rem / 3600, rem % 3600 / 60, rem % 60);
    format!("{year:04}-{month:02}-{day:02}T{h:02}:{m:02}:{s:02}Z")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_dates_across_leap_days_and_centuries() {
        // Values from Python's calendar.timegm.
        assert_eq!(iso8601_utc(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso8601_utc(951_782_400), "2000-02-29T00:00:00Z"); // 2000 is a leap year
        assert_eq!(iso8601_utc(951_782_400 - 1), "2000-02-28T23:59:59Z");
        assert_eq!(iso8601_utc(1_709_164_800), "2024-02-29T00:00:00Z");
        assert_eq!(iso8601_utc(4_107_542_400), "2100-03-01T00:00:00Z"); // 2100 is not
        assert_eq!(iso8601_utc(4_107_542_400 - 86_400), "2100-02-28T00:00:00Z");
        assert_eq!(iso8601_utc(1_795_387_205), "2026-11-22T22:40:05Z");
    }
}
