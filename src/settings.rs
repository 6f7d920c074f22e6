//! Render settings written as text (command-line values, scene-file numbers): the one set of
//! rules for sample counts, image sizes, path depths, samplers, filters and durations that every
//! subcommand and the scene reader share. `what` names the value in messages (`--spp`,
//! `"maxdepth"`).

use crate::filter::Filter;
use crate::named::UnknownName;
use crate::sampling::SamplerKind;
use std::time::Duration;

/// A `max_depth` of no limit: Russian roulette alone ends paths.
pub const UNBOUNDED_DEPTH: u32 = u32::MAX;

/// The largest image side accepted [pixels].
pub const MAX_RESOLUTION: u32 = 32768;

/// A setting that does not follow its rule.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SettingsError {
    /// A count (samples, sizes) that is 0 or negative.
    #[error("{what} must be positive, got {value}")]
    NotPositive {
        /// The value's name.
        what: String,
        /// As given.
        value: i64,
    },
    /// Text that is not a number where a count is expected.
    #[error("{what}: '{text}' is not a count")]
    NotCount {
        /// The value's name.
        what: String,
        /// As given.
        text: String,
    },
    /// An image size that is not WxH.
    #[error("resolution '{0}' is not WxH")]
    NotResolution(String),
    /// A side of the image that is not positive.
    #[error("resolution must be positive, got {0}x{1}")]
    ResolutionNotPositive(i64, i64),
    /// A side larger than [`MAX_RESOLUTION`].
    #[error("resolution {0}x{1} is larger than {MAX_RESOLUTION} on a side")]
    ResolutionTooLarge(i64, i64),
    /// A path depth below −1.
    #[error("{what} must be at least 0, or -1 for no limit, got {depth}")]
    Depth {
        /// The value's name.
        what: String,
        /// As given.
        depth: i64,
    },
    /// A sampler name prism does not have.
    #[error(transparent)]
    UnknownSampler(#[from] UnknownName),
    /// A pixel filter name prism does not have.
    #[error("unknown filter '{0}' (valid: box, gaussian, mitchell, sinc, triangle)")]
    UnknownFilter(String),
    /// Text that is not a duration.
    #[error("'{0}' is not a duration (e.g. 30s, 2m)")]
    NotDuration(String),
    /// A duration that is not positive.
    #[error("duration '{0}' must be positive")]
    DurationNotPositive(String),
    /// A duration longer than a `Duration` holds (about 5.8·10¹¹ years).
    #[error("duration '{0}' is too long")]
    DurationTooLong(String),
    /// A comma-separated list with nothing in it.
    #[error("{0} is empty")]
    EmptyList(String),
}

/// A count ≥ 1 (samples per pixel, image sides).
pub fn count(value: i64, what: &str) -> Result<u64, SettingsError> {
    if value <= 0 {
        return Err(SettingsError::NotPositive { what: what.into(), value });
    }
    Ok(value as u64)
}

/// A count ≥ 1 written as text.
pub fn parse_count(text: &str, what: &str) -> Result<u64, SettingsError> {
    let value =
        text.trim().parse::<i64>().map_err(|_| SettingsError::NotCount { what: what.into(), text: text.into() })?;
    count(value, what)
}

/// An image size "WxH" (or "WXH"), each side in 1..=[`MAX_RESOLUTION`].
pub fn parse_resolution(text: &str) -> Result<(u32, u32), SettingsError> {
    let bad = || SettingsError::NotResolution(text.into());
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: i64 = w.trim().parse().map_err(|_| bad())?;
    let h: i64 = h.trim().parse().map_err(|_| bad())?;
    if w <= 0 || h <= 0 {
        return Err(SettingsError::ResolutionNotPositive(w, h));
    }
    if w > MAX_RESOLUTION as i64 || h > MAX_RESOLUTION as i64 {
        return Err(SettingsError::ResolutionTooLarge(w, h));
    }
    Ok((w as u32, h as u32))
}

/// A maximum path depth: ≥ 0, or −1 for no limit ([`UNBOUNDED_DEPTH`], as in Mitsuba 3).
pub fn max_depth(depth: i64, what: &str) -> Result<u32, SettingsError> {
    match depth {
        -1 => Ok(UNBOUNDED_DEPTH),
        d => u32::try_from(d).map_err(|_| SettingsError::Depth { what: what.into(), depth }),
    }
}

/// A sampler by name: prism's "sobol", "independent", or one of pbrt-v4's ("zsobol",
/// "paddedsobol", "halton", "pmj02bn", "stratified") with pbrt-v4's default parameters.
pub fn parse_sampler(name: &str) -> Result<SamplerKind, SettingsError> {
    Ok(SamplerKind::parse(name)?)
}

/// A pixel filter by name ([`Filter::by_name`]).
pub fn parse_filter(name: &str) -> Result<Filter, SettingsError> {
    Filter::by_name(name).ok_or_else(|| SettingsError::UnknownFilter(name.into()))
}

/// A duration "30", "30s", "2m" or "1h" (seconds without a unit).
pub fn parse_duration(text: &str) -> Result<Duration, SettingsError> {
    let s = text.trim();
    let (num, seconds) = match s.chars().last() {
        Some('s') => (&s[..s.len() - 1], 1.0),
        Some('m') => (&s[..s.len() - 1], 60.0),
        Some('h') => (&s[..s.len() - 1], 3600.0),
        _ => (s, 1.0),
    };
    let v: f64 = num.parse().map_err(|_| SettingsError::NotDuration(s.into()))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(SettingsError::DurationNotPositive(s.into()));
    }
    Duration::try_from_secs_f64(v * seconds).map_err(|_| SettingsError::DurationTooLong(s.into()))
}

/// A comma-separated list, each item read by `parse`; an empty list is an error.
pub fn parse_list<T, E: From<SettingsError>>(
    text: &str,
    what: &str,
    parse: impl Fn(&str) -> Result<T, E>,
) -> Result<Vec<T>, E> {
    let v: Vec<T> = text.split(',').map(str::trim).filter(|s| !s.is_empty()).map(parse).collect::<Result<_, _>>()?;
    if v.is_empty() {
        return Err(SettingsError::EmptyList(what.into()).into());
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_sizes_depths_and_durations_follow_one_rule() {
        assert_eq!(count(3, "--spp"), Ok(3));
        assert_eq!(count(0, "--spp").unwrap_err().to_string(), "--spp must be positive, got 0");
        assert_eq!(parse_count(" 7", "--ladder"), Ok(7));
        assert_eq!(parse_count("x", "--ladder").unwrap_err().to_string(), "--ladder: 'x' is not a count");
        assert_eq!(parse_resolution("640x480"), Ok((640, 480)));
        assert_eq!(parse_resolution("64X 32"), Ok((64, 32)));
        assert_eq!(parse_resolution("0x10"), Err(SettingsError::ResolutionNotPositive(0, 10)));
        assert_eq!(parse_resolution("-5x10"), Err(SettingsError::ResolutionNotPositive(-5, 10)));
        assert_eq!(parse_resolution("40000x10"), Err(SettingsError::ResolutionTooLarge(40000, 10)));
        assert_eq!(parse_resolution("abc"), Err(SettingsError::NotResolution("abc".into())));
        assert_eq!(max_depth(0, "d"), Ok(0));
        assert_eq!(max_depth(-1, "d"), Ok(UNBOUNDED_DEPTH));
        assert_eq!(max_depth(-2, "d").unwrap_err().to_string(), "d must be at least 0, or -1 for no limit, got -2");
        assert_eq!(max_depth(1 << 40, "d"), Err(SettingsError::Depth { what: "d".into(), depth: 1 << 40 }));
        assert_eq!(parse_sampler("zsobol"), Ok(SamplerKind::ZSobol(crate::sampling::Randomize::FastOwen)));
        assert_eq!(parse_sampler("independent"), Ok(SamplerKind::Independent));
        assert_eq!(parse_sampler("globalsobol"), Ok(SamplerKind::GlobalSobol(crate::sampling::Randomize::FastOwen)));
        assert!(parse_sampler("sobol2").is_err());
        assert!(parse_filter("mitchell").is_ok() && parse_filter("sinc").is_ok() && parse_filter("cubic").is_err());
        assert_eq!(parse_duration("30s"), Ok(Duration::from_secs(30)));
        assert_eq!(parse_duration("2m"), Ok(Duration::from_secs(120)));
        assert_eq!(parse_duration("1.5"), Ok(Duration::from_millis(1500)));
        assert!(parse_duration("-1").is_err() && parse_duration("soon").is_err());
        // Longer than a Duration holds: an error, not a panic.
        assert_eq!(parse_duration("1e30s"), Err(SettingsError::DurationTooLong("1e30s".into())));
        assert_eq!(parse_duration("1e300h"), Err(SettingsError::DurationTooLong("1e300h".into())));
        let list = |s: &str| parse_list(s, "--spp-ladder", |x| parse_count(x, "--spp-ladder"));
        assert_eq!(list("1, 4,16"), Ok(vec![1, 4, 16]));
        assert_eq!(list(""), Err(SettingsError::EmptyList("--spp-ladder".into())));
        assert!(list("1,0").is_err());
    }
}
