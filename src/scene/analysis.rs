//! The `analysis` section: the driver's [`Settings`], read and written by
//! their own serde derive (fields, defaults and docs live there), beside
//! the few fields the scene decides itself.
//!
//! serde's `flatten` cannot refuse unknown fields, and the located errors
//! need `deny_unknown_fields` and the parser's positions. So the section
//! is read twice from the text, each time by one derive that passes over
//! the other's fields: [`Analysis`] with the whole scene, then
//! [`Settings`] alone ([`settings_of`]). Unknown fields are refused in the
//! first pass, naming every field either reads.

use std::ops::{Deref, DerefMut};
use std::sync::OnceLock;

use dda_core::settings::{non_negative, positive};
use dda_core::{DdaError, Settings};
use serde::de::{self, DeserializeSeed, IgnoredAny, IntoDeserializer, MapAccess, Visitor};
use serde::ser::{self, Impossible, SerializeStruct};
use serde::{forward_to_deserialize_any, Deserialize, Deserializer, Serialize, Serializer};

use dda_2d::{Plane, RotationUpdate};

use super::{is_default, Coords};
use crate::guard::OnFailure;

/// The analysis: what the scene decides, and the driver's settings
/// (`analysis.dt` reads `analysis.settings.dt`). `None` means automatic.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Analysis {
    /// Simulated time, s; required (0 is rejected).
    pub duration: f64,
    /// `Dynamic` (default) carries velocities from step to step, `Static`
    /// starts each step at rest.
    pub mode: Mode,
    /// Fraction of the velocity carried into the next step, in [0, 1];
    /// default the mode's (1 dynamic, 0 static).
    pub velocity_ratio: Option<f64>,
    /// (gx, gy) in 2D, (gx, gy, gz) in 3D, m/s²; default (0, −9.81) or
    /// (0, 0, −9.81): see [`super::Scene::gravity`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gravity: Option<Coords>,
    /// Plane strain (default) or plane stress: 2D scenes only.
    #[serde(with = "PlaneDef", skip_serializing_if = "is_default")]
    pub plane: Plane,
    /// `Exact` (default) turns blocks by the exact rotation, `Linear` by
    /// Shi's first-order update.
    pub rotation_update: RotationUpdate,
    /// Stiffness of the springs holding fixed points, N/m; default 10 × a
    /// typical contact's spring.
    pub fixed_penalty: Option<f64>,
    /// Mass-proportional viscous damping; default none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping: Option<Damping>,
    /// What a run does when a guard trips (energy growth in a scene nothing
    /// works on, a penetration past the bound or a step without open-close
    /// agreement, both at the smallest step): `Stop` (default) ends it,
    /// status "failed", with a report; `Continue` runs on and warns.
    #[serde(skip_serializing_if = "is_default")]
    pub on_failure: OnFailure,
    /// The driver's settings as written (see [`Settings`] for each field's
    /// unit, meaning and default), but for the velocity ratio and the mass
    /// damping, which the fields above give.
    #[serde(skip)]
    pub settings: Settings,
}

impl Deref for Analysis {
    type Target = Settings;

    fn deref(&self) -> &Settings {
        &self.settings
    }
}

impl DerefMut for Analysis {
    fn deref_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }
}

/// Mass-proportional damping giving the ratio `ratio` of critical damping
/// at `frequency` (Hz): α = 2·ratio·2π·frequency (1/s), a force −α·m·v on
/// every block. Lower frequencies are damped more, higher ones less.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damping {
    /// Fraction of critical damping, like 0.05; required, not negative.
    pub ratio: f64,
    /// Where the ratio holds, Hz; required, positive.
    pub frequency: f64,
}

impl Damping {
    /// Whether the ratio and frequency make a damping: the first field at
    /// fault and what to change.
    pub fn check(&self) -> Result<(), DdaError> {
        let hint = "it is a fraction of critical damping, like 0.05";
        non_negative("ratio", "the damping ratio", self.ratio, hint)?;
        let hint =
            "give the frequency (Hz) at which the ratio holds, like the structure's first mode";
        positive("frequency", "the damping frequency", self.frequency, hint)
    }

    /// The coefficient α in 1/s.
    pub fn mass_coefficient(&self) -> f64 {
        2.0 * self.ratio * std::f64::consts::TAU * self.frequency
    }
}

/// Dynamic carries the velocity from step to step; static starts each step at rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Mode {
    #[default]
    Dynamic,
    Static,
}

impl Mode {
    pub fn velocity_ratio(self) -> f64 {
        match self {
            Mode::Dynamic => 1.0,
            Mode::Static => 0.0,
        }
    }
}

/// The file names of [`Plane`] (serde's mirror of the 2D crate's enum).
#[derive(Serialize, Deserialize)]
#[serde(remote = "Plane")]
enum PlaneDef {
    Strain,
    Stress,
}

/// The field names a derived struct reads, as serde hands them to
/// `deserialize_struct`.
fn fields_of<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
    struct Probe<'a>(&'a mut &'static [&'static str]);
    impl<'de> Deserializer<'de> for Probe<'_> {
        type Error = de::value::Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
            Err(de::Error::custom("only the field names are read"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Self::Error> {
            *self.0 = fields;
            Err(de::Error::custom("only the field names are read"))
        }
        forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
            byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map enum
            identifier ignored_any
        }
    }
    let mut fields: &'static [&'static str] = &[];
    let _ = T::deserialize(Probe(&mut fields));
    fields
}

/// The scene's own fields, the settings it writes (not those it gives
/// itself, nor `mass_damping`: it writes `damping`, a ratio at a
/// frequency), and both.
fn own() -> &'static [&'static str] {
    fields_of::<Analysis>()
}

fn written_settings() -> &'static [&'static str] {
    static FIELDS: OnceLock<Vec<&'static str>> = OnceLock::new();
    FIELDS.get_or_init(|| {
        let written = |f: &&str| !own().contains(f) && *f != "mass_damping";
        fields_of::<Settings>()
            .iter()
            .copied()
            .filter(written)
            .collect()
    })
}

fn every_field() -> &'static [&'static str] {
    static FIELDS: OnceLock<Vec<&'static str>> = OnceLock::new();
    FIELDS.get_or_init(|| own().iter().chain(written_settings()).copied().collect())
}

/// Reads the scene's own fields (the `analysis` of [`super::Scene`]).
pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Analysis, D::Error> {
    Analysis::deserialize(Part {
        inner: d,
        skip: written_settings(),
    })
}

/// Writes the scene's own fields, then the settings a scene writes (all
/// of them, so a study finds each by its path in the text).
pub(super) fn serialize<S: Serializer>(a: &Analysis, s: S) -> Result<S::Ok, S::Error> {
    let mut out = s.serialize_struct("Analysis", every_field().len())?;
    a.serialize(Fields(&mut out, own()))?;
    a.settings.serialize(Fields(&mut out, written_settings()))?;
    out.end()
}

/// The second pass: the `analysis` section's settings, every other field
/// of the scene passed over.
pub(super) fn settings_of(text: &str) -> Result<Settings, ron::error::SpannedError> {
    #[derive(Deserialize)]
    #[serde(rename = "Scene")]
    struct Pass {
        #[serde(default, deserialize_with = "settings")]
        analysis: Settings,
    }
    fn settings<'de, D: Deserializer<'de>>(d: D) -> Result<Settings, D::Error> {
        Settings::deserialize(Part {
            inner: d,
            skip: own(),
        })
    }
    super::ron_options()
        .from_str::<Pass>(text)
        .map(|p| p.analysis)
}

/// A struct's deserializer that passes over the fields in `skip` (the
/// other pass reads them) and refuses any field neither pass reads.
struct Part<D> {
    inner: D,
    skip: &'static [&'static str],
}

impl<'de, D: Deserializer<'de>> Deserializer<'de> for Part<D> {
    type Error = D::Error;

    fn deserialize_any<V: Visitor<'de>>(self, v: V) -> Result<V::Value, D::Error> {
        self.inner.deserialize_any(v)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, D::Error> {
        // Both passes read the struct the file names `Analysis`.
        let skip = self.skip;
        self.inner
            .deserialize_struct("Analysis", fields, Skipping { visitor, skip })
    }

    forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes
        byte_buf option unit unit_struct newtype_struct seq tuple tuple_struct map enum
        identifier ignored_any
    }
}

struct Skipping<V> {
    visitor: V,
    skip: &'static [&'static str],
}

impl<'de, V: Visitor<'de>> Visitor<'de> for Skipping<V> {
    type Value = V::Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        self.visitor.expecting(f)
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<V::Value, A::Error> {
        self.visitor.visit_map(Skipping {
            visitor: map,
            skip: self.skip,
        })
    }
}

impl<'de, A: MapAccess<'de>> MapAccess<'de> for Skipping<A> {
    type Error = A::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, A::Error> {
        while let Some(key) = self.visitor.next_key::<String>()? {
            if self.skip.contains(&key.as_str()) {
                self.visitor.next_value::<IgnoredAny>()?;
            } else if every_field().contains(&key.as_str()) {
                return seed.deserialize(key.into_deserializer()).map(Some);
            } else {
                return Err(de::Error::unknown_field(&key, every_field()));
            }
        }
        Ok(None)
    }

    fn next_value_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<T::Value, A::Error> {
        self.visitor.next_value_seed(seed)
    }
}

/// A serializer that writes the fields of a struct named in its list into
/// another struct being written.
struct Fields<'a, M>(&'a mut M, &'static [&'static str]);

impl<M: SerializeStruct> SerializeStruct for Fields<'_, M> {
    type Ok = ();
    type Error = M::Error;

    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), M::Error> {
        if self.1.contains(&key) {
            self.0.serialize_field(key, value)?;
        }
        Ok(())
    }

    fn end(self) -> Result<(), M::Error> {
        Ok(())
    }
}

/// Anything but a struct is refused.
macro_rules! refuse {
    ($($method:ident $(<$t:ident>)? ($($ty:ty),*) -> $out:ty;)*) => {
        $(fn $method $(<$t: ?Sized + Serialize>)? (self, $(_: $ty),*) -> Result<$out, M::Error> {
            Err(ser::Error::custom("a struct was expected"))
        })*
    };
}

impl<'a, M: SerializeStruct> Serializer for Fields<'a, M> {
    type Ok = ();
    type Error = M::Error;
    type SerializeSeq = Impossible<(), M::Error>;
    type SerializeTuple = Impossible<(), M::Error>;
    type SerializeTupleStruct = Impossible<(), M::Error>;
    type SerializeTupleVariant = Impossible<(), M::Error>;
    type SerializeMap = Impossible<(), M::Error>;
    type SerializeStruct = Self;
    type SerializeStructVariant = Impossible<(), M::Error>;

    fn serialize_struct(self, _: &'static str, _: usize) -> Result<Self, M::Error> {
        Ok(self)
    }

    refuse! {
        serialize_bool(bool) -> (); serialize_i8(i8) -> (); serialize_i16(i16) -> ();
        serialize_i32(i32) -> (); serialize_i64(i64) -> (); serialize_u8(u8) -> ();
        serialize_u16(u16) -> (); serialize_u32(u32) -> (); serialize_u64(u64) -> ();
        serialize_f32(f32) -> (); serialize_f64(f64) -> (); serialize_char(char) -> ();
        serialize_str(&str) -> (); serialize_bytes(&[u8]) -> (); serialize_none() -> ();
        serialize_unit() -> (); serialize_unit_struct(&'static str) -> ();
        serialize_unit_variant(&'static str, u32, &'static str) -> ();
        serialize_some<T>(&T) -> (); serialize_newtype_struct<T>(&'static str, &T) -> ();
        serialize_newtype_variant<T>(&'static str, u32, &'static str, &T) -> ();
        serialize_seq(Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(usize) -> Self::SerializeTuple;
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(&'static str, u32, &'static str, usize) -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct_variant(&'static str, u32, &'static str, usize) -> Self::SerializeStructVariant;
    }
}
