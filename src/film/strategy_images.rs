//! pbrt-v4 `bdpt`'s debugging images (`visualizestrategies`, `visualizeweights`): one image per
//! bidirectional strategy (s light vertices, t camera vertices) of every depth s + t − 2, each
//! contribution recorded at its film position (the camera sample's for t ≥ 2, the lens
//! connection's for t = 1) through a box filter of radius ½ and scaled by M / N as splats are
//! ([`SplatBuffer`]), so that a pixel holds its strategy's mean contribution per camera sample.
//! With the weights applied, the images of all strategies sum to the main image rendered with a
//! box filter.

use super::SplatBuffer;

/// The deepest depth that has strategy images (deeper paths add to the main image only).
pub const MAX_STRATEGY_DEPTH: u32 = 16;

/// The strategy images of depths 0 ..= `max_depth`.
#[derive(Clone, Debug, PartialEq)]
pub struct StrategyImages {
    /// Deepest depth recorded.
    pub max_depth: u32,
    /// One buffer per (s, t), at [`StrategyImages::index`]; (s, t) pairs no strategy uses stay
    /// empty.
    pub images: Vec<SplatBuffer>,
}

impl StrategyImages {
    /// Empty images of `pixels` film pixels (of an image of `full_pixels`) for depths up to
    /// `max_depth` (at most [`MAX_STRATEGY_DEPTH`]).
    pub fn new(max_depth: u32, pixels: usize, full_pixels: u64) -> Self {
        let max_depth = max_depth.min(MAX_STRATEGY_DEPTH);
        let count = Self::index(0, max_depth as usize + 3);
        Self { max_depth, images: vec![SplatBuffer::new(pixels, full_pixels); count] }
    }

    /// The buffer of strategy (s, t): those of depth d = s + t − 2 follow those of all
    /// shallower depths, in order of s (pbrt-v4's `BufferIndex`).
    pub fn index(s: usize, t: usize) -> usize {
        let depth = s + t - 2;
        depth * (depth + 5) / 2 + s
    }

    /// Every strategy the images hold: (depth, s, t), by depth then s. t = 0 and (s, t) =
    /// (1, 1) are no strategies of the estimator.
    pub fn strategies(&self) -> impl Iterator<Item = (usize, usize, usize)> {
        (0..=self.max_depth as usize).flat_map(|depth| {
            (0..=depth + 2).map(move |s| (depth, s, depth + 2 - s)).filter(|&(_, s, t)| t != 0 && (s, t) != (1, 1))
        })
    }

    /// The file name pbrt-v4 gives the image of strategy (s, t) of `depth`.
    pub fn file_name(depth: usize, s: usize, t: usize) -> String {
        format!("bdpt_d{depth:02}_s{s:02}_t{t:02}.exr")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_strategy_has_its_own_buffer() {
        let images = StrategyImages::new(4, 1, 1);
        let mut seen = vec![false; images.images.len()];
        let mut count = 0;
        for (depth, s, t) in images.strategies() {
            assert_eq!(s + t, depth + 2);
            let i = StrategyImages::index(s, t);
            assert!(!seen[i], "({s}, {t}) shares buffer {i}");
            seen[i] = true;
            count += 1;
        }
        // Depth d has d + 3 pairs (s = 0 … d + 2), less t = 0 and, at depth 0, (1, 1).
        assert_eq!(count, (0..=4).map(|d| d + 2).sum::<usize>() - 1);
        assert_eq!(StrategyImages::file_name(3, 1, 4), "bdpt_d03_s01_t04.exr");
    }
}
