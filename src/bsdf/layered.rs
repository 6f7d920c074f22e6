//! Stochastic layered BSDF: two interfaces bounding a homogeneous slab, evaluated and sampled
//! by random walks between them (Guo, Hašan, Yan & Zhao 2018, "Position-free Monte Carlo
//! simulation for arbitrary layered BSDFs"; pbrt-v4 §14.3 `LayeredBxDF`).
//!
//! The slab has thickness d in units of its mean free path (σ_t = 1), single-scattering
//! albedo ϖ and a Henyey–Greenstein phase function of asymmetry g; with ϖ = 0 it only absorbs,
//! with transmittance e^{−d/|cos θ|} per crossing. Light enters through the top interface;
//! the model is two-sided (directions below are mirrored above), as pbrt-v4's coated materials.
//!
//! - [`Layered::f`] averages `n_samples` random-walk estimates of f, each a path between the
//!   interfaces that connects to the exit direction ωi at every vertex (next-event estimation
//!   through the exit interface, MIS-weighted against the walk's own sampling). Where the walk's
//!   own direction leaves through a rough exit, its weight uses the density with which the
//!   next-event technique samples that direction; pbrt-v4 uses the reverse transmission's
//!   density there, so its weights do not sum to one and its f exceeds what its sampling
//!   returns (by 8% in albedo for a coat of α = 0.4 over Lambert, ρ ≈ 0.5).
//! - [`Layered::sample_f`] follows one walk from ωo until it leaves; the returned f and pdf
//!   are the walk's throughput and density, whose ratio is an unbiased weight
//!   (`pdf_is_proportional`: the integrator asks [`Layered::pdf`] for MIS).
//! - [`Layered::pdf`] is pbrt-v4's stochastic approximation of the sampling density (the
//!   top's reflection plus the density of one transmission–reflection–transmission walk),
//!   mixed with the uniform sphere density, 0.9 : 0.1, so it is never 0.
//!
//! Random numbers come from a PCG32 stream seeded with a hash of the call's arguments, so one
//! call gives the same answer on every thread and in every run.

use super::layer_interface::LayerInterface;
use super::local::same_hemisphere;
use super::HenyeyGreenstein;
use super::{BsdfSample, BxdfFlags, Conductor, Dielectric, Diffuse, Lobes, TransportMode};
use crate::math::{Vec2, Vec3, PI};
use crate::sampling::mis::power_heuristic;
use crate::sampling::rng::hash64;
use crate::sampling::Rng;
use crate::spectrum::SampledSpectrum;

/// pbrt-v4's `coateddiffuse`: a dielectric coat over a Lambertian base.
pub type LayeredDiffuse = Layered<Dielectric, Diffuse>;
/// pbrt-v4's `coatedconductor`: a dielectric coat over a metal (its η, k relative to the coat).
pub type LayeredConductor = Layered<Dielectric, Conductor>;

/// The slab between the interfaces and the random walk's limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    /// Thickness in mean free paths (> 0).
    pub thickness: f32,
    /// Single-scattering albedo ϖ per wavelength (0: an absorbing, non-scattering slab).
    pub albedo: SampledSpectrum,
    /// Henyey–Greenstein asymmetry g.
    pub g: f32,
    /// Scattering events a walk may have.
    pub max_depth: u32,
    /// Walks averaged per evaluation of f and pdf.
    pub n_samples: u32,
}

impl Slab {
    /// pbrt-v4's clamps: thickness ≥ the smallest positive float, albedo in [0, 1], g in
    /// [−1, 1], at least one sample. Non-finite values become pbrt-v4's defaults.
    pub fn new(thickness: f32, albedo: SampledSpectrum, g: f32, max_depth: u32, n_samples: u32) -> Self {
        let finite_or = |v: f32, d: f32| if v.is_finite() { v } else { d };
        Self {
            thickness: finite_or(thickness, 0.01).max(f32::MIN_POSITIVE),
            albedo: albedo.map(|a| finite_or(a, 0.0).clamp(0.0, 1.0)),
            g: finite_or(g, 0.0).clamp(-1.0, 1.0),
            max_depth,
            n_samples: n_samples.max(1),
        }
    }

    /// Transmittance e^{−|Δz / cos θ|} along `w` across the height difference `dz`.
    #[inline]
    fn tr(dz: f32, w: Vec3) -> f32 {
        if dz.abs() <= f32::MIN_POSITIVE {
            1.0
        } else {
            (-(dz / w.z).abs()).exp()
        }
    }
}

/// Where a walk goes from one height to the next.
enum Step {
    /// Reaches the interface at this height, with this transmittance on the way.
    Interface(f32, f32),
    /// Scatters in the slab at this height.
    Scatter(f32),
    /// Went nowhere (a zero distance in f32): the event is void.
    Stuck,
}

impl Slab {
    /// Advances a walk at height `z` (0 at the bottom, `thickness` at the top) along `w`: an
    /// absorbing slab is crossed to the other interface with its transmittance; a scattering
    /// one samples a free-flight distance, e^{−s} in optical depth along `w`, and either
    /// scatters inside or stops at the interface it reaches (transmittance 1: the flight's
    /// probability already accounts for it).
    fn step(&self, z: f32, w: Vec3, rng: &mut WalkRng) -> Step {
        let d = self.thickness;
        if self.albedo.is_black() {
            return Step::Interface(if z == d { 0.0 } else { d }, Slab::tr(d, w));
        }
        let dz = -(1.0 - rng.next()).ln() * w.z.abs();
        let zp = if w.z > 0.0 { z + dz } else { z - dz };
        if zp == z {
            Step::Stuck
        } else if 0.0 < zp && zp < d {
            Step::Scatter(zp)
        } else {
            Step::Interface(zp.clamp(0.0, d), 1.0)
        }
    }
}

/// A layered BxDF with interfaces `top` (entrance) and `bottom`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layered<T, B> {
    /// Upper interface.
    pub top: T,
    /// Lower interface.
    pub bottom: B,
    /// The medium between them.
    pub slab: Slab,
}

/// One of the two interfaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Top,
    Bottom,
}

/// A usable interface sample: nonzero value, positive density, off the tangent plane.
fn usable(s: Option<BsdfSample>) -> Option<BsdfSample> {
    s.filter(|s| !s.f.is_black() && s.pdf > 0.0 && s.wi.z != 0.0)
}

/// The walk's random numbers, from a stream named by two directions (or a direction and the
/// sample's uniforms).
struct WalkRng(Rng);

impl WalkRng {
    fn new(a: Vec3, b: [f32; 3]) -> Self {
        let bits = |v: [f32; 3]| v.map(|x| x.to_bits() as u64);
        let [ax, ay, az] = bits(a.to_array());
        let [bx, by, bz] = bits(b);
        Self(Rng::new(hash64(&[ax, ay, az]), hash64(&[bx, by, bz])))
    }
    #[inline]
    fn next(&mut self) -> f32 {
        self.0.uniform()
    }
    #[inline]
    fn next2(&mut self) -> Vec2 {
        let x = self.next();
        Vec2::new(x, self.next())
    }
}

impl<T: LayerInterface, B: LayerInterface> Layered<T, B> {
    /// Interfaces `top` over `bottom` around `slab`.
    pub fn new(top: T, bottom: B, slab: Slab) -> Self {
        Self { top, bottom, slab }
    }

    fn side_f(&self, s: Side, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match s {
            Side::Top => self.top.f(wo, wi, mode),
            Side::Bottom => self.bottom.f(wo, wi, mode),
        }
    }

    fn side_sample(
        &self,
        s: Side,
        wo: Vec3,
        rng: &mut WalkRng,
        mode: TransportMode,
        lobes: Lobes,
    ) -> Option<BsdfSample> {
        let (uc, u) = (rng.next(), rng.next2());
        usable(match s {
            Side::Top => self.top.sample_lobes(wo, uc, u, mode, lobes),
            Side::Bottom => self.bottom.sample_lobes(wo, uc, u, mode, lobes),
        })
    }

    fn side_pdf(&self, s: Side, wo: Vec3, wi: Vec3, mode: TransportMode, lobes: Lobes) -> f32 {
        match s {
            Side::Top => self.top.pdf_lobes(wo, wi, mode, lobes),
            Side::Bottom => self.bottom.pdf_lobes(wo, wi, mode, lobes),
        }
    }

    fn side_specular(&self, s: Side) -> bool {
        match s {
            Side::Top => self.top.flags().is_specular(),
            Side::Bottom => self.bottom.flags().is_specular(),
        }
    }

    /// Lobes present: reflection, specular when the top is, diffuse when either interface or
    /// the slab scatters diffusely (else glossy), transmission when both interfaces transmit.
    pub fn flags(&self) -> BxdfFlags {
        let (top, bottom) = (self.top.flags(), self.bottom.flags());
        let mut flags = BxdfFlags::REFLECTION;
        if top.is_specular() {
            flags = flags | BxdfFlags::SPECULAR;
        }
        if top.is_diffuse() || bottom.is_diffuse() || !self.slab.albedo.is_black() {
            flags = flags | BxdfFlags::DIFFUSE;
        } else if top.is_glossy() || bottom.is_glossy() {
            flags = flags | BxdfFlags::GLOSSY;
        }
        if top.is_transmissive() && bottom.is_transmissive() {
            flags = flags | BxdfFlags::TRANSMISSION;
        }
        flags
    }

    /// Random-walk estimate of f(ωo, ωi) [1/sr], the mean of `n_samples` walks.
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        if wo.z == 0.0 || wi.z == 0.0 {
            return SampledSpectrum::zero();
        }
        let reflect = same_hemisphere(wo, wi);
        // Leaving through the bottom needs a bottom that transmits.
        if !reflect && !self.bottom.flags().is_transmissive() {
            return SampledSpectrum::zero();
        }
        let (exit, non_exit) = if reflect { (Side::Top, Side::Bottom) } else { (Side::Bottom, Side::Top) };
        let d = self.slab.thickness;
        let exit_z = if reflect { d } else { 0.0 };
        let n = self.slab.n_samples;
        let mut f = if reflect { self.top.f(wo, wi, mode) * n as f32 } else { SampledSpectrum::zero() };
        let mut rng = WalkRng::new(wo, wi.to_array());
        for _ in 0..n {
            f += self.f_walk(wo, wi, mode, (exit, non_exit, exit_z), &mut rng);
        }
        f / n as f32
    }

    /// One walk's contribution to f (without the top's direct reflection).
    fn f_walk(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        (exit, non_exit, exit_z): (Side, Side, f32),
        rng: &mut WalkRng,
    ) -> SampledSpectrum {
        let mut f = SampledSpectrum::zero();
        let Some(wos) = self.side_sample(Side::Top, wo, rng, mode, Lobes::Transmission) else { return f };
        // The light's end: a direction through the exit interface toward ωi, sampled once
        // and reused for every next-event connection of this walk.
        let Some(wis) = self.side_sample(exit, wi, rng, mode.adjoint(), Lobes::Transmission) else { return f };
        let d = self.slab.thickness;
        let albedo = self.slab.albedo;
        let phase = HenyeyGreenstein::new(self.slab.g);
        let exit_specular = self.side_specular(exit);
        let non_exit_specular = self.side_specular(non_exit);
        let mut beta = wos.f * wos.wi.z.abs() / wos.pdf;
        let mut z = d;
        let mut w = wos.wi;
        for depth in 0..self.slab.max_depth {
            if depth > 3 && beta.max_value() < 0.25 {
                let q = (1.0 - beta.max_value()).max(0.0);
                if rng.next() < q {
                    break;
                }
                beta /= 1.0 - q;
            }
            match self.slab.step(z, w, rng) {
                Step::Stuck => continue,
                Step::Interface(next_z, tr) => {
                    z = next_z;
                    beta *= tr;
                }
                Step::Scatter(zp) => {
                    // Scattering in the slab: connect to ωi through the exit along wis.
                    let toward_exit = -wis.wi;
                    let p_exit = phase.p(w, toward_exit);
                    let wt = if exit_specular { 1.0 } else { power_heuristic(1, wis.pdf, 1, p_exit) };
                    f += beta * albedo * (p_exit * wt * Slab::tr(zp - exit_z, wis.wi) / wis.pdf) * wis.f;
                    let next = phase.sample(w, rng.next2());
                    if next.z == 0.0 {
                        continue;
                    }
                    let p_next = phase.p(w, next);
                    // HG sampling is exact: p / pdf = 1.
                    beta *= albedo;
                    w = next;
                    z = zp;
                    let heads_out = (z < exit_z && w.z > 0.0) || (z > exit_z && w.z < 0.0);
                    if heads_out && !exit_specular {
                        let f_exit = self.side_f(exit, -w, wi, mode);
                        if !f_exit.is_black() {
                            let wt = power_heuristic(1, p_next, 1, self.light_end_pdf(exit, wi, w, mode));
                            f += beta * f_exit * (Slab::tr(zp - exit_z, w) * wt);
                        }
                    }
                    continue;
                }
            }
            if z == exit_z {
                // Reflection back into the slab at the exit interface.
                let Some(bs) = self.side_sample(exit, -w, rng, mode, Lobes::Reflection) else { break };
                beta *= bs.f * bs.wi.z.abs() / bs.pdf;
                w = bs.wi;
            } else {
                if !non_exit_specular {
                    // Next event: scatter at the far interface toward wis, then out.
                    let wt = if exit_specular {
                        1.0
                    } else {
                        power_heuristic(1, wis.pdf, 1, self.side_pdf(non_exit, -w, -wis.wi, mode, Lobes::All))
                    };
                    let fr = self.side_f(non_exit, -w, -wis.wi, mode);
                    f += beta * fr * (wis.wi.z.abs() * wt * Slab::tr(d, wis.wi) / wis.pdf) * wis.f;
                }
                let Some(bs) = self.side_sample(non_exit, -w, rng, mode, Lobes::Reflection) else { break };
                beta *= bs.f * bs.wi.z.abs() / bs.pdf;
                w = bs.wi;
                if !exit_specular {
                    // The sampled direction may itself leave through the exit toward ωi.
                    let f_exit = self.side_f(exit, -w, wi, mode);
                    if !f_exit.is_black() {
                        let wt = if non_exit_specular {
                            1.0
                        } else {
                            power_heuristic(1, bs.pdf, 1, self.light_end_pdf(exit, wi, w, mode))
                        };
                        f += beta * f_exit * (Slab::tr(d, bs.wi) * wt);
                    }
                }
            }
        }
        f
    }

    /// Density [1/sr] with which the next-event strategy of [`Self::f_walk`] (a transmission
    /// sampled at `exit` from ωi, in the adjoint mode) arrives at the walk's direction `w`
    /// inside the slab: the other technique's density in its MIS weights. pbrt-v4 takes the
    /// reverse transmission's density, from −`w` toward ωi, here; the two differ at a rough
    /// interface, and with it the weights of a path no longer sum to one.
    fn light_end_pdf(&self, exit: Side, wi: Vec3, w: Vec3, mode: TransportMode) -> f32 {
        self.side_pdf(exit, wi, -w, mode.adjoint(), Lobes::Transmission)
    }

    /// Samples ωi by one walk from ωo; f and pdf are the walk's (`pdf_is_proportional`).
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let flip = wo.z < 0.0;
        let wo = if flip { -wo } else { wo };
        let unflip = |w: Vec3| if flip { -w } else { w };
        let mut bs = usable(self.top.sample_lobes(wo, uc, u, mode, Lobes::All))?;
        if bs.is_reflection() {
            bs.wi = unflip(bs.wi);
            bs.pdf_is_proportional = true;
            return Some(bs);
        }
        let mut w = bs.wi;
        let mut specular_path = bs.is_specular();
        let mut rng = WalkRng::new(wo, [uc, u.x, u.y]);
        let d = self.slab.thickness;
        let albedo = self.slab.albedo;
        let phase = HenyeyGreenstein::new(self.slab.g);
        let mut f = bs.f * bs.wi.z.abs();
        let mut pdf = bs.pdf;
        let mut z = d;
        for depth in 0..self.slab.max_depth {
            // Only f / pdf matters (the pdf is proportional): keep the product of densities
            // of a long walk from underflowing.
            if pdf < 1e-16 {
                f /= pdf;
                pdf = 1.0;
            }
            let rr_beta = f.max_value() / pdf;
            if depth > 3 && rr_beta < 0.25 {
                let q = (1.0 - rr_beta).max(0.0);
                if rng.next() < q {
                    return None;
                }
                pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            match self.slab.step(z, w, &mut rng) {
                Step::Stuck => return None,
                Step::Interface(next_z, tr) => {
                    z = next_z;
                    f *= tr;
                }
                Step::Scatter(zp) => {
                    let next = phase.sample(w, rng.next2());
                    if next.z == 0.0 {
                        return None;
                    }
                    let p = phase.p(w, next);
                    f *= albedo * p;
                    pdf *= p;
                    specular_path = false;
                    w = next;
                    z = zp;
                    continue;
                }
            }
            let side = if z == 0.0 { Side::Bottom } else { Side::Top };
            let bs = self.side_sample(side, -w, &mut rng, mode, Lobes::All)?;
            f *= bs.f;
            pdf *= bs.pdf;
            specular_path &= bs.is_specular();
            w = bs.wi;
            if bs.is_transmission() {
                let dir = if same_hemisphere(wo, w) { BxdfFlags::REFLECTION } else { BxdfFlags::TRANSMISSION };
                let kind = if specular_path { BxdfFlags::SPECULAR } else { BxdfFlags::GLOSSY };
                let mut out = BsdfSample::new(f, unflip(w), pdf, dir | kind);
                out.pdf_is_proportional = true;
                return Some(out);
            }
            f *= bs.wi.z.abs();
        }
        None
    }

    /// pbrt-v4's stochastic estimate of the density of [`Self::sample_f`] [1/sr].
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let mut rng = WalkRng::new(wi, wo.to_array());
        let reflect = same_hemisphere(wo, wi);
        let n = self.slab.n_samples;
        let mut sum = if reflect { n as f32 * self.top.pdf_lobes(wo, wi, mode, Lobes::Reflection) } else { 0.0 };
        for _ in 0..n {
            sum += if reflect { self.pdf_trt(wo, wi, mode, &mut rng) } else { self.pdf_tt(wo, wi, mode, &mut rng) };
        }
        0.1 / (4.0 * PI) + 0.9 * sum / n as f32
    }

    /// Density of transmission into the slab, reflection at the bottom, transmission out.
    fn pdf_trt(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut WalkRng) -> f32 {
        let wos = self.side_sample(Side::Top, wo, rng, mode, Lobes::Transmission);
        let wis = self.side_sample(Side::Top, wi, rng, mode.adjoint(), Lobes::Transmission);
        let (Some(wos), Some(wis)) = (wos, wis) else { return 0.0 };
        if !self.top.flags().is_non_specular() {
            return self.bottom.pdf_lobes(-wos.wi, -wis.wi, mode, Lobes::All);
        }
        let Some(rs) = self.side_sample(Side::Bottom, -wos.wi, rng, mode, Lobes::All) else { return 0.0 };
        if !self.bottom.flags().is_non_specular() {
            return self.top.pdf_lobes(-rs.wi, wi, mode, Lobes::All);
        }
        // Two estimates of the same product of densities, combined by MIS.
        let r_pdf = self.bottom.pdf_lobes(-wos.wi, -wis.wi, mode, Lobes::All);
        let t_pdf = self.top.pdf_lobes(-rs.wi, wi, mode, Lobes::All);
        power_heuristic(1, wis.pdf, 1, r_pdf) * r_pdf + power_heuristic(1, rs.pdf, 1, t_pdf) * t_pdf
    }

    /// Density of transmission through both interfaces.
    fn pdf_tt(&self, wo: Vec3, wi: Vec3, mode: TransportMode, rng: &mut WalkRng) -> f32 {
        let through = |s: Option<BsdfSample>| s.filter(|s| !s.is_reflection());
        let Some(wos) = through(self.side_sample(Side::Top, wo, rng, mode, Lobes::All)) else { return 0.0 };
        let Some(wis) = through(self.side_sample(Side::Bottom, wi, rng, mode.adjoint(), Lobes::All)) else {
            return 0.0;
        };
        if self.top.flags().is_specular() {
            self.bottom.pdf_lobes(-wos.wi, wi, mode, Lobes::All)
        } else if self.bottom.flags().is_specular() {
            self.top.pdf_lobes(wo, -wis.wi, mode, Lobes::All)
        } else {
            0.5 * (self.top.pdf_lobes(wo, -wis.wi, mode, Lobes::All)
                + self.bottom.pdf_lobes(-wos.wi, wi, mode, Lobes::All))
        }
    }
}
