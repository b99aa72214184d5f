//! Checks every value of a scene before anything is built, so errors point
//! at the file instead of surfacing mid-run.

use std::fmt;

use dda_2d::polygon::{self, PolygonError};
use nalgebra::{Point2, Vector2};

use super::locate::Seg;
use super::{BlockSpec, JointLaw, Load, Scene, SceneError, Weakening};

/// A path into the scene, like `blocks[2].vertices[1]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Place(Vec<Part>);

#[derive(Debug, Clone)]
enum Part {
    Field(String),
    Index(usize),
    Key(String),
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

    pub fn segs(&self) -> impl Iterator<Item = Seg<'_>> {
        self.0.iter().map(|p| match p {
            Part::Field(f) => Seg::Field(f),
            Part::Index(k) => Seg::Index(*k),
            Part::Key(k) => Seg::Key(k),
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
        self.check_joints()?;
        self.check_blocks()?;
        self.check_loads()
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
        self.finite_all(&at("gravity"), "gravity", &a.gravity)
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

    fn check_joints(&self) -> Result {
        self.check_law(&Place::root().field("default_joint"), &self.default_joint)?;
        let n = self.blocks.len();
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

    fn check_blocks(&self) -> Result {
        if self.blocks.is_empty() {
            return Err(self.error(
                &Place::root().field("blocks"),
                "the scene has no blocks; add at least one, like Rectangle(center: (0.0, 0.0), width: 1.0, height: 1.0)",
            ));
        }
        let mut outlines = Vec::with_capacity(self.blocks.len());
        for (k, block) in self.blocks.iter().enumerate() {
            outlines.push(self.check_block(k, block)?);
        }
        self.check_overlaps(&outlines)
    }

    fn check_block(&self, k: usize, block: &BlockSpec) -> Result<Vec<Point2<f64>>> {
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
        }
        self.finite_all(
            &at.field("velocity"),
            "the initial velocity",
            &block.velocity(),
        )?;
        self.finite_all(&at.field("stress"), "the initial stress", &block.stress())?;
        let points = to_points(&block.vertices());
        polygon::validate(&points).map_err(|e| self.error(&at, polygon_message(&e)))
    }

    /// Blocks may touch at the start but not overlap (beyond 1e-6 of the model size).
    fn check_overlaps(&self, outlines: &[Vec<Point2<f64>>]) -> Result {
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
                        &Place::root().field("blocks").index(b),
                        format!(
                            "the block overlaps blocks[{a}] at the start; move or resize one of them so they touch at most"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_loads(&self) -> Result {
        let n = self.blocks.len();
        for (k, load) in self.loads.iter().enumerate() {
            let at = Place::root().field("loads").index(k);
            match load {
                Load::PointLoad {
                    block,
                    point,
                    force,
                    history,
                } => {
                    self.check_block_index(&at.field("block"), *block, n)?;
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
            self.check_block_index(&at.field("block"), fp.block, n)?;
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

    fn check_block_index(&self, at: &Place, block: usize, n: usize) -> Result {
        if block < n {
            Ok(())
        } else if n == 0 {
            Err(self.error(
                at,
                format!("there is no block {block}: the scene has no blocks"),
            ))
        } else {
            Err(self.error(
                at,
                format!(
                    "there is no block {block}: the scene has {n} blocks, numbered from 0 to {}",
                    n - 1
                ),
            ))
        }
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
