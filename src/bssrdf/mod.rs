//! The diffusion BSSRDF: photon beam diffusion (PBD) profiles tabulated over single-scattering
//! albedo × optical radius (`table`), built from the PBD formulas (`pbd`), and the separable
//! tabulated BSSRDF at a point with probe-ray importance sampling (`probe`).
//!
//! S(p_i, ω_i, p_o, ω_o) ≈ (1 − F_r(cos θ_o)) S_p(|p_i − p_o|) S_ω(ω_i) (pbrt-v4 §11.4, after
//! Christensen & Burley; PBD: Habel, Christensen & Jarosz 2013, "Photon Beam Diffusion: A
//! Hybrid Monte Carlo Method for Subsurface Scattering").

mod pbd;
mod probe;
mod reference;
mod table;

pub use pbd::{beam_diffusion_ms, beam_diffusion_ss, fresnel_moment1, fresnel_moment2};
pub use probe::{ProbeSegment, TabulatedBssrdf};
pub use reference::{dipole_total_reflectance, half_space_albedo};
pub use table::BssrdfTable;
