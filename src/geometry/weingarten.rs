//! The Weingarten equations: the derivatives of a surface's unit normal along its parameters
//! from the first and second fundamental forms (do Carmo, *Differential Geometry of Curves and
//! Surfaces*, 1976, §3.3; PBR 4th ed. §6.2.3, which bump mapping needs them for).

use glam::Vec3;

/// ∂n/∂u and ∂n/∂v of the unit normal n = ∂p/∂u × ∂p/∂v / |…| from ∂p/∂u, ∂p/∂v and the
/// second derivatives `[∂²p/∂u², ∂²p/∂u∂v, ∂²p/∂v²]`. With E = ∂p/∂u·∂p/∂u, F = ∂p/∂u·∂p/∂v,
/// G = ∂p/∂v·∂p/∂v and e, f, g the second derivatives' components along n:
/// ∂n/∂u = ((fF − eG) ∂p/∂u + (eF − fE) ∂p/∂v) / (EG − F²),
/// ∂n/∂v = ((gF − fG) ∂p/∂u + (fF − gE) ∂p/∂v) / (EG − F²);
/// both zero where the parameterisation is degenerate (EG = F²).
pub fn normal_derivatives(dpdu: Vec3, dpdv: Vec3, [duu, duv, dvv]: [Vec3; 3]) -> (Vec3, Vec3) {
    let n = dpdu.cross(dpdv).normalize_or_zero();
    let (e1, f1, g1) = (dpdu.dot(dpdu), dpdu.dot(dpdv), dpdv.dot(dpdv));
    let (e2, f2, g2) = (n.dot(duu), n.dot(duv), n.dot(dvv));
    let det = e1 * g1 - f1 * f1;
    let inv = if det != 0.0 && det.is_finite() { 1.0 / det } else { 0.0 };
    let dndu = ((f2 * f1 - e2 * g1) * inv) * dpdu + ((e2 * f1 - f2 * e1) * inv) * dpdv;
    let dndv = ((g2 * f1 - f2 * g1) * inv) * dpdu + ((f2 * f1 - g2 * e1) * inv) * dpdv;
    (dndu, dndv)
}

#[cfg(test)]
mod tests {
    use crate::geometry::Quadric;

    /// ∂n/∂u, ∂n/∂v against central differences of the unit normal of each quadric, taken
    /// through its (u, v) parameterisation (`Quadric::point`), at interior points.
    #[test]
    fn normal_derivatives_match_finite_differences_of_the_normal() {
        let shapes = [
            Quadric::Sphere { radius: 1.7, z_min: -1.2, z_max: 1.5, phi_max: 300.0 },
            Quadric::Cylinder { radius: 0.6, z_min: -0.3, z_max: 1.1, phi_max: 250.0 },
            Quadric::Disk { height: 0.2, radius: 1.0, inner_radius: 0.3, phi_max: 200.0 },
        ];
        let h = 1e-3;
        for q in shapes {
            for (u, v) in [(0.2, 0.3), (0.55, 0.7), (0.8, 0.45)] {
                let c = q.point(u, v);
                // A ray straight at the point from along its normal.
                let o = c.p + c.n * 3.0;
                let hit = q.surface_at(o, -c.n, 3.0);
                assert!((hit.p - c.p).length() < 1e-4, "{q:?}: {} vs {}", hit.p, c.p);
                let (dndu, dndv) = q.normal_derivatives(&hit);
                let fd_u = (q.point(u + h, v).n - q.point(u - h, v).n) / (2.0 * h);
                let fd_v = (q.point(u, v + h).n - q.point(u, v - h).n) / (2.0 * h);
                let scale = 1.0 + fd_u.length() + fd_v.length();
                assert!((dndu - fd_u).length() < 2e-3 * scale, "{q:?} ({u}, {v}): ∂n/∂u {dndu} vs {fd_u}");
                assert!((dndv - fd_v).length() < 2e-3 * scale, "{q:?} ({u}, {v}): ∂n/∂v {dndv} vs {fd_v}");
            }
        }
    }
}
