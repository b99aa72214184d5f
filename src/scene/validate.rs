//! Checks every value of a scene before anything is built, so errors point
//! at the file instead of surfacing mid-run.

use std::fmt;
use std::sync::Arc;

use dda_2d::polygon::{self, PolygonError};
use dda_core::{GroundMotion, Record};
use nalgebra::{Point2, Vector2};

use super::generate::{self, MAX_PARTS};
use super::locate::Seg;
use super::motion::read_record;
use super::{
    BlockSpec, GroundMotionSpec, JointLaw, Load, MotionSpec, Scene, SceneBlock, SceneError,
    Weakening,
};

/// A path into the scene, like `blocks[2].vertices[1]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Place(Vec<Part>);

#[derive(Debug, Clone)]
enum Part {
    Field(String),
    Index(usize),
    Key(String),
    /// Which block of a generator; shown, not located.
    Label(String),
}

impl Place {
    pub fn root() -> Self {
        Self::default()
    }

    fn with(&self, part: Part) -> Self {
        let mut p = self.clone();
        p.0.push(part);
        p
    }

    pub fn field(&self, name: &str) -> Self {
        self.with(Part::Field(name.to_string()))
    }

    pub fn index(&self, k: usize) -> Self {
        self.with(Part::Index(k))
    }

    pub fn key(&self, k: &str) -> Self {
        self.with(Part::Key(k.to_string()))
    }

    /// A note after the place, like `blocks[0] (voussoir 3)`.
    pub fn label(&self, label: &str) -> Self {
        self.with(Part::Label(label.to_string()))
    }

    pub fn segs(&self) -> impl Iterator<Item = Seg<'_>> {
        self.0.iter().filter_map(|p| match p {
            Part::Field(f) => Some(Seg::Field(f)),
            Part::Index(k) => Some(Seg::Index(*k)),
            Part::Key(k) => Some(Seg::Key(k)),
            Part::Label(_) => None,
        })
    }
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, p) in self.0.iter().enumerate() {
            match p {
                Part::Field(name) if i == 0 => f.write_str(name)?,
                Part::Field(name) => write!(f, ".{name}")?,
                Part::Index(k) => write!(f, "[{k}]")?,
                Part::Key(k) => write!(f, "[{k:?}]")?,
                Part::Label(label) => write!(f, " ({label})")?,
            }
        }
        Ok(())
    }
}

type Result<T = ()> = std::result::Result<T, SceneError>;

impl Scene {
    /// Checks the whole scene; the first problem found is returned.
    pub fn validate(&self) -> Result {
        let root = Place::root();
        if self.dimension != 2 {
            return Err(self.error(
                &root.field("dimension"),
                format!(
                    "3D scenes are not supported yet (dimension: {}); only dimension: 2 can be run for now",
                    self.dimension
                ),
            ));
        }
        self.check_analysis()?;
        let interval = self.output.interval;
        let at = root.field("output").field("interval");
        self.finite(&at, "the output interval", interval)?;
        if interval < 0.0 {
            return Err(self.error(
                &at,
                format!("the output interval must not be negative, got {interval}; use 0 to write every step"),
            ));
        }
        self.check_materials()?;
        let blocks = self.check_blocks()?;
        self.check_joints(&blocks)?;
        self.check_loads(&blocks)?;
        self.ground_motion(&blocks)?;
        Ok(())
    }

    pub(super) fn error(&self, place: &Place, message: impl Into<String>) -> SceneError {
        self.source.invalid(place, message)
    }

    fn finite(&self, place: &Place, what: &str, v: f64) -> Result {
        if v.is_finite() {
            Ok(())
        } else {
            Err(self.error(
                place,
                format!("{what} is {v}, not a finite number; write a finite value"),
            ))
        }
    }

    fn finite_all(&self, place: &Place, what: &str, values: &[f64]) -> Result {
        for v in values {
            self.finite(place, what, *v)?;
        }
        Ok(())
    }

    fn positive(&self, place: &Place, what: &str, v: f64, hint: &str) -> Result {
        self.finite(place, what, v)?;
        if v > 0.0 {
            Ok(())
        } else {
            Err(self.error(place, format!("{what} must be positive, got {v}; {hint}")))
        }
    }

    fn non_negative(&self, place: &Place, what: &str, v: f64, hint: &str) -> Result {
        self.finite(place, what, v)?;
        if v >= 0.0 {
            Ok(())
        } else {
            Err(self.error(
                place,
                format!("{what} must not be negative, got {v}; {hint}"),
            ))
        }
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
        if let Some(dt) = a.dt {
            self.positive(
                &at("dt"),
                "the time step dt",
                dt,
                "give a time step in seconds or leave dt out for an automatic one",
            )?;
        }
        if let Some(k) = a.velocity_ratio {
            self.finite(&at("velocity_ratio"), "velocity_ratio", k)?;
            if !(0.0..=1.0).contains(&k) {
                return Err(self.error(
                    &at("velocity_ratio"),
                    format!("velocity_ratio must lie in [0, 1] (1 dynamic, 0 static), got {k}"),
                ));
            }
        }
        if a.open_close_limit == 0 {
            return Err(self.error(
                &at("open_close_limit"),
                "open_close_limit must be at least 1 (6 is usual)",
            ));
        }
        let ratio_hint = "it is a fraction of the model size, like 0.01";
        self.positive(
            &at("max_displacement_ratio"),
            "max_displacement_ratio",
            a.max_displacement_ratio,
            ratio_hint,
        )?;
        self.positive(
            &at("max_penetration_ratio"),
            "max_penetration_ratio",
            a.max_penetration_ratio,
            ratio_hint,
        )?;
        self.positive(
            &at("min_dt_ratio"),
            "min_dt_ratio",
            a.min_dt_ratio,
            "it is a fraction of dt, like 0.001",
        )?;
        if a.min_dt_ratio > 1.0 {
            return Err(self.error(
                &at("min_dt_ratio"),
                format!(
                    "min_dt_ratio is a fraction of dt and must not exceed 1, got {}",
                    a.min_dt_ratio
                ),
            ));
        }
        let auto = "give a value or leave it out for an automatic one";
        if let Some(p) = a.penalty {
            self.positive(&at("penalty"), "the penalty", p, auto)?;
        }
        if let Some(w) = a.length_scale {
            self.positive(&at("length_scale"), "the length scale", w, auto)?;
        }
        if let Some(p) = a.fixed_penalty {
            self.positive(&at("fixed_penalty"), "the fixed-point penalty", p, auto)?;
        }
        self.finite_all(&at("gravity"), "gravity", &a.gravity)?;
        if let Some(d) = &a.damping {
            let at = at("damping");
            self.non_negative(
                &at.field("ratio"),
                "the damping ratio",
                d.ratio,
                "it is a fraction of critical damping, like 0.05",
            )?;
            self.positive(
                &at.field("frequency"),
                "the damping frequency",
                d.frequency,
                "give the frequency (Hz) at which the ratio holds, like the structure's first mode",
            )?;
        }
        Ok(())
    }

    fn check_materials(&self) -> Result {
        for (name, m) in &self.materials {
            let at = |f: &str| Place::root().field("materials").key(name).field(f);
            self.positive(
                &at("density"),
                "the density",
                m.density,
                "give the mass per unit volume (kg/m³)",
            )?;
            self.positive(
                &at("young"),
                "Young's modulus",
                m.young,
                "give the elastic modulus (Pa)",
            )?;
            self.finite(&at("poisson"), "Poisson's ratio", m.poisson)?;
            if !(0.0..0.5).contains(&m.poisson) {
                return Err(self.error(
                    &at("poisson"),
                    format!(
                        "Poisson's ratio must lie in [0, 0.5), got {}; rock is usually 0.2–0.3",
                        m.poisson
                    ),
                ));
            }
        }
        Ok(())
    }

    fn check_law(&self, at: &Place, law: &JointLaw) -> Result {
        let (normal_stiffness, shear_stiffness) = match law {
            JointLaw::Coulomb {
                friction_angle,
                cohesion,
                tensile_strength,
                normal_stiffness,
                shear_stiffness,
            } => {
                self.angle(at, "friction_angle", "the friction angle", *friction_angle)?;
                self.strength(at, "cohesion", "the cohesion", *cohesion)?;
                self.strength(
                    at,
                    "tensile_strength",
                    "the tensile strength",
                    *tensile_strength,
                )?;
                (normal_stiffness, shear_stiffness)
            }
            JointLaw::ThresholdBond {
                friction_angle,
                max_opening,
                max_shear,
                normal_stiffness,
                shear_stiffness,
            } => {
                self.angle(at, "friction_angle", "the friction angle", *friction_angle)?;
                let hint = "it is the displacement (m) at which the bond breaks, like 1e-4";
                self.positive(&at.field("max_opening"), "max_opening", *max_opening, hint)?;
                self.positive(&at.field("max_shear"), "max_shear", *max_shear, hint)?;
                (normal_stiffness, shear_stiffness)
            }
            JointLaw::DisplacementStrength {
                friction_angle,
                residual_friction_angle,
                cohesion,
                residual_cohesion,
                tensile_strength,
                weakening,
                normal_stiffness,
                shear_stiffness,
            } => {
                self.angle(at, "friction_angle", "the friction angle", *friction_angle)?;
                if let Some(phi) = residual_friction_angle {
                    self.angle(
                        at,
                        "residual_friction_angle",
                        "the residual friction angle",
                        *phi,
                    )?;
                }
                self.strength(at, "cohesion", "the cohesion", *cohesion)?;
                self.strength(
                    at,
                    "residual_cohesion",
                    "the residual cohesion",
                    *residual_cohesion,
                )?;
                self.strength(
                    at,
                    "tensile_strength",
                    "the tensile strength",
                    *tensile_strength,
                )?;
                self.check_weakening(&at.field("weakening"), weakening)?;
                (normal_stiffness, shear_stiffness)
            }
            JointLaw::SlipFriction {
                peak_friction_angle,
                residual_friction_angle,
                weakening,
                normal_stiffness,
                shear_stiffness,
            } => {
                self.angle(
                    at,
                    "peak_friction_angle",
                    "the peak friction angle",
                    *peak_friction_angle,
                )?;
                self.angle(
                    at,
                    "residual_friction_angle",
                    "the residual friction angle",
                    *residual_friction_angle,
                )?;
                self.check_weakening(&at.field("weakening"), weakening)?;
                (normal_stiffness, shear_stiffness)
            }
            JointLaw::RateFriction {
                static_friction_angle,
                dynamic_friction_angle,
                characteristic_rate,
                normal_stiffness,
                shear_stiffness,
            } => {
                self.angle(
                    at,
                    "static_friction_angle",
                    "the static friction angle",
                    *static_friction_angle,
                )?;
                self.angle(
                    at,
                    "dynamic_friction_angle",
                    "the dynamic friction angle",
                    *dynamic_friction_angle,
                )?;
                self.positive(
                    &at.field("characteristic_rate"),
                    "the characteristic rate",
                    *characteristic_rate,
                    "it is the slip rate (m/s) over which friction falls, like 0.1",
                )?;
                (normal_stiffness, shear_stiffness)
            }
            JointLaw::Custom { name, params } => {
                if name.trim().is_empty() {
                    return Err(self.error(
                        &at.field("name"),
                        "the law's name is empty; give the name it is registered under",
                    ));
                }
                for (key, value) in params {
                    self.finite(
                        &at.field("params").key(key),
                        &format!("the parameter {key:?}"),
                        *value,
                    )?;
                }
                // The registry checks the rest when the scene is built.
                return Ok(());
            }
        };
        let auto = "give a positive stiffness or leave it out for an automatic one";
        if let Some(k) = normal_stiffness {
            self.positive(
                &at.field("normal_stiffness"),
                "the normal stiffness",
                *k,
                auto,
            )?;
        }
        if let Some(k) = shear_stiffness {
            self.positive(
                &at.field("shear_stiffness"),
                "the shear stiffness",
                *k,
                auto,
            )?;
        }
        Ok(())
    }

    /// A friction angle in [0, 90) degrees.
    fn angle(&self, law: &Place, field: &str, what: &str, phi: f64) -> Result {
        let at = law.field(field);
        self.finite(&at, what, phi)?;
        if (0.0..90.0).contains(&phi) {
            Ok(())
        } else {
            Err(self.error(
                &at,
                format!("{what} must lie in [0, 90) degrees, got {phi}"),
            ))
        }
    }

    /// A cohesion or tensile strength: zero or positive.
    fn strength(&self, law: &Place, field: &str, what: &str, v: f64) -> Result {
        self.non_negative(&law.field(field), what, v, "use 0 for none")
    }

    fn check_weakening(&self, at: &Place, w: &Weakening) -> Result {
        let values: &[f64] = match w {
            Weakening::Step { at } => &[*at],
            Weakening::Linear { start, end } => &[*start, *end],
            Weakening::Exponential { length } => &[*length],
        };
        self.finite_all(at, "the weakening slip", values)?;
        w.check().map_err(|reason| {
            self.error(
                at,
                format!("{reason}; slips are in m, like Step(at: 0.001) or Linear(start: 0.0, end: 0.01)"),
            )
        })
    }

    fn check_joints(&self, blocks: &[SceneBlock]) -> Result {
        self.check_law(&Place::root().field("default_joint"), &self.default_joint)?;
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        let mut block_pairs: Vec<((usize, usize), usize)> = Vec::new();
        for (k, joint) in self.joints.iter().enumerate() {
            let at = Place::root().field("joints").index(k);
            match (&joint.between, &joint.blocks) {
                (Some(between), None) => {
                    let mut pair = [0; 2];
                    for (side, name) in [&between.0, &between.1].into_iter().enumerate() {
                        pair[side] = self.find_material(&at.field("between").index(side), name)?;
                    }
                    let pair = (pair[0].min(pair[1]), pair[0].max(pair[1]));
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
                            self.check_block_index(&at_pair, block, blocks)?;
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

    /// Checks every entry, expands the generators and checks the blocks
    /// they make; returns the expanded blocks.
    fn check_blocks(&self) -> Result<Vec<SceneBlock>> {
        if self.blocks.is_empty() {
            return Err(self.error(
                &Place::root().field("blocks"),
                "the scene has no blocks; add at least one, like Rectangle(center: (0.0, 0.0), width: 1.0, height: 1.0)",
            ));
        }
        let mut blocks = Vec::new();
        let mut outlines = Vec::new();
        for (k, spec) in self.blocks.iter().enumerate() {
            self.check_block(k, spec)?;
            for block in spec.expand(k) {
                let points = to_points(&block.vertices);
                polygon::validate(&points).map_err(|e| {
                    let message = polygon_message(&e);
                    let message = match block.part {
                        // "Remove a vertex" is no help with generated blocks.
                        Some(_) => format!(
                            "the generated block is degenerate: {}; change the generator's sizes",
                            message.split(';').next().unwrap_or_default()
                        ),
                        None => message,
                    };
                    self.error(&self.block_place(&block), message)
                })?;
                outlines.push(points);
                blocks.push(block);
            }
        }
        self.check_overlaps(&blocks, &outlines)?;
        Ok(blocks)
    }

    /// `blocks[k]`, with the part for a generated block.
    pub(super) fn block_place(&self, block: &SceneBlock) -> Place {
        let at = Place::root().field("blocks").index(block.entry);
        match &block.part {
            Some(part) => at.label(part),
            None => at,
        }
    }

    /// "block 7", and which entry makes it when that is not plain.
    fn block_name(&self, index: usize, blocks: &[SceneBlock]) -> String {
        match blocks.get(index) {
            Some(SceneBlock {
                entry,
                part: Some(part),
                ..
            }) => format!("block {index} (blocks[{entry}], {part})"),
            Some(SceneBlock { entry, .. }) if *entry != index => {
                format!("block {index} (blocks[{entry}])")
            }
            _ => format!("block {index}"),
        }
    }

    /// The entry's own values: material, sizes, counts, initial state.
    fn check_block(&self, k: usize, block: &BlockSpec) -> Result {
        let at = Place::root().field("blocks").index(k);
        match block.material() {
            Some(name) => {
                self.find_material(&at.field("material"), name)?;
            }
            None if self.materials.len() == 1 => {}
            None => {
                return Err(self.error(
                    &at,
                    format!(
                        "the block names no material; add material: with one of {}",
                        self.material_names()
                    ),
                ))
            }
        }
        match block {
            BlockSpec::Polygon { vertices, .. } => {
                for (i, v) in vertices.iter().enumerate() {
                    self.finite_all(&at.field("vertices").index(i), &format!("vertex {i}"), v)?;
                }
            }
            BlockSpec::Rectangle {
                center,
                width,
                height,
                angle,
                ..
            } => {
                self.finite_all(&at.field("center"), "the center", center)?;
                self.positive(
                    &at.field("width"),
                    "the width",
                    *width,
                    "give the rectangle's size",
                )?;
                self.positive(
                    &at.field("height"),
                    "the height",
                    *height,
                    "give the rectangle's size",
                )?;
                self.finite(&at.field("angle"), "the angle", *angle)?;
            }
            BlockSpec::Arch {
                center,
                radius,
                thickness,
                voussoirs,
                span_angle,
                pointed,
                ..
            } => self.check_arch(
                &at,
                &generate::ArchShape {
                    center: *center,
                    radius: *radius,
                    thickness: *thickness,
                    voussoirs: *voussoirs,
                    span_angle: *span_angle,
                    pointed: *pointed,
                    abutments: true,
                },
            )?,
            BlockSpec::Column {
                base,
                drums,
                drum_height,
                width,
                ..
            } => {
                self.finite_all(&at.field("base"), "the base", base)?;
                self.count(&at.field("drums"), "drums", *drums, 1)?;
                let hint = "give the column's size in m";
                self.positive(
                    &at.field("drum_height"),
                    "the drum height",
                    *drum_height,
                    hint,
                )?;
                self.positive(&at.field("width"), "the width", *width, hint)?;
            }
            BlockSpec::Wall {
                origin,
                length,
                courses,
                brick_length,
                brick_height,
                ..
            } => {
                self.finite_all(&at.field("origin"), "the origin", origin)?;
                let hint = "give the wall's sizes in m";
                self.positive(&at.field("length"), "the length", *length, hint)?;
                self.count(&at.field("courses"), "courses", *courses, 1)?;
                self.positive(
                    &at.field("brick_length"),
                    "the brick length",
                    *brick_length,
                    hint,
                )?;
                self.positive(
                    &at.field("brick_height"),
                    "the brick height",
                    *brick_height,
                    hint,
                )?;
                let n = generate::wall_count(*length, *courses, *brick_length);
                if n > MAX_PARTS as f64 {
                    return Err(self.error(
                        &at,
                        format!(
                            "the wall would have about {n:.0} bricks, more than {MAX_PARTS}; use longer bricks, fewer courses or a shorter wall"
                        ),
                    ));
                }
            }
        }
        self.finite_all(
            &at.field("velocity"),
            "the initial velocity",
            &block.velocity(),
        )?;
        self.finite_all(&at.field("stress"), "the initial stress", &block.stress())
    }

    /// A number of generated blocks: at least `min`, at most [`MAX_PARTS`].
    fn count(&self, at: &Place, what: &str, n: usize, min: usize) -> Result {
        if n < min {
            Err(self.error(at, format!("{what} must be at least {min}, got {n}")))
        } else if n > MAX_PARTS {
            Err(self.error(
                at,
                format!("{n} {what} is more than the {MAX_PARTS} a generator makes; use fewer"),
            ))
        } else {
            Ok(())
        }
    }

    fn check_arch(&self, at: &Place, arch: &generate::ArchShape) -> Result {
        self.finite_all(&at.field("center"), "the center", &arch.center)?;
        let hint = "give the arch's size in m";
        self.positive(&at.field("radius"), "the radius", arch.radius, hint)?;
        self.positive(
            &at.field("thickness"),
            "the thickness",
            arch.thickness,
            hint,
        )?;
        if arch.radius <= arch.thickness / 2.0 {
            return Err(self.error(
                &at.field("radius"),
                format!(
                    "the radius ({}) must exceed half the thickness ({}): it is the centreline's, with the intrados at radius − thickness/2; use a larger radius or a thinner arch",
                    arch.radius, arch.thickness
                ),
            ));
        }
        self.count(&at.field("voussoirs"), "voussoirs", arch.voussoirs, 2)?;
        let span = arch.span_angle;
        self.finite(&at.field("span_angle"), "the span angle", span)?;
        if !(span > 0.0 && span <= 180.0) {
            return Err(self.error(
                &at.field("span_angle"),
                format!(
                    "the span angle must lie in (0, 180] degrees, got {span}; 180 is a semicircular arch, less a segmental one"
                ),
            ));
        }
        let e = arch.pointed;
        self.finite(&at.field("pointed"), "pointed", e)?;
        if !(0.0..1.0).contains(&e) {
            return Err(self.error(
                &at.field("pointed"),
                format!(
                    "pointed must lie in [0, 1), got {e}; it is the offset of the two centres as a fraction of the radius (0 for a round arch)"
                ),
            ));
        }
        if e > 0.0 {
            if arch.voussoirs % 2 == 1 {
                return Err(self.error(
                    &at.field("voussoirs"),
                    format!(
                        "a pointed arch needs an even number of voussoirs (half on each side of the crown joint), got {}",
                        arch.voussoirs
                    ),
                ));
            }
            let (ri, _) = arch.radii();
            if ri <= e * arch.radius {
                return Err(self.error(
                    &at.field("pointed"),
                    format!(
                        "the intrados (radius {ri}) does not reach the crown: the centres are {} from it; use a smaller pointed or a thinner arch",
                        e * arch.radius
                    ),
                ));
            }
        }
        if arch.springing_angle() <= arch.crown_angle() {
            return Err(self.error(
                &at.field("span_angle"),
                format!(
                    "a span angle of {span} degrees ends above the crown of this pointed arch; use more than {} degrees",
                    2.0 * (arch.crown_angle() - 90.0)
                ),
            ));
        }
        Ok(())
    }

    /// Blocks may touch at the start but not overlap (beyond 1e-6 of the model size).
    fn check_overlaps(&self, blocks: &[SceneBlock], outlines: &[Vec<Point2<f64>>]) -> Result {
        let bounds: Vec<(Point2<f64>, Point2<f64>)> = outlines.iter().map(|o| bounds(o)).collect();
        let lo = bounds.iter().fold(bounds[0].0, |a, b| a.inf(&b.0));
        let hi = bounds.iter().fold(bounds[0].1, |a, b| a.sup(&b.1));
        let tol = 1e-6 * (hi - lo).norm();
        // Sweep along x so large scenes are not quadratic.
        let mut order: Vec<usize> = (0..outlines.len()).collect();
        order.sort_by(|&a, &b| bounds[a].0.x.total_cmp(&bounds[b].0.x));
        for (n, &i) in order.iter().enumerate() {
            for &j in &order[n + 1..] {
                if bounds[j].0.x > bounds[i].1.x + tol {
                    break;
                }
                if polygon::overlap(&outlines[i], &outlines[j], tol) {
                    let (a, b) = (i.min(j), i.max(j));
                    return Err(self.error(
                        &self.block_place(&blocks[b]),
                        format!(
                            "the block overlaps {} at the start; move or resize one of them so they touch at most",
                            self.block_place(&blocks[a])
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_loads(&self, blocks: &[SceneBlock]) -> Result {
        for (k, load) in self.loads.iter().enumerate() {
            let at = Place::root().field("loads").index(k);
            match load {
                Load::PointLoad {
                    block,
                    point,
                    force,
                    history,
                } => {
                    self.check_block_index(&at.field("block"), *block, blocks)?;
                    self.finite_all(&at.field("point"), "the load point", point)?;
                    match (force, history) {
                        (Some(f), None) => self.finite_all(&at.field("force"), "the force", f)?,
                        (None, Some(h)) => self.check_history(&at.field("history"), h)?,
                        _ => {
                            return Err(self.error(
                                &at,
                                "give either force: (fx, fy) or history: [(t, fx, fy), ...], not both or neither",
                            ))
                        }
                    }
                }
            }
        }
        for (k, fp) in self.fixed_points.iter().enumerate() {
            let at = Place::root().field("fixed_points").index(k);
            self.check_block_index(&at.field("block"), fp.block, blocks)?;
            self.finite_all(&at.field("point"), "the fixed point", &fp.point)?;
            self.finite_all(&at.field("velocity"), "the velocity", &fp.velocity)?;
            if let Some(axis) = fp.axis {
                let at = at.field("axis");
                self.finite_all(&at, "the axis", &axis)?;
                if unit_axis(axis).is_none() {
                    return Err(self.error(
                        &at,
                        format!(
                            "the axis ({}, {}) has no direction; give the direction to hold, like (1.0, 0.0), or leave axis out to hold both",
                            axis[0], axis[1]
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_block_index(&self, at: &Place, block: usize, blocks: &[SceneBlock]) -> Result {
        let n = blocks.len();
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
    /// with the blocks it drives.
    pub(super) fn ground_motion(
        &self,
        blocks: &[SceneBlock],
    ) -> Result<Option<(Vec<usize>, Arc<GroundMotion<2>>)>> {
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
            self.check_block_index(&at, b, blocks)?;
            if driven[..i].contains(&b) {
                return Err(self.error(
                    &at,
                    format!("block {b} is listed twice; list each base block once"),
                ));
            }
            let block = &blocks[b];
            if !block.fixed {
                let fix = match block.part {
                    Some(_) => {
                        "list fixed base blocks instead, like an arch's abutments".to_string()
                    }
                    None => format!(
                        "add fixed: true to blocks[{}], or list the fixed base blocks",
                        block.entry
                    ),
                };
                return Err(self.error(
                    &at,
                    format!(
                        "{} is not fixed, so the ground cannot carry it; {fix}",
                        self.block_name(b, blocks),
                    ),
                ));
            }
        }
        let at = root.field("motion");
        let amplitude = |a: &[f64; 2]| Vector2::from(*a);
        let motion = match motion {
            MotionSpec::Sine {
                amplitude: a,
                frequency,
                duration,
            } => {
                self.finite_all(&at.field("amplitude"), "the amplitude", a)?;
                self.positive(
                    &at.field("frequency"),
                    "the frequency",
                    *frequency,
                    "give it in Hz",
                )?;
                self.positive(
                    &at.field("duration"),
                    "the duration",
                    *duration,
                    "give how long the shaking lasts, in s",
                )?;
                GroundMotion::Sine {
                    amplitude: amplitude(a),
                    frequency: *frequency,
                    duration: *duration,
                }
            }
            MotionSpec::Pulse {
                amplitude: a,
                period,
            } => {
                self.finite_all(&at.field("amplitude"), "the amplitude", a)?;
                self.positive(
                    &at.field("period"),
                    "the period",
                    *period,
                    "give the pulse's length in s",
                )?;
                GroundMotion::Pulse {
                    amplitude: amplitude(a),
                    period: *period,
                }
            }
            MotionSpec::Record {
                path,
                quantity,
                scale,
            } => {
                self.finite(&at.field("scale"), "the scale", *scale)?;
                if path.trim().is_empty() {
                    return Err(self.error(
                        &at.field("path"),
                        "the record's path is empty; name a CSV file of rows `time, ax, ay`",
                    ));
                }
                let file = self.resolve(path);
                let samples = read_record(&file).map_err(|message| {
                    let place = if file.is_file() {
                        at.clone()
                    } else {
                        at.field("path")
                    };
                    self.error(&place, message)
                })?;
                let samples: Vec<(f64, Vector2<f64>)> = samples
                    .iter()
                    .map(|&(_, t, v)| (t, amplitude(&v) * *scale))
                    .collect();
                let record = Record::new(*quantity, &samples)
                    .map_err(|e| self.error(&at, format!("{}: {e}", file.display())))?;
                GroundMotion::Record(record)
            }
        };
        Ok(Some((driven.clone(), Arc::new(motion))))
    }

    fn check_history(&self, at: &Place, samples: &[[f64; 3]]) -> Result {
        if samples.is_empty() {
            return Err(self.error(
                at,
                "the history is empty; give at least one (t, fx, fy) sample",
            ));
        }
        for (i, s) in samples.iter().enumerate() {
            self.finite_all(&at.index(i), "the sample", s)?;
            if i > 0 && s[0] < samples[i - 1][0] {
                return Err(self.error(
                    &at.index(i),
                    format!(
                        "the sample's time {} comes before the previous one's ({}); list samples in time order",
                        s[0],
                        samples[i - 1][0]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The unit vector along `axis`, if it has a direction.
pub(super) fn unit_axis(axis: [f64; 2]) -> Option<Vector2<f64>> {
    let v = Vector2::from(axis);
    let scale = v.amax();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    // Scaled first so tiny or huge components neither underflow nor overflow.
    let v = v / scale;
    Some(v / v.norm())
}

pub(super) fn to_points(v: &[[f64; 2]]) -> Vec<Point2<f64>> {
    v.iter().map(|p| Point2::new(p[0], p[1])).collect()
}

fn bounds(points: &[Point2<f64>]) -> (Point2<f64>, Point2<f64>) {
    points
        .iter()
        .fold((points[0], points[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

/// The polygon error with what to do about it.
pub(super) fn polygon_message(e: &PolygonError) -> String {
    match e {
        PolygonError::TooFewVertices(n) => {
            format!("a polygon needs at least 3 vertices, this one has {n}; add vertices")
        }
        PolygonError::NotFinite { index } => {
            format!("vertex {index} is not a finite number; write finite coordinates")
        }
        PolygonError::DuplicateVertex { a, b } => {
            format!("vertices {a} and {b} coincide; remove one of them")
        }
        PolygonError::SelfIntersecting { a, b } => format!(
            "the polygon is self-intersecting (edges {a} and {b} cross each other); reorder its vertices so the boundary does not cross itself"
        ),
        PolygonError::ZeroArea => {
            "the polygon has zero area (its vertices lie on one line); give vertices that enclose an area".to_string()
        }
    }
}
