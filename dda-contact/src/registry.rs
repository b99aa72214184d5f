//! Laws by name, so scenes can name laws written in other crates.
//!
//! ```
//! use dda_contact::{Coulomb, LawRegistry, Params};
//!
//! let mut registry = LawRegistry::with_builtin();
//! registry.register("sticky", |p: &mut Params| {
//!     Ok(Coulomb { cohesion: p.take_or("cohesion", 1e5)?, ..Coulomb::frictional(p.take("friction_angle")?) })
//! });
//! let mut params = Params::from([("friction_angle", 35.0)]);
//! assert!(registry.build("sticky", &mut params).is_ok());
//! assert!(registry.build("no such law", &mut Params::default()).is_err());
//! ```

use std::collections::BTreeMap;

use dda_core::{ContactLaw, DynContactLaw};

use crate::{Coulomb, RateFriction, SlipWeakening, ThresholdBond, Weakening};

/// Numeric parameters of a law, by name. Builders `take` what they use; a
/// parameter nobody took is an error (a misspelling, most likely).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params(BTreeMap<String, f64>);

impl<const K: usize> From<[(&str, f64); K]> for Params {
    fn from(pairs: [(&str, f64); K]) -> Self {
        Params(pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect())
    }
}

impl From<BTreeMap<String, f64>> for Params {
    fn from(map: BTreeMap<String, f64>) -> Self {
        Params(map)
    }
}

impl Params {
    /// A required parameter.
    pub fn take(&mut self, name: &str) -> Result<f64, String> {
        self.0
            .remove(name)
            .ok_or_else(|| format!("the parameter `{name}` is required"))
    }

    /// An optional parameter with a default.
    pub fn take_or(&mut self, name: &str, default: f64) -> Result<f64, String> {
        Ok(self.0.remove(name).unwrap_or(default))
    }

    /// An optional parameter.
    pub fn take_opt(&mut self, name: &str) -> Option<f64> {
        self.0.remove(name)
    }

    /// Names no builder took.
    pub fn leftover(&self) -> Vec<&str> {
        self.0.keys().map(String::as_str).collect()
    }
}

type Builder = Box<dyn Fn(&mut Params) -> Result<Box<dyn DynContactLaw>, String> + Send + Sync>;

/// Contact-law builders by name.
#[derive(Default)]
pub struct LawRegistry {
    builders: BTreeMap<String, Builder>,
}

impl LawRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// The laws of this crate under their scene names: `coulomb`,
    /// `threshold_bond`, `displacement_strength`, `slip_friction`,
    /// `rate_friction` (parameters as the fields of each law, stiffnesses
    /// optional; weakening as `weakening_step`, or `weakening_start` and
    /// `weakening_end`, or `weakening_length`).
    pub fn with_builtin() -> Self {
        let mut r = Self::new();
        r.register("coulomb", |p| {
            Ok(Coulomb {
                friction_angle: p.take("friction_angle")?,
                cohesion: p.take_or("cohesion", 0.0)?,
                tensile_strength: p.take_or("tensile_strength", 0.0)?,
                normal_stiffness: p.take_opt("normal_stiffness"),
                shear_stiffness: p.take_opt("shear_stiffness"),
            })
        });
        r.register("threshold_bond", |p| {
            Ok(ThresholdBond {
                friction_angle: p.take("friction_angle")?,
                max_opening: p.take("max_opening")?,
                max_shear: p.take("max_shear")?,
                normal_stiffness: p.take_opt("normal_stiffness"),
                shear_stiffness: p.take_opt("shear_stiffness"),
            })
        });
        r.register("displacement_strength", |p| {
            let peak = p.take("friction_angle")?;
            Ok(SlipWeakening {
                peak_friction_angle: peak,
                residual_friction_angle: p.take_or("residual_friction_angle", peak)?,
                peak_cohesion: p.take("cohesion")?,
                residual_cohesion: p.take_or("residual_cohesion", 0.0)?,
                tensile_strength: p.take_or("tensile_strength", 0.0)?,
                weakening: weakening(p)?,
                normal_stiffness: p.take_opt("normal_stiffness"),
                shear_stiffness: p.take_opt("shear_stiffness"),
            })
        });
        r.register("slip_friction", |p| {
            Ok(SlipWeakening {
                normal_stiffness: p.take_opt("normal_stiffness"),
                shear_stiffness: p.take_opt("shear_stiffness"),
                ..SlipWeakening::friction(
                    p.take("peak_friction_angle")?,
                    p.take("residual_friction_angle")?,
                    weakening(p)?,
                )
            })
        });
        r.register("rate_friction", |p| {
            Ok(RateFriction {
                static_friction_angle: p.take("static_friction_angle")?,
                dynamic_friction_angle: p.take("dynamic_friction_angle")?,
                characteristic_rate: p.take("characteristic_rate")?,
                normal_stiffness: p.take_opt("normal_stiffness"),
                shear_stiffness: p.take_opt("shear_stiffness"),
            })
        });
        r
    }

    /// Registers (or replaces) a law under `name`.
    pub fn register<L, F>(&mut self, name: &str, build: F)
    where
        L: ContactLaw,
        F: Fn(&mut Params) -> Result<L, String> + Send + Sync + 'static,
    {
        self.builders.insert(
            name.to_string(),
            Box::new(move |p| build(p).map(|law| Box::new(law) as Box<dyn DynContactLaw>)),
        );
    }

    /// Builds the law `name` from `params`, which must all be used.
    pub fn build(&self, name: &str, params: &mut Params) -> Result<Box<dyn DynContactLaw>, String> {
        let builder = self.builders.get(name).ok_or_else(|| {
            format!(
                "no contact law is registered as `{name}`; known laws: {}",
                self.names().collect::<Vec<_>>().join(", ")
            )
        })?;
        let law = builder(params)?;
        match params.leftover().as_slice() {
            [] => law.check().map(|_| law).map_err(|e| e.to_string()),
            unused => Err(format!(
                "the law `{name}` has no parameter {}",
                unused.join(", ")
            )),
        }
    }

    /// Registered names, sorted.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.builders.keys().map(String::as_str)
    }
}

/// The weakening curve from `weakening_step`, `weakening_start`/`_end` or
/// `weakening_length`.
fn weakening(p: &mut Params) -> Result<Weakening, String> {
    let w = match (
        p.take_opt("weakening_step"),
        p.take_opt("weakening_start"),
        p.take_opt("weakening_end"),
        p.take_opt("weakening_length"),
    ) {
        (Some(at), None, None, None) => Weakening::Step { at },
        (None, Some(start), Some(end), None) => Weakening::Linear { start, end },
        (None, None, None, Some(length)) => Weakening::Exponential { length },
        _ => {
            return Err("give one weakening: `weakening_step`, or `weakening_start` and `weakening_end`, or `weakening_length`".into())
        }
    };
    w.check().map_err(|e| e.to_string())?;
    Ok(w)
}
