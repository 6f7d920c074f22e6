//! Time per stage of the wavefront loop: the thread's CPU time (so that other processes on a
//! loaded machine do not enter), read once between stages (a stage runs over a whole queue, so
//! the reads cost nothing measurable).

use cpu_time::ThreadTime;

/// The stages the clock tells apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Sampler start, film position, wavelengths, filter, camera ray.
    Camera,
    /// Closest hits of the queued rays.
    Intersect,
    /// Interaction, emission, material and textures, light choice, sampler draws, binning.
    Surface,
    /// The Lambertian queue on vectors.
    Diffuse,
    /// Every other BSDF kind, path by path.
    OtherKinds,
    /// The vector results written back to paths: throughput, next ray, shadow ray.
    Scatter,
    /// Shadow rays.
    Shadow,
    /// Shadow results, Russian roulette, the next queue.
    Roulette,
    /// Sensor response and pixel sums.
    Film,
}

/// Number of [`Stage`]s.
pub const STAGES: usize = 9;

impl Stage {
    /// Every stage, in loop order.
    pub const ALL: [Stage; STAGES] = [
        Stage::Camera,
        Stage::Intersect,
        Stage::Surface,
        Stage::Diffuse,
        Stage::OtherKinds,
        Stage::Scatter,
        Stage::Shadow,
        Stage::Roulette,
        Stage::Film,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Camera => "camera",
            Stage::Intersect => "intersect",
            Stage::Surface => "surface",
            Stage::Diffuse => "diffuse (vector)",
            Stage::OtherKinds => "other BSDFs",
            Stage::Scatter => "scatter",
            Stage::Shadow => "shadow rays",
            Stage::Roulette => "roulette",
            Stage::Film => "film",
        }
    }
}

/// CPU nanoseconds per stage since the clock started.
pub(super) struct Clock {
    last: ThreadTime,
    pub ns: [u64; STAGES],
}

impl Clock {
    pub fn new() -> Self {
        Self { last: ThreadTime::now(), ns: [0; STAGES] }
    }

    /// Charges the time since the last lap to `stage`.
    #[inline]
    pub fn lap(&mut self, stage: Stage) {
        let now = ThreadTime::now();
        self.ns[stage as usize] += now.duration_since(self.last).as_nanos() as u64;
        self.last = now;
    }
}
