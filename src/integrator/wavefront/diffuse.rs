//! The Lambertian shading queue: every path whose vertex has a Lambertian BSDF, in columns,
//! and the stage that runs next-event estimation and BSDF sampling on sixteen of them per
//! instruction. The physics is the lane-generic code the scalar loop runs with one lane
//! (`BsdfLanes`/`DiffuseLanes`, `TriangleLightLanes::sample`, `offset_ray_origin_lanes`,
//! `power_heuristic_lanes`), so a lane computes what the scalar path computes.

use super::columns::{load, load_mask, store, store_mask, Col3, Col4, L, W};
use crate::bsdf::{BsdfLanes, DiffuseLanes};
use crate::light::{AreaLight, TriangleLightLanes};
use crate::math::offset::offset_ray_origin_lanes;
use crate::math::{Frame, FrameLanes};
use crate::sampling::mis::power_heuristic_lanes;
use crate::simd::Real;
use crate::spectrum::{SampledSpectrum, S4};
use glam::{Vec2, Vec3};
use multiversion::multiversion;

/// What the surface stage gives a Lambertian vertex.
pub(super) struct DiffuseVertex<'a> {
    pub path: u32,
    pub p: Vec3,
    pub p_err: Vec3,
    /// The normal ray origins are offset along (the interaction's `shading.ng`).
    pub ng: Vec3,
    pub frame: Frame,
    pub wo: Vec3,
    pub rho: SampledSpectrum,
    pub beta: SampledSpectrum,
    /// The light chosen, its probability, the rest of the draw and its radiance at the path's
    /// wavelengths; `None`: no light sample.
    pub light: Option<(&'a AreaLight, f32, Vec2, SampledSpectrum)>,
    /// The BSDF sample's 2D draw.
    pub u_bsdf: Vec2,
}

/// The queue's inputs and the stage's outputs, one entry per vertex, padded to whole vectors.
#[derive(Default)]
pub(super) struct DiffuseQueue {
    pub path: Vec<u32>,
    pub p: Col3,
    p_err: Col3,
    ng: Col3,
    s: Col3,
    t: Col3,
    pub n: Col3,
    wo: Col3,
    rho: Col4,
    beta: Col4,
    light: [Col3; 3],
    light_n: Col3,
    light_area: Vec<f32>,
    two_sided: Vec<bool>,
    pmf: Vec<f32>,
    u_light: [Vec<f32>; 2],
    le: Col4,
    u_bsdf: [Vec<f32>; 2],
    // Outputs.
    /// Shadow ray origin and the vector to its end (the light point).
    pub shadow_o: Col3,
    pub shadow_d: Col3,
    /// Entries with a shadow ray to trace.
    pub shadow_ok: Vec<bool>,
    /// β times the light it brings when unblocked.
    pub contribution: Col4,
    /// Next ray origin and direction.
    pub next_o: Col3,
    pub next_d: Col3,
    /// f |cos θ| / pdf of the BSDF sample, and its density.
    pub factor: Col4,
    pub pdf: Vec<f32>,
    /// Entries with a BSDF sample.
    pub next_ok: Vec<bool>,
}

impl DiffuseQueue {
    pub fn clear(&mut self) {
        self.path.clear();
        for c in [&mut self.p, &mut self.p_err, &mut self.ng, &mut self.s, &mut self.t, &mut self.n, &mut self.wo] {
            c.clear();
        }
        for c in self.light.iter_mut().chain([&mut self.light_n]) {
            c.clear();
        }
        for c in [&mut self.rho, &mut self.beta, &mut self.le] {
            c.clear();
        }
        for c in [&mut self.light_area, &mut self.pmf]
            .into_iter()
            .chain(self.u_light.iter_mut())
            .chain(self.u_bsdf.iter_mut())
        {
            c.clear();
        }
        self.two_sided.clear();
    }

    pub fn len(&self) -> usize {
        self.path.len()
    }

    pub fn push(&mut self, v: DiffuseVertex) {
        self.path.push(v.path);
        self.p.push(v.p);
        self.p_err.push(v.p_err);
        self.ng.push(v.ng);
        self.s.push(v.frame.s);
        self.t.push(v.frame.t);
        self.n.push(v.frame.n);
        self.wo.push(v.wo);
        self.rho.push(v.rho);
        self.beta.push(v.beta);
        // No light: probability 0 (the stage then traces no shadow ray).
        let (light, pmf, u, le) = match v.light {
            Some((l, pmf, u, le)) => ((l.p, l.n, l.area, l.two_sided), pmf, u, le),
            None => (([Vec3::ZERO; 3], Vec3::Z, 0.0, false), 0.0, Vec2::ZERO, SampledSpectrum::zero()),
        };
        for (c, q) in self.light.iter_mut().zip(light.0) {
            c.push(q);
        }
        self.light_n.push(light.1);
        self.light_area.push(light.2);
        self.two_sided.push(light.3);
        self.pmf.push(pmf);
        self.u_light[0].push(u.x);
        self.u_light[1].push(u.y);
        self.le.push(le);
        self.u_bsdf[0].push(v.u_bsdf.x);
        self.u_bsdf[1].push(v.u_bsdf.y);
    }

    /// Runs the stage on every entry; the outputs then hold `len()` valid entries.
    pub fn shade(&mut self) {
        let n = self.len().div_ceil(W) * W;
        for c in [&mut self.p, &mut self.p_err, &mut self.ng, &mut self.s, &mut self.t, &mut self.n, &mut self.wo] {
            c.pad(n);
        }
        for c in self.light.iter_mut().chain([&mut self.light_n]) {
            c.pad(n);
        }
        for c in [&mut self.rho, &mut self.beta, &mut self.le] {
            c.pad(n);
        }
        for c in [&mut self.light_area, &mut self.pmf]
            .into_iter()
            .chain(self.u_light.iter_mut())
            .chain(self.u_bsdf.iter_mut())
        {
            c.resize(n, 0.0);
        }
        self.two_sided.resize(n, false);
        for c in [&mut self.shadow_o, &mut self.shadow_d, &mut self.next_o, &mut self.next_d] {
            c.reset(n);
        }
        self.contribution.reset(n);
        self.factor.reset(n);
        self.pdf.clear();
        self.pdf.resize(n, 0.0);
        for m in [&mut self.shadow_ok, &mut self.next_ok] {
            m.clear();
            m.resize(n, false);
        }
        shade_all(self, n);
    }
}

/// The stage over `n` entries, compiled for AVX-512 and AVX2 besides the baseline and chosen
/// once at run time.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2+fma"))]
fn shade_all(q: &mut DiffuseQueue, n: usize) {
    for i in (0..n).step_by(W) {
        shade16(q, i);
    }
}

/// Entries `i..i + W`: next-event estimation as the scalar loop's `sample_light` (a point on
/// the chosen triangle, f |cos θ|, the power heuristic against the BSDF's density, the shadow
/// ray's origin offset past the error bound), then the BSDF sample as its `sample_bsdf`.
#[inline(always)]
fn shade16(q: &mut DiffuseQueue, i: usize) {
    let zero = L::splat(0.0);
    let (p, p_err, ng, wo) = (q.p.load(i), q.p_err.load(i), q.ng.load(i), q.wo.load(i));
    let frame = FrameLanes { s: q.s.load(i), t: q.t.load(i), n: q.n.load(i) };
    let ns = frame.n;
    let bsdf = BsdfLanes { frame, bxdf: DiffuseLanes { r: q.rho.load(i) } };
    let beta = q.beta.load(i);

    let light = TriangleLightLanes {
        p: [q.light[0].load(i), q.light[1].load(i), q.light[2].load(i)],
        n: q.light_n.load(i),
        area: load(&q.light_area, i),
        two_sided: load_mask(&q.two_sided, i),
    };
    let ls = light.sample(p, load(&q.u_light[0], i), load(&q.u_light[1], i));
    let le = q.le.load(i);
    let pmf = load(&q.pmf, i);
    let f = bsdf.f(wo, ls.wi).scale(ls.wi.dot(ns).abs());
    let ok = ls.valid & zero.lt(pmf) & zero.lt(ls.pdf) & !le.is_black() & !f.is_black();
    let o = offset_ray_origin_lanes(p, p_err, ng, ls.p_light - p);
    q.shadow_o.store(i, o);
    q.shadow_d.store(i, ls.p_light - o);
    store_mask(&mut q.shadow_ok, i, ok);
    let p_light = pmf * ls.pdf;
    let weight = power_heuristic_lanes(p_light, bsdf.pdf(wo, ls.wi));
    let ld = (f * le).scale(weight / p_light);
    q.contribution.store(i, S4::select(ok, beta * ld, S4::splat(0.0)));

    let bs = bsdf.sample_f(wo, load(&q.u_bsdf[0], i), load(&q.u_bsdf[1], i));
    let cos = bs.wi.dot(ns).abs();
    q.factor.store(i, bs.f.scale(cos / bs.pdf));
    store(&mut q.pdf, i, bs.pdf);
    store_mask(&mut q.next_ok, i, bs.valid);
    q.next_o.store(i, offset_ray_origin_lanes(p, p_err, ng, bs.wi));
    q.next_d.store(i, bs.wi);
}
