//! A 2D scene as its 3D prism model (`dda extrude`), to check a 3D run
//! against the 2D one or to start a 3D model from a 2D section.
//!
//! The 2D plane becomes the 3D xz plane, z up: a 2D point (x, y) is the 3D
//! point (x, 0, y), so 2D gravity (0, −9.81) becomes (0, 0, −9.81). Every
//! block (generators expanded first, so block numbers are kept) becomes a
//! [`BlockSpec::Polyhedron`]: the prism of its outline from y = −depth/2 to
//! y = +depth/2. The 2D counter-clockwise direction is a turn about −y, so:
//!
//! * velocity (vx, vy, ω) becomes (vx, 0, vy, 0, −ω, 0);
//! * stress (σx, σy, τxy) becomes (σx, 0, σy, 0, τxy, 0) in the 3D order
//!   (σx, σy, σz, τyz, τzx, τxy): the 2D σy is the 3D σz and τxy is τzx;
//!   the out-of-plane σy starts at 0;
//! * point loads, fixed and measured points sit on the mid-plane y = 0. 2D forces are
//!   per unit thickness, so a force (fx, fy) becomes (fx·depth, 0,
//!   fy·depth), and stresses stay the same; fixed-point velocities and axes
//!   map like points;
//! * a fixed block keeps `fixed: true`, which holds all its corners;
//! * ground motions map their amplitudes like points, and a record keeps
//!   its file, read as `components: "xz"`.
//!
//! Materials, joint laws, joint sets and the other analysis settings carry
//! over; `plane` is dropped (a 3D model has none). An automatic length
//! scale is fixed at the 2D model's, so the step and contact-range controls
//! (fractions of it) are the 2D ones whatever the depth.
//!
//! A free prism is not in plane strain: its ends are free to move along y.
//! [`Extrusion::plane_strain`] adds a roller (a fixed point with `axis:
//! (0.0, 1.0, 0.0)`) at every corner of every free block, which holds the
//! out-of-plane motion and strain at zero, as plane strain assumes. The
//! rollers are penalty springs (`analysis.fixed_penalty`), so they hold to
//! about (block stiffness) / (spring stiffness).

use dda_2d::polygon;
use dda_3d::polyhedron::prism;
use nalgebra::Point2;

use crate::scene::{
    BlockSpec, Coords, FixedPointSpec, Load, MeasuredPointSpec, MotionSpec, Scene, SceneBlock,
    SceneError,
};

/// How to extrude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrusion {
    /// The prisms' length along y, in m.
    pub depth: f64,
    /// Hold every free block against motion along y at all its corners.
    pub plane_strain: bool,
}

/// Why a scene cannot be extruded.
#[derive(Debug, thiserror::Error)]
pub enum ExtrudeError {
    /// The 2D scene itself is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error("the depth must be a positive length in m, got {}", crate::output::plain_number(*.0))]
    Depth(f64),
    #[error("{0} is already a 3D scene (dimension: 3); extrude takes a 2D scene")]
    NotTwoD(String),
}

/// The 3D prism model of a 2D scene, `depth` m deep along y (see the
/// module documentation for the mapping).
pub fn extrude(scene: &Scene, depth: f64) -> Result<Scene, ExtrudeError> {
    extrude_with(
        scene,
        &Extrusion {
            depth,
            plane_strain: false,
        },
    )
}

/// [`extrude`] with options.
pub fn extrude_with(scene: &Scene, how: &Extrusion) -> Result<Scene, ExtrudeError> {
    let depth = how.depth;
    if !(depth.is_finite() && depth > 0.0) {
        return Err(ExtrudeError::Depth(depth));
    }
    if scene.dimension != 2 {
        return Err(ExtrudeError::NotTwoD(scene.origin().to_string()));
    }
    scene.validate()?;
    let blocks = scene.expanded_blocks();
    let mut out = scene.clone();
    let shown = crate::output::plain_number(depth);
    out.derive_origin(format!("{} (extruded {shown} m)", scene.origin()));
    out.dimension = 3;

    let g = scene.gravity();
    out.analysis.gravity = Some(Coords(vec![g[0], 0.0, g[1]]));
    out.analysis.plane = Default::default();
    if out.analysis.length_scale.is_none() {
        out.analysis.length_scale = Some(length_scale(&blocks));
    }

    out.blocks = blocks
        .iter()
        .map(|b| {
            let (vertices, faces) = prism_of(b, depth);
            let [vx, vy, w] = b.velocity;
            let [sx, sy, sxy] = b.stress;
            BlockSpec::Polyhedron {
                material: scene.blocks[b.entry].material().map(str::to_string),
                kind: scene.blocks[b.entry].block_kind(),
                vertices,
                faces,
                fixed: b.fixed,
                // 0 − ω, not −ω: no −0 in the file.
                velocity: [vx, 0.0, vy, 0.0, 0.0 - w, 0.0],
                stress: [sx, 0.0, sy, 0.0, sxy, 0.0],
            }
        })
        .collect();

    // The laws a jointed domain's sets give its block pairs, listed as
    // block pairs now that the domain is written block by block.
    let table = scene.law_table();
    let listed: std::collections::HashSet<(usize, usize)> = scene
        .joints
        .iter()
        .flat_map(|j| j.blocks.iter().flatten())
        .map(|&[a, b]| (a.min(b), a.max(b)))
        .collect();
    let mut by_law: std::collections::BTreeMap<usize, Vec<[usize; 2]>> = Default::default();
    for (&(a, b), &law) in &table.pairs {
        if !listed.contains(&(a, b)) {
            by_law.entry(law).or_default().push([a, b]);
        }
    }
    for (law, mut pairs) in by_law {
        pairs.sort_unstable();
        out.joints.push(crate::scene::Joint {
            between: None,
            blocks: Some(pairs),
            law: table.laws[law].clone(),
        });
    }

    let point = |c: &Coords| Coords(vec![c.get(0), 0.0, c.get(1)]);
    out.loads = scene
        .loads
        .iter()
        .map(|load| match load {
            Load::PointLoad {
                block,
                point: p,
                force,
                history,
            } => Load::PointLoad {
                block: *block,
                point: point(p),
                force: force
                    .as_ref()
                    .map(|f| Coords(vec![f.get(0) * depth, 0.0, f.get(1) * depth])),
                history: history.as_ref().map(|h| {
                    h.iter()
                        .map(|s| Coords(vec![s.get(0), s.get(1) * depth, 0.0, s.get(2) * depth]))
                        .collect()
                }),
            },
        })
        .collect();

    out.fixed_points = scene
        .fixed_points
        .iter()
        .map(|fp| FixedPointSpec {
            block: fp.block,
            point: point(&fp.point),
            velocity: if fp.velocity.is_empty() {
                Coords::default()
            } else {
                point(&fp.velocity)
            },
            axis: fp.axis.as_ref().map(point),
        })
        .collect();
    out.measured_points = scene
        .measured_points
        .iter()
        .map(|m| MeasuredPointSpec {
            block: m.block,
            point: point(&m.point),
        })
        .collect();
    if how.plane_strain {
        for (k, block) in out.blocks.iter().enumerate() {
            if let BlockSpec::Polyhedron {
                vertices,
                fixed: false,
                ..
            } = block
            {
                for v in vertices {
                    out.fixed_points.push(FixedPointSpec {
                        block: k,
                        point: Coords(v.to_vec()),
                        velocity: Coords::default(),
                        axis: Some(Coords(vec![0.0, 1.0, 0.0])),
                    });
                }
            }
        }
    }

    if let Some(ground) = &mut out.ground_motion {
        match &mut ground.motion {
            MotionSpec::Sine { amplitude, .. } | MotionSpec::Pulse { amplitude, .. } => {
                *amplitude = point(amplitude);
            }
            MotionSpec::Record { components, .. } => {
                let axes = components.as_deref().unwrap_or("xy");
                *components = Some(axes.replace('y', "z"));
            }
        }
    }
    out.validate()?;
    Ok(out)
}

/// The prism of a 2D block's outline (counter-clockwise) from y = +depth/2
/// to y = −depth/2, as 3D corners and faces.
fn prism_of(block: &SceneBlock, depth: f64) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let outline: Vec<Point2<f64>> = block
        .vertices
        .iter()
        .map(|p| Point2::new(p[0], p[1]))
        .collect();
    // Validated already; the check also puts the outline counter-clockwise.
    let outline = polygon::validate(&outline).unwrap_or(outline);
    let (v, f) = prism(&outline, -depth / 2.0, depth / 2.0);
    // (x, y, z) → (x, −z, y): a right-handed turn of 90° about x.
    let vertices = v.iter().map(|p| [p.x, -p.z, p.y]).collect();
    (vertices, f)
}

/// The 2D model's automatic length scale: half the diagonal of its bounds.
fn length_scale(blocks: &[SceneBlock]) -> f64 {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in blocks.iter().flat_map(|b| &b.vertices) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1]) / 2.0
}
