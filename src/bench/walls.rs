//! The walls `dda bench` times: running bond, 0.5 m × 0.25 m bricks on a
//! fixed base, in 2D or as their 3D prism model, and the sine their base
//! is shaken by (`--shake`).

use serde::Serialize;

use crate::scene::{BlockKind, Coords, GroundMotionSpec, MotionSpec, Scene};

/// The bricks' depth in the 3D wall (one brick deep), m.
pub const DEPTH_3D: f64 = 0.25;

/// The penalty of the walls stepped at dt 1 ms ([`Stepping::Fixed`]), N/m
/// per m of contact in 2D, N/m per m² in 3D.
pub const FIXED_PENALTY: f64 = 1e9;

/// How a wall's time step and penalty are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Stepping {
    /// dt 1 ms and a penalty of 1e9 (N/m per m of contact in 2D, N/m per
    /// m² in 3D): every size steps alike, for time per step.
    Fixed,
    /// Both left out of the scene, so the scene's automatic choice applies
    /// (dt = 0.2·√(m/k), penalty 2E over the median block size).
    Automatic,
    /// This time step, s, and the automatic penalty: how large a step the
    /// wall stands at.
    Given(f64),
}

/// The running-bond wall of `n` courses of `n` bricks (0.5 m × 0.25 m,
/// density 1800 kg/m³, E 5 GPa, ν 0.2, friction angle 35°) on a fixed base,
/// at rest under gravity, dt 1 ms and penalty 1e9: the wall `dda bench`
/// times by default.
pub fn wall_scene(n: usize) -> Scene {
    wall(n, 2, Stepping::Fixed, BlockKind::Deformable).expect("the benchmark wall is a valid scene")
}

/// The wall of `n` courses of `n` bricks in `dimension` 2 or 3 (the 2D
/// wall's prism model, [`DEPTH_3D`] deep: 2D (x, y) is 3D (x, 0, y)), its
/// bricks of `kind`, stepped as `stepping` says. The duration is 1 s.
pub fn wall(
    n: usize,
    dimension: u32,
    stepping: Stepping,
    kind: BlockKind,
) -> anyhow::Result<Scene> {
    anyhow::ensure!(n >= 1, "a wall needs at least one course of one brick");
    let length = 0.5 * n as f64;
    let fixed = match stepping {
        Stepping::Fixed => format!("dt: 0.001, penalty: {FIXED_PENALTY:?}, "),
        Stepping::Automatic => String::new(),
        Stepping::Given(dt) => format!("dt: {dt:?}, "),
    };
    let text = format!(
        r#"Scene(
    analysis: (duration: 1.0, {fixed}gravity: (0.0, -9.81)),
    materials: {{ "brick": (density: 1800.0, young: 5e9, poisson: 0.2) }},
    default_joint: Coulomb(friction_angle: 35.0),
    blocks: [
        Rectangle(center: ({c:?}, -0.5), width: {w:?}, height: 1.0, fixed: true),
        Wall(origin: (0.0, 0.0), length: {length:?}, courses: {n}, brick_length: 0.5, brick_height: 0.25, bond: Running),
    ],
)"#,
        c = length / 2.0,
        w = length + 2.0,
    );
    let mut scene = Scene::from_str(&text, &format!("wall_{n}x{n}.ron"))?;
    scene.materials[0].1.kind = kind;
    match dimension {
        2 => Ok(scene),
        3 => Ok(crate::extrude::extrude(&scene, DEPTH_3D)?),
        d => anyhow::bail!("a wall is 2D or 3D, not {d}D"),
    }
}

/// The frequency of the sine a shaken wall's base follows (`dda bench
/// --shake`), Hz.
pub const SHAKE_FREQUENCY: f64 = 2.0;

/// Shakes `scene`'s wall (built by [`wall`]) through its base: a
/// horizontal ground acceleration `amplitude`·sin(2π·2 Hz·t) along the
/// wall (m/s², toward +x) for `seconds`. The bed joints of a rigid wall
/// slide beyond g·tan 35° = 6.87 m/s².
pub fn shake(scene: &mut Scene, amplitude: f64, seconds: f64) {
    let mut along = vec![0.0; scene.dimension as usize];
    along[0] = amplitude;
    scene.ground_motion = Some(GroundMotionSpec {
        // The base is the wall scene's first block.
        blocks: vec![0],
        motion: MotionSpec::Sine {
            amplitude: Coords(along),
            frequency: SHAKE_FREQUENCY,
            duration: seconds,
        },
    });
}
