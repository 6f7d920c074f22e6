//! Connectivity of a triangle mesh for subdivision: its edges (found by a hash of vertex pairs)
//! with the vertices opposite them, and each vertex's one-ring in counter-clockwise order.
//!
//! Only 2-manifold meshes with consistently wound triangles have Loop (1987) limit surfaces:
//! every edge borders one triangle (boundary) or two with opposite directions, and the triangles
//! around a vertex form one fan (closed for an interior vertex, open for a boundary vertex).

use std::collections::HashMap;

/// Marks "no vertex" in [`Edge::opposite`] (the far side of a boundary edge).
pub const NONE: u32 = u32::MAX;

/// Why a control mesh has no Loop subdivision surface.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TopologyError {
    /// A triangle names one vertex twice.
    #[error("triangle {face} uses vertex {vertex} twice")]
    DegenerateTriangle {
        /// Triangle index.
        face: usize,
        /// The repeated vertex.
        vertex: u32,
    },
    /// More than two triangles share an edge.
    #[error("the edge between vertices {a} and {b} is shared by more than two triangles (non-manifold)")]
    NonManifoldEdge {
        /// One end.
        a: u32,
        /// The other end.
        b: u32,
    },
    /// Two triangles traverse a shared edge in the same direction.
    #[error("the triangles sharing the edge from vertex {a} to {b} are wound inconsistently")]
    InconsistentWinding {
        /// Start of the edge as both triangles traverse it.
        a: u32,
        /// End of the edge.
        b: u32,
    },
    /// The triangles around a vertex form more than one fan.
    #[error("the triangles around vertex {vertex} do not form a single fan (non-manifold vertex)")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
    },
}

/// An undirected edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    /// Its ends, in the direction the first triangle that uses it traverses it.
    pub ends: [u32; 2],
    /// The third vertex of each triangle on it; `opposite[1]` is [`NONE`] on a boundary.
    pub opposite: [u32; 2],
}

impl Edge {
    /// True when only one triangle borders the edge.
    pub fn is_boundary(&self) -> bool {
        self.opposite[1] == NONE
    }
}

/// Edges and one-rings of a triangle mesh.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Every edge once.
    pub edges: Vec<Edge>,
    /// For triangle `[a, b, c]`, the indices into `edges` of its edges a→b, b→c, c→a.
    pub face_edges: Vec<[u32; 3]>,
    /// Vertex `v`'s ring is `ring[ring_start[v]..ring_start[v + 1]]`.
    ring_start: Vec<u32>,
    ring: Vec<u32>,
    boundary: Vec<bool>,
}

impl Topology {
    /// The connectivity of `triangles` over `vertex_count` vertices (every index must be below
    /// it), or why they are not a consistently wound 2-manifold.
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Result<Self, TopologyError> {
        let (edges, face_edges) = edges(triangles)?;
        let mut t = Self { edges, face_edges, ring_start: Vec::new(), ring: Vec::new(), boundary: Vec::new() };
        t.build_rings(vertex_count, triangles)?;
        Ok(t)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.boundary.len()
    }

    /// Vertex `v`'s neighbours counter-clockwise (seen from the side the triangles' winding faces).
    /// For a boundary vertex the first and last are its neighbours along the boundary and the
    /// ring has one more vertex than the triangles around `v`; otherwise it has as many.
    pub fn ring(&self, v: usize) -> &[u32] {
        &self.ring[self.ring_start[v] as usize..self.ring_start[v + 1] as usize]
    }

    /// True when `v` lies on the mesh boundary.
    pub fn is_boundary(&self, v: usize) -> bool {
        self.boundary[v]
    }

    /// True when every edge borders two triangles.
    pub fn is_closed(&self) -> bool {
        self.edges.iter().all(|e| !e.is_boundary())
    }

    /// The one-rings, from the (next, previous) corners of each triangle around each vertex:
    /// triangle (v, a, b) is followed counter-clockwise by the one that starts with (v, b).
    fn build_rings(&mut self, vertex_count: usize, triangles: &[[u32; 3]]) -> Result<(), TopologyError> {
        let mut start = vec![0u32; vertex_count + 1];
        for t in triangles {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut corners = vec![(0u32, 0u32); triangles.len() * 3];
        for t in triangles {
            for k in 0..3 {
                let v = t[k] as usize;
                corners[fill[v] as usize] = (t[(k + 1) % 3], t[(k + 2) % 3]);
                fill[v] += 1;
            }
        }
        let mut ring = Vec::with_capacity(corners.len() + vertex_count);
        let mut ring_start = Vec::with_capacity(vertex_count + 1);
        let mut boundary = vec![false; vertex_count];
        let mut prevs = Vec::new();
        for v in 0..vertex_count {
            ring_start.push(ring.len() as u32);
            let fan = &mut corners[start[v] as usize..start[v + 1] as usize];
            if fan.is_empty() {
                continue;
            }
            // Edge-manifold and consistently wound: each `next` corner is unique around `v`.
            fan.sort_unstable();
            prevs.clear();
            prevs.extend(fan.iter().map(|c| c.1));
            prevs.sort_unstable();
            let find = |a: u32| fan.binary_search_by_key(&a, |c| c.0).ok().map(|i| fan[i]);
            let mut starts = fan.iter().filter(|c| prevs.binary_search(&c.0).is_err());
            let first = match (starts.next(), starts.next()) {
                (None, _) => fan[0],
                (Some(&s), None) => {
                    boundary[v] = true;
                    s
                }
                (Some(_), Some(_)) => return Err(TopologyError::NonManifoldVertex { vertex: v as u32 }),
            };
            let mut corner = first;
            let mut walked = 0;
            loop {
                ring.push(corner.0);
                walked += 1;
                match find(corner.1) {
                    Some(c) if c != first => corner = c,
                    _ => break,
                }
                if walked > fan.len() {
                    break;
                }
            }
            if boundary[v] {
                ring.push(corner.1);
            }
            if walked != fan.len() {
                return Err(TopologyError::NonManifoldVertex { vertex: v as u32 });
            }
        }
        ring_start.push(ring.len() as u32);
        self.ring_start = ring_start;
        self.ring = ring;
        self.boundary = boundary;
        Ok(())
    }
}

/// The edges of `triangles`, each found once by a hash of its (smaller, larger) vertex pair.
fn edges(triangles: &[[u32; 3]]) -> Result<(Vec<Edge>, Vec<[u32; 3]>), TopologyError> {
    let mut index: HashMap<u64, u32> = HashMap::with_capacity(triangles.len() * 3 / 2 + 3);
    let mut edges: Vec<Edge> = Vec::with_capacity(triangles.len() * 3 / 2 + 3);
    let mut face_edges = Vec::with_capacity(triangles.len());
    for (f, t) in triangles.iter().enumerate() {
        let mut fe = [0u32; 3];
        for k in 0..3 {
            let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            if a == b {
                return Err(TopologyError::DegenerateTriangle { face: f, vertex: a });
            }
            let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
            let id = *index.entry(key).or_insert_with(|| {
                edges.push(Edge { ends: [a, b], opposite: [NONE, NONE] });
                (edges.len() - 1) as u32
            });
            let e = &mut edges[id as usize];
            if e.opposite[0] == NONE {
                e.opposite[0] = c;
            } else if e.opposite[1] != NONE {
                return Err(TopologyError::NonManifoldEdge { a: a.min(b), b: a.max(b) });
            } else if e.ends == [a, b] {
                return Err(TopologyError::InconsistentWinding { a, b });
            } else {
                e.opposite[1] = c;
            }
            fe[k] = id;
        }
        face_edges.push(fe);
    }
    Ok((edges, face_edges))
}
