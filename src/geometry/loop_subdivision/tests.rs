use glam::Vec3;

use super::*;
use crate::geometry::shapes::{axis_box, icosphere};
use crate::sampling::rng::Rng;

/// The octahedron with vertices ±x, ±y, ±z, wound outward (every vertex of valence 4).
fn octahedron() -> Level {
    let p = vec![Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let t = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]];
    Level::new(p, t).unwrap()
}

/// An `n` × `n` patch of the equilateral triangle lattice (unit edges, valence 6 inside) in the
/// xy-plane, lifted to z = `height(x, y)`, wound counter-clockwise seen from +z.
fn lattice(n: u32, height: impl Fn(f32, f32) -> f32) -> Level {
    let h = 3f32.sqrt() / 2.0;
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 + 0.5 * j as f32, h * j as f32);
            p.push(Vec3::new(x, y, height(x, y)));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
            t.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Level::new(p, t).unwrap()
}

fn mesh_level(m: &Mesh) -> Level {
    Level::new(m.positions.clone(), m.indices.clone()).unwrap()
}

/// Refined `k` times.
fn refined(mut l: Level, k: u32) -> Level {
    for _ in 0..k {
        l = l.refine();
    }
    l
}

#[test]
fn warren_weights_and_limit_weights_by_hand() {
    // β = 3/16 at valence 3, else 3/(8n); then 3/(8β) = 2 at n = 3 and n otherwise, so
    // χ = 1/(3/(8β) + n) is 1/5 at n = 3 and 1/(2n) beyond.
    assert_eq!(beta(3), 3.0 / 16.0);
    assert_eq!(beta(6), 1.0 / 16.0);
    assert!((beta(5) - 0.075).abs() < 1e-7);
    for (n, chi) in [(3, 0.2), (4, 0.125), (5, 0.1), (6, 1.0 / 12.0), (7, 1.0 / 14.0)] {
        assert!((limit_weight(n) - chi).abs() < 1e-7, "n = {n}: {} vs {chi}", limit_weight(n));
    }
}

#[test]
fn limit_position_of_a_valence_5_apex_is_the_hand_weighted_sum() {
    // A pentagonal bipyramid over an irregular pentagon: both apices have valence 5, so their
    // limit is (1 − 5χ)·apex + χ·Σ ring with χ = 1/10, i.e. ½·apex + (1/10)·Σ equator.
    let eq = [
        Vec3::new(1.0, 0.1, 0.2),
        Vec3::new(0.3, 1.1, -0.1),
        Vec3::new(-0.9, 0.6, 0.0),
        Vec3::new(-0.7, -0.8, 0.3),
        Vec3::new(0.4, -1.0, -0.2),
    ];
    let (top, bottom) = (Vec3::new(0.1, -0.2, 1.5), Vec3::new(-0.1, 0.1, -1.2));
    let mut p = eq.to_vec();
    p.extend([top, bottom]);
    let mut t = Vec::new();
    for i in 0..5u32 {
        t.push([i, (i + 1) % 5, 5]);
        t.push([(i + 1) % 5, i, 6]);
    }
    let l = Level::new(p, t).unwrap();
    let sum: Vec3 = eq.iter().sum();
    let want_top = 0.5 * top + 0.1 * sum;
    assert!((l.limit_point(5) - want_top).length() < 1e-6, "{} vs {want_top}", l.limit_point(5));
    assert!((l.limit_point(6) - (0.5 * bottom + 0.1 * sum)).length() < 1e-6);
    // An equator vertex has valence 4 (two neighbours on the equator, both apices): χ = 1/8.
    let want = 0.5 * eq[0] + 0.125 * (eq[1] + eq[4] + top + bottom);
    assert!((l.limit_point(0) - want).length() < 1e-6, "{} vs {want}", l.limit_point(0));
}

#[test]
fn tetrahedron_limit_uses_the_valence_3_weights() {
    // Valence 3: χ = 1/5, limit = (2/5)·v + (1/5)·(the other three) = (v + Σ all four)/5, with
    // Σ all four = (2, 3, 5).
    let p =
        vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.0, 0.0, 5.0)];
    let l = Level::new(p, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]).unwrap();
    let want = [Vec3::new(0.4, 0.6, 1.0), Vec3::new(0.8, 0.6, 1.0), Vec3::new(0.4, 1.2, 1.0), Vec3::new(0.4, 0.6, 2.0)];
    for (v, w) in want.iter().enumerate() {
        assert!((l.limit_point(v) - *w).length() < 1e-6, "{v}: {} vs {w}", l.limit_point(v));
    }
}

#[test]
fn closed_mesh_refines_to_four_to_the_k_closed_triangles() {
    for (name, l) in [("octahedron", octahedron()), ("cube", mesh_level(&axis_box(-Vec3::ONE, Vec3::ONE)))] {
        let (v0, f0) = (l.positions.len(), l.triangles.len());
        let valence0: Vec<usize> = (0..v0).map(|u| l.topology.ring(u).len()).collect();
        let mut l = l;
        for k in 0..=4u32 {
            assert_eq!(l.triangles.len(), f0 * 4usize.pow(k), "{name} level {k}");
            assert!(l.topology.is_closed(), "{name} level {k} is open");
            // Closed 2-manifold: 3F = 2E, and the Euler characteristic of a sphere, V − E + F = 2.
            let (v, e, f) = (l.positions.len(), l.topology.edges.len(), l.triangles.len());
            assert_eq!(3 * f, 2 * e, "{name} level {k}");
            assert_eq!(v as i64 - e as i64 + f as i64, 2, "{name} level {k}");
            // The control vertices keep their valence; inserted vertices are regular (valence 6).
            for (u, &n) in valence0.iter().enumerate() {
                assert_eq!(l.topology.ring(u).len(), n, "{name} level {k} vertex {u}");
            }
            assert!((v0..v).all(|u| l.topology.ring(u).len() == 6), "{name} level {k}");
            l = l.refine();
        }
    }
}

#[test]
fn limit_of_a_convex_mesh_lies_strictly_inside_its_control_hull() {
    // Every refinement and limit weight is positive and sums to 1, so limit points are convex
    // combinations of control points, strictly inside the hull where the surface is curved.
    let oct = refined(octahedron(), 3).limit_mesh();
    for p in &oct.positions {
        let l1 = p.x.abs() + p.y.abs() + p.z.abs();
        assert!(l1 < 1.0 - 1e-3, "{p}: |x| + |y| + |z| = {l1}");
    }
    let ico = icosphere(Vec3::ZERO, 1.0, 0);
    let limit = refined(mesh_level(&ico), 3).limit_mesh();
    for &[a, b, c] in &ico.indices {
        let [a, b, c] = [a, b, c].map(|i| ico.positions[i as usize]);
        let n = (b - a).cross(c - a).normalize();
        for p in &limit.positions {
            assert!(n.dot(*p - a) < -1e-3, "{p} is not strictly inside the face plane through {a}");
        }
    }
}

#[test]
fn planar_patch_stays_planar_with_normals_across_it() {
    // A jittered square grid with diagonals (valences 3 to 8, boundary and corners) in z = 0.
    let n = 6u32;
    let mut rng = Rng::new(7, 0);
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let jitter =
                |r: &mut Rng| if i == 0 || j == 0 || i == n || j == n { 0.0 } else { 0.3 * (r.uniform() - 0.5) };
            p.push(Vec3::new(i as f32 + jitter(&mut rng), j as f32 + jitter(&mut rng), 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if (i + j) % 2 == 0 {
                t.extend([[id(i, j), id(i + 1, j), id(i + 1, j + 1)], [id(i, j), id(i + 1, j + 1), id(i, j + 1)]]);
            } else {
                t.extend([[id(i, j), id(i + 1, j), id(i, j + 1)], [id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]]);
            }
        }
    }
    let m = subdivide(&p, &t, 3).unwrap();
    assert_eq!(m.len(), t.len() * 64);
    let normals = m.normals.as_ref().unwrap();
    for (q, nrm) in m.positions.iter().zip(normals) {
        assert_eq!(q.z, 0.0, "{q} left the plane");
        assert!((*nrm - Vec3::Z).length() < 1e-5, "normal {nrm} at {q}");
        assert!(q.x >= 0.0 && q.x <= n as f32 && q.y >= 0.0 && q.y <= n as f32, "{q} outside the patch");
    }
}

#[test]
fn regular_region_reproduces_a_quadratic_up_to_the_box_spline_offset() {
    // Control points z = q(x, y) on the unit three-direction lattice: the limit is the box
    // spline Σ q(u_i) B(u − u_i) = q + (second moments), which for the quartic box spline is
    // q + (a + c)/4 for q = a x² + b xy + c y² (its limit mask ½, 1/12 × 6 has Σ w dx² =
    // Σ w dy² = 1/4 and Σ w dx dy = 0). Checked 3 lattice units from the boundary, beyond the
    // reach of the boundary rules.
    let (a, b, c) = (0.1f32, 0.07f32, -0.05f32);
    let q = |x: f32, y: f32| a * x * x + b * x * y + c * y * y;
    let n = 10;
    let l = refined(lattice(n, q), 3);
    let h = 3f32.sqrt() / 2.0;
    let mut checked = 0;
    for v in 0..l.positions.len() {
        let p = l.limit_point(v);
        // Lattice coordinates in units of this level's edge (1/8).
        let (j, i) = (8.0 * p.y / h, 8.0 * (p.x - 0.5 * p.y / h));
        let (i8, j8) = (i.round(), j.round());
        let inner = 8.0 * 3.0..=8.0 * (n - 3) as f32;
        if !inner.contains(&i8) || !inner.contains(&j8) {
            continue;
        }
        let offset = p.z - q(p.x, p.y);
        assert!((offset - (a + c) / 4.0).abs() < 1e-4, "at ({}, {}): offset {offset}", p.x, p.y);
        // Linear precision: x and y stay on the lattice of this level.
        assert!((i - i8).abs() < 1e-3 && (j - j8).abs() < 1e-3, "({i}, {j})");
        checked += 1;
    }
    // (4·8 + 1)² lattice points in the checked square.
    assert_eq!(checked, 33 * 33);
}

#[test]
fn limit_points_stay_put_under_refinement() {
    // A vertex's limit point is a point of the limit surface, so refining the mesh and taking
    // the limit of the same vertex gives it again (interior and boundary masks alike).
    let bumpy = {
        let mut rng = Rng::new(3, 1);
        let mut l = octahedron();
        for p in &mut l.positions {
            *p *= 1.0 + 0.4 * rng.uniform();
        }
        l
    };
    let open = lattice(6, |x, y| 0.3 * (1.3 * x).sin() + 0.2 * y * y);
    for (name, l) in
        [("bumpy octahedron", bumpy), ("open lattice", open), ("cube", mesh_level(&axis_box(Vec3::ZERO, Vec3::ONE)))]
    {
        let l = l.refine();
        let finer = l.refine();
        for v in 0..l.positions.len() {
            let (p, q) = (l.limit_point(v), finer.limit_point(v));
            assert!((p - q).length() < 2e-6 * (1.0 + p.length()), "{name} vertex {v}: {p} then {q}");
        }
    }
}

/// The largest angle [degrees] between `normals` at the vertices of `l` and the normals of the
/// limit mesh two levels finer, from its triangles' area-weighted normals around the same vertex.
fn worst_normal_angle(l: &Level, normals: &[Vec3]) -> f32 {
    let fine = refined(l.clone(), 2);
    let m = fine.limit_mesh();
    let mut fd = vec![Vec3::ZERO; m.positions.len()];
    for &[a, b, c] in &m.indices {
        let [pa, pb, pc] = [a, b, c].map(|i| m.positions[i as usize]);
        let n = (pb - pa).cross(pc - pa);
        for i in [a, b, c] {
            fd[i as usize] += n;
        }
    }
    (0..l.positions.len())
        .map(|v| normals[v].dot(fd[v].normalize()).clamp(-1.0, 1.0).acos().to_degrees())
        .fold(0.0, f32::max)
}

#[test]
fn limit_normals_agree_with_finite_differences_of_the_finer_limit_mesh() {
    // Measured worst angles after one level (degrees), exact limit normals: bumpy octahedron
    // 0.056, cube 0.23 (its valence-3 corners), open lattice 0.76 (the boundary masks); the
    // mesh's normals (the masks over the ring's limit points, as pbrt-v4): 0.56, 3.5, 1.7. The
    // bounds are twice the measured angles.
    let mut rng = Rng::new(11, 2);
    let mut bumpy = octahedron();
    for p in &mut bumpy.positions {
        *p *= 1.0 + 0.4 * rng.uniform();
    }
    let cases = [
        ("bumpy octahedron", bumpy, 0.12, 1.2),
        ("cube", mesh_level(&axis_box(Vec3::ZERO, Vec3::ONE)), 0.5, 7.0),
        ("open lattice", lattice(6, |x, y| 0.3 * (1.3 * x).sin() + 0.2 * y * y), 1.5, 3.5),
    ];
    for (name, l, bound, mesh_bound) in cases {
        let l = l.refine();
        let exact: Vec<Vec3> = (0..l.positions.len()).map(|v| l.limit_normal(v)).collect();
        let worst = worst_normal_angle(&l, &exact);
        assert!(worst < bound, "{name}: {worst}° ≥ {bound}°");
        let mesh = l.limit_mesh();
        let worst_mesh = worst_normal_angle(&l, mesh.normals.as_ref().unwrap());
        assert!(worst_mesh < mesh_bound, "{name}: mesh normals {worst_mesh}° ≥ {mesh_bound}°");
    }
}

#[test]
fn boundary_is_the_cubic_b_spline_of_the_boundary_polygon() {
    let l = lattice(4, |x, y| 0.3 * (1.3 * x).sin() + 0.2 * y * y - 0.1 * x * y);
    // The control boundary loop, in the winding's direction: from each boundary vertex to the
    // first vertex of its (counter-clockwise) ring.
    let start = (0..l.positions.len()).find(|&v| l.topology.is_boundary(v)).unwrap();
    let mut control = vec![start];
    loop {
        let next = l.topology.ring(*control.last().unwrap())[0] as usize;
        if next == start {
            break;
        }
        control.push(next);
    }
    assert_eq!(control.len(), 16);
    let cp: Vec<Vec3> = control.iter().map(|&v| l.positions[v]).collect();
    let k = 3;
    let per_span = 1usize << k;
    // Uniform periodic cubic B-spline at t = m/2^k of each span.
    let mut curve = Vec::new();
    let m = cp.len();
    for i in 0..m {
        let p = |d: isize| cp[(i as isize + d).rem_euclid(m as isize) as usize];
        for s in 0..per_span {
            let t = s as f32 / per_span as f32;
            let w = [
                (1.0 - t).powi(3) / 6.0,
                (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
                (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                t.powi(3) / 6.0,
            ];
            curve.push(w[0] * p(-1) + w[1] * p(0) + w[2] * p(1) + w[3] * p(2));
        }
    }
    let fine = refined(l, k);
    let boundary: Vec<Vec3> =
        (0..fine.positions.len()).filter(|&v| fine.topology.is_boundary(v)).map(|v| fine.limit_point(v)).collect();
    assert_eq!(boundary.len(), curve.len());
    let mut matched = vec![false; curve.len()];
    for p in &boundary {
        let (i, d) =
            curve.iter().enumerate().map(|(i, c)| (i, (*c - *p).length())).min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
        assert!(d < 1e-5, "boundary limit point {p} is {d} from the B-spline");
        assert!(!matched[i], "two boundary points at B-spline point {i}");
        matched[i] = true;
    }
}

#[test]
fn valence_and_boundary_of_a_lattice() {
    let l = lattice(3, |_, _| 0.0);
    let t = &l.topology;
    // Interior vertices of the lattice have 6 neighbours; boundary ones ring = triangles + 1.
    let id = |i: usize, j: usize| j * 4 + i;
    assert!(!t.is_boundary(id(1, 1)) && t.ring(id(1, 1)).len() == 6);
    // The acute corner (0, 0) touches one triangle; the obtuse corner (3, 0) two.
    assert!(t.is_boundary(id(0, 0)) && t.ring(id(0, 0)).len() == 2);
    assert!(t.is_boundary(id(3, 0)) && t.ring(id(3, 0)).len() == 3);
    assert!(t.is_boundary(id(1, 0)) && t.ring(id(1, 0)).len() == 4);
    assert_eq!(t.edges.iter().filter(|e| e.is_boundary()).count(), 12);
    // Counter-clockwise rings: consecutive neighbours of (1, 1) turn left around it.
    let c = l.positions[id(1, 1)];
    let ring = t.ring(id(1, 1));
    for j in 0..ring.len() {
        let (a, b) = (l.positions[ring[j] as usize] - c, l.positions[ring[(j + 1) % ring.len()] as usize] - c);
        assert!(a.cross(b).z > 0.0);
    }
}

#[test]
fn bad_topology_is_an_error() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, Vec3::ONE];
    let err = |t: &[[u32; 3]]| subdivide(&p, t, 1).unwrap_err();
    // Three triangles on the edge 0–1.
    assert_eq!(
        err(&[[0, 1, 2], [1, 0, 3], [0, 1, 5]]),
        SubdivisionError::Topology(TopologyError::NonManifoldEdge { a: 0, b: 1 })
    );
    // Both triangles run 0 → 1.
    assert_eq!(
        err(&[[0, 1, 2], [0, 1, 3]]),
        SubdivisionError::Topology(TopologyError::InconsistentWinding { a: 0, b: 1 })
    );
    // Two fans meeting at vertex 0 (a bow tie).
    assert_eq!(
        err(&[[0, 1, 2], [0, 4, 5]]),
        SubdivisionError::Topology(TopologyError::NonManifoldVertex { vertex: 0 })
    );
    assert_eq!(err(&[[0, 1, 1]]), SubdivisionError::Topology(TopologyError::DegenerateTriangle { face: 0, vertex: 1 }));
    assert_eq!(err(&[[0, 1, 9]]), SubdivisionError::IndexOutOfRange { index: 9, vertices: 7 });
    // 8·4^12 = 2^27 triangles, above the limit; and levels whose 4^levels overflows.
    let oct = octahedron();
    assert!(matches!(subdivide(&oct.positions, &oct.triangles, 12), Err(SubdivisionError::TooLarge { .. })));
    assert!(matches!(subdivide(&p, &[[0, 1, 2]], 40), Err(SubdivisionError::TooLarge { .. })));
    assert_eq!(subdivide(&p, &[], u32::MAX).unwrap().len(), 0);
    // Unused vertices are carried along.
    let m = subdivide(&p, &[[0, 1, 2]], 0).unwrap();
    assert_eq!((m.len(), m.positions.len()), (1, 7));
}

#[test]
fn two_closed_fans_at_one_vertex_are_non_manifold() {
    // Two octahedra sharing the vertex 0: its triangles form two closed fans.
    let mut oct = octahedron();
    let n = oct.positions.len() as u32;
    let shifted: Vec<Vec3> = oct.positions.iter().map(|p| *p + 2.0 * Vec3::X).collect();
    // The second octahedron's −x vertex (index 2) is the first one's +x vertex (index 0).
    let remap = |i: u32| if i == 2 { 0 } else { i + n };
    let mut t = oct.triangles.clone();
    t.extend(oct.triangles.iter().map(|tri| tri.map(remap)));
    oct.positions.extend(shifted);
    assert_eq!(
        Level::new(oct.positions, t).unwrap_err(),
        SubdivisionError::Topology(TopologyError::NonManifoldVertex { vertex: 0 })
    );
}
