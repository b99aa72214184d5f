//! The cases: the README's "Examples and what they verify" tables, one
//! quantity per example, each reference computed from the scene's own
//! blocks, materials, joints and loads.

use anyhow::{bail, Context};
use dda_2d::polygon;
use dda_core::ContactState;
use nalgebra::{Point2, Rotation3, Vector2, Vector3};

use super::formulas;
use super::{Case, ErrorMeasure, Ran};
use crate::output::{HistoryRow, HistoryRow3};
use crate::scene::{BlockSpec, JointLaw, MotionSpec, Scene};

use ErrorMeasure::{Absolute, Relative};

/// Every case, 2D then 3D.
pub fn catalogue() -> Vec<Case> {
    vec![
        Case {
            name: "free_fall_2d",
            example: "free_fall_2d.ron",
            description: "a block falling from rest: y = y0 − g t²/2",
            quantity: "centroid y at the end, m",
            measure: Relative,
            tolerance: 1e-9,
            quick: true,
            reference: free_fall_2d,
            value: |ran| Ok(end_2d(ran, 0)?.y),
        },
        Case {
            name: "spinning_block_2d",
            example: "spinning_block_2d.ron",
            description: "one free revolution at ω·Δt = 0.01 keeps the area",
            quantity: "area after / before",
            measure: Absolute,
            tolerance: 1e-9,
            quick: true,
            reference: |_| Ok(1.0),
            value: size_ratio,
        },
        Case {
            name: "uniaxial_compression_2d",
            example: "uniaxial_compression_2d.ron",
            description: "one block under a top pressure q: σy = −q",
            quantity: "σy, Pa",
            measure: Relative,
            tolerance: 1e-6,
            quick: true,
            reference: |scene| {
                let (_, width, _, _) = rectangle(scene, 0)?;
                Ok(load_sum(scene, 1)? / width)
            },
            value: |ran| Ok(end_2d(ran, 0)?.syy),
        },
        Case {
            name: "self_weight_2d",
            example: "self_weight_2d.ron",
            description: "a block standing under its weight: σy = −ρgh/2",
            quantity: "σy, Pa",
            measure: Relative,
            tolerance: 1e-4,
            quick: true,
            reference: |scene| {
                let (_, _, height, _) = rectangle(scene, 1)?;
                Ok(-density(scene, 1)? * gravity(scene) * height / 2.0)
            },
            value: |ran| Ok(end_2d(ran, 1)?.syy),
        },
        Case {
            name: "sliding_block_2d",
            example: "sliding_block_2d.ron",
            description: "a block sliding down an incline: d = ½ g (sin θ − cos θ tan φ) t²",
            quantity: "slide at the end, m",
            measure: Relative,
            tolerance: 0.01,
            quick: true,
            reference: |scene| {
                let theta = incline_2d(scene)?;
                let phi = friction(&scene.default_joint)?;
                Ok(formulas::incline_slide(
                    gravity(scene),
                    theta,
                    phi,
                    scene.analysis.duration,
                ))
            },
            value: slide_2d,
        },
        Case {
            name: "resting_block_2d",
            example: "resting_block_2d.ron",
            description: "friction beyond the incline holds the block",
            quantity: "movement at the end, m",
            measure: Absolute,
            tolerance: 1e-4,
            quick: true,
            reference: |_| Ok(0.0),
            value: |ran| moved_2d(ran, 1),
        },
        Case {
            name: "stacked_blocks_2d",
            example: "stacked_blocks_2d.ron",
            description: "ten blocks settle by Σ weight / (penalty × joint length)",
            quantity: "settlement of the top block, m",
            measure: Relative,
            tolerance: 0.1,
            quick: false,
            reference: stack_settlement,
            value: |ran| {
                let top = ran.scene.blocks.len() - 1;
                Ok(start_2d(ran, top)?.y - end_2d(ran, top)?.y)
            },
        },
        Case {
            name: "two_stage_friction_2d",
            example: "two_stage_friction_2d.ron",
            description: "friction dropping after a slip: two parabolas",
            quantity: "slide at the end, m",
            measure: Relative,
            tolerance: 0.01,
            quick: true,
            reference: two_stage_slide,
            value: slide_2d,
        },
        Case {
            name: "shaken_block_2d",
            example: "shaken_block_2d.ron",
            description: "a block on a shaken incline: Newmark's rigid-plastic slip",
            quantity: "slip on the ground at the end, m",
            measure: Relative,
            tolerance: 0.05,
            quick: true,
            reference: newmark_slip,
            value: |ran| {
                let theta = incline_2d(ran.scene)?;
                let down = Vector2::new(-theta.cos(), -theta.sin());
                let rel = |block: HistoryRow, ground: HistoryRow| {
                    Vector2::new(block.x - ground.x, block.y - ground.y)
                };
                let start = rel(start_2d(ran, 1)?, start_2d(ran, 0)?);
                let end = rel(end_2d(ran, 1)?, end_2d(ran, 0)?);
                Ok((end - start).dot(&down))
            },
        },
        Case {
            name: "rocking_column_2d",
            example: "rocking_column_2d.ron",
            description: "a column released at a tilt: first impact of the rigid block",
            quantity: "time of the first impact, s",
            measure: Relative,
            tolerance: 0.03,
            quick: false,
            reference: |scene| {
                let (b, h, theta0) = rocking_column(scene)?;
                Ok(formulas::rocking_first_impact(b, h, gravity(scene), theta0))
            },
            value: first_impact,
        },
        Case {
            name: "arch_heyman_2d",
            example: "arch_heyman_2d.ron",
            description: "a semicircular arch 5 % above Heyman's minimum thickness stands",
            quantity: "crown movement / R",
            measure: Absolute,
            tolerance: 1e-3,
            quick: false,
            reference: |scene| {
                // Heyman's minimum t/R of a semicircular arch (1969): only
                // a thicker one stands.
                let minimum = 0.1074;
                let (radius, _) = arch(scene)?;
                let BlockSpec::Arch { thickness, .. } = &scene.blocks[0] else {
                    bail!("block 0 is not an Arch");
                };
                if thickness / radius < minimum {
                    bail!(
                        "t/R = {} is below Heyman's minimum: the arch cannot stand",
                        thickness / radius
                    );
                }
                Ok(0.0)
            },
            value: |ran| {
                let (radius, voussoirs) = arch(ran.scene)?;
                Ok(moved_2d(ran, voussoirs / 2)? / radius)
            },
        },
        Case {
            name: "jointed_slope_2d",
            example: "jointed_slope_2d.ron",
            description: "the crest wedge slides on the daylighting bedding joint",
            quantity: "slide at the end, m",
            measure: Relative,
            tolerance: 0.02,
            quick: false,
            reference: |scene| {
                let (dip, phi) = bedding(scene)?;
                Ok(formulas::incline_slide(
                    gravity(scene),
                    dip,
                    phi,
                    scene.analysis.duration,
                ))
            },
            value: |ran| {
                let (dip, _) = bedding(ran.scene)?;
                let wedge = crest_wedge(ran.scene)?;
                let (a, b) = (start_2d(ran, wedge)?, end_2d(ran, wedge)?);
                Ok((b.x - a.x) * dip.cos() - (b.y - a.y) * dip.sin())
            },
        },
        Case {
            name: "direct_shear_2d",
            example: "direct_shear_2d.ron",
            description: "a block sheared over a base: peak = N tan φ + c L",
            quantity: "peak shear force of the joint, N",
            measure: Relative,
            tolerance: 0.01,
            quick: false,
            reference: |scene| {
                let JointLaw::Coulomb(law) = &scene.default_joint else {
                    bail!("the joint is not a Coulomb joint");
                };
                let (_, length, _, _) = rectangle(scene, 1)?;
                let normal = -load_sum(scene, 1)?;
                Ok(normal * law.friction_angle.to_radians().tan() + law.cohesion * length)
            },
            value: peak_shear,
        },
        Case {
            name: "drum_column_2d",
            example: "drum_column_2d.ron",
            description: "a plinth on a baseline-corrected record ends where it started",
            quantity: "plinth's distance from its start at the end, m",
            measure: Absolute,
            tolerance: 1e-5,
            quick: false,
            reference: |_| Ok(0.0),
            value: |ran| moved_2d(ran, 0),
        },
        Case {
            name: "free_fall_3d",
            example: "free_fall_3d.ron",
            description: "a box thrown upward: z = z0 + v0 t + g t²/2",
            quantity: "centroid z at the end, m",
            measure: Relative,
            tolerance: 1e-9,
            quick: true,
            reference: |scene| {
                let block = &scene.expanded_blocks_3d()[0];
                let n = block.vertices.len() as f64;
                let z0 = block.vertices.iter().map(|v| v[2]).sum::<f64>() / n;
                let t = scene.analysis.duration;
                Ok(z0 + block.velocity[2] * t + scene.gravity()[2] * t * t / 2.0)
            },
            value: |ran| Ok(end_3d(ran, 0)?.position[2]),
        },
        Case {
            name: "spinning_block_3d",
            example: "spinning_block_3d.ron",
            description: "one free revolution at ω·Δt = 0.01 keeps the volume",
            quantity: "volume after / before",
            measure: Absolute,
            tolerance: 1e-9,
            quick: true,
            reference: |_| Ok(1.0),
            value: size_ratio,
        },
        Case {
            name: "uniaxial_compression_3d",
            example: "uniaxial_compression_3d.ron",
            description: "one box under a top pressure q: σz = −q",
            quantity: "σz, Pa",
            measure: Relative,
            tolerance: 1e-6,
            quick: true,
            reference: |scene| {
                let BlockSpec::Box { size, .. } = &scene.blocks[0] else {
                    bail!("block 0 is not a Box");
                };
                Ok(load_sum(scene, 2)? / (size[0] * size[1]))
            },
            value: |ran| Ok(end_3d(ran, 0)?.stress[2]),
        },
        Case {
            name: "sliding_block_3d",
            example: "sliding_block_3d.ron",
            description: "a cube sliding down an incline dipping along no axis",
            quantity: "slide along the dip at the end, m",
            measure: Relative,
            tolerance: 0.01,
            quick: true,
            reference: |scene| {
                let dip = dip_3d(scene)?;
                let phi = friction(&scene.default_joint)?;
                Ok(formulas::incline_slide(
                    gravity(scene),
                    (-dip.z).asin(),
                    phi,
                    scene.analysis.duration,
                ))
            },
            value: |ran| Ok(moved_3d(ran, 1)?.dot(&dip_3d(ran.scene)?)),
        },
        Case {
            name: "resting_block_3d",
            example: "resting_block_3d.ron",
            description: "friction beyond the incline holds the cube",
            quantity: "movement at the end, m",
            measure: Absolute,
            tolerance: 1e-4,
            quick: true,
            reference: |_| Ok(0.0),
            value: |ran| Ok(moved_3d(ran, 1)?.norm()),
        },
        Case {
            name: "wedge_3d",
            example: "wedge_3d.ron",
            description: "a wedge on two planes slides along their intersection",
            quantity: "a/g along the intersection",
            measure: Relative,
            tolerance: 0.02,
            quick: true,
            reference: |scene| {
                let (_, along, reactions) = reference_wedge();
                Ok(along - reactions * friction(&scene.default_joint)?.tan())
            },
            value: |ran| {
                let (s, _, _) = reference_wedge();
                let t = ran.scene.analysis.duration;
                // From rest: d = a t² / 2.
                Ok(2.0 * moved_3d(ran, 1)?.dot(&s) / (gravity(ran.scene) * t * t))
            },
        },
        Case {
            name: "wedge_stable_3d",
            example: "wedge_stable_3d.ron",
            description: "the same wedge with friction beyond its slide holds",
            quantity: "movement at the end, m",
            measure: Absolute,
            tolerance: 1e-4,
            quick: true,
            reference: |scene| {
                let (_, along, reactions) = reference_wedge();
                if along - reactions * friction(&scene.default_joint)?.tan() > 0.0 {
                    bail!("the friction angle is too small to hold the wedge");
                }
                Ok(0.0)
            },
            value: |ran| Ok(moved_3d(ran, 1)?.norm()),
        },
        Case {
            name: "jointed_slope_3d",
            example: "jointed_slope_3d.ron",
            description:
                "blocks above the daylighting joint slide between half and all of the free slide",
            quantity: "least slide above the joint / free slide",
            // Between 0.5 and 1: the middle of that range, ± half its width.
            measure: Absolute,
            tolerance: 0.25,
            quick: false,
            reference: |_| Ok(0.75),
            value: slope_slide_3d,
        },
        Case {
            name: "stacked_cubes_3d",
            example: "stacked_cubes_3d.ron",
            description: "a cube resting on a fixed cube does not drift",
            quantity: "movement at the end / cube size",
            measure: Absolute,
            tolerance: 1e-4,
            quick: false,
            reference: |_| Ok(0.0),
            value: |ran| {
                let BlockSpec::Box { size, .. } = &ran.scene.blocks[1] else {
                    bail!("block 1 is not a Box");
                };
                Ok(moved_3d(ran, 1)?.norm() / size[2])
            },
        },
    ]
}

/// The wedge of `wedge_3d.ron` and `wedge_stable_3d.ron`: the planes its
/// faces are cut on, dip/dip direction 50/130 and 50/230, as the files say.
pub fn reference_wedge() -> (Vector3<f64>, f64, f64) {
    formulas::wedge(
        formulas::plane_normal(50.0, 130.0),
        formulas::plane_normal(50.0, 230.0),
    )
}

fn gravity(scene: &Scene) -> f64 {
    scene.gravity().iter().map(|g| g * g).sum::<f64>().sqrt()
}

/// A Coulomb joint's friction angle, radians.
fn friction(law: &JointLaw) -> anyhow::Result<f64> {
    match law {
        JointLaw::Coulomb(c) => Ok(c.friction_angle.to_radians()),
        _ => bail!("the joint is not a Coulomb joint"),
    }
}

/// Block entry `k` as a rectangle: centre, width, height, angle (degrees).
fn rectangle(scene: &Scene, k: usize) -> anyhow::Result<([f64; 2], f64, f64, f64)> {
    match scene.blocks.get(k) {
        Some(BlockSpec::Rectangle {
            center,
            width,
            height,
            angle,
            ..
        }) => Ok((*center, *width, *height, *angle)),
        _ => bail!("block {k} is not a Rectangle"),
    }
}

/// The density of block entry `k`.
fn density(scene: &Scene, k: usize) -> anyhow::Result<f64> {
    let m = scene
        .blocks
        .get(k)
        .and_then(|b| scene.material_index(b.material()))
        .with_context(|| format!("block {k} has no material"))?;
    Ok(scene.materials[m].1.density)
}

/// The sum of the constant point loads along `axis`, N.
fn load_sum(scene: &Scene, axis: usize) -> anyhow::Result<f64> {
    let mut sum = 0.0;
    for load in &scene.loads {
        let crate::scene::Load::PointLoad { force, .. } = load;
        let force = force.as_ref().context("a load has no constant force")?;
        sum += force.0[axis];
    }
    Ok(sum)
}

/// The incline (block 0) of a 2D incline scene, radians.
fn incline_2d(scene: &Scene) -> anyhow::Result<f64> {
    Ok(rectangle(scene, 0)?.3.to_radians())
}

/// The down-dip unit vector of a 3D incline (block 0): the Box's x axis
/// turned by its rotation.
fn dip_3d(scene: &Scene) -> anyhow::Result<Vector3<f64>> {
    let BlockSpec::Box { rotation, .. } = &scene.blocks[0] else {
        bail!("the incline is not a Box");
    };
    let turn = Rotation3::from_scaled_axis(Vector3::from(*rotation).map(f64::to_radians));
    let x = turn * Vector3::x();
    Ok(if x.z > 0.0 { -x } else { x })
}

fn free_fall_2d(scene: &Scene) -> anyhow::Result<f64> {
    let block = &scene.expanded_blocks()[0];
    let corners: Vec<Point2<f64>> = block
        .vertices
        .iter()
        .map(|v| Point2::new(v[0], v[1]))
        .collect();
    let y0 = polygon::central_moments(&corners).centroid.y;
    let t = scene.analysis.duration;
    Ok(y0 + block.velocity[1] * t + scene.gravity()[1] * t * t / 2.0)
}

/// Settlement of the top of a stack on a fixed base: each joint closes by
/// the weight above it over its springs' stiffness (penalty × length).
fn stack_settlement(scene: &Scene) -> anyhow::Result<f64> {
    let penalty = scene
        .analysis
        .penalty
        .context("the scene sets no penalty")?;
    let g = gravity(scene);
    let mut blocks = Vec::new();
    for k in 1..scene.blocks.len() {
        let (_, width, height, _) = rectangle(scene, k)?;
        blocks.push((width, density(scene, k)? * width * height * g));
    }
    let mut settlement = 0.0;
    for j in 0..blocks.len() {
        let above: f64 = blocks[j..].iter().map(|b| b.1).sum();
        settlement += above / (penalty * blocks[j].0);
    }
    Ok(settlement)
}

fn two_stage_slide(scene: &Scene) -> anyhow::Result<f64> {
    let JointLaw::SlipFriction {
        peak_friction_angle,
        residual_friction_angle,
        weakening: dda_contact::Weakening::Step { at },
        ..
    } = &scene.default_joint
    else {
        bail!("the joint is not a SlipFriction with a Step weakening");
    };
    Ok(formulas::two_stage_slide(
        gravity(scene),
        incline_2d(scene)?,
        peak_friction_angle.to_radians(),
        residual_friction_angle.to_radians(),
        *at,
        scene.analysis.duration,
    ))
}

fn newmark_slip(scene: &Scene) -> anyhow::Result<f64> {
    let Some(MotionSpec::Sine {
        amplitude,
        frequency,
        duration,
    }) = scene.ground_motion.as_ref().map(|g| &g.motion)
    else {
        bail!("the ground motion is not a Sine");
    };
    let (a, f, d) = (amplitude.0[0], *frequency, *duration);
    let shake = |t: f64| {
        if t < d {
            a * (std::f64::consts::TAU * f * t).sin()
        } else {
            0.0
        }
    };
    Ok(formulas::newmark_slip(
        gravity(scene),
        incline_2d(scene)?,
        friction(&scene.default_joint)?,
        shake,
        scene.analysis.duration,
    ))
}

/// The rocking column (block 1, four corners from its left base corner):
/// half-width, half-height and the tilt it is released at, radians
/// (clockwise positive).
fn rocking_column(scene: &Scene) -> anyhow::Result<(f64, f64, f64)> {
    let blocks = scene.expanded_blocks();
    let v = &blocks.get(1).context("no block 1")?.vertices;
    if v.len() != 4 {
        bail!("the column is not a quadrilateral");
    }
    let p: Vec<Vector2<f64>> = v.iter().map(|c| Vector2::new(c[0], c[1])).collect();
    let base = p[1] - p[0];
    Ok((
        base.norm() / 2.0,
        (p[2] - p[1]).norm() / 2.0,
        -base.y.atan2(base.x),
    ))
}

/// When the rocking column first lands on its other corner: where |ω|
/// peaks, just after its tilt first passes zero.
fn first_impact(ran: &Ran) -> anyhow::Result<f64> {
    let (_, _, theta0) = rocking_column(ran.scene)?;
    let rows = ran.history()?;
    let column: Vec<&HistoryRow> = rows.iter().filter(|r| r.block == 1).collect();
    // A counter-clockwise rotation rights it.
    let landing = column
        .iter()
        .position(|r| theta0 - r.rotation <= 0.0)
        .context("the column never rocks back")?;
    let peak = column[..(landing + 6).min(column.len())]
        .iter()
        .max_by(|a, b| a.omega.abs().total_cmp(&b.omega.abs()))
        .context("no rows")?;
    Ok(peak.time)
}

/// The Arch generator's radius and voussoir count.
fn arch(scene: &Scene) -> anyhow::Result<(f64, usize)> {
    match scene.blocks.first() {
        Some(BlockSpec::Arch {
            radius, voussoirs, ..
        }) => Ok((*radius, *voussoirs)),
        _ => bail!("block 0 is not an Arch"),
    }
}

/// The first joint set of the jointed domain (the bedding): dip and
/// friction angle, radians.
fn bedding(scene: &Scene) -> anyhow::Result<(f64, f64)> {
    let set = scene
        .blocks
        .iter()
        .flat_map(|b| b.joint_sets())
        .next()
        .context("no joint sets")?;
    let law = set.law.as_ref().unwrap_or(&scene.default_joint);
    Ok((set.dip.to_radians(), friction(law)?))
}

/// The block of the 2D slope's crest wedge: the one holding a point above
/// the daylighting bedding joint, under the crest.
fn crest_wedge(scene: &Scene) -> anyhow::Result<usize> {
    let point = Point2::new(4.0, 5.5);
    scene
        .expanded_blocks()
        .iter()
        .position(|b| {
            let v: Vec<Point2<f64>> = b.vertices.iter().map(|q| Point2::new(q[0], q[1])).collect();
            polygon::contains(&v, &point)
        })
        .context("no block holds the crest point")
}

/// The largest shear force of the joint between blocks 0 and 1 (the sum
/// over its closed contacts at a step), from contacts.csv.
fn peak_shear(ran: &Ran) -> anyhow::Result<f64> {
    let rows = crate::read_contacts(ran.dir.join("contacts.csv"))?;
    let mut per_step = std::collections::BTreeMap::<usize, f64>::new();
    for r in rows.iter().filter(|r| r.state != ContactState::Open) {
        if r.block_a.min(r.block_b) == 0 && r.block_a.max(r.block_b) == 1 {
            *per_step.entry(r.step).or_default() += r.shear_force;
        }
    }
    Ok(per_step.values().copied().fold(0.0, f64::max))
}

/// The smallest slide along the dip of the 3D slope's blocks above its
/// daylighting bedding joint (one spacing above the set's origin), over
/// the free slide on that joint.
fn slope_slide_3d(ran: &Ran) -> anyhow::Result<f64> {
    let set = ran
        .scene
        .blocks
        .iter()
        .flat_map(|b| b.joint_sets())
        .next()
        .context("no joint sets")?;
    let law = set.law.as_ref().unwrap_or(&ran.scene.default_joint);
    let (dip, phi) = (set.dip.to_radians(), friction(law)?);
    let normal = formulas::plane_normal(set.dip, set.dip_direction);
    let down =
        Vector3::new(normal.x, normal.y, 0.0).normalize() * dip.cos() - Vector3::z() * dip.sin();
    let origin = Vector3::from_iterator(set.origin.0.iter().copied());
    let joint = normal.dot(&origin) + set.spacing;
    let free = formulas::incline_slide(gravity(ran.scene), dip, phi, ran.scene.analysis.duration);
    let mut least: Option<f64> = None;
    for block in 0..ran.scene.block_count() {
        let start = Vector3::from(start_3d(ran, block)?.position);
        if normal.dot(&start) > joint {
            let slid = moved_3d(ran, block)?.dot(&down);
            least = Some(least.map_or(slid, |l: f64| l.min(slid)));
        }
    }
    Ok(least.context("no block above the joint")? / free)
}

/// Row of `block` at the output time `t`.
fn row_at<R: Copy>(
    rows: &[R],
    block: usize,
    t: f64,
    of: impl Fn(&R) -> (usize, f64),
) -> anyhow::Result<R> {
    let row = rows
        .iter()
        .filter(|r| of(r).0 == block)
        .min_by(|a, b| (of(a).1 - t).abs().total_cmp(&(of(b).1 - t).abs()))
        .with_context(|| format!("block {block} has no rows in history.csv"))?;
    let found = of(row).1;
    if (found - t).abs() > 1e-9 * t.max(1.0) {
        bail!("history.csv has no output at t = {t} s (nearest {found} s)");
    }
    Ok(*row)
}

fn start_2d(ran: &Ran, block: usize) -> anyhow::Result<HistoryRow> {
    row_at(ran.history()?, block, 0.0, |r| (r.block, r.time))
}

fn end_2d(ran: &Ran, block: usize) -> anyhow::Result<HistoryRow> {
    let t = ran.scene.analysis.duration;
    row_at(ran.history()?, block, t, |r| (r.block, r.time))
}

/// How far `block`'s centroid is from where it started, at the end, m.
fn moved_2d(ran: &Ran, block: usize) -> anyhow::Result<f64> {
    let (a, b) = (start_2d(ran, block)?, end_2d(ran, block)?);
    Ok((b.x - a.x).hypot(b.y - a.y))
}

/// Block 1's slide down a 2D incline (block 0), m.
fn slide_2d(ran: &Ran) -> anyhow::Result<f64> {
    let theta = incline_2d(ran.scene)?;
    let (a, b) = (start_2d(ran, 1)?, end_2d(ran, 1)?);
    Ok(-((b.x - a.x) * theta.cos() + (b.y - a.y) * theta.sin()))
}

fn start_3d(ran: &Ran, block: usize) -> anyhow::Result<HistoryRow3> {
    row_at(ran.history_3d()?, block, 0.0, |r| (r.block, r.time))
}

fn end_3d(ran: &Ran, block: usize) -> anyhow::Result<HistoryRow3> {
    let t = ran.scene.analysis.duration;
    row_at(ran.history_3d()?, block, t, |r| (r.block, r.time))
}

/// `block`'s centroid displacement from the start to the end, m.
fn moved_3d(ran: &Ran, block: usize) -> anyhow::Result<Vector3<f64>> {
    let (a, b) = (start_3d(ran, block)?, end_3d(ran, block)?);
    Ok(Vector3::from(b.position) - Vector3::from(a.position))
}

/// Each block's end area (2D) or volume (3D) over its start, for a scene
/// of one block.
fn size_ratio(ran: &Ran) -> anyhow::Result<f64> {
    let m = ran.measures;
    match (m.size_start.first(), m.size_end.first()) {
        (Some(a), Some(b)) => Ok(b / a),
        _ => bail!("the run measured no block sizes"),
    }
}
