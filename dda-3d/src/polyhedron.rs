//! Closed polyhedral surfaces: validation, topology, volume integrals,
//! generators and an overlap test.
//!
//! A polyhedron is a list of vertices and a list of faces, each face a loop of
//! vertex indices ordered counter-clockwise seen from outside (so the
//! right-hand normal points out). Faces may be concave polygons and the
//! polyhedron may be non-convex; faces must be planar and simple, and the
//! surface closed, manifold and consistently oriented.
//!
//! Volume integrals sum signed tetrahedra from a local origin over a
//! triangulation of every face (A9.2), so they are exact for any closed
//! polyhedron, convex or not, and keep their digits far from the global origin.

use std::collections::{BTreeMap, HashMap, HashSet, VecDeque};
use std::sync::Arc;

use dda_core::overlap::Found;
use dda_core::planar;
use nalgebra::{Matrix3, Point2, Point3, Rotation3, Vector3};

use crate::face::FaceFrame;

/// Angle tolerance of the convexity and entrance tests (Shi's h1 = 3°).
pub use dda_core::block_set::ANGLE_TOLERANCE;

/// A face vertex farther than this fraction of the block size from the face's
/// plane makes the face non-planar.
pub const PLANARITY_TOLERANCE: f64 = 1e-6;

/// A face area below this fraction of size² is zero.
const AREA_EPS: f64 = 1e-14;
/// A volume below this fraction of size³ is zero.
const VOLUME_EPS: f64 = 1e-12;
/// Vertices of an edge closer than this fraction of the size coincide.
const LENGTH_EPS: f64 = 1e-12;

/// Why a polyhedron was rejected, with what to do about it. Indices are
/// those of the input; [`PolyhedronError::place`] says which one is at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolyhedronError {
    #[error("a polyhedron needs at least 4 corners, this one has {0}; add corners")]
    TooFewVertices(usize),
    #[error("a closed polyhedron needs at least 4 faces, this one has {0}; add the missing faces")]
    TooFewFaces(usize),
    /// `value` is the first coordinate that is not a finite number.
    #[error("vertex {vertex} is {value}, not a finite number; write finite coordinates")]
    NotFinite { vertex: usize, value: f64 },
    #[error("face {face} has {count} corners; a face needs at least 3")]
    FaceTooSmall { face: usize, count: usize },
    #[error("face {face} refers to vertex {index}, but there are only {count} vertices (numbered 0 to {}); correct the index", count.saturating_sub(1))]
    IndexOutOfRange {
        face: usize,
        index: usize,
        count: usize,
    },
    #[error("face {face} visits vertex {vertex} twice; list each corner once")]
    RepeatedVertex { face: usize, vertex: usize },
    #[error("faces {first} and {second} have the same corners; remove one of them")]
    DuplicateFace { first: usize, second: usize },
    #[error("face {face}: the surface is open: its edge {a}-{b} belongs to no other face; add the missing faces so every edge is shared by exactly two")]
    OpenEdge { face: usize, a: usize, b: usize },
    #[error("the surface is not manifold: edge {a}-{b} belongs to {count} faces, not 2; make blocks that touch along an edge separate blocks")]
    NonManifoldEdge { a: usize, b: usize, count: usize },
    #[error("face {face} is oriented against its neighbours: list its corners counter-clockwise seen from outside (reverse their order)")]
    InconsistentOrientation { face: usize },
    #[error("face {face}: the surface is in several pieces (this face is not connected to face 0); give each piece as a block of its own")]
    Disconnected { face: usize },
    #[error("vertex {vertex} is used by no face; remove it or add it to its faces")]
    UnusedVertex { vertex: usize },
    #[error("vertex {vertex}: the surface is not manifold there (its faces do not form one fan); make blocks that touch at a corner separate blocks")]
    NonManifoldVertex { vertex: usize },
    #[error(
        "face {face} has zero area against the block's size (its corners lie on one line, or the block is a needle); remove it or correct its corners, or split a long block"
    )]
    DegenerateFace { face: usize },
    #[error("face {face}: vertices {a} and {b} coincide; merge them into one")]
    CoincidentVertices { face: usize, a: usize, b: usize },
    #[error("face {face} is not planar: vertex {vertex} is {distance:.3e} off its plane; move the corner onto the plane or split the face into triangles")]
    NonPlanarFace {
        face: usize,
        vertex: usize,
        distance: f64,
    },
    #[error("face {face} is not a simple polygon (two of its edges cross); reorder its corners around the face")]
    SelfIntersectingFace { face: usize },
    /// `volume` (m³) at most `VOLUME_EPS` times the cube of `size`, the
    /// diagonal of the corners' bounds (m): flat, or a needle.
    #[error("the polyhedron has zero volume against its size ({volume:.3e} m³, at most 1e-12 of the cube of its size, {size:.3e} m corner to corner): its corners lie in one plane, or it is a needle; give corners that enclose a volume, or split a long block")]
    ZeroVolume { volume: f64, size: f64 },
    /// Refused by [`validate_outward`] only.
    #[error("the faces are listed clockwise seen from outside (the surface faces inward); reverse the order of every face's corners")]
    InsideOut,
}

/// The part of a polyhedron's input an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The vertex list as a whole.
    Vertices,
    /// The face list as a whole.
    Faces,
    Vertex(usize),
    Face(usize),
    /// The whole block.
    Block,
}

impl PolyhedronError {
    /// Which part of the input is at fault, so a caller can point at it.
    pub fn place(&self) -> Fault {
        use PolyhedronError as E;
        match *self {
            E::TooFewVertices(_) => Fault::Vertices,
            E::TooFewFaces(_) | E::NonManifoldEdge { .. } | E::InsideOut => Fault::Faces,
            E::NotFinite { vertex, .. }
            | E::UnusedVertex { vertex }
            | E::NonManifoldVertex { vertex } => Fault::Vertex(vertex),
            E::DuplicateFace { second: face, .. }
            | E::FaceTooSmall { face, .. }
            | E::IndexOutOfRange { face, .. }
            | E::RepeatedVertex { face, .. }
            | E::OpenEdge { face, .. }
            | E::InconsistentOrientation { face }
            | E::Disconnected { face }
            | E::DegenerateFace { face }
            | E::CoincidentVertices { face, .. }
            | E::NonPlanarFace { face, .. }
            | E::SelfIntersectingFace { face } => Fault::Face(face),
            E::ZeroVolume { .. } => Fault::Block,
        }
    }
}

/// An edge between two vertices and the two faces that share it: `faces[0]`
/// runs from `ends[0]` to `ends[1]`, `faces[1]` the other way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Edge {
    pub ends: [usize; 2],
    pub faces: [usize; 2],
}

/// Whether the solid angle at an edge is below, at or above 180°.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeKind {
    Convex,
    /// The two faces are coplanar within the angle tolerance.
    Flat,
    Reflex,
}

/// Volume, centroid and central second moments J_ab = ∫ a b dV (a, b ∈ {X,
/// Y, Z} measured from the centroid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentralMoments {
    pub volume: f64,
    pub centroid: Point3<f64>,
    pub second: Matrix3<f64>,
}

/// What never changes when a block moves: faces and their adjacency.
/// Blocks of one topology may share it ([`share_topologies`]).
#[derive(Debug, PartialEq, Eq, Hash)]
struct Topology {
    faces: Vec<Vec<usize>>,
    edges: Vec<Edge>,
    vertex_edges: Vec<Vec<usize>>,
    vertex_faces: Vec<Vec<usize>>,
    /// Edge id of each face side: side k runs from vertex k to vertex k + 1.
    face_edges: Vec<Vec<usize>>,
    /// Triangles of each face (vertex indices). Affine motions keep them valid.
    triangles: Vec<Vec<[usize; 3]>>,
    /// Whether each face is convex (counter-clockwise seen from outside, no
    /// reflex corner): clipped against whole. Affine motions keep it.
    convex_faces: Vec<bool>,
}

/// A validated closed polyhedron with its derived geometry.
#[derive(Debug, Clone)]
pub struct Polyhedron {
    vertices: Vec<Point3<f64>>,
    topology: Arc<Topology>,
    normals: Vec<Vector3<f64>>,
    areas: Vec<f64>,
    /// Each face's frame and area centroid, made when the vertices move:
    /// the narrow phase reads them for every contact a face takes part in.
    frames: Vec<FaceFrame>,
    centroids: Vec<Point3<f64>>,
    /// Each edge's unit direction from its first end to its second, made
    /// when the vertices move: the narrow phase tests every plane a corner
    /// might enter against the directions of the corner's edges.
    directions: Vec<Vector3<f64>>,
    moments: CentralMoments,
    edge_kinds: Vec<EdgeKind>,
    convex_vertices: Vec<bool>,
    /// Axis-aligned bounds, made when the vertices move: each search reads
    /// them for both blocks of every near pair.
    bounds: (Point3<f64>, Point3<f64>),
}

impl Polyhedron {
    pub fn vertices(&self) -> &[Point3<f64>] {
        &self.vertices
    }

    /// Faces as counter-clockwise loops seen from outside.
    pub fn faces(&self) -> &[Vec<usize>] {
        &self.topology.faces
    }

    /// Edges, sorted by their end vertices; the index is the edge id.
    pub fn edges(&self) -> &[Edge] {
        &self.topology.edges
    }

    /// Edge ids at a vertex.
    pub fn vertex_edges(&self, v: usize) -> &[usize] {
        &self.topology.vertex_edges[v]
    }

    /// Face ids at a vertex.
    pub fn vertex_faces(&self, v: usize) -> &[usize] {
        &self.topology.vertex_faces[v]
    }

    /// Edge ids of a face's sides: side k runs from its vertex k to k + 1.
    pub fn face_edges(&self, f: usize) -> &[usize] {
        &self.topology.face_edges[f]
    }

    /// Triangles of a face, as vertex indices, counter-clockwise from outside.
    pub fn face_triangles(&self, f: usize) -> &[[usize; 3]] {
        &self.topology.triangles[f]
    }

    /// Whether face `f` is convex, so a polygon can be clipped against it
    /// whole rather than triangle by triangle.
    pub fn is_convex_face(&self, f: usize) -> bool {
        self.topology.convex_faces[f]
    }

    /// Outward unit normal of a face.
    pub fn normal(&self, f: usize) -> Vector3<f64> {
        self.normals[f]
    }

    pub fn face_area(&self, f: usize) -> f64 {
        self.areas[f]
    }

    /// The face's frame: origin at its first vertex, `u` along its first edge.
    pub fn face_frame(&self, f: usize) -> FaceFrame {
        self.frames[f]
    }

    /// The face's vertices in its own frame (counter-clockwise).
    pub fn face_polygon(&self, f: usize) -> Vec<Point2<f64>> {
        let frame = self.face_frame(f);
        self.topology.faces[f]
            .iter()
            .map(|&v| frame.to_plane(&self.vertices[v]))
            .collect()
    }

    /// Area centroid of a face.
    pub fn face_centroid(&self, f: usize) -> Point3<f64> {
        self.centroids[f]
    }

    pub fn moments(&self) -> &CentralMoments {
        &self.moments
    }

    pub fn volume(&self) -> f64 {
        self.moments.volume
    }

    pub fn centroid(&self) -> Point3<f64> {
        self.moments.centroid
    }

    pub fn edge_kind(&self, e: usize) -> EdgeKind {
        self.edge_kinds[e]
    }

    /// Whether the solid at a vertex is a convex cone: every edge at the
    /// vertex lies on the inner side of every face at it (within the angle
    /// tolerance). Flat vertices count as convex.
    pub fn is_convex_vertex(&self, v: usize) -> bool {
        self.convex_vertices[v]
    }

    /// Unit direction of edge `e` leaving vertex `from`.
    pub fn edge_direction(&self, e: usize, from: usize) -> Vector3<f64> {
        // Negated, the same to the last bit as normalised from the other end.
        if self.topology.edges[e].ends[0] == from {
            self.directions[e]
        } else {
            -self.directions[e]
        }
    }

    /// Unit directions perpendicular to edge `e`, in each of its two faces,
    /// pointing into the face: the edge's solid wedge lies between them.
    pub fn edge_wedge(&self, e: usize) -> [Vector3<f64>; 2] {
        let edge = self.topology.edges[e];
        let d = self.directions[e];
        // Face 0 runs along d, face 1 against it; the face lies to the left.
        [
            self.normals[edge.faces[0]].cross(&d),
            -self.normals[edge.faces[1]].cross(&d),
        ]
    }

    /// Whether this polyhedron and `other` read one shared topology
    /// ([`share_topologies`]).
    pub fn shares_topology(&self, other: &Polyhedron) -> bool {
        Arc::ptr_eq(&self.topology, &other.topology)
    }

    /// Axis-aligned bounds (min, max).
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        self.bounds
    }

    /// The same polyhedron with every vertex moved by `f` (an
    /// orientation-preserving affine motion keeps it valid).
    pub fn moved(&self, f: impl Fn(&Point3<f64>) -> Point3<f64>) -> Self {
        let vertices = self.vertices.iter().map(f).collect();
        Self::with_topology(vertices, self.topology.clone())
    }

    /// [`Polyhedron::moved`] in place: a block's commit moves every block
    /// at every step, and its derived lists keep their memory.
    pub fn move_by(&mut self, f: impl Fn(&Point3<f64>) -> Point3<f64>) {
        for v in &mut self.vertices {
            *v = f(v);
        }
        self.derive();
    }

    /// The same polyhedron with its vertices at these points (same count and
    /// order), its integrals derived as [`Polyhedron::moved`] derives them.
    pub fn with_vertices(&self, vertices: Vec<Point3<f64>>) -> Self {
        assert_eq!(vertices.len(), self.vertices.len(), "one point per vertex");
        Self::with_topology(vertices, self.topology.clone())
    }

    fn with_topology(vertices: Vec<Point3<f64>>, topology: Arc<Topology>) -> Self {
        // Every derived field is made by `derive`: these only hold places.
        let mut shape = Self {
            moments: CentralMoments {
                volume: 0.0,
                centroid: Point3::origin(),
                second: Matrix3::zeros(),
            },
            bounds: (Point3::origin(), Point3::origin()),
            vertices,
            topology,
            normals: Vec::new(),
            areas: Vec::new(),
            frames: Vec::new(),
            centroids: Vec::new(),
            directions: Vec::new(),
            edge_kinds: Vec::new(),
            convex_vertices: Vec::new(),
        };
        shape.derive();
        shape
    }

    /// Everything made from the vertices: faces' normals, areas, frames
    /// and centroids, the moments, edges' directions and kinds, which
    /// corners are convex, and the bounds.
    fn derive(&mut self) {
        let (vertices, topology) = (&self.vertices, &*self.topology);
        self.normals.clear();
        self.areas.clear();
        for f in &topology.faces {
            let n = newell(vertices, f);
            let a = n.norm();
            self.normals.push(n / a.max(f64::MIN_POSITIVE));
            self.areas.push(a / 2.0);
        }
        let normals = &self.normals;
        self.frames.clear();
        self.frames.extend(
            (topology.faces.iter().zip(normals))
                .map(|(face, n)| FaceFrame::new(vertices[face[0]], vertices[face[1]], *n)),
        );
        self.centroids.clear();
        self.centroids.extend(
            (topology.triangles.iter().zip(&topology.faces).zip(normals))
                .map(|((triangles, face), n)| face_centroid(vertices, face, triangles, n)),
        );
        self.moments = central_moments(vertices, &topology.faces);
        self.directions.clear();
        self.directions.extend(
            (topology.edges.iter())
                .map(|e| (vertices[e.ends[1]] - vertices[e.ends[0]]).normalize()),
        );
        let directions = &self.directions;
        self.edge_kinds.clear();
        self.edge_kinds
            .extend((topology.edges.iter().zip(directions)).map(|(e, &d)| {
                let (n0, n1) = (normals[e.faces[0]], normals[e.faces[1]]);
                let turn = n0.cross(&n1).dot(&d).atan2(n0.dot(&n1));
                if turn > ANGLE_TOLERANCE {
                    EdgeKind::Convex
                } else if turn < -ANGLE_TOLERANCE {
                    EdgeKind::Reflex
                } else {
                    EdgeKind::Flat
                }
            }));
        let sin_tol = ANGLE_TOLERANCE.sin();
        // Each edge's direction as made once above, not normalised again
        // for every face at the corner.
        let mut convex = std::mem::take(&mut self.convex_vertices);
        convex.clear();
        convex.extend((0..self.vertices.len()).map(|v| {
            let topology = &*self.topology;
            topology.vertex_faces[v].iter().all(|&f| {
                (topology.vertex_edges[v].iter())
                    .all(|&e| self.normals[f].dot(&self.edge_direction(e, v)) <= sin_tol)
            })
        }));
        self.convex_vertices = convex;
        self.bounds = bounds(&self.vertices);
    }

    /// Distance from `p` to the surface, inside or out.
    pub fn distance(&self, p: &Point3<f64>) -> f64 {
        let mut nearest = f64::INFINITY;
        for tris in &self.topology.triangles {
            for t in tris {
                let [a, b, c] = t.map(|i| self.vertices[i]);
                nearest = nearest.min((closest_on_triangle(p, &a, &b, &c) - p).norm());
            }
        }
        nearest
    }

    /// How far `p` lies outside: 0 inside, or within a millionth of the
    /// polyhedron's size of its surface (a point written on a corner keeps
    /// its round-off).
    pub fn distance_outside(&self, p: &Point3<f64>) -> f64 {
        let (lo, hi) = self.bounds();
        let distance = self.distance(p);
        if self.contains(p, 0.0) || distance <= 1e-6 * (hi - lo).norm() {
            0.0
        } else {
            distance
        }
    }

    /// Whether `p` lies inside, farther than `tol` from the surface.
    pub fn contains(&self, p: &Point3<f64>, tol: f64) -> bool {
        let mut solid_angle = 0.0;
        let mut nearest = f64::INFINITY;
        for tris in &self.topology.triangles {
            for t in tris {
                let [a, b, c] = t.map(|i| self.vertices[i]);
                nearest = nearest.min((closest_on_triangle(p, &a, &b, &c) - p).norm());
                solid_angle += triangle_solid_angle(&(a - p), &(b - p), &(c - p));
            }
        }
        // The solid angle is 4π inside and 0 outside.
        nearest > tol && solid_angle > 2.0 * std::f64::consts::PI
    }
}

/// Newell's normal of a face: twice its area times its unit normal.
fn newell(vertices: &[Point3<f64>], face: &[usize]) -> Vector3<f64> {
    let o = vertices[face[0]];
    let mut n = Vector3::zeros();
    for k in 1..face.len().saturating_sub(1) {
        n += (vertices[face[k]] - o).cross(&(vertices[face[k + 1]] - o));
    }
    n
}

fn bounds(vertices: &[Point3<f64>]) -> (Point3<f64>, Point3<f64>) {
    let mut lo = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut hi = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for v in vertices {
        lo = lo.inf(v);
        hi = hi.sup(v);
    }
    (lo, hi)
}

/// Volume, centroid and central second moments of a closed surface, by signed
/// tetrahedra from the mean vertex over fan triangles of each face. Signed: an
/// inward-oriented surface gives a negative volume. Exact for planar faces,
/// concave or not.
pub fn central_moments(vertices: &[Point3<f64>], faces: &[Vec<usize>]) -> CentralMoments {
    let origin = if vertices.is_empty() {
        Point3::origin()
    } else {
        Point3::from(
            vertices.iter().fold(Vector3::zeros(), |s, v| s + v.coords) / vertices.len() as f64,
        )
    };
    let mut volume = 0.0;
    let mut first = Vector3::zeros();
    let mut second = Matrix3::zeros();
    for face in faces {
        let a = vertices[face[0]] - origin;
        for k in 1..face.len().saturating_sub(1) {
            let b = vertices[face[k]] - origin;
            let c = vertices[face[k + 1]] - origin;
            let v = a.dot(&b.cross(&c)) / 6.0;
            let s = a + b + c;
            volume += v;
            first += s * (v / 4.0);
            // ∫x_i x_j over the tetrahedron (0, a, b, c).
            second +=
                (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose())
                    * (v / 20.0);
        }
    }
    let c = if volume != 0.0 {
        first / volume
    } else {
        Vector3::zeros()
    };
    CentralMoments {
        volume,
        centroid: origin + c,
        second: second - c * c.transpose() * volume,
    }
}

/// [`validate`], refusing a surface listed inside out (which `validate`
/// flips), so a face order mistake in written input is caught rather than
/// silently fixed.
pub fn validate_outward(
    vertices: &[Point3<f64>],
    faces: &[Vec<usize>],
) -> Result<Polyhedron, PolyhedronError> {
    let shape = validate(vertices, faces)?;
    if central_moments(vertices, faces).volume < 0.0 {
        return Err(PolyhedronError::InsideOut);
    }
    Ok(shape)
}

/// Checks a closed surface and builds the polyhedron.
///
/// Rejects, in this order: fewer than 4 vertices or faces, NaN/inf, faces
/// with fewer than 3 vertices, indices out of range or a vertex repeated in a
/// face, duplicate faces, open or non-manifold edges (every edge must belong to
/// exactly two faces), inconsistent orientation (an edge used twice in the
/// same direction: the error names the face of the smaller group), several
/// pieces, unused vertices, non-manifold vertices, zero-area faces,
/// zero-length edges (coincident vertices), non-planar (off
/// the plane by more than 1e-6 of the block size) or self-intersecting faces,
/// and zero volume. A surface oriented consistently inward is accepted and
/// flipped. Self-intersection of the surface as a whole is not checked.
pub fn validate(
    vertices: &[Point3<f64>],
    faces: &[Vec<usize>],
) -> Result<Polyhedron, PolyhedronError> {
    let n = vertices.len();
    if n < 4 {
        return Err(PolyhedronError::TooFewVertices(n));
    }
    for (vertex, v) in vertices.iter().enumerate() {
        if let Some(&value) = v.coords.iter().find(|x| !x.is_finite()) {
            return Err(PolyhedronError::NotFinite { vertex, value });
        }
    }
    if faces.len() < 4 {
        return Err(PolyhedronError::TooFewFaces(faces.len()));
    }
    for (face, f) in faces.iter().enumerate() {
        if f.len() < 3 {
            return Err(PolyhedronError::FaceTooSmall {
                face,
                count: f.len(),
            });
        }
        for (k, &index) in f.iter().enumerate() {
            if index >= n {
                return Err(PolyhedronError::IndexOutOfRange {
                    face,
                    index,
                    count: n,
                });
            }
            if f[..k].contains(&index) {
                return Err(PolyhedronError::RepeatedVertex {
                    face,
                    vertex: index,
                });
            }
        }
    }
    let mut seen: HashMap<Vec<usize>, usize> = HashMap::new();
    for (face, f) in faces.iter().enumerate() {
        let mut key = f.clone();
        key.sort_unstable();
        if let Some(&first) = seen.get(&key) {
            return Err(PolyhedronError::DuplicateFace {
                first,
                second: face,
            });
        }
        seen.insert(key, face);
    }

    // Each undirected edge with the faces using it and their directions.
    let mut uses: BTreeMap<(usize, usize), Vec<(usize, bool)>> = BTreeMap::new();
    for (face, f) in faces.iter().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            uses.entry((a.min(b), a.max(b)))
                .or_default()
                .push((face, a < b));
        }
    }
    for (&(a, b), u) in &uses {
        match u.len() {
            2 => {}
            1 => {
                let face = u[0].0;
                let (a, b) = if u[0].1 { (a, b) } else { (b, a) };
                return Err(PolyhedronError::OpenEdge { face, a, b });
            }
            count => return Err(PolyhedronError::NonManifoldEdge { a, b, count }),
        }
    }
    check_orientation(faces, &uses)?;
    let mut used = vec![false; n];
    for f in faces {
        for &v in f {
            used[v] = true;
        }
    }
    if let Some(vertex) = used.iter().position(|u| !u) {
        return Err(PolyhedronError::UnusedVertex { vertex });
    }
    check_vertex_fans(n, faces)?;

    let (lo, hi) = bounds(vertices);
    let size = (hi - lo).norm();
    for (face, f) in faces.iter().enumerate() {
        let nn = newell(vertices, f);
        if nn.norm() / 2.0 <= AREA_EPS * size * size {
            return Err(PolyhedronError::DegenerateFace { face });
        }
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            if (vertices[b] - vertices[a]).norm() <= LENGTH_EPS * size {
                return Err(PolyhedronError::CoincidentVertices { face, a, b });
            }
        }
        let normal = nn.normalize();
        let centre = f
            .iter()
            .fold(Vector3::zeros(), |s, &v| s + vertices[v].coords)
            / f.len() as f64;
        // Name the vertex farthest from the plane through the face's centre.
        let (vertex, distance) = f
            .iter()
            .map(|&v| (v, normal.dot(&(vertices[v].coords - centre)).abs()))
            .fold((f[0], 0.0), |best, x| if x.1 > best.1 { x } else { best });
        if distance > PLANARITY_TOLERANCE * size {
            return Err(PolyhedronError::NonPlanarFace {
                face,
                vertex,
                distance,
            });
        }
        let frame = FaceFrame::new(vertices[f[0]], vertices[f[1]], normal);
        let poly: Vec<Point2<f64>> = f.iter().map(|&v| frame.to_plane(&vertices[v])).collect();
        if f.len() > 3 && planar::self_intersects(&poly) {
            return Err(PolyhedronError::SelfIntersectingFace { face });
        }
    }
    let volume = central_moments(vertices, faces).volume;
    if volume.abs() <= VOLUME_EPS * size * size * size {
        return Err(PolyhedronError::ZeroVolume { volume, size });
    }
    let faces: Vec<Vec<usize>> = if volume < 0.0 {
        faces
            .iter()
            .map(|f| f.iter().rev().copied().collect())
            .collect()
    } else {
        faces.to_vec()
    };
    let topology = build_topology(vertices, faces);
    Ok(Polyhedron::with_topology(
        vertices.to_vec(),
        Arc::new(topology),
    ))
}

/// Orients every face like face 0 across shared edges; any disagreement is
/// an error naming a face of the smaller group. Also checks connectivity.
fn check_orientation(
    faces: &[Vec<usize>],
    uses: &BTreeMap<(usize, usize), Vec<(usize, bool)>>,
) -> Result<(), PolyhedronError> {
    let mut neighbours: Vec<Vec<(usize, bool)>> = vec![Vec::new(); faces.len()];
    for u in uses.values() {
        let ((f, df), (g, dg)) = (u[0], u[1]);
        // Consistent neighbours use the shared edge in opposite directions.
        let same = df != dg;
        neighbours[f].push((g, same));
        neighbours[g].push((f, same));
    }
    let mut sign: Vec<Option<bool>> = vec![None; faces.len()];
    sign[0] = Some(true);
    let mut queue = VecDeque::from([0]);
    let mut conflict = None;
    while let Some(f) = queue.pop_front() {
        let s = sign[f].unwrap_or(true);
        for &(g, same) in &neighbours[f] {
            let want = if same { s } else { !s };
            match sign[g] {
                None => {
                    sign[g] = Some(want);
                    queue.push_back(g);
                }
                Some(have) if have != want => conflict = conflict.or(Some(g)),
                _ => {}
            }
        }
    }
    if let Some(face) = sign.iter().position(|s| s.is_none()) {
        return Err(PolyhedronError::Disconnected { face });
    }
    let flipped: Vec<usize> = (0..faces.len())
        .filter(|&f| sign[f] == Some(false))
        .collect();
    if !flipped.is_empty() {
        let face = if 2 * flipped.len() <= faces.len() {
            flipped[0]
        } else {
            (0..faces.len())
                .find(|f| sign[*f] == Some(true))
                .unwrap_or(0)
        };
        return Err(PolyhedronError::InconsistentOrientation { face });
    }
    if let Some(face) = conflict {
        return Err(PolyhedronError::InconsistentOrientation { face });
    }
    Ok(())
}

/// Every vertex's faces must form a single fan around it.
fn check_vertex_fans(n: usize, faces: &[Vec<usize>]) -> Result<(), PolyhedronError> {
    // Directed edge (a, b) -> the face that runs along it.
    let mut along: HashMap<(usize, usize), usize> = HashMap::new();
    let mut at_vertex: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..f.len() {
            along.insert((f[k], f[(k + 1) % f.len()]), fi);
            at_vertex[f[k]].push(fi);
        }
    }
    for (vertex, incident) in at_vertex.iter().enumerate() {
        let Some(&start) = incident.first() else {
            continue;
        };
        // Walk around the vertex: leave each face by its edge into the vertex.
        let mut face = start;
        let mut visited = 0;
        loop {
            let f = &faces[face];
            let k = f.iter().position(|&v| v == vertex).unwrap_or(0);
            let prev = f[(k + f.len() - 1) % f.len()];
            // The neighbour runs (vertex, prev).
            match along.get(&(vertex, prev)) {
                Some(&g) => face = g,
                None => break,
            }
            visited += 1;
            if face == start || visited > incident.len() {
                break;
            }
        }
        if visited != incident.len() {
            return Err(PolyhedronError::NonManifoldVertex { vertex });
        }
    }
    Ok(())
}

/// Makes polyhedra of one topology (the same faces, edges and face
/// triangles) read one copy of it. The narrow phase and the commit read
/// a block's adjacency lists for every feature; a wall's bricks, each with
/// lists of its own, scattered some 35 small allocations a block over the
/// heap, where one shared set stays in cache (the 10,051-block 3D wall:
/// narrow phase about 11 % shorter, commit 16 %). Nothing read changes.
pub fn share_topologies(shapes: &mut [Polyhedron]) {
    let mut seen: HashSet<Arc<Topology>> = HashSet::new();
    for shape in shapes {
        match seen.get(&shape.topology) {
            Some(shared) => shape.topology = shared.clone(),
            None => {
                seen.insert(shape.topology.clone());
            }
        }
    }
}

fn build_topology(vertices: &[Point3<f64>], faces: Vec<Vec<usize>>) -> Topology {
    let mut edge_faces: BTreeMap<(usize, usize), [usize; 2]> = BTreeMap::new();
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            let slot = edge_faces.entry((a.min(b), a.max(b))).or_insert([0, 0]);
            slot[usize::from(a > b)] = fi;
        }
    }
    let edges: Vec<Edge> = edge_faces
        .into_iter()
        .map(|((a, b), faces)| Edge {
            ends: [a, b],
            faces,
        })
        .collect();
    let id: HashMap<(usize, usize), usize> = edges
        .iter()
        .enumerate()
        .map(|(e, edge)| ((edge.ends[0], edge.ends[1]), e))
        .collect();
    let face_edges = faces
        .iter()
        .map(|f| {
            (0..f.len())
                .map(|k| {
                    let (a, b) = (f[k], f[(k + 1) % f.len()]);
                    id[&(a.min(b), a.max(b))]
                })
                .collect()
        })
        .collect();
    let mut vertex_edges = vec![Vec::new(); vertices.len()];
    for (e, edge) in edges.iter().enumerate() {
        vertex_edges[edge.ends[0]].push(e);
        vertex_edges[edge.ends[1]].push(e);
    }
    let mut vertex_faces = vec![Vec::new(); vertices.len()];
    for (fi, f) in faces.iter().enumerate() {
        for &v in f {
            vertex_faces[v].push(fi);
        }
    }
    let (triangles, convex_faces) = faces
        .iter()
        .map(|f| {
            let normal = newell(vertices, f).normalize();
            let frame = FaceFrame::new(vertices[f[0]], vertices[f[1]], normal);
            let poly: Vec<Point2<f64>> = f.iter().map(|&v| frame.to_plane(&vertices[v])).collect();
            let convex = planar::is_convex(&poly);
            let triangles = planar::triangulate(&poly)
                .into_iter()
                .map(|t| t.map(|k| f[k]))
                .collect();
            (triangles, convex)
        })
        .unzip();
    Topology {
        faces,
        edges,
        vertex_edges,
        vertex_faces,
        face_edges,
        triangles,
        convex_faces,
    }
}

/// A box with the given centre, edge lengths (along its own axes) and
/// rotation. Vertices 0-3 are the bottom (local −z) corners counter-clockwise
/// seen from above, 4-7 the top ones above them.
pub fn cuboid(
    center: Point3<f64>,
    size: Vector3<f64>,
    rotation: Rotation3<f64>,
) -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
    let h = size / 2.0;
    let corners = [
        (-1.0, -1.0, -1.0),
        (1.0, -1.0, -1.0),
        (1.0, 1.0, -1.0),
        (-1.0, 1.0, -1.0),
        (-1.0, -1.0, 1.0),
        (1.0, -1.0, 1.0),
        (1.0, 1.0, 1.0),
        (-1.0, 1.0, 1.0),
    ];
    let vertices = corners
        .iter()
        .map(|&(x, y, z)| center + rotation * Vector3::new(x * h.x, y * h.y, z * h.z))
        .collect();
    let faces = vec![
        vec![0, 3, 2, 1], // bottom
        vec![4, 5, 6, 7], // top
        vec![0, 1, 5, 4], // −y
        vec![1, 2, 6, 5], // +x
        vec![2, 3, 7, 6], // +y
        vec![3, 0, 4, 7], // −x
    ];
    (vertices, faces)
}

/// A vertical prism over a counter-clockwise outline in the xy plane (convex
/// or concave), from `z0` to `z1`. Vertices `0..n` are the outline at `z0`,
/// `n..2n` the outline at `z1`; face 0 is the bottom, face 1 the top, face
/// 2 + k the side over outline edge k.
pub fn prism(outline: &[Point2<f64>], z0: f64, z1: f64) -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
    let n = outline.len();
    let mut vertices: Vec<Point3<f64>> =
        outline.iter().map(|p| Point3::new(p.x, p.y, z0)).collect();
    vertices.extend(outline.iter().map(|p| Point3::new(p.x, p.y, z1)));
    let mut faces = vec![(0..n).rev().collect(), (n..2 * n).collect()];
    for k in 0..n {
        let next = (k + 1) % n;
        faces.push(vec![k, next, n + next, n + k]);
    }
    (vertices, faces)
}

/// The first pair of polyhedra (i, j), j < i, in the order of i then j,
/// that overlap by more than 1e-6 of the set's size, found in about N log N
/// ([`dda_core::overlap`]; a face of each block is a plane that may split
/// the set); and how many pairs were tested.
pub fn first_overlap(shapes: &[Polyhedron]) -> Found {
    let corners = |s: &Polyhedron| s.vertices().iter().map(|p| p.coords.into()).collect();
    let sides = |s: &Polyhedron| {
        (0..s.faces().len())
            .map(|f| {
                let point = s.vertices()[s.faces()[f][0]];
                (s.normal(f).into(), point.coords.into())
            })
            .collect()
    };
    dda_core::overlap::first_overlap(shapes, corners, sides, overlap)
}

/// Whether two polyhedra overlap by more than `tol` ("blocks overlapping at
/// the start"). Touching faces, edges or vertices are not an overlap.
///
/// Tested, both ways: a vertex, edge midpoint or face-triangle centroid of
/// one lying inside the other deeper than `tol`; an edge of one crossing the
/// interior of a face of the other with both ends farther than `tol` from its
/// plane and the crossing farther than `tol` from the face's boundary; and a
/// point just inside each face (by the larger of 2·tol and 1e-9 of the size)
/// lying inside both deeper than `tol`, which catches coincident blocks.
pub fn overlap(a: &Polyhedron, b: &Polyhedron, tol: f64) -> bool {
    let (alo, ahi) = a.bounds();
    let (blo, bhi) = b.bounds();
    let apart = (0..3).any(|k| alo[k] > bhi[k] + tol || blo[k] > ahi[k] + tol);
    if apart {
        return false;
    }
    // A face of a convex block with the other wholly beyond it: apart. Cheap,
    // and it settles most pairs that touch (neighbouring drums or staves).
    if separated_by_a_face(a, b, tol) || separated_by_a_face(b, a, tol) {
        return false;
    }
    one_way_overlap(a, b, tol) || one_way_overlap(b, a, tol)
}

/// Whether `a` is convex and every corner of `b` lies within `tol` of the
/// far side of one of its faces' planes (so the two overlap by no more than
/// `tol`).
fn separated_by_a_face(a: &Polyhedron, b: &Polyhedron, tol: f64) -> bool {
    a.edge_kinds.iter().all(|k| *k != EdgeKind::Reflex)
        && (0..a.faces().len()).any(|f| {
            let (normal, point) = (a.normals[f], a.vertices[a.faces()[f][0]]);
            b.vertices.iter().all(|v| normal.dot(&(v - point)) >= -tol)
        })
}

fn one_way_overlap(a: &Polyhedron, b: &Polyhedron, tol: f64) -> bool {
    if a.vertices.iter().any(|v| b.contains(v, tol)) {
        return true;
    }
    for edge in a.edges() {
        let [p, q] = edge.ends.map(|i| a.vertices[i]);
        if b.contains(&Point3::from((p.coords + q.coords) / 2.0), tol) {
            return true;
        }
        for f in 0..b.faces().len() {
            let frame = b.face_frame(f);
            let (hp, hq) = (frame.height(&p), frame.height(&q));
            if !((hp > tol && hq < -tol) || (hp < -tol && hq > tol)) {
                continue;
            }
            let x = p + (q - p) * (hp / (hp - hq));
            let poly = b.face_polygon(f);
            let x2 = frame.to_plane(&x);
            let inside = planar::contains(&poly, &x2);
            let clear = (0..poly.len())
                .all(|k| planar::point_segment(&x2, &poly[k], &poly[(k + 1) % poly.len()]).0 > tol);
            if inside && clear {
                return true;
            }
        }
    }
    let (lo, hi) = a.bounds();
    let step = (2.0 * tol).max(1e-9 * (hi - lo).norm());
    for f in 0..a.faces().len() {
        for t in a.face_triangles(f) {
            let [p, q, r] = t.map(|i| a.vertices[i]);
            let c = Point3::from((p.coords + q.coords + r.coords) / 3.0);
            if b.contains(&c, tol) {
                return true;
            }
            let inner = c - a.normal(f) * step;
            if a.contains(&inner, 0.0) && b.contains(&inner, tol) {
                return true;
            }
        }
    }
    false
}

/// Solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom
/// and Strackee), signed by orientation.
fn triangle_solid_angle(a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> f64 {
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let numerator = a.dot(&b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// The point of triangle (a, b, c) nearest to p (Ericson, Real-Time Collision
/// Detection, 5.1.5).
pub fn closest_on_triangle(
    p: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Point3<f64> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Area centroid of a face with these triangles and unit normal.
fn face_centroid(
    vertices: &[Point3<f64>],
    face: &[usize],
    triangles: &[[usize; 3]],
    normal: &Vector3<f64>,
) -> Point3<f64> {
    let mut sum = Vector3::zeros();
    let mut total = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i]);
        let w = (b - a).cross(&(c - a)).dot(normal) / 2.0;
        sum += (a.coords + b.coords + c.coords) * (w / 3.0);
        total += w;
    }
    if total.abs() > 0.0 {
        Point3::from(sum / total)
    } else {
        vertices[face[0]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept face frames, centroids and bounds follow the vertices
    /// through a move and a restore: each frame starts at its face's first vertex
    /// with `u` along the first side and the face's normal, and a
    /// rectangle's centroid is the mean of its corners.
    #[test]
    fn face_frames_and_centroids_follow_the_vertices() {
        let (points, faces) = cuboid(
            Point3::new(1.0, -2.0, 0.5),
            Vector3::new(2.0, 1.0, 0.5),
            Rotation3::from_euler_angles(0.3, -0.2, 0.7),
        );
        let check = |s: &Polyhedron| {
            for (f, face) in s.faces().iter().enumerate() {
                let corners = face.iter().map(|&k| s.vertices()[k].coords);
                let mean = corners.sum::<Vector3<f64>>() / face.len() as f64;
                assert!(
                    (s.face_centroid(f).coords - mean).norm() < 1e-12,
                    "face {f}"
                );
                let frame = s.face_frame(f);
                let side = s.vertices()[face[1]] - s.vertices()[face[0]];
                assert_eq!(frame.origin, s.vertices()[face[0]]);
                assert!((frame.u - side.normalize()).norm() < 1e-12, "face {f}");
                assert!((frame.normal - s.normal(f)).norm() < 1e-15, "face {f}");
            }
            assert_eq!(s.bounds(), bounds(s.vertices()));
        };
        let shape = validate(&points, &faces).unwrap();
        check(&shape);
        let turn = Rotation3::from_euler_angles(-0.5, 0.1, 1.2);
        let moved = shape.moved(|p| turn * p + Vector3::new(3.0, 0.0, -1.0));
        check(&moved);
        assert!((moved.face_centroid(0) - shape.face_centroid(0)).norm() > 0.1);
        let back = moved.with_vertices(points.clone());
        check(&back);
        assert_eq!(back.face_centroid(0), shape.face_centroid(0));
    }

    #[test]
    fn a_shape_moved_in_place_is_the_moved_shape_to_the_last_bit() {
        // The L prism has a reflex edge and two concave corners, so every
        // derived list has both kinds to get right.
        let (points, faces) = l_prism();
        let turn = Rotation3::from_euler_angles(0.3, -0.7, 2.1);
        let motion = |p: &Point3<f64>| turn * p + Vector3::new(-2.0, 5.0, 0.5);
        let shape = validate(&points, &faces).unwrap();
        let moved = shape.moved(motion);
        let mut in_place = shape.clone();
        in_place.move_by(motion);
        assert_eq!(in_place.vertices(), moved.vertices());
        for f in 0..faces.len() {
            assert_eq!(in_place.normal(f), moved.normal(f));
            assert_eq!(in_place.face_area(f), moved.face_area(f));
            assert_eq!(in_place.face_frame(f), moved.face_frame(f));
            assert_eq!(in_place.face_centroid(f), moved.face_centroid(f));
        }
        for (e, edge) in moved.edges().iter().enumerate() {
            assert_eq!(in_place.edge_kind(e), moved.edge_kind(e));
            for end in edge.ends {
                assert_eq!(
                    in_place.edge_direction(e, end),
                    moved.edge_direction(e, end)
                );
            }
        }
        for v in 0..points.len() {
            assert_eq!(in_place.is_convex_vertex(v), moved.is_convex_vertex(v));
        }
        assert_eq!(in_place.moments(), moved.moments());
        assert_eq!(in_place.bounds(), moved.bounds());
        let concave: Vec<usize> = (0..points.len())
            .filter(|&v| !in_place.is_convex_vertex(v))
            .collect();
        assert_eq!(concave, vec![3, 9]);
        // The inner corner pulled out past the L's arms: every corner and
        // edge turns convex, and the lists made in place must say so.
        let pull = |p: &Point3<f64>| {
            let corner = (p.x - 1.0).abs() < 1e-12 && (p.y - 1.0).abs() < 1e-12;
            if corner {
                Point3::new(1.8, 1.8, p.z)
            } else {
                *p
            }
        };
        let mut pulled = shape.clone();
        pulled.move_by(pull);
        assert!((0..points.len()).all(|v| pulled.is_convex_vertex(v)));
        assert!((0..pulled.edges().len()).all(|e| pulled.edge_kind(e) == EdgeKind::Convex));
        assert_eq!(pulled.volume(), shape.moved(pull).volume());
    }

    /// Blocks of one topology read one copy of it after sharing, a block
    /// of another keeps its own, and nothing any of them reads changes.
    #[test]
    fn shapes_of_one_topology_share_it_and_read_the_same() {
        let cuboid_at = |x: f64, turn: f64| {
            let (v, f) = cuboid(
                Point3::new(x, 0.5, -1.0),
                Vector3::new(0.5, 0.25, 0.25),
                Rotation3::from_euler_angles(turn, 0.2, -0.1),
            );
            validate(&v, &f).unwrap()
        };
        let (v, f) = l_prism();
        let mut shapes = vec![cuboid_at(0.0, 0.0), validate(&v, &f).unwrap()];
        shapes.extend([cuboid_at(2.0, 0.7), cuboid_at(-3.0, 1.3)]);
        let before = shapes.clone();
        assert!(!shapes[0].shares_topology(&shapes[2]));
        share_topologies(&mut shapes);
        assert!(shapes[0].shares_topology(&shapes[2]));
        assert!(shapes[0].shares_topology(&shapes[3]));
        assert!(!shapes[0].shares_topology(&shapes[1]));
        for (s, b) in shapes.iter().zip(&before) {
            assert_eq!(s.faces(), b.faces());
            assert_eq!(s.edges(), b.edges());
            for f in 0..s.faces().len() {
                assert_eq!(s.face_triangles(f), b.face_triangles(f));
                assert_eq!(s.face_edges(f), b.face_edges(f));
            }
            for v in 0..s.vertices().len() {
                assert_eq!(s.vertex_edges(v), b.vertex_edges(v));
                assert_eq!(s.vertex_faces(v), b.vertex_faces(v));
            }
        }
    }

    #[test]
    fn an_inside_out_surface_is_refused_by_validate_outward_only() {
        let (points, faces) = cuboid(
            Point3::origin(),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        assert!(validate_outward(&points, &faces).is_ok());
        let inward: Vec<Vec<usize>> = faces
            .iter()
            .map(|f| f.iter().rev().copied().collect())
            .collect();
        assert!(validate(&points, &inward).is_ok());
        let e = validate_outward(&points, &inward).unwrap_err();
        assert_eq!(e, PolyhedronError::InsideOut);
        assert_eq!(e.place(), Fault::Faces);
    }

    #[test]
    fn distance_outside_is_zero_inside_and_on_the_surface() {
        let (points, faces) = cuboid(
            Point3::origin(),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let cube = validate(&points, &faces).unwrap();
        assert_eq!(cube.distance_outside(&Point3::origin()), 0.0);
        assert_eq!(
            cube.distance_outside(&Point3::new(0.5, 0.5, 0.5 + 1e-9)),
            0.0
        );
        assert!((cube.distance_outside(&Point3::new(1.5, 0.0, 0.0)) - 1.0).abs() < 1e-12);
    }

    fn unit_cube() -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
        cuboid(
            Point3::new(0.5, 0.5, 0.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        )
    }

    fn l_prism() -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
        let outline = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]
        .map(|(x, y)| Point2::new(x, y));
        prism(&outline, 0.0, 3.0)
    }

    fn tetrahedron() -> (Vec<Point3<f64>>, Vec<Vec<usize>>) {
        let v = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
            Point3::new(0.0, 3.0, 0.0),
            Point3::new(0.0, 0.0, 4.0),
        ];
        let f = vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![0, 3, 2]];
        (v, f)
    }

    fn check(
        (v, f): &(Vec<Point3<f64>>, Vec<Vec<usize>>),
        volume: f64,
        centroid: [f64; 3],
        j: [[f64; 3]; 3],
    ) {
        let p = validate(v, f).unwrap();
        let m = p.moments();
        assert!(
            (m.volume - volume).abs() < 1e-12 * volume,
            "volume {}",
            m.volume
        );
        let c = Vector3::from(centroid);
        assert!(
            (m.centroid.coords - c).norm() < 1e-12,
            "centroid {}",
            m.centroid
        );
        let j = Matrix3::from_fn(|r, s| j[r][s]);
        assert!(
            (m.second - j).norm() < 1e-12 * j.norm(),
            "J = {} expected {j}",
            m.second
        );
        // Far from the origin the central moments keep their digits.
        let shift = Vector3::new(1e6, -2e6, 3e5);
        let far: Vec<Point3<f64>> = v.iter().map(|p| p + shift).collect();
        let m2 = *validate(&far, f).unwrap().moments();
        assert!((m2.volume - volume).abs() < 1e-9 * volume);
        assert!((m2.centroid.coords - c - shift).norm() < 1e-9 * shift.norm());
        assert!(
            (m2.second - j).norm() < 1e-9 * j.norm(),
            "{}",
            (m2.second - j).norm()
        );
    }

    #[test]
    fn integrals_match_the_closed_forms() {
        let d = 1.0 / 12.0;
        check(
            &unit_cube(),
            1.0,
            [0.5; 3],
            [[d, 0.0, 0.0], [0.0, d, 0.0], [0.0, 0.0, d]],
        );
        // Box a × b × c: J_xx = V a² / 12 …
        let (a, b, c) = (3.0, 0.5, 2.0);
        let v = a * b * c;
        let boxed = cuboid(
            Point3::new(1.0, -2.0, 0.5),
            Vector3::new(a, b, c),
            Rotation3::identity(),
        );
        check(
            &boxed,
            v,
            [1.0, -2.0, 0.5],
            [
                [v * a * a / 12.0, 0.0, 0.0],
                [0.0, v * b * b / 12.0, 0.0],
                [0.0, 0.0, v * c * c / 12.0],
            ],
        );
        // Tetrahedron (0, 2x, 3y, 4z): V = 4, ∫x_i x_j = V/20 (Σ p_i p_j + Σp_i Σp_j).
        check(
            &tetrahedron(),
            4.0,
            [0.5, 0.75, 1.0],
            [[0.6, -0.3, -0.4], [-0.3, 1.35, -0.6], [-0.4, -0.6, 2.4]],
        );
        // L-shaped (non-convex) prism: area 3, height 3, centroid (5/6, 5/6, 3/2).
        check(
            &l_prism(),
            9.0,
            [5.0 / 6.0, 5.0 / 6.0, 1.5],
            [[2.75, -1.0, 0.0], [-1.0, 2.75, 0.0], [0.0, 0.0, 6.75]],
        );
    }

    #[test]
    fn a_rotated_box_has_the_rotated_moments() {
        let r = Rotation3::from_euler_angles(0.3, -0.7, 1.2);
        let (v, f) = cuboid(Point3::new(4.0, 5.0, 6.0), Vector3::new(1.0, 2.0, 3.0), r);
        let p = validate(&v, &f).unwrap();
        let local = Matrix3::from_diagonal(&Vector3::new(1.0, 4.0, 9.0)) * (6.0 / 12.0);
        let expect = r.matrix() * local * r.matrix().transpose();
        assert!((p.moments().second - expect).norm() < 1e-12 * expect.norm());
        assert!((p.volume() - 6.0).abs() < 1e-12);
    }

    #[test]
    fn topology_and_convexity_are_found() {
        let cube = validate(&unit_cube().0, &unit_cube().1).unwrap();
        assert_eq!(cube.edges().len(), 12);
        assert!((0..12).all(|e| cube.edge_kind(e) == EdgeKind::Convex));
        assert!((0..8).all(|v| cube.is_convex_vertex(v)));
        for f in 0..6 {
            assert!((cube.face_area(f) - 1.0).abs() < 1e-15);
            assert_eq!(cube.face_edges(f).len(), 4);
        }
        assert!(
            (cube.normal(1) - Vector3::z()).norm() < 1e-15,
            "top faces up"
        );
        let (v, f) = l_prism();
        let l = validate(&v, &f).unwrap();
        // The inner corner of the L: vertices 3 and 9 and the edge between them.
        let reflex: Vec<usize> = (0..l.edges().len())
            .filter(|&e| l.edge_kind(e) == EdgeKind::Reflex)
            .collect();
        assert_eq!(reflex.len(), 1);
        assert_eq!(l.edges()[reflex[0]].ends, [3, 9]);
        let concave: Vec<usize> = (0..12).filter(|&k| !l.is_convex_vertex(k)).collect();
        assert_eq!(concave, vec![3, 9]);
        // The concave top and bottom are triangulated into 4 triangles each.
        assert_eq!(l.face_triangles(0).len(), 4);
        assert_eq!(l.face_triangles(1).len(), 4);
        assert!((l.face_area(1) - 3.0).abs() < 1e-15);
    }

    #[test]
    fn bad_surfaces_are_rejected_with_their_indices() {
        let (v, f) = unit_cube();
        let err = |v: &[Point3<f64>], f: &[Vec<usize>]| validate(v, f).unwrap_err();
        // Open: the top is missing.
        let open: Vec<Vec<usize>> = f
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != 1)
            .map(|(_, x)| x.clone())
            .collect();
        assert!(matches!(err(&v, &open), PolyhedronError::OpenEdge { .. }));
        // One face listed clockwise.
        let mut flipped = f.clone();
        flipped[3].reverse();
        assert_eq!(
            err(&v, &flipped),
            PolyhedronError::InconsistentOrientation { face: 3 }
        );
        let mut first = f.clone();
        first[0].reverse();
        assert_eq!(
            err(&v, &first),
            PolyhedronError::InconsistentOrientation { face: 0 }
        );
        // A face listed twice.
        let mut twice = f.clone();
        twice.push(f[2].clone());
        assert_eq!(
            err(&v, &twice),
            PolyhedronError::DuplicateFace {
                first: 2,
                second: 6
            }
        );
        // Flat: four coplanar points as a tetrahedron.
        let flat = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        let tf = tetrahedron().1;
        assert!(matches!(
            err(&flat, &tf),
            PolyhedronError::ZeroVolume { .. }
        ));
        // A needle three million times as long as it is wide is refused,
        // saying so, not that its corners lie in one plane.
        let (long, sides) = cuboid(
            Point3::origin(),
            Vector3::new(3e6, 1.0, 1.0),
            Rotation3::identity(),
        );
        let needle = err(&long, &sides);
        assert!(
            matches!(needle, PolyhedronError::ZeroVolume { volume, .. } if (volume - 3e6).abs() < 1e-2),
            "{needle:?}"
        );
        assert!(needle.to_string().contains("or it is a needle"), "{needle}");
        // A box of zero height has zero-area sides.
        let (v0, f0) = cuboid(
            Point3::origin(),
            Vector3::new(1.0, 1.0, 0.0),
            Rotation3::identity(),
        );
        assert!(matches!(
            err(&v0, &f0),
            PolyhedronError::DegenerateFace { .. }
        ));
        // NaN and infinity.
        let mut nan = v.clone();
        nan[5].y = f64::NAN;
        // NaN is not equal to itself, so the value is matched apart.
        assert!(matches!(
            err(&nan, &f),
            PolyhedronError::NotFinite { vertex: 5, value } if value.is_nan()
        ));
        let mut inf = v.clone();
        inf[2].z = f64::INFINITY;
        assert_eq!(
            err(&inf, &f),
            PolyhedronError::NotFinite {
                vertex: 2,
                value: f64::INFINITY
            }
        );
        // Indices and sizes.
        let mut bad = f.clone();
        bad[4][2] = 8;
        assert_eq!(
            err(&v, &bad),
            PolyhedronError::IndexOutOfRange {
                face: 4,
                index: 8,
                count: 8
            }
        );
        let mut small = f.clone();
        small[1] = vec![4, 5];
        assert_eq!(
            err(&v, &small),
            PolyhedronError::FaceTooSmall { face: 1, count: 2 }
        );
        let mut repeat = f.clone();
        repeat[1] = vec![4, 5, 6, 5];
        assert_eq!(
            err(&v, &repeat),
            PolyhedronError::RepeatedVertex { face: 1, vertex: 5 }
        );
        assert_eq!(err(&v[..3], &f), PolyhedronError::TooFewVertices(3));
        assert_eq!(err(&v, &f[..3]), PolyhedronError::TooFewFaces(3));
        // A vertex pulled off its faces' planes.
        let mut bent = v.clone();
        bent[6].z += 1e-3;
        // A twisted quad's corners are all 1e-3 / 4 off its best plane.
        match err(&bent, &f) {
            PolyhedronError::NonPlanarFace { face, distance, .. } => {
                assert!(f[face].contains(&6));
                assert!((distance - 2.5e-4).abs() < 1e-9, "{distance}");
            }
            other => panic!("{other}"),
        }
        // Two corners of the top at one point.
        let mut pinched = v.clone();
        pinched[5] = pinched[4];
        assert!(matches!(
            err(&pinched, &f),
            PolyhedronError::CoincidentVertices { .. } | PolyhedronError::NonPlanarFace { .. }
        ));
        // An unused vertex.
        let mut extra = v.clone();
        extra.push(Point3::new(5.0, 5.0, 5.0));
        assert_eq!(err(&extra, &f), PolyhedronError::UnusedVertex { vertex: 8 });
        // Two cubes in one block, and two cubes sharing only a corner.
        let (v2, f2) = cuboid(
            Point3::new(3.5, 0.5, 0.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        let mut both = v.clone();
        both.extend(v2);
        let mut faces = f.clone();
        faces.extend(
            f2.iter()
                .map(|x| x.iter().map(|k| k + 8).collect::<Vec<_>>()),
        );
        assert!(matches!(
            err(&both, &faces),
            PolyhedronError::Disconnected { .. }
        ));
        let (v3, f3) = cuboid(
            Point3::new(1.5, 1.5, 1.5),
            Vector3::repeat(1.0),
            Rotation3::identity(),
        );
        // Corner 0 of the second cube is corner 6 of the first.
        let mut touching = v.clone();
        touching.extend(v3[1..].iter().copied());
        let map = |k: usize| if k == 0 { 6 } else { k + 7 };
        let mut faces = f.clone();
        faces.extend(
            f3.iter()
                .map(|x| x.iter().map(|&k| map(k)).collect::<Vec<_>>()),
        );
        assert!(matches!(
            err(&touching, &faces),
            PolyhedronError::Disconnected { .. } | PolyhedronError::NonManifoldVertex { vertex: 6 }
        ));
        // A bow-tie face.
        let bow = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.5, 0.5, 1.0),
        ];
        let faces = vec![
            vec![0, 1, 2, 3],
            vec![0, 4, 1],
            vec![1, 4, 2],
            vec![2, 4, 3],
            vec![3, 4, 0],
        ];
        assert!(validate(&bow, &faces).is_err());
        // Every message names what is wrong.
        assert_eq!(
            PolyhedronError::NonPlanarFace {
                face: 2,
                vertex: 6,
                distance: 1e-3
            }
            .to_string(),
            "face 2 is not planar: vertex 6 is 1.000e-3 off its plane; move the corner onto the plane or split the face into triangles"
        );
    }

    #[test]
    fn an_inward_surface_is_flipped() {
        let (v, f) = unit_cube();
        let inward: Vec<Vec<usize>> = f
            .iter()
            .map(|x| x.iter().rev().copied().collect())
            .collect();
        let p = validate(&v, &inward).unwrap();
        assert!((p.volume() - 1.0).abs() < 1e-15);
        assert!((p.normal(1) - Vector3::z()).norm() < 1e-15);
    }

    #[test]
    fn generated_prisms_are_valid_even_when_concave() {
        let (v, f) = l_prism();
        let p = validate(&v, &f).unwrap();
        assert_eq!(p.faces().len(), 8);
        assert!((p.normal(0) + Vector3::z()).norm() < 1e-15);
        assert!((p.normal(1) - Vector3::z()).norm() < 1e-15);
        assert!(
            (p.normal(2) + Vector3::y()).norm() < 1e-15,
            "side over the first edge faces out"
        );
    }

    #[test]
    fn overlap_tells_touching_from_overlapping() {
        let block = |c: (f64, f64, f64), s: (f64, f64, f64), angle: f64| {
            let (v, f) = cuboid(
                Point3::new(c.0, c.1, c.2),
                Vector3::new(s.0, s.1, s.2),
                Rotation3::from_axis_angle(&Vector3::z_axis(), angle),
            );
            validate(&v, &f).unwrap()
        };
        let cube = block((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), 0.0);
        let tol = 1e-9;
        // Touching face to face, edge to edge, corner to corner: no overlap.
        assert!(!overlap(
            &cube,
            &block((0.0, 0.0, 1.0), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        assert!(!overlap(
            &cube,
            &block((0.0, 0.0, 1.0), (1.0, 1.0, 1.0), 0.7),
            tol
        ));
        assert!(!overlap(
            &cube,
            &block((1.0, 1.0, 0.0), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        assert!(!overlap(
            &cube,
            &block((1.0, 1.0, 1.0), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        assert!(!overlap(
            &cube,
            &block((3.0, 0.0, 0.0), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        // Slightly pressed in, but within the tolerance.
        assert!(!overlap(
            &cube,
            &block((0.0, 0.0, 1.0 - 1e-10), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        // Overlapping: shifted by half, identical, nested, pressed in, crossing bars.
        assert!(overlap(
            &cube,
            &block((0.5, 0.0, 0.0), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        assert!(overlap(&cube, &cube, tol));
        assert!(overlap(
            &cube,
            &block((0.0, 0.0, 0.0), (0.5, 0.5, 0.5), 0.3),
            tol
        ));
        assert!(overlap(
            &cube,
            &block((0.0, 0.0, 0.99), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        let bar = block((0.0, 0.0, 0.0), (4.0, 0.4, 0.4), 0.0);
        let across = block((0.0, 0.0, 0.1), (0.4, 4.0, 0.4), 0.0);
        assert!(overlap(&bar, &across, tol));
        assert!(!overlap(
            &bar,
            &block((0.0, 0.0, 0.4), (0.4, 4.0, 0.4), 0.0),
            tol
        ));
        // Concave: a cube sitting in the notch of an L, touching it.
        let outline = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ]
        .map(|(x, y)| Point2::new(x, y));
        let (v, f) = prism(&outline, 0.0, 1.0);
        let l = validate(&v, &f).unwrap();
        assert!(!overlap(
            &l,
            &block((1.5, 1.5, 0.5), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
        assert!(overlap(
            &l,
            &block((1.4, 1.5, 0.5), (1.0, 1.0, 1.0), 0.0),
            tol
        ));
    }
}
