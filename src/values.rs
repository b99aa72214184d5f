//! Values a scene file writes that its generators read too: tuples of
//! numbers ([`Coords`]), joint laws ([`JointLaw`]) and maps kept in file
//! order. They are here, not in the scene, so the generators (a jointed
//! domain's sets name a law and an origin) and the scene both use them
//! without either importing the other.

use dda_contact::{
    Coulomb, LawRegistry, Params, RateFriction, SlipWeakening, ThresholdBond, Weakening,
};
use dda_core::{DdaError, DynContactLaw};
use serde::{Deserialize, Serialize};

/// A contact law as a scene names it. Angles are in degrees, strengths in
/// Pa, lengths in m; stiffnesses left out (`None`) are automatic: the
/// driver's penalty and 1/2.5 of it for shear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum JointLaw {
    /// Penalty Coulomb joint with a bond (cohesion, tensile strength) that
    /// breaks the first time the joint opens or slides.
    Coulomb(Coulomb),
    /// A bond with no strength limit until the opening passes `max_opening`
    /// or the shear displacement passes `max_shear`; frictional after.
    ThresholdBond(ThresholdBond),
    /// Cohesion (and friction) falling from peak to residual with
    /// accumulated slip; the residual angle defaults to `friction_angle`.
    DisplacementStrength {
        friction_angle: f64,
        #[serde(default)]
        residual_friction_angle: Option<f64>,
        #[serde(default)]
        cohesion: f64,
        #[serde(default)]
        residual_cohesion: f64,
        #[serde(default)]
        tensile_strength: f64,
        weakening: Weakening,
        #[serde(default)]
        normal_stiffness: Option<f64>,
        #[serde(default)]
        shear_stiffness: Option<f64>,
    },
    /// Friction falling from a peak to a residual angle with accumulated slip.
    SlipFriction {
        peak_friction_angle: f64,
        residual_friction_angle: f64,
        weakening: Weakening,
        #[serde(default)]
        normal_stiffness: Option<f64>,
        #[serde(default)]
        shear_stiffness: Option<f64>,
    },
    /// Friction falling from its static to its dynamic value as the slip
    /// rate grows past `characteristic_rate` (m/s).
    RateFriction(RateFriction),
    /// A law built by name through a [`dda_contact::LawRegistry`], like
    /// `Custom(name: "coulomb", params: {"friction_angle": 30.0})`.
    Custom {
        name: String,
        #[serde(default, with = "ordered_map")]
        params: Vec<(String, f64)>,
    },
}

impl Default for JointLaw {
    fn default() -> Self {
        JointLaw::Coulomb(Coulomb::frictional(30.0))
    }
}

impl JointLaw {
    /// The contact law it names; typed laws are built directly, `Custom`
    /// ones by the registry, whose error says what to change.
    pub fn build(&self, registry: &LawRegistry) -> Result<Box<dyn DynContactLaw>, String> {
        Ok(match self.clone() {
            JointLaw::Coulomb(law) => Box::new(law),
            JointLaw::ThresholdBond(law) => Box::new(law),
            JointLaw::DisplacementStrength {
                friction_angle,
                residual_friction_angle,
                cohesion,
                residual_cohesion,
                tensile_strength,
                weakening,
                normal_stiffness,
                shear_stiffness,
            } => Box::new(SlipWeakening {
                peak_friction_angle: friction_angle,
                residual_friction_angle: residual_friction_angle.unwrap_or(friction_angle),
                peak_cohesion: cohesion,
                residual_cohesion,
                tensile_strength,
                weakening,
                normal_stiffness,
                shear_stiffness,
            }),
            JointLaw::SlipFriction {
                peak_friction_angle,
                residual_friction_angle,
                weakening,
                normal_stiffness,
                shear_stiffness,
            } => Box::new(SlipWeakening {
                normal_stiffness,
                shear_stiffness,
                ..SlipWeakening::friction(peak_friction_angle, residual_friction_angle, weakening)
            }),
            JointLaw::RateFriction(law) => Box::new(law),
            JointLaw::Custom { name, params } => {
                let mut params = Params::from(
                    params
                        .into_iter()
                        .collect::<std::collections::BTreeMap<_, _>>(),
                );
                return registry.build(&name, &mut params).map_err(|e| {
                    if registry.names().any(|n| n == name) {
                        let hint = if e.contains("is required") {
                            "; add it to params"
                        } else if e.contains("has no parameter") {
                            "; remove it from params or correct its spelling"
                        } else {
                            ""
                        };
                        if e.contains(&format!("`{name}`")) {
                            format!("{e}{hint}")
                        } else {
                            format!("the law `{name}`: {e}{hint}")
                        }
                    } else {
                        format!("{e}; correct the name, or register the law with LawRegistry::register and build the scene with Scene::build_with")
                    }
                });
            }
        })
    }

    /// The law's own check of its values, naming the field as the scene
    /// writes it. A `Custom` law's parameters are checked by its registry
    /// when it is built; here only its name.
    pub fn check(&self) -> Result<(), DdaError> {
        let checked = match self {
            JointLaw::Custom { name, .. } if name.trim().is_empty() => Err(DdaError::Setting {
                field: "name",
                message: "the law's name is empty; give the name it is registered under".into(),
            }),
            JointLaw::Custom { .. } => Ok(()),
            law => law.build(&LawRegistry::new()).map_or(Ok(()), |l| l.check()),
        };
        checked.map_err(|e| match (self, e) {
            // A displacement-strength law names its peaks plainly.
            (JointLaw::DisplacementStrength { .. }, DdaError::Setting { field, message }) => {
                let field = match field {
                    "peak_friction_angle" => "friction_angle",
                    "peak_cohesion" => "cohesion",
                    f => f,
                };
                DdaError::Setting { field, message }
            }
            (_, e) => e,
        })
    }
}

/// Numbers written as a tuple, like `(0.0, -9.81)` or `(1.0, 2.0, 3.0)`: a
/// point or vector with one number per dimension of the scene (a load
/// history's samples have the time first). The count is checked against
/// the scene's dimension ([`Coords::numbers`]), and the scene names the
/// place.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Coords(pub Vec<f64>);

impl Coords {
    /// The numbers once there is one per axis of a `d`D scene (after a
    /// time when `timed`), or what to write: `what` names the tuple and
    /// `prefix` its numbers, like "f" for (fx, fy).
    pub fn numbers(
        &self,
        d: usize,
        what: &str,
        timed: bool,
        prefix: &str,
    ) -> Result<&[f64], String> {
        let axes = ["x", "y", "z"][..d].iter().map(|a| format!("{prefix}{a}"));
        let names: Vec<String> = timed
            .then(|| "t".to_string())
            .into_iter()
            .chain(axes)
            .collect();
        if self.len() == names.len() {
            return Ok(&self.0);
        }
        let other = if d == 3 {
            ""
        } else {
            " (or add dimension: 3 at the top for a 3D scene)"
        };
        Err(format!(
            "{what} has {} numbers, but this is a {d}D scene: write ({}){other}",
            self.len(),
            names.join(", ")
        ))
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.0
    }

    /// The `k`th number, 0 beyond the end (so an omitted velocity is zero).
    pub fn get(&self, k: usize) -> f64 {
        self.0.get(k).copied().unwrap_or(0.0)
    }
}

impl<const N: usize> From<[f64; N]> for Coords {
    fn from(v: [f64; N]) -> Self {
        Coords(v.to_vec())
    }
}

impl Serialize for Coords {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeTuple;
        let mut t = s.serialize_tuple(self.0.len())?;
        for v in &self.0 {
            t.serialize_element(v)?;
        }
        t.end()
    }
}

impl<'de> Deserialize<'de> for Coords {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Numbers;
        impl<'de> serde::de::Visitor<'de> for Numbers {
            type Value = Coords;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a tuple of numbers, like (0.0, -9.81) or (1.0, 2.0, 3.0)")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Coords, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(Coords(out))
            }
        }
        // RON takes the tuple's length from the text.
        d.deserialize_tuple(3, Numbers)
    }
}

/// A map kept in file order, with duplicate keys rejected.
pub(crate) mod ordered_map {
    use std::fmt;

    use serde::de::{self, MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer, V: Serialize>(
        entries: &[(String, V)],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(entries.len()))?;
        for (k, v) in entries {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }

    pub fn deserialize<'de, D: Deserializer<'de>, V: Deserialize<'de>>(
        d: D,
    ) -> Result<Vec<(String, V)>, D::Error> {
        struct Ordered<V>(std::marker::PhantomData<V>);
        impl<'de, V: Deserialize<'de>> Visitor<'de> for Ordered<V> {
            type Value = Vec<(String, V)>;

            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(r#"a map of names to values, like { "rock": (...) }"#)
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out: Vec<(String, V)> = Vec::new();
                while let Some((k, v)) = map.next_entry::<String, V>()? {
                    if out.iter().any(|(n, _)| *n == k) {
                        return Err(de::Error::custom(format!(
                            "\"{k}\" is defined twice; give each entry its own name"
                        )));
                    }
                    out.push((k, v));
                }
                Ok(out)
            }
        }
        d.deserialize_map(Ordered(std::marker::PhantomData))
    }
}
