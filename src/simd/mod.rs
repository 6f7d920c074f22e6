//! Arithmetic generic over the number of paths traced together ("paths in lanes"). A [`Real`]
//! is one `f32` per path: `f32` itself (one lane, the scalar renderer) or [`Lanes<N>`] (N paths,
//! one per SIMD lane). Code written against `Real` is compiled once per lane width, as Mitsuba 3
//! compiles one code base for its scalar and vectorised variants (Jakob et al. 2022, "Dr.Jit: A
//! Just-In-Time Compiler for Differentiable Rendering"); divergence between paths is expressed by
//! masks and `select`, never by branches on one lane.

mod lanes;
mod real;
mod vec3;

pub use lanes::{Lanes, LanesMask};
pub use real::{Mask, Real};
pub use vec3::V3;
