//! What differs between a 2D and a 3D scene, so that checking and
//! building are written once over the dimension: which entries make a
//! block type's blocks, each block's checked shape, and the block and
//! elastic law made of them.

use dda_2d::polygon::{self, PolygonError};
use dda_2d::{Plane, PlaneElastic};
use dda_3d::polyhedron::{self as polyhedra, Fault, Polyhedron, PolyhedronError};
use dda_3d::IsotropicElastic;
use dda_core::{BlockKind, ConstitutiveLaw};
use nalgebra::{Point, Point2, Point3};

use super::locate::{place_of, Place};
use super::{BlockSpec, Material, Scene, SceneBlock, SceneError};
use crate::generators::{Failure, Generated};

/// A block type as a scene of its dimension `D` makes it; `S` is the
/// length of its initial velocity and stress.
pub(super) trait SceneElement<const D: usize, const S: usize>: Sized {
    /// A corner as the file writes it.
    type Corner;
    /// A block's checked outline or surface.
    type Shape;

    /// What an entry makes in this dimension (nothing for the other's).
    fn generate(spec: &BlockSpec) -> Result<Generated<Self::Corner>, Failure>;

    /// The block's checked shape; the error names the corner or face at
    /// fault within `at` (its entry), and a corner where the text writes it.
    fn shape(
        scene: &Scene,
        at: &Place,
        block: &SceneBlock<Self::Corner, S>,
    ) -> Result<Self::Shape, SceneError>;

    fn first_overlap(shapes: &[Self::Shape]) -> Option<(usize, usize)>;

    /// Lets shapes of one topology share it, as they become blocks; an
    /// outline has none to share.
    fn share(_shapes: &mut [Self::Shape]) {}

    /// How far `p` lies outside the shape (0 inside or on it).
    fn outside(shape: &Self::Shape, p: &Point<f64, D>) -> f64;

    /// The elastic law of a material's blocks.
    fn elastic(material: &Material, plane: Plane) -> Box<dyn ConstitutiveLaw<S>>;

    /// The block of a checked shape, with its material, kind and initial
    /// stress.
    fn block(
        shape: Self::Shape,
        material: usize,
        density: f64,
        kind: BlockKind,
        stress: [f64; S],
    ) -> Result<Self, String>;
}

impl SceneElement<2, 3> for dda_2d::Block {
    type Corner = [f64; 2];
    type Shape = Vec<Point2<f64>>;

    fn generate(spec: &BlockSpec) -> Result<Generated<[f64; 2]>, Failure> {
        spec.generate_2d()
    }

    fn shape(scene: &Scene, at: &Place, block: &SceneBlock) -> Result<Self::Shape, SceneError> {
        let points: Vec<Point2<f64>> = block.vertices.iter().map(|&v| v.into()).collect();
        polygon::validate(&points).map_err(|e| {
            let place = match e {
                PolygonError::NotFinite { index, .. } if scene.written(&at.field("vertices")) => {
                    at.field("vertices").index(index)
                }
                _ => place_of(block.entry, block.part.as_deref()),
            };
            let message = match block.part {
                // "Remove a vertex" is no help with generated blocks.
                Some(_) => format!(
                    "the generated block is degenerate: {}; change the generator's sizes",
                    e.to_string().split(';').next().unwrap_or_default()
                ),
                None => e.to_string(),
            };
            scene.error(&place, message)
        })?;
        Ok(points)
    }

    fn first_overlap(shapes: &[Self::Shape]) -> Option<(usize, usize)> {
        polygon::first_overlap(shapes).first
    }

    fn outside(shape: &Self::Shape, p: &Point2<f64>) -> f64 {
        polygon::distance_outside(shape, p)
    }

    fn elastic(material: &Material, plane: Plane) -> Box<dyn ConstitutiveLaw<3>> {
        Box::new(PlaneElastic {
            young: material.young,
            poisson: material.poisson,
            plane,
        })
    }

    fn block(
        shape: Self::Shape,
        material: usize,
        density: f64,
        kind: BlockKind,
        stress: [f64; 3],
    ) -> Result<Self, String> {
        let mut block = dda_2d::Block::new(&shape, material, density).map_err(|e| e.to_string())?;
        block.stress = stress.into();
        block.kind = kind;
        Ok(block)
    }
}

impl SceneElement<3, 6> for dda_3d::Block {
    type Corner = [f64; 3];
    type Shape = Polyhedron;

    fn generate(spec: &BlockSpec) -> Result<Generated<[f64; 3]>, Failure> {
        spec.generate_3d()
    }

    fn shape(
        scene: &Scene,
        at: &Place,
        block: &SceneBlock<[f64; 3], 6>,
    ) -> Result<Polyhedron, SceneError> {
        let points: Vec<Point3<f64>> = block.vertices.iter().map(|&v| v.into()).collect();
        polyhedra::validate_outward(&points, &block.faces).map_err(|e| {
            let vertices = at.field("vertices");
            let place = match (e.place(), &e) {
                (_, PolyhedronError::NotFinite { vertex, .. }) if scene.written(&vertices) => {
                    vertices.index(*vertex)
                }
                (Fault::Vertices, _) => vertices,
                (Fault::Faces, _) => at.field("faces"),
                (Fault::Vertex(v), _) => at.pointing_at("vertices", v),
                (Fault::Face(f), _) => at.pointing_at("faces", f),
                (Fault::Block, _) => at.clone(),
            };
            scene.error(&place, e.to_string())
        })
    }

    fn first_overlap(shapes: &[Polyhedron]) -> Option<(usize, usize)> {
        polyhedra::first_overlap(shapes).first
    }

    fn share(shapes: &mut [Polyhedron]) {
        polyhedra::share_topologies(shapes);
    }

    fn outside(shape: &Polyhedron, p: &Point3<f64>) -> f64 {
        shape.distance_outside(p)
    }

    fn elastic(material: &Material, _: Plane) -> Box<dyn ConstitutiveLaw<6>> {
        Box::new(IsotropicElastic {
            young: material.young,
            poisson: material.poisson,
        })
    }

    fn block(
        shape: Polyhedron,
        material: usize,
        density: f64,
        kind: BlockKind,
        stress: [f64; 6],
    ) -> Result<Self, String> {
        let mut block = dda_3d::Block::from_shape(shape, material, density);
        block.stress = stress.into();
        block.kind = kind;
        Ok(block)
    }
}
