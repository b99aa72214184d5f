//! Checks every value of a scene before anything is built, so errors point
//! at the file instead of surfacing mid-run. A value is checked by the type
//! that owns it; the scene names its place and checks what only it knows:
//! tuple counts against the dimension, names, block indices, overlaps.

use std::collections::HashMap;
use std::sync::Arc;

use dda_core::motion::Layout;
use dda_core::{
    settings, DdaError, FixedPoint, Force, GroundMotion, MeasuredPoint, PointLoad, Record,
};
use nalgebra::SVector;

use super::dimension::SceneElement;
use super::locate::{locate_exact, place_of, Place};
use super::{BlockSpec, Coords, GroundMotionSpec, JointLaw, LawTable, Load, Material, MotionSpec};
use super::{Scene, SceneBlock, SetLaws};
use super::{SceneError, Source};

/// The strongest gravity a scene may have, m/s²: about 10,000 g, where a
/// geotechnical centrifuge spins models at a few hundred.
const STRONGEST_GRAVITY: f64 = 1e5;

type Result<T = ()> = std::result::Result<T, SceneError>;

/// The blocks the ground motion drives, the motion, and a note on a
/// record's baseline.
pub(super) type Ground<const D: usize> = (Vec<usize>, Arc<GroundMotion<D>>, Option<String>);

/// A scene checked as one of `D` dimensions: its blocks (generators
/// expanded) with their shapes, and what acts on them.
pub(super) struct Checked<P, Shape, const D: usize, const S: usize> {
    pub blocks: Vec<SceneBlock<P, S>>,
    pub shapes: Vec<Shape>,
    pub loads: Vec<PointLoad<D>>,
    pub fixed: Vec<FixedPoint<D>>,
    pub measured: Vec<MeasuredPoint<D>>,
    pub ground: Option<Ground<D>>,
    pub laws: LawTable,
}

impl Source {
    /// Refuses a dimension other than 2 and 3.
    pub(super) fn check_dimension(&self, dimension: u32) -> Result {
        if (2..=3).contains(&dimension) {
            return Ok(());
        }
        Err(self.invalid(
            &Place::root().field("dimension"),
            format!("dimension must be 2 (polygons in the xy plane) or 3 (polyhedra, z up), got {dimension}"),
        ))
    }
}

impl Scene {
    /// Checks the whole scene; the first problem found is returned.
    pub fn validate(&self) -> Result {
        self.source.check_dimension(self.dimension)?;
        match self.dimension {
            3 => self.checked::<dda_3d::Block, 3, 6>().map(drop),
            _ => self.checked::<dda_2d::Block, 2, 3>().map(drop),
        }
    }

    /// Checks the scene as one of `D` dimensions made of `B` blocks, and
    /// returns what building it needs.
    pub(super) fn checked<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
    ) -> Result<Checked<B::Corner, B::Shape, D, S>> {
        let root = Place::root();
        self.check_analysis::<D>()?;
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
        let (blocks, shapes, set_laws) = self.check_blocks::<B, D, S>()?;
        self.check_joints(blocks.len())?;
        Ok(Checked {
            laws: self.laws_of(set_laws),
            loads: self.loads(blocks.len())?,
            fixed: self.fixed_points(blocks.len())?,
            measured: self.measured_points::<B, D, S>(&shapes)?,
            ground: self.ground_motion(&blocks)?,
            blocks,
            shapes,
        })
    }

    /// Whether the text the scene was read from writes a value at `place`.
    pub(super) fn written(&self, place: &Place) -> bool {
        locate_exact(&self.source.text, place.segs()).is_some()
    }

    /// `c` as a vector once it has one number per axis (`prefix` names
    /// them, like "f" for (fx, fy)); its values are checked by the type it
    /// goes into.
    fn vector<const D: usize>(
        &self,
        at: &Place,
        what: &str,
        c: &Coords,
        prefix: &str,
    ) -> Result<SVector<f64, D>> {
        let numbers = c
            .numbers(D, what, false, prefix)
            .map_err(|m| self.error(at, m))?;
        Ok(SVector::from_column_slice(numbers))
    }

    pub(super) fn error(&self, place: &Place, message: impl Into<String>) -> SceneError {
        self.source.invalid(place, message)
    }

    /// A check's value, or its error at the field it names within `base`
    /// (at `base` itself when it names none; any other error there too).
    fn core_field<T>(&self, base: &Place, check: std::result::Result<T, DdaError>) -> Result<T> {
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

    fn check_analysis<const D: usize>(&self) -> Result {
        let a = &self.analysis;
        let at = |name: &str| Place::root().field("analysis").field(name);
        let hint = "set analysis.duration to the simulated time in seconds (it is required)";
        let duration = settings::positive("", "the duration", a.duration, hint);
        self.core_field(&at("duration"), duration)?;
        if let Some(p) = a.fixed_penalty {
            let auto = "give a value or leave it out for an automatic one";
            let penalty = settings::positive("", "the fixed-point penalty", p, auto);
            self.core_field(&at("fixed_penalty"), penalty)?;
        }
        if let Some(g) = &a.gravity {
            let g = self.vector::<D>(&at("gravity"), "gravity", g, "g")?;
            let finite = |v: &f64| settings::finite("", "gravity", *v);
            self.core_field(&at("gravity"), g.iter().try_for_each(finite))?;
            // Beyond it a run overflowed and asked for a smaller step.
            let magnitude = g.iter().fold(0.0_f64, |m, v| m.hypot(*v));
            if magnitude > STRONGEST_GRAVITY {
                return Err(self.error(
                    &at("gravity"),
                    format!("gravity's magnitude {magnitude:e} m/s² is above {STRONGEST_GRAVITY:e} (about 10,000 g; a geotechnical centrifuge spins models at a few hundred g); give it in m/s² (the Earth's 9.81)"),
                ));
            }
        }
        if D == 3 && self.written(&at("plane")) {
            return Err(self.error(
                &at("plane"),
                "plane (plane strain or plane stress) is for 2D scenes; a 3D scene has no plane: remove it",
            ));
        }
        if let Some(d) = &a.damping {
            self.core_field(&at("damping"), d.check())?;
        }
        if let Some(settle) = &a.settle {
            if settle.steps == 0 {
                return Err(self.error(
                    &at("settle").field("steps"),
                    "settling takes at least one static step; give 1 or more, or leave steps out for 20",
                ));
            }
            if a.integrator == dda_core::Integrator::Explicit {
                return Err(self.error(
                    &at("settle"),
                    "settling takes implicit steps; with integrator: Explicit, relax the model to rest in a run of its own with local_damping: 0.8, or remove settle",
                ));
            }
        }
        // The driver checks its own settings; the scene names the place.
        self.core_field(&Place::root().field("analysis"), a.settings().validate())
    }

    /// A law's values are checked by the law itself; the scene names the
    /// place (a `Custom` law's parameters by its registry, when the scene
    /// is built, but for their being numbers).
    fn check_law(&self, at: &Place, law: &JointLaw) -> Result {
        self.core_field(at, law.check())?;
        if let JointLaw::Custom { params, .. } = law {
            for (key, value) in params {
                let finite = settings::finite("", &format!("the parameter {key:?}"), *value);
                self.core_field(&at.field("params").key(key), finite)?;
            }
        }
        Ok(())
    }

    fn check_joints(&self, n: usize) -> Result {
        self.check_law(&Place::root().field("default_joint"), &self.default_joint)?;
        // Each pair of materials or of blocks, with the set that gives it.
        let (mut pairs, mut block_pairs) = (HashMap::new(), HashMap::new());
        for (k, joint) in self.joints.iter().enumerate() {
            let at = Place::root().field("joints").index(k);
            match (&joint.between, &joint.blocks) {
                (Some((a, b)), None) => {
                    let side = |k| at.field("between").index(k);
                    let i = self.find_material(&side(0), Some(a))?;
                    let j = self.find_material(&side(1), Some(b))?;
                    let pair = (i.min(j), i.max(j));
                    if let Some(first) = pairs.insert(pair, k) {
                        return Err(self.error(
                            &at,
                            format!("the pair ({a:?}, {b:?}) already has a law in joints[{first}]; keep one of them"),
                        ));
                    }
                }
                (None, Some(list)) if list.is_empty() => {
                    return Err(self.error(
                        &at.field("blocks"),
                        "the joint set lists no block pairs; add pairs like (0, 1) or remove the entry",
                    ));
                }
                (None, Some(list)) => {
                    for (i, &[a, b]) in list.iter().enumerate() {
                        let at_pair = at.field("blocks").index(i);
                        self.check_block_index(&at_pair, a, n)?;
                        self.check_block_index(&at_pair, b, n)?;
                        if a == b {
                            return Err(self.error(
                                &at_pair,
                                format!("({a}, {b}) pairs block {a} with itself; a joint is between two different blocks"),
                            ));
                        }
                        let key = (a.min(b), a.max(b));
                        if let Some(first) = block_pairs.insert(key, k) {
                            let where_ = match first == k {
                                true => "earlier in this set".to_string(),
                                false => format!("in joints[{first}]"),
                            };
                            return Err(self.error(
                                &at_pair,
                                format!("the block pair ({a}, {b}) is already listed {where_}; a pair belongs to one joint set only"),
                            ));
                        }
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

    /// The index of the material `name` (at `at`), or of the scene's only
    /// one when the entry at `at` names none.
    fn find_material(&self, at: &Place, name: Option<&str>) -> Result<usize> {
        self.material_index(name).ok_or_else(|| {
            let quoted = |(n, _): &(String, Material)| format!("{n:?}");
            let names: Vec<String> = self.materials.iter().map(quoted).collect();
            let names = match names.is_empty() {
                true => "none: add one under materials".to_string(),
                false => names.join(", "),
            };
            let message = match name {
                Some(name) => format!("unknown material {name:?}; the materials are {names}"),
                None => format!("the block names no material; add material: with one of {names}"),
            };
            self.error(at, message)
        })
    }

    /// Checks every entry and the blocks it makes (each generator checks
    /// its own values); returns them, their shapes and the laws of the
    /// joints their sets make.
    #[allow(clippy::type_complexity)]
    fn check_blocks<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
    ) -> Result<(Vec<SceneBlock<B::Corner, S>>, Vec<B::Shape>, SetLaws<'_>)> {
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
        let (mut blocks, mut shapes, mut set_laws) = (Vec::new(), Vec::new(), Vec::new());
        for (k, spec) in self.blocks.iter().enumerate() {
            let at = root.index(k);
            // An entry of the other dimension has its state's length.
            if spec.velocity().len() != S {
                return Err(self.error(&at, self.wrong_entry(spec)));
            }
            let material = spec.material().map_or(at.clone(), |_| at.field("material"));
            self.find_material(&material, spec.material())?;
            let kind = self.kind_of(spec);
            self.core_field(&at, kind.check_state(spec.velocity(), spec.stress()))?;
            // A jointed domain's sets: their origins' counts and their laws
            // (each set checks its own values when the domain is cut).
            for (s, set) in spec.joint_sets().iter().enumerate() {
                let at = at.field("sets").index(s);
                if !set.origin.is_empty() {
                    self.vector::<D>(&at.field("origin"), "the origin", &set.origin, "")?;
                }
                if let Some(law) = &set.law {
                    self.check_law(&at.field("law"), law)?;
                }
            }
            // Why the entry makes no blocks, at the field to change.
            let made = B::generate(spec).map_err(|e| {
                let at = e.set.map_or(at.clone(), |k| at.field("sets").index(k));
                self.error(&e.field.map_or(at.clone(), |f| at.field(f)), e.message)
            })?;
            set_laws.extend(spec.set_laws(made.joints, blocks.len()));
            for block in spec.blocks_of(k, made.pieces) {
                shapes.push(B::shape(self, &at, &block)?);
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
        Ok((blocks, shapes, set_laws))
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

    /// The scene's loads: the scene checks their blocks and tuples'
    /// counts, `PointLoad::check` their values.
    fn loads<const D: usize>(&self, n: usize) -> Result<Vec<PointLoad<D>>> {
        let mut loads = Vec::new();
        for (k, load) in self.loads.iter().enumerate() {
            let Load::PointLoad {
                block,
                point,
                force,
                history,
            } = load;
            let at = Place::root().field("loads").index(k);
            self.check_block_index(&at.field("block"), *block, n)?;
            let point = self.vector::<D>(&at.field("point"), "the load point", point, "")?;
            let force = match (force, history) {
                (Some(f), None) => {
                    Force::Constant(self.vector(&at.field("force"), "the force", f, "f")?)
                }
                (None, Some(h)) => {
                    // Each sample: one time and one force component per axis.
                    let sample = |(i, s): (usize, &Coords)| {
                        let n = s.numbers(D, "the sample", true, "f");
                        let n = n.map_err(|m| self.error(&at.field("history").index(i), m))?;
                        Ok((n[0], SVector::from_column_slice(&n[1..])))
                    };
                    Force::History(h.iter().enumerate().map(sample).collect::<Result<_>>()?)
                }
                _ => {
                    let f = ["fx", "fy", "fz"][..D].join(", ");
                    return Err(self.error(
                        &at,
                        format!("give either force: ({f}) or history: [(t, {f}), ...], not both or neither"),
                    ));
                }
            };
            let load = PointLoad {
                block: *block,
                point: point.into(),
                force,
            };
            self.core_field(&at, load.check())?;
            loads.push(load);
        }
        Ok(loads)
    }

    /// The scene's fixed points, checked by `FixedPoint::check` once their
    /// blocks and counts are.
    fn fixed_points<const D: usize>(&self, n: usize) -> Result<Vec<FixedPoint<D>>> {
        let mut fixed = Vec::new();
        for (k, fp) in self.fixed_points.iter().enumerate() {
            let at = Place::root().field("fixed_points").index(k);
            self.check_block_index(&at.field("block"), fp.block, n)?;
            let point = self.vector::<D>(&at.field("point"), "the fixed point", &fp.point, "")?;
            let mut held = FixedPoint::at(fp.block, point.into());
            if !fp.velocity.is_empty() {
                held.velocity =
                    self.vector(&at.field("velocity"), "the velocity", &fp.velocity, "v")?;
            }
            if let Some(axis) = &fp.axis {
                held.axis = Some(self.vector(&at.field("axis"), "the axis", axis, "")?);
            }
            self.core_field(&at, held.check())?;
            // Checked: the axis has a direction.
            held.axis = held.axis.and_then(|a| dda_core::loads::direction(&a).ok());
            fixed.push(held);
        }
        Ok(fixed)
    }

    /// The scene's measured points, each inside or on its block.
    fn measured_points<B: SceneElement<D, S>, const D: usize, const S: usize>(
        &self,
        shapes: &[B::Shape],
    ) -> Result<Vec<MeasuredPoint<D>>> {
        let mut measured = Vec::new();
        for (k, m) in self.measured_points.iter().enumerate() {
            let at = Place::root().field("measured_points").index(k);
            self.check_block_index(&at.field("block"), m.block, shapes.len())?;
            let point = self.vector::<D>(&at.field("point"), "the measured point", &m.point, "")?;
            let point = MeasuredPoint::at(m.block, point.into());
            self.core_field(&at, point.check())?;
            let off = B::outside(&shapes[m.block], &point.point);
            if off != 0.0 {
                let shown: Vec<String> = m.point.as_slice().iter().map(f64::to_string).collect();
                let inside = |s: &B::Shape| B::outside(s, &point.point) == 0.0;
                let hint = match shapes.iter().position(inside) {
                    Some(other) => format!("it lies in block {other}: give block: {other}, or"),
                    None => "it lies in no block:".to_string(),
                };
                let off = match off {
                    x if x >= 1e-3 => format!("{x:.3}"),
                    x => format!("{x:.1e}"),
                };
                return Err(self.error(
                    &at.field("point"),
                    format!(
                        "the measured point ({}) is {off} m outside block {}; {hint} move the point inside or onto the block",
                        shown.join(", "),
                        m.block
                    ),
                ));
            }
            measured.push(point);
        }
        Ok(measured)
    }

    fn check_block_index(&self, at: &Place, block: usize, n: usize) -> Result {
        if block < n {
            return Ok(());
        }
        // Some entry made several blocks.
        let generated = if n != self.blocks.len() {
            " (generators counted block by block)"
        } else {
            ""
        };
        let last = n - 1;
        Err(self.error(
            at,
            format!("there is no block {block}: the scene has {n} blocks{generated}, numbered from 0 to {last}"),
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
        if driven.is_empty() {
            return Err(self.error(
                &root.field("blocks"),
                "the ground motion drives no blocks; list the fixed base blocks, like blocks: [0]",
            ));
        }
        for (i, &b) in driven.iter().enumerate() {
            let at = root.field("blocks").index(i);
            self.check_block_index(&at, b, blocks.len())?;
            if driven[..i].contains(&b) {
                return Err(self.error(
                    &at,
                    format!("block {b} is listed twice; list each base block once"),
                ));
            }
            let (block, entry) = (&blocks[b], blocks[b].entry);
            if !block.fixed {
                let name = match (&block.part, entry == b) {
                    (Some(part), _) => format!("block {b} (blocks[{entry}], {part})"),
                    (None, true) => format!("block {b}"),
                    (None, false) => format!("block {b} (blocks[{entry}])"),
                };
                let fix = match block.part {
                    Some(_) => "list fixed base blocks instead, like an arch's abutments".into(),
                    None => {
                        format!("add fixed: true to blocks[{entry}], or list the fixed base blocks")
                    }
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
                let layout = Layout::new(components.as_deref(), D as u32)
                    .map_err(|m| self.error(&at.field("components"), m))?;
                let file = self.resolve(path);
                let record = Record::load(&file, &layout, *quantity, *scale, *baseline_correction);
                let (record, baseline) = self.core_field(&at, record)?;
                note = baseline.map(|n| format!("ground-motion record {path}: {n}"));
                GroundMotion::Record(record)
            }
        };
        self.core_field(&at, motion.check())?;
        Ok(Some((driven.clone(), Arc::new(motion), note)))
    }
}
