//! Checks every value of a scene before anything is built, so errors point
//! at the file instead of surfacing mid-run.

use std::sync::Arc;

use dda_core::{
    loads, motion::Layout, settings, DdaError, FixedPoint, Force, GroundMotion, MeasuredPoint,
    PointLoad, Quantity, Record,
};
use nalgebra::{Point, SVector};

use super::dimension::SceneElement;
use super::locate::{locate_exact, place_of, Place};
use super::{
    BlockSpec, Coords, GroundMotionSpec, JointLaw, JointSet, Load, MotionSpec, Scene, SceneBlock,
    SceneError,
};
use crate::generators::Failure;

type Result<T = ()> = std::result::Result<T, SceneError>;

/// A scene's loads, fixed and measured points, checked, in `D` dimensions.
pub(super) struct Points<const D: usize> {
    pub loads: Vec<PointLoad<D>>,
    pub fixed: Vec<FixedPoint<D>>,
    pub measured: Vec<MeasuredPoint<D>>,
}

/// The blocks the ground motion drives, the motion, and a note on a
/// record's baseline.
pub(super) type Ground<const D: usize> = (Vec<usize>, Arc<GroundMotion<D>>, Option<String>);

/// A scene checked as one of `D` dimensions: its blocks (generators
/// expanded) with their shapes, and what acts on them.
pub(super) struct Checked<P, Shape, const D: usize, const S: usize> {
    pub blocks: Vec<SceneBlock<P, S>>,
    pub shapes: Vec<Shape>,
    pub points: Points<D>,
    pub ground: Option<Ground<D>>,
}

/// Why a dimension is refused.
pub(super) fn dimension_message(dimension: u32) -> String {
    format!(
        "dimension must be 2 (polygons in the xy plane) or 3 (polyhedra, z up), got {dimension}"
    )
}

/// A magnitude in a note: 3.726, 0.012 or 3.1e-5.
fn short(x: f64) -> String {
    if x >= 1e-3 {
        format!("{x:.3}")
    } else {
        format!("{x:.1e}")
    }
}

impl Scene {
    /// Checks the whole scene; the first problem found is returned.
    pub fn validate(&self) -> Result {
        if !(2..=3).contains(&self.dimension) {
            let at = Place::root().field("dimension");
            return Err(self.error(&at, dimension_message(self.dimension)));
        }
        if self.dimension == 3 {
            self.checked::<dda_3d::Block, 3, 6>().map(drop)
        } else {
            self.checked::<dda_2d::Block, 2, 3>().map(drop)
        }
    }

    /// Checks the scene as one of `D` dimensions made of `B` blocks, and
    /// returns what building it needs.
    pub(super) fn checked<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
    ) -> Result<Checked<B::Corner, B::Shape, D, S>> {
        let root = Place::root();
        self.check_analysis()?;
        if let Some(interval) = self.output.interval {
            let hint = "use 0 to write every step, or leave it out for an automatic one";
            let check = settings::non_negative("", "the output interval", interval, hint);
            self.core_field(&root.field("output").field("interval"), check)?;
        }
        // A material's values are checked by the core (its density) and
        // by the elastic law of the scene's dimension.
        for (name, m) in &self.materials {
            let checked = dda_core::constitutive::check_density(m.density)
                .and_then(|()| B::elastic(m, self.analysis.plane).check());
            self.core_field(&root.field("materials").key(name), checked)?;
        }
        let (blocks, shapes) = self.check_blocks::<B, D, S>()?;
        self.check_joints(blocks.len())?;
        let points = self.points::<D>(blocks.len())?;
        self.check_measured_points::<B, D, S>(&points.measured, &shapes)?;
        let ground = self.ground_motion(&blocks)?;
        Ok(Checked {
            blocks,
            shapes,
            points,
            ground,
        })
    }

    /// Whether the text the scene was read from writes a value at `place`.
    fn written(&self, place: &Place) -> bool {
        locate_exact(&self.source.text, place.segs()).is_some()
    }

    /// Checks that `c` has one number per name (`names` like `["fx",
    /// "fy"]`), saying what to write when the count is off; the values are
    /// checked by the type they go into.
    fn count(&self, at: &Place, what: &str, c: &Coords, names: &[String]) -> Result {
        if c.len() == names.len() {
            return Ok(());
        }
        let d = self.dimension;
        let other = if d == 3 {
            ""
        } else {
            " (or add dimension: 3 at the top for a 3D scene)"
        };
        Err(self.error(
            at,
            format!(
                "{what} has {} numbers, but this is a {d}D scene: write ({}){other}",
                c.len(),
                names.join(", ")
            ),
        ))
    }

    /// Names like "fx", "fy"(, "fz") for this scene's dimension.
    fn names(&self, prefix: &str) -> Vec<String> {
        let axes = ["x", "y", "z"].into_iter().take(self.dimension as usize);
        axes.map(|a| format!("{prefix}{a}")).collect()
    }

    /// `c` as a vector once it has one number per axis (names like "fx"
    /// with `prefix` "f").
    fn vector<const D: usize>(
        &self,
        at: &Place,
        what: &str,
        c: &Coords,
        prefix: &str,
    ) -> Result<SVector<f64, D>> {
        self.count(at, what, c, &self.names(prefix))?;
        Ok(SVector::from_fn(|k, _| c.get(k)))
    }

    /// `c` as a point once it has one number per axis.
    fn point<const D: usize>(&self, at: &Place, what: &str, c: &Coords) -> Result<Point<f64, D>> {
        self.vector(at, what, c, "").map(Point::from)
    }

    pub(super) fn error(&self, place: &Place, message: impl Into<String>) -> SceneError {
        self.source.invalid(place, message)
    }

    /// A check that names its own field: the error at that field of
    /// `base` (at `base` itself when it names none, and any other error
    /// there too, never dropped).
    fn core_field(&self, base: &Place, check: std::result::Result<(), DdaError>) -> Result {
        check.map_err(|e| match e {
            DdaError::Setting { field, message } if !field.is_empty() => {
                self.error(&base.field(field), message)
            }
            DdaError::Setting { message, .. } => self.error(base, message),
            DdaError::Entry {
                field,
                index,
                message,
            } => self.error(&base.field(field).index(index), message),
            e => self.error(base, e.to_string()),
        })
    }

    fn finite(&self, place: &Place, what: &str, v: f64) -> Result {
        self.core_field(place, settings::finite("", what, v))
    }

    fn positive(&self, place: &Place, what: &str, v: f64, hint: &str) -> Result {
        self.core_field(place, settings::positive("", what, v, hint))
    }

    fn check_analysis(&self) -> Result {
        let a = &self.analysis;
        let at = |name: &str| Place::root().field("analysis").field(name);
        self.positive(
            &at("duration"),
            "the duration",
            a.duration,
            "set analysis.duration to the simulated time in seconds (it is required)",
        )?;
        let auto = "give a value or leave it out for an automatic one";
        if let Some(p) = a.fixed_penalty {
            self.positive(&at("fixed_penalty"), "the fixed-point penalty", p, auto)?;
        }
        if let Some(g) = &a.gravity {
            self.count(&at("gravity"), "gravity", g, &self.names("g"))?;
            let finite = |v: &f64| self.finite(&at("gravity"), "gravity", *v);
            g.as_slice().iter().try_for_each(finite)?;
        }
        if self.dimension == 3 && self.written(&at("plane")) {
            return Err(self.error(
                &at("plane"),
                "plane (plane strain or plane stress) is for 2D scenes; a 3D scene has no plane: remove it",
            ));
        }
        if let Some(d) = &a.damping {
            self.core_field(&at("damping"), d.check())?;
        }
        // The driver checks its own settings; the scene names the place.
        self.core_field(&Place::root().field("analysis"), self.settings().validate())?;
        Ok(())
    }

    /// A law's values are checked by the law itself; the scene names the
    /// place (a `Custom` law's parameters by its registry, when the scene
    /// is built, but for their being numbers).
    fn check_law(&self, at: &Place, law: &JointLaw) -> Result {
        self.core_field(at, law.check())?;
        if let JointLaw::Custom { params, .. } = law {
            for (key, value) in params {
                let what = format!("the parameter {key:?}");
                self.finite(&at.field("params").key(key), &what, *value)?;
            }
        }
        Ok(())
    }

    fn check_joints(&self, n: usize) -> Result {
        self.check_law(&Place::root().field("default_joint"), &self.default_joint)?;
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        let mut block_pairs: Vec<((usize, usize), usize)> = Vec::new();
        for (k, joint) in self.joints.iter().enumerate() {
            let at = Place::root().field("joints").index(k);
            match (&joint.between, &joint.blocks) {
                (Some(between), None) => {
                    let side = |k| at.field("between").index(k);
                    let a = self.find_material(&side(0), &between.0)?;
                    let b = self.find_material(&side(1), &between.1)?;
                    let pair = (a.min(b), a.max(b));
                    if let Some(first) = pairs.iter().position(|p| *p == pair) {
                        return Err(self.error(
                            &at,
                            format!(
                                "the pair ({:?}, {:?}) already has a law in joints[{first}]; keep one of them",
                                between.0, between.1
                            ),
                        ));
                    }
                    pairs.push(pair);
                }
                (None, Some(list)) => {
                    if list.is_empty() {
                        return Err(self.error(
                            &at.field("blocks"),
                            "the joint set lists no block pairs; add pairs like (0, 1) or remove the entry",
                        ));
                    }
                    for (i, &[a, b]) in list.iter().enumerate() {
                        let at_pair = at.field("blocks").index(i);
                        for block in [a, b] {
                            self.check_block_index(&at_pair, block, n)?;
                        }
                        if a == b {
                            return Err(self.error(
                                &at_pair,
                                format!("({a}, {b}) pairs block {a} with itself; a joint is between two different blocks"),
                            ));
                        }
                        let key = (a.min(b), a.max(b));
                        if let Some(&(_, first)) = block_pairs.iter().find(|(p, _)| *p == key) {
                            let where_ = if first == k {
                                "earlier in this set".to_string()
                            } else {
                                format!("in joints[{first}]")
                            };
                            return Err(self.error(
                                &at_pair,
                                format!(
                                    "the block pair ({a}, {b}) is already listed {where_}; a pair belongs to one joint set only"
                                ),
                            ));
                        }
                        block_pairs.push((key, k));
                    }
                }
                (Some(_), Some(_)) => {
                    return Err(self.error(
                        &at,
                        "give either between: (material, material) or blocks: [(i, j), ...], not both",
                    ))
                }
                (None, None) => {
                    return Err(self.error(
                        &at,
                        r#"the joint set says neither which materials nor which blocks; add between: ("rock", "rock") or blocks: [(0, 1)]"#,
                    ))
                }
            }
            self.check_law(&at.field("law"), &joint.law)?;
        }
        Ok(())
    }

    fn find_material(&self, at: &Place, name: &str) -> Result<usize> {
        self.materials
            .iter()
            .position(|(n, _)| n == name)
            .ok_or_else(|| {
                self.error(
                    at,
                    format!(
                        "unknown material {name:?}; the materials are {}",
                        self.material_names()
                    ),
                )
            })
    }

    fn material_names(&self) -> String {
        if self.materials.is_empty() {
            return "none: add one under materials".to_string();
        }
        let names: Vec<String> = self
            .materials
            .iter()
            .map(|(n, _)| format!("{n:?}"))
            .collect();
        names.join(", ")
    }

    /// Checks every entry and the blocks it makes (each generator checks
    /// its own values); returns them and their shapes.
    #[allow(clippy::type_complexity)]
    fn check_blocks<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
    ) -> Result<(Vec<SceneBlock<B::Corner, S>>, Vec<B::Shape>)> {
        let root = Place::root().field("blocks");
        if self.blocks.is_empty() {
            let like = if D == 3 {
                "Box(center: (0.0, 0.0, 0.5), size: (1.0, 1.0, 1.0))"
            } else {
                "Rectangle(center: (0.0, 0.0), width: 1.0, height: 1.0)"
            };
            return Err(self.error(
                &root,
                format!("the scene has no blocks; add at least one, like {like}"),
            ));
        }
        let (mut blocks, mut shapes) = (Vec::new(), Vec::new());
        for (k, spec) in self.blocks.iter().enumerate() {
            let at = root.index(k);
            if spec.dimension() != self.dimension {
                return Err(self.error(&at, self.wrong_entry(spec)));
            }
            self.check_block_material(&at, spec)?;
            let kind = self.kind_of(spec);
            self.core_field(&at, kind.check_state(spec.velocity(), spec.stress()))?;
            self.check_sets(&at, spec.joint_sets())?;
            let written = matches!(
                spec,
                BlockSpec::Polygon { .. } | BlockSpec::Polyhedron { .. }
            );
            let made = B::generate(spec).map_err(|e| self.failure(&at, e))?;
            for block in spec.blocks_of(k, made.pieces) {
                shapes.push(B::shape(self, &at, &block, written)?);
                blocks.push(block);
            }
        }
        if let Some((i, j)) = B::first_overlap(&shapes) {
            let place = |b: &SceneBlock<_, S>| place_of(b.entry, b.part.as_deref());
            return Err(self.error(
                &place(&blocks[i]),
                format!(
                    "the block overlaps {} at the start; move or resize one of them so they touch at most",
                    place(&blocks[j])
                ),
            ));
        }
        Ok((blocks, shapes))
    }

    /// Why an entry of the other dimension does not belong.
    fn wrong_entry(&self, spec: &BlockSpec) -> String {
        let kind = spec.kind();
        if self.dimension == 3 {
            return format!("{kind} is a 2D block, but this is a 3D scene (dimension: 3); use Polyhedron, Box or Prism (`dda extrude` turns a 2D scene into prisms)");
        }
        let d = if self.written(&Place::root().field("dimension")) {
            "dimension: 2"
        } else {
            "dimension: 2, the default"
        };
        format!("{kind} is a 3D block, but this is a 2D scene ({d}); add dimension: 3 at the top for a 3D scene, or use Polygon or Rectangle")
    }

    /// The entry names an existing material, or the scene has only one.
    fn check_block_material(&self, at: &Place, block: &BlockSpec) -> Result {
        match block.material() {
            Some(name) => {
                self.find_material(&at.field("material"), name)?;
            }
            None if self.materials.len() == 1 => {}
            None => {
                return Err(self.error(
                    at,
                    format!(
                        "the block names no material; add material: with one of {}",
                        self.material_names()
                    ),
                ))
            }
        }
        Ok(())
    }

    /// Why an entry makes no blocks, at the field to change.
    fn failure(&self, at: &Place, e: Failure) -> SceneError {
        let at = match e.set {
            Some(k) => at.field("sets").index(k),
            None => at.clone(),
        };
        self.error(&e.field.map_or(at.clone(), |f| at.field(f)), e.message)
    }

    /// What the scene checks of a jointed domain's sets: their origins
    /// against its axes, and their laws at their place (each set checks
    /// its own values when the domain is cut).
    fn check_sets(&self, at: &Place, sets: &[JointSet]) -> Result {
        for (k, set) in sets.iter().enumerate() {
            let at = at.field("sets").index(k);
            if !set.origin.is_empty() {
                self.count(
                    &at.field("origin"),
                    "the origin",
                    &set.origin,
                    &self.names(""),
                )?;
            }
            if let Some(law) = &set.law {
                self.check_law(&at.field("law"), law)?;
            }
        }
        Ok(())
    }

    /// The scene's loads, fixed and measured points in `D` dimensions: the
    /// scene checks their blocks and their tuples' counts, the core their
    /// values (`PointLoad::check`, `FixedPoint::check`,
    /// `MeasuredPoint::check`).
    pub(super) fn points<const D: usize>(&self, n: usize) -> Result<Points<D>> {
        let root = Place::root();
        let mut loads = Vec::new();
        for (k, load) in self.loads.iter().enumerate() {
            let Load::PointLoad {
                block,
                point,
                force,
                history,
            } = load;
            let at = root.field("loads").index(k);
            self.check_block_index(&at.field("block"), *block, n)?;
            let point = self.point(&at.field("point"), "the load point", point)?;
            let force = match (force, history) {
                (Some(f), None) => {
                    Force::Constant(self.vector(&at.field("force"), "the force", f, "f")?)
                }
                (None, Some(h)) => Force::History(self.history(&at.field("history"), h)?),
                _ => {
                    let f = self.names("f").join(", ");
                    return Err(self.error(
                        &at,
                        format!("give either force: ({f}) or history: [(t, {f}), ...], not both or neither"),
                    ));
                }
            };
            let load = PointLoad {
                block: *block,
                point,
                force,
            };
            self.core_field(&at, load.check())?;
            loads.push(load);
        }
        let mut fixed = Vec::new();
        for (k, fp) in self.fixed_points.iter().enumerate() {
            let at = root.field("fixed_points").index(k);
            self.check_block_index(&at.field("block"), fp.block, n)?;
            let point = self.point(&at.field("point"), "the fixed point", &fp.point)?;
            let mut held = FixedPoint::at(fp.block, point);
            if !fp.velocity.is_empty() {
                held.velocity =
                    self.vector(&at.field("velocity"), "the velocity", &fp.velocity, "v")?;
            }
            if let Some(axis) = &fp.axis {
                held.axis = Some(self.vector(&at.field("axis"), "the axis", axis, "")?);
            }
            self.core_field(&at, held.check())?;
            // Checked: the axis has a direction.
            held.axis = held.axis.and_then(|a| loads::direction(&a).ok());
            fixed.push(held);
        }
        let mut measured = Vec::new();
        for (k, m) in self.measured_points.iter().enumerate() {
            let at = root.field("measured_points").index(k);
            self.check_block_index(&at.field("block"), m.block, n)?;
            let point = self.point(&at.field("point"), "the measured point", &m.point)?;
            let point = MeasuredPoint::at(m.block, point);
            self.core_field(&at, point.check())?;
            measured.push(point);
        }
        Ok(Points {
            loads,
            fixed,
            measured,
        })
    }

    /// Each measured point lies inside or on its block.
    fn check_measured_points<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
        measured: &[MeasuredPoint<D>],
        shapes: &[B::Shape],
    ) -> Result {
        for (k, m) in measured.iter().enumerate() {
            let off = B::outside(&shapes[m.block], &m.point);
            if off == 0.0 {
                continue;
            }
            let shown: Vec<String> = m.point.iter().map(|x| x.to_string()).collect();
            let hint = match shapes.iter().position(|s| B::outside(s, &m.point) == 0.0) {
                Some(other) => format!("it lies in block {other}: give block: {other}, or"),
                None => "it lies in no block:".to_string(),
            };
            return Err(self.error(
                &Place::root().field("measured_points").index(k).field("point"),
                format!(
                    "the measured point ({}) is {} m outside block {}; {hint} move the point inside or onto the block",
                    shown.join(", "),
                    short(off),
                    m.block
                ),
            ));
        }
        Ok(())
    }

    fn check_block_index(&self, at: &Place, block: usize, n: usize) -> Result {
        if block < n {
            return Ok(());
        }
        let generated = if self.blocks.iter().any(BlockSpec::is_generator) {
            " (generators counted block by block)"
        } else {
            ""
        };
        Err(self.error(
            at,
            format!(
                "there is no block {block}: the scene has {n} blocks{generated}, numbered from 0 to {}",
                n - 1
            ),
        ))
    }

    /// Checks the ground motion (reading its record, if any) and returns it
    /// with the blocks it drives and a note on a record's baseline.
    fn ground_motion<P, const D: usize, const S: usize>(
        &self,
        blocks: &[SceneBlock<P, S>],
    ) -> Result<Option<Ground<D>>> {
        let Some(GroundMotionSpec {
            blocks: driven,
            motion,
        }) = &self.ground_motion
        else {
            return Ok(None);
        };
        let root = Place::root().field("ground_motion");
        let at = root.field("blocks");
        if driven.is_empty() {
            return Err(self.error(
                &at,
                "the ground motion drives no blocks; list the fixed base blocks, like blocks: [0]",
            ));
        }
        for (i, &b) in driven.iter().enumerate() {
            let at = at.index(i);
            self.check_block_index(&at, b, blocks.len())?;
            if driven[..i].contains(&b) {
                return Err(self.error(
                    &at,
                    format!("block {b} is listed twice; list each base block once"),
                ));
            }
            let (block, entry) = (&blocks[b], blocks[b].entry);
            if !block.fixed {
                let (name, fix) = match &block.part {
                    Some(part) => (
                        format!("block {b} (blocks[{entry}], {part})"),
                        "list fixed base blocks instead, like an arch's abutments".to_string(),
                    ),
                    None => (
                        if entry == b {
                            format!("block {b}")
                        } else {
                            format!("block {b} (blocks[{entry}])")
                        },
                        format!(
                            "add fixed: true to blocks[{entry}], or list the fixed base blocks"
                        ),
                    ),
                };
                return Err(self.error(
                    &at,
                    format!("{name} is not fixed, so the ground cannot carry it; {fix}"),
                ));
            }
        }
        let at = root.field("motion");
        let amplitude = |a| self.vector(&at.field("amplitude"), "the amplitude", a, "a");
        let mut note = None;
        let motion = match motion {
            MotionSpec::Sine {
                amplitude: a,
                frequency,
                duration,
            } => GroundMotion::Sine {
                amplitude: amplitude(a)?,
                frequency: *frequency,
                duration: *duration,
            },
            MotionSpec::Pulse {
                amplitude: a,
                period,
            } => GroundMotion::Pulse {
                amplitude: amplitude(a)?,
                period: *period,
            },
            MotionSpec::Record {
                path,
                quantity,
                scale,
                components,
                baseline_correction,
            } => {
                self.finite(&at.field("scale"), "the scale", *scale)?;
                if *baseline_correction == Some(true) && *quantity != Quantity::Acceleration {
                    return Err(self.error(
                        &at.field("baseline_correction"),
                        "baseline correction applies to acceleration records only; remove baseline_correction or give quantity: Acceleration",
                    ));
                }
                let layout = Layout::new(components.as_deref(), D as u32)
                    .map_err(|m| self.error(&at.field("components"), m))?;
                if path.trim().is_empty() {
                    return Err(self.error(
                        &at.field("path"),
                        format!(
                            "the record's path is empty; name a CSV file of rows {}",
                            layout.row()
                        ),
                    ));
                }
                let file = self.resolve(path);
                let record = Record::<D>::read(&file, &layout, *quantity, *scale).map_err(|m| {
                    let place = if file.is_file() {
                        at.clone()
                    } else {
                        at.field("path")
                    };
                    self.error(&place, m)
                })?;
                if *quantity == Quantity::Acceleration {
                    let (u, v) = (record.end_displacement(), record.end_velocity());
                    let drift = format!(
                        "as recorded it ends {} m from where it started, moving at {} m/s",
                        short(u.norm()),
                        short(v.norm())
                    );
                    if *baseline_correction == Some(false) {
                        note = Some(format!(
                            "ground-motion record {path}: no baseline correction (baseline_correction: false); {drift}"
                        ));
                        GroundMotion::Record(record)
                    } else {
                        let fixed = record.baseline_corrected();
                        note = Some(format!(
                            "ground-motion record {path}: baseline corrected (a polynomial of degree {} fitted by least squares taken out of the acceleration, so the ground ends at rest where it started; baseline_correction: false turns this off); {drift}; corrected, {} m and {} m/s",
                            dda_core::motion::BASELINE_DEGREE,
                            short(fixed.end_displacement().norm()),
                            short(fixed.end_velocity().norm()),
                        ));
                        GroundMotion::Record(fixed)
                    }
                } else {
                    GroundMotion::Record(record)
                }
            }
        };
        self.core_field(&at, motion.check())?;
        Ok(Some((driven.clone(), Arc::new(motion), note)))
    }

    /// A load's history samples once each has one time and one force
    /// component per axis.
    fn history<const D: usize>(
        &self,
        at: &Place,
        samples: &[Coords],
    ) -> Result<Vec<(f64, SVector<f64, D>)>> {
        let mut names = vec!["t".to_string()];
        names.extend(self.names("f"));
        samples
            .iter()
            .enumerate()
            .map(|(i, s)| {
                self.count(&at.index(i), "the sample", s, &names)?;
                Ok((s.get(0), SVector::from_fn(|k, _| s.get(k + 1))))
            })
            .collect()
    }
}
