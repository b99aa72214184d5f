//! Scene files: one RON file describes one experiment (see `examples/`).
//!
//! [`Scene::load`] parses and validates; [`Scene::build`] turns a valid 2D
//! scene into a [`Model`] ready to run, [`Scene::build_3d`] a 3D one into a
//! [`Model3`], and [`Scene::build_any`] either into an [`AnyModel`]. Every
//! error names the file, the place in it (with line and column where they can
//! be found) and what to change.
//!
//! A scene is 2D (`dimension: 2`, the default: polygons in the xy plane) or
//! 3D (`dimension: 3`: polyhedra, z up). Points, forces, velocities, axes,
//! gravity and ground-motion amplitudes are tuples with one number per
//! dimension ([`Coords`]).

mod analysis;
mod build;
mod dimension;
mod error;
mod locate;
mod validate;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use dda_2d::{Plane, RotationUpdate};
pub use dda_contact::{Coulomb, RateFriction, ThresholdBond, Weakening};
pub use dda_core::{BlockKind, Integrator, Quantity, Solver};

pub use crate::generators::jointed::{JointSet, Placement, Region3};
pub use crate::generators::Bond;
use crate::generators::{self as g, Failure, Generated};
use crate::values::ordered_map;
pub use crate::values::{Coords, JointLaw};
pub use analysis::{Analysis, Damping, Mode, Settle};
pub use build::{AnyModel, LawTable, Model, Model3};
use dimension::SceneElement;
pub use error::SceneError;
pub use locate::dotted_path;

/// One experiment. Field order and names are the file format.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename = "Scene", deny_unknown_fields)]
pub struct Scene {
    /// 2 (the default) or 3.
    #[serde(default = "default_dimension")]
    pub dimension: u32,
    #[serde(default)]
    pub analysis: Analysis,
    #[serde(default)]
    pub output: Output,
    /// Materials by name, in file order (the order gives material indices).
    #[serde(default, with = "ordered_map")]
    pub materials: Vec<(String, Material)>,
    /// Joint laws for pairs of materials or sets of block pairs.
    #[serde(default)]
    pub joints: Vec<Joint>,
    /// The law of the joints not listed in `joints`.
    #[serde(default)]
    pub default_joint: JointLaw,
    #[serde(default)]
    pub blocks: Vec<BlockSpec>,
    #[serde(default)]
    pub loads: Vec<Load>,
    #[serde(default)]
    pub fixed_points: Vec<FixedPointSpec>,
    /// Points whose motion is written to `points.csv`; none by default.
    #[serde(default)]
    pub measured_points: Vec<MeasuredPointSpec>,
    /// Shaking of fixed base blocks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground_motion: Option<GroundMotionSpec>,
    /// Where the scene came from, for error messages.
    #[serde(skip)]
    source: Source,
}

fn default_dimension() -> u32 {
    2
}

/// The file name and text a scene was read from.
#[derive(Debug, Clone, Default, PartialEq)]
struct Source {
    origin: String,
    text: String,
    /// The folder that files named in the scene are relative to; `None`
    /// for the current one.
    dir: Option<PathBuf>,
}

/// How many output times an automatic output interval makes.
pub const AUTO_OUTPUT_ROWS: f64 = 200.0;

#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Output {
    /// Time between history rows in seconds; 0 writes every step. Left
    /// out, it is the duration / [`AUTO_OUTPUT_ROWS`], and never less than
    /// the time step (see [`Scene::output_interval`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval: Option<f64>,
    /// Also write `contacts.csv`: every contact at every output time.
    pub contacts: bool,
    /// Also write VTK frames for ParaView at every output time
    /// (`blocks.pvd`, `contacts.pvd`, `vtk/`); default false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub vtk: bool,
    /// Also write `steps.csv`: a row per accepted step with its length,
    /// passes, moves, factorisations, cuts and wall time
    /// ([`crate::step_log`]); default false.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub steps: bool,
}

/// Isotropic elastic material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Mass per volume, kg/m³; required, positive.
    pub density: f64,
    /// Young's modulus, Pa; required, at least 1 Pa.
    pub young: f64,
    /// Poisson's ratio, in [0, 0.5); default 0.25.
    #[serde(default = "default_poisson")]
    pub poisson: f64,
    /// `Rigid` (translation and rotation only) or `Deformable` (also
    /// uniform strain, the default) for the blocks of this material.
    #[serde(default, skip_serializing_if = "is_default")]
    pub kind: BlockKind,
}

fn default_poisson() -> f64 {
    0.25
}

/// A joint set: the law of the joints between two materials (in either
/// order), or between particular pairs of blocks. Exactly one of `between`
/// and `blocks` is given; block pairs override material pairs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Two material names, like `("rock", "rock")`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub between: Option<(String, String)>,
    /// Block index pairs (in either order), like `[(0, 1), (1, 2)]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blocks: Option<Vec<[usize; 2]>>,
    pub law: JointLaw,
}

/// Declares [`BlockSpec`], giving every entry the fields all blocks have:
/// `material`, `kind` (first), then `fixed`, `velocity` and `stress` (last),
/// the state three numbers in 2D and six in 3D. serde's `flatten` would
/// lose `deny_unknown_fields`, so the fields are written into each variant
/// here. `terse: true` leaves them out of the written text when they are
/// at their defaults (`false` writes them). After its fields, each entry
/// says what it makes (`BlockSpec::generate_2d` and `generate_3d`, by the
/// length of its state), or why its values make nothing: each generator
/// checks its own.
macro_rules! block_specs {
    (@made 3, 3, $make:expr) => { $make };
    (@made 6, 6, $make:expr) => { $make };
    (@made $k:tt, $made:tt, $make:expr) => { Ok(Vec::new().into()) };
    ($($(#[$doc:meta])* $name:ident([f64; $k:tt], terse: $terse:tt) {
        $($(#[$attr:meta])* $field:ident: $ty:ty,)*
    } => $make:expr,)*) => {
        /// A block, or a generator of several (`Arch`, `Column`, `Wall`):
        /// shape, material and initial state. A generator's blocks take its
        /// place in the block numbering, in the order documented for each.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub enum BlockSpec {
            $($(#[$doc])* $name {
                #[serde(default)]
                #[cfg_attr($terse, serde(skip_serializing_if = "Option::is_none"))]
                material: Option<String>,
                /// `Rigid` or `Deformable`; the material's kind when left out.
                #[serde(default, skip_serializing_if = "Option::is_none")]
                kind: Option<BlockKind>,
                $($(#[$attr])* $field: $ty,)*
                #[serde(default)]
                #[cfg_attr($terse, serde(skip_serializing_if = "is_default"))]
                fixed: bool,
                /// (vx, vy, ω) in 2D, (vx, vy, vz, ωx, ωy, ωz) in 3D.
                #[serde(default)]
                #[cfg_attr($terse, serde(skip_serializing_if = "is_default"))]
                velocity: [f64; $k],
                /// (σx, σy, τxy) in 2D, (σx, σy, σz, τyz, τzx, τxy) in 3D,
                /// tension positive.
                #[serde(default)]
                #[cfg_attr($terse, serde(skip_serializing_if = "is_default"))]
                stress: [f64; $k],
            },)*
        }

        impl BlockSpec {
            pub fn material(&self) -> Option<&str> {
                match self { $(BlockSpec::$name { material, .. } => material.as_deref(),)* }
            }

            /// The block's own kind, if it gives one.
            pub fn block_kind(&self) -> Option<BlockKind> {
                match self { $(BlockSpec::$name { kind, .. } => *kind,)* }
            }

            pub fn fixed(&self) -> bool {
                match self { $(BlockSpec::$name { fixed, .. } => *fixed,)* }
            }

            /// (vx, vy, ω) for 2D entries, (vx, vy, vz, ωx, ωy, ωz) for 3D ones.
            pub fn velocity(&self) -> &[f64] {
                match self { $(BlockSpec::$name { velocity, .. } => velocity,)* }
            }

            /// (σx, σy, τxy) for 2D entries, (σx, σy, σz, τyz, τzx, τxy) for 3D ones.
            pub fn stress(&self) -> &[f64] {
                match self { $(BlockSpec::$name { stress, .. } => stress,)* }
            }

            /// The entry's name in the file, like "Rectangle".
            pub fn kind(&self) -> &'static str {
                match self { $(BlockSpec::$name { .. } => stringify!($name),)* }
            }

            /// What a 2D entry makes (nothing for a 3D one).
            #[allow(unused_variables)]
            pub(crate) fn generate_2d(&self) -> Result<Generated<[f64; 2]>, Failure> {
                match self {
                    $(BlockSpec::$name { $($field,)* .. } => block_specs!(@made $k, 3, $make),)*
                }
            }

            /// What a 3D entry makes (nothing for a 2D one).
            #[allow(unused_variables)]
            pub(crate) fn generate_3d(&self) -> Result<Generated<[f64; 3]>, Failure> {
                match self {
                    $(BlockSpec::$name { $($field,)* .. } => block_specs!(@made $k, 6, $make),)*
                }
            }
        }
    };
}

block_specs! {
    Polygon([f64; 3], terse: false) {
        vertices: Vec<[f64; 2]>,
    } => Ok(whole((vertices.clone(), vec![]))),
    Rectangle([f64; 3], terse: false) {
        center: [f64; 2],
        width: f64,
        height: f64,
        /// Degrees, counter-clockwise.
        #[serde(default)]
        angle: f64,
    } => Ok(g::rectangle(*center, *width, *height, *angle)?.into()),
    /// Voussoirs between radial joints (chords, no arc subdivision), numbered
    /// from the left springing to the right, then (with `abutments`) a fixed
    /// block under each springing joint, left then right.
    Arch([f64; 3], terse: false) {
        center: [f64; 2],
        /// Of the centreline; the intrados is at radius − thickness/2, the
        /// extrados at radius + thickness/2.
        radius: f64,
        thickness: f64,
        voussoirs: usize,
        /// Degrees, the arc's total angle, symmetric about the vertical
        /// through `center`: 180 is semicircular, less is segmental.
        #[serde(default = "default_span_angle")]
        span_angle: f64,
        /// Horizontal offset of the two centres of a pointed arch, as a
        /// fraction of `radius`; 0 is a round arch.
        #[serde(default)]
        pointed: f64,
        /// Fixed blocks under the springing joints: their top face lies along
        /// the joint, t/2 longer at each end, and they reach t below it.
        #[serde(default = "default_true")]
        abutments: bool,
    } => Ok(g::arch(&g::ArchShape {
        center: *center,
        radius: *radius,
        thickness: *thickness,
        voussoirs: *voussoirs,
        span_angle: *span_angle,
        pointed: *pointed,
        abutments: *abutments,
    })?
    .into()),
    /// A stack of rectangular drums, the bottom one's base centred at `base`.
    Column([f64; 3], terse: false) {
        base: [f64; 2],
        drums: usize,
        drum_height: f64,
        width: f64,
    } => Ok(g::column(*base, *drums, *drum_height, *width)?.into()),
    /// A polyhedron (3D scenes): its corners and its faces, each face the
    /// indices of its corners counter-clockwise seen from outside the block.
    /// The surface must be closed, with every edge shared by two faces, and
    /// each face plane.
    Polyhedron([f64; 6], terse: true) {
        vertices: Vec<[f64; 3]>,
        faces: Vec<Vec<usize>>,
    } => Ok(whole((vertices.clone(), faces.clone()))),
    /// A rectangular box (3D scenes): its centre, its edge lengths along its
    /// own axes, and the rotation taking those axes to the global ones as a
    /// rotation vector in degrees (the axis times the angle: `(0.0, 30.0,
    /// 0.0)` turns it 30° about y, right-handed). Corners 0-3 are the bottom
    /// ones (own −z), counter-clockwise seen from above, 4-7 the top ones
    /// above them; faces: bottom, top, −y, +x, +y, −x.
    Box([f64; 6], terse: false) {
        center: [f64; 3],
        size: [f64; 3],
        #[serde(default)]
        rotation: [f64; 3],
    } => Ok(whole(g::cuboid(*center, *size, *rotation)?)),
    /// A vertical prism (3D scenes): a polygon in the xy plane (in either
    /// order; it is made counter-clockwise seen from above) from z = `z0` up
    /// to z = `z1`. Corners 0..n are the outline at z0, n..2n the outline at
    /// z1; faces: bottom, top, then the side over each outline edge.
    Prism([f64; 6], terse: false) {
        outline: Vec<[f64; 2]>,
        z0: f64,
        z1: f64,
    } => Ok(whole(g::prism(outline, *z0, *z1)?)),
    /// Courses of bricks from `origin` (the bottom-left corner) upward,
    /// each spanning exactly `length`; bricks numbered course by course,
    /// left to right.
    Wall([f64; 3], terse: false) {
        origin: [f64; 2],
        length: f64,
        courses: usize,
        brick_length: f64,
        brick_height: f64,
        #[serde(default)]
        bond: Bond,
    } => Ok(g::wall(*origin, *length, *courses, *brick_length, *brick_height, *bond)?.into()),
    /// A 2D region cut into blocks by joint sets (Shi's DC step): blocks
    /// are the closed faces of the joint traces and the region's boundary,
    /// numbered in the order the cutter finds them (the same for the same
    /// scene); traces ending inside a block leave it whole.
    JointedDomain([f64; 3], terse: false) {
        /// The region's corners (a simple polygon, either order), m.
        region: Vec<[f64; 2]>,
        /// The joint sets; none leaves the region one block.
        #[serde(default)]
        sets: Vec<JointSet>,
        /// Blocks smaller than this are left out, m²; default 1e-3 × the
        /// smallest spacing².
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min_block_area: Option<f64>,
        /// Blocks with every corner at or below this height are fixed, m;
        /// default none.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fixed_below: Option<f64>,
    } => g::jointed::cut_2d(region, sets, *min_block_area, *fixed_below),
    /// A convex 3D region cut into convex blocks by persistent joint sets.
    JointedDomain3D([f64; 6], terse: false) {
        /// `Box(min: (x, y, z), max: (x, y, z))` or `Hull([corners])`, m.
        region: Region3,
        #[serde(default)]
        sets: Vec<JointSet>,
        /// Blocks smaller than this are left out, m³; default 1e-3 × the
        /// smallest spacing³.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        min_block_volume: Option<f64>,
        /// Blocks with every corner at or below this z are fixed, m;
        /// default none.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        fixed_below: Option<f64>,
    } => g::jointed::cut_3d(region, sets, *min_block_volume, *fixed_below),
}

/// Whether a value is left out of the written text: at its default.
fn is_default<T: Default + PartialEq>(value: &T) -> bool {
    *value == T::default()
}

/// One block of the corners and faces given.
fn whole<P>((vertices, faces): (Vec<P>, Vec<Vec<usize>>)) -> Generated<P> {
    vec![g::Piece::new(None, vertices, faces)].into()
}

fn default_span_angle() -> f64 {
    180.0
}

fn default_true() -> bool {
    true
}

/// One block once generators are expanded: the numbering used by loads,
/// fixed points, joint sets, the ground motion and the outputs. In 2D
/// (`SceneBlock`) corners are (x, y), the velocity (vx, vy, ω) and the
/// stress (σx, σy, τxy); in 3D ([`SceneBlock3`]) corners are (x, y, z), the
/// velocity (vx, vy, vz, ωx, ωy, ωz) and the stress (σx, σy, σz, τyz, τzx,
/// τxy); tension positive.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneBlock<P = [f64; 2], const K: usize = 3> {
    /// Index of the `blocks` entry that makes it.
    pub entry: usize,
    /// Which block of a generator it is, like "voussoir 3"; `None` for an
    /// entry that makes one block.
    pub part: Option<String>,
    /// The outline (as written for a polygon, counter-clockwise otherwise)
    /// or the corners of a polyhedron.
    pub vertices: Vec<P>,
    /// Each face's corners, counter-clockwise seen from outside; none in 2D.
    pub faces: Vec<Vec<usize>>,
    pub fixed: bool,
    pub velocity: [f64; K],
    pub stress: [f64; K],
}

/// One block of a 3D scene.
pub type SceneBlock3 = SceneBlock<[f64; 3], 6>;

/// The laws a jointed domain's sets give its block pairs: (lower, higher)
/// block and law.
type SetLaws<'a> = Vec<((usize, usize), &'a JointLaw)>;

impl BlockSpec {
    /// A jointed domain's joint sets; none for other entries.
    pub fn joint_sets(&self) -> &[JointSet] {
        match self {
            BlockSpec::JointedDomain { sets, .. } | BlockSpec::JointedDomain3D { sets, .. } => sets,
            _ => &[],
        }
    }

    /// The laws the entry's sets give the `joints` it makes, as (block,
    /// block, set), its blocks numbered from `first`.
    fn set_laws(
        &self,
        joints: Vec<(usize, usize, usize)>,
        first: usize,
    ) -> impl Iterator<Item = ((usize, usize), &JointLaw)> {
        let law = move |(a, b, set): (usize, usize, usize)| {
            Some(((first + a, first + b), self.joint_sets()[set].law.as_ref()?))
        };
        joints.into_iter().filter_map(law)
    }

    /// The entry's pieces as blocks numbered `entry`, with its initial state
    /// (none if that has the other dimension's length).
    pub(crate) fn blocks_of<P, const K: usize>(
        &self,
        entry: usize,
        pieces: Vec<crate::generators::Piece<P>>,
    ) -> Vec<SceneBlock<P, K>> {
        let (Ok(velocity), Ok(stress)) = (self.velocity().try_into(), self.stress().try_into())
        else {
            return Vec::new();
        };
        pieces
            .into_iter()
            .map(|p| SceneBlock {
                entry,
                part: p.name,
                vertices: p.vertices,
                faces: p.faces,
                fixed: self.fixed() || p.always_fixed,
                // Abutments and blocks fixed below a level stay put.
                velocity: if p.always_fixed { [0.0; K] } else { velocity },
                stress,
            })
            .collect()
    }
}

/// Shaking of the ground under fixed base blocks: every fixed point of the
/// listed blocks follows the ground's displacement.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundMotionSpec {
    /// Block indices (generators expanded); each must be fixed.
    pub blocks: Vec<usize>,
    pub motion: MotionSpec,
}

/// The ground's motion, starting from rest at t = 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum MotionSpec {
    /// Acceleration `amplitude`·sin(2π·frequency·t) (m/s², Hz) for
    /// `duration` seconds, then none; the amplitude is (ax, ay) in 2D,
    /// (ax, ay, az) in 3D.
    Sine {
        amplitude: Coords,
        frequency: f64,
        duration: f64,
    },
    /// One sine pulse of acceleration (m/s²) lasting `period` seconds.
    Pulse { amplitude: Coords, period: f64 },
    /// A CSV file of `time, ax, ay` rows in 2D, `time, ax, ay, az` in 3D (a
    /// header line and `#` comment lines allowed), relative to the scene
    /// file's folder; values are multiplied by `scale` (9.81 for records in
    /// g). `components` names the axes of the value columns, in order, when
    /// they are not all of them: `"xz"` reads `time, ax, az` rows (the other
    /// components are zero). Acceleration records are baseline corrected
    /// unless `baseline_correction` is `false` (see
    /// [`dda_core::Record::baseline_corrected`]).
    Record {
        path: String,
        #[serde(default)]
        quantity: Quantity,
        #[serde(default = "default_scale")]
        scale: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        components: Option<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        baseline_correction: Option<bool>,
    },
}

fn default_scale() -> f64 {
    1.0
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Load {
    /// A force at a point of a block (moving with it): constant `force`, or a
    /// `history` of (t, fx, fy) samples ((t, fx, fy, fz) in 3D), linear in
    /// between.
    PointLoad {
        block: usize,
        point: Coords,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        force: Option<Coords>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        history: Option<Vec<Coords>>,
    },
}

/// A point of a block held by a penalty spring at `point + velocity·t`: in
/// place when `velocity` is zero (the default), driven otherwise. With an
/// `axis` only the motion along it is held (a roller); it need not be a unit
/// vector. Points, velocities and axes have one number per dimension; a
/// velocity left out is zero.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedPointSpec {
    pub block: usize,
    pub point: Coords,
    #[serde(default, skip_serializing_if = "Coords::is_empty")]
    pub velocity: Coords,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<Coords>,
}

/// A point of a block whose position and displacement from the start are
/// written to `points.csv` at every output time; nothing acts there. The
/// point (one number per dimension, m) must lie inside or on the block.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredPointSpec {
    pub block: usize,
    pub point: Coords,
}

/// Only the dimension, read first so a scene of another dimension gets a
/// clear answer instead of a complaint about its first field.
#[derive(Deserialize)]
#[serde(rename = "Scene")]
struct DimensionOnly {
    #[serde(default = "default_dimension")]
    dimension: u32,
}

/// Laws are written `Coulomb(friction_angle: 30.0)`, not
/// `Coulomb((friction_angle: 30.0))`, hence unwrapped newtypes.
fn extensions() -> ron::extensions::Extensions {
    ron::extensions::Extensions::IMPLICIT_SOME
        | ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES
}

fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(extensions())
}

impl Scene {
    /// Reads, parses and validates a scene file.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|error| SceneError::Read {
            file: origin.clone(),
            error,
        })?;
        let dir = path.parent().map(Path::to_path_buf);
        Scene::parse(&text, &origin, dir)
    }

    /// Parses and validates scene text; `origin` names it in errors. Files
    /// it names (ground-motion records) are relative to the current folder.
    pub fn from_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Scene::parse(text, origin, None)
    }

    fn parse(text: &str, origin: &str, dir: Option<PathBuf>) -> Result<Scene, SceneError> {
        let source = Source {
            origin: origin.to_string(),
            text: text.to_string(),
            dir,
        };
        if let Ok(d) = ron_options().from_str::<DimensionOnly>(text) {
            source.check_dimension(d.dimension)?;
        }
        let mut scene: Scene = ron_options()
            .from_str(text)
            .map_err(|e| source.syntax(&e))?;
        scene.source = source;
        scene.validate()?;
        Ok(scene)
    }

    /// The name of the file (or other origin) the scene was read from.
    pub fn origin(&self) -> &str {
        &self.source.origin
    }

    /// Renames where the scene came from, for a scene made from another one
    /// (files it names stay relative to the original's folder); its text is
    /// forgotten, so errors are no longer located by line.
    pub(crate) fn derive_origin(&mut self, origin: String) {
        self.source.origin = origin;
        self.source.text.clear();
    }

    /// The scene as RON text that [`Scene::from_str`] reads back (comments
    /// are not kept).
    pub fn to_ron(&self) -> String {
        let config = ron::ser::PrettyConfig::new()
            .struct_names(true)
            .depth_limit(4)
            .extensions(extensions());
        ron::ser::to_string_pretty(self, config).expect("a scene is always serialisable")
    }

    /// Where a file named in the scene is: relative paths are taken from
    /// the scene file's folder (the current one for [`Scene::from_str`]).
    pub fn resolve(&self, path: impl AsRef<Path>) -> PathBuf {
        let path = path.as_ref();
        match &self.source.dir {
            Some(dir) if path.is_relative() => dir.join(path),
            _ => path.to_path_buf(),
        }
    }

    /// The blocks of a 2D scene with generators expanded in place: what
    /// block indices in the scene (loads, fixed points, joint sets, ground
    /// motion) and in the outputs count. 3D entries are left out, and so
    /// are entries whose values make no blocks (see [`Scene::validate`]).
    pub fn expanded_blocks(&self) -> Vec<SceneBlock> {
        self.expanded::<dda_2d::Block, 2, 3>().0
    }

    /// The blocks of a 3D scene, as corners and faces. 2D entries are left
    /// out.
    pub fn expanded_blocks_3d(&self) -> Vec<SceneBlock3> {
        self.expanded::<dda_3d::Block, 3, 6>().0
    }

    /// The blocks with generators expanded, and the laws the sets of a
    /// jointed domain give its block pairs.
    fn expanded<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
    ) -> (Vec<SceneBlock<B::Corner, S>>, SetLaws<'_>) {
        let (mut blocks, mut set_laws) = (Vec::new(), Vec::new());
        for (k, spec) in self.blocks.iter().enumerate() {
            if let Ok(made) = B::generate(spec) {
                set_laws.extend(spec.set_laws(made.joints, blocks.len()));
                blocks.extend(spec.blocks_of(k, made.pieces));
            }
        }
        (blocks, set_laws)
    }

    /// How many blocks the scene has, generators expanded.
    pub fn block_count(&self) -> usize {
        match self.dimension {
            3 => self.expanded_blocks_3d().len(),
            _ => self.expanded_blocks().len(),
        }
    }

    /// The time between outputs for a nominal time step `dt` (`None`:
    /// every step), and a note when it was chosen automatically.
    pub fn output_interval(&self, dt: f64) -> (Option<f64>, Option<String>) {
        match self.output.interval {
            Some(interval) if interval > 0.0 && interval < dt => (
                None,
                Some(format!(
                    "output interval {interval:.4e} s is shorter than the time step {dt:.4e} s, so every step is written (as with output.interval: 0)"
                )),
            ),
            Some(interval) => ((interval > 0.0).then_some(interval), None),
            None => {
                let duration = self.analysis.duration;
                let interval = (duration / AUTO_OUTPUT_ROWS).max(dt);
                let rows = (duration / interval).round() + 1.0;
                (
                    Some(interval),
                    Some(format!(
                        "output interval {interval:.4e} s: the duration / {AUTO_OUTPUT_ROWS}, at least the time step, so history.csv has {rows} rows per block (give output.interval to choose, 0 for every step)"
                    )),
                )
            }
        }
    }

    /// Gravity as written, or the default: (0, −9.81) in 2D, (0, 0, −9.81)
    /// in 3D.
    pub fn gravity(&self) -> Vec<f64> {
        match &self.analysis.gravity {
            Some(g) => g.0.clone(),
            None if self.dimension == 3 => vec![0.0, 0.0, -9.81],
            None => vec![0.0, -9.81],
        }
    }

    /// A block entry's kind: its own, or else its material's.
    pub fn kind_of(&self, block: &BlockSpec) -> BlockKind {
        block.block_kind().unwrap_or_else(|| {
            self.material_index(block.material())
                .map_or(BlockKind::Deformable, |m| self.materials[m].1.kind)
        })
    }

    /// Index of the material `name`, if there is one (or of the only
    /// material for `None`, as for a block that names none).
    pub fn material_index(&self, name: Option<&str>) -> Option<usize> {
        match name {
            Some(name) => self.materials.iter().position(|(n, _)| n == name),
            None => (self.materials.len() == 1).then_some(0),
        }
    }
}
