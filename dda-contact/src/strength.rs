//! Laws that are Shi's penalty springs plus a strength rule.
//!
//! Most joint laws differ only in how strong the joint is: the normal and
//! shear springs and the open-close rules ([`Springs`]) are the same. Such a
//! law implements [`StrengthLaw`] and gets its `ContactLaw` from
//! [`strength_law!`](crate::strength_law). (A blanket `impl<L: StrengthLaw> ContactLaw for L`
//! would have to live in `dda-core`, beside `ContactLaw`, by the orphan
//! rule; the macro keeps the springs out of the core.)

use dda_core::settings::{finite, non_negative, positive};
use dda_core::{ContactResponse, ContactState, DdaError, LocalKinematics};

use crate::springs::Springs;

/// How strong a closed contact is at its trial normal force.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Strength {
    /// Friction force a sliding contact carries, N (per unit thickness in
    /// 2D): the limit of the locked shear spring's force.
    pub shear: f64,
    /// Tension a closed contact carries before it opens, N (per unit
    /// thickness in 2D); 0 for a dry joint.
    pub tension: f64,
}

/// A contact law that is Shi's penalty springs plus a strength rule. Write
/// `strength`, and `new_history` and `update_history` if the law remembers
/// something; then `dda_contact::strength_law!(MyLaw);` makes it a
/// `ContactLaw`.
pub trait StrengthLaw: Send + Sync + 'static {
    /// What the law remembers about one contact between steps.
    type History: Clone + Send + Sync + serde::Serialize + serde::de::DeserializeOwned + 'static;

    /// The law's own normal and shear penalties per unit contact length (2D)
    /// or area (3D), N/m³; `None` takes the driver's penalty and, for the
    /// shear, the normal one over 2.5.
    fn penalties(&self) -> (Option<f64>, Option<f64>) {
        (None, None)
    }

    /// History of a new contact; `at_start` is true for joints closed in
    /// the initial geometry (where bonds live).
    fn new_history(&self, at_start: bool) -> Self::History;

    /// Shear strength and tensile capacity at the trial normal force
    /// (compression positive).
    fn strength(
        &self,
        normal_force: f64,
        kin: &LocalKinematics,
        history: &Self::History,
    ) -> Strength;

    /// The state after a pass that assumed `from`, given the springs'
    /// decision `by_strength`; override for a rule of the law's own.
    fn adjust_state(
        &self,
        _from: ContactState,
        by_strength: ContactState,
        _kin: &LocalKinematics,
        _history: &Self::History,
    ) -> ContactState {
        by_strength
    }

    /// Whether a locked contact slides exactly when its spring's force
    /// passes `strength().shear` ([`dda_core::ContactLaw::yields_at_strength`]):
    /// true unless `adjust_state` holds a contact in one state beyond that
    /// limit, as a bond or a sliding-until-reversal rule does.
    fn yields_at_strength(&self) -> bool {
        true
    }

    /// Whether the parameters make sense (see [`angle`], [`stiffnesses`]).
    fn check(&self) -> Result<(), DdaError> {
        Ok(())
    }

    /// Changes the history at the end of an accepted step.
    fn update_history(
        &self,
        _state: ContactState,
        _kin: &LocalKinematics,
        _history: &mut Self::History,
    ) {
    }
}

/// A friction angle in [0, 90) degrees.
pub fn angle(field: &'static str, what: &str, phi: f64) -> Result<(), DdaError> {
    finite(field, what, phi)?;
    if (0.0..90.0).contains(&phi) {
        Ok(())
    } else {
        Err(DdaError::Setting {
            field,
            message: format!("{what} must lie in [0, 90) degrees, got {phi}"),
        })
    }
}

/// A cohesion or tensile strength, Pa: zero or positive.
pub fn strength(field: &'static str, what: &str, value: f64) -> Result<(), DdaError> {
    non_negative(field, what, value, "use 0 for none")
}

/// A law's own penalties, when it gives them: positive.
pub fn stiffnesses(normal: Option<f64>, shear: Option<f64>) -> Result<(), DdaError> {
    let auto = "give a positive stiffness or leave it out for an automatic one";
    if let Some(k) = normal {
        positive("normal_stiffness", "the normal stiffness", k, auto)?;
    }
    if let Some(k) = shear {
        positive("shear_stiffness", "the shear stiffness", k, auto)?;
    }
    Ok(())
}

fn springs<L: StrengthLaw>(law: &L, kin: &LocalKinematics) -> Springs {
    let (normal, shear) = law.penalties();
    Springs::new(normal, shear, kin)
}

/// `ContactLaw::response` of a strength law.
pub fn response<L: StrengthLaw>(
    law: &L,
    state: ContactState,
    kin: &LocalKinematics,
    history: &L::History,
) -> ContactResponse {
    let springs = springs(law, kin);
    let strength = law.strength(springs.normal_force(kin), kin, history);
    springs.response(state, kin, strength.shear)
}

/// `ContactLaw::next_state` of a strength law.
pub fn next_state<L: StrengthLaw>(
    law: &L,
    state: ContactState,
    kin: &LocalKinematics,
    history: &L::History,
) -> ContactState {
    let springs = springs(law, kin);
    let strength = law.strength(springs.normal_force(kin), kin, history);
    let next = springs.next_state(state, kin, strength.shear, strength.tension);
    law.adjust_state(state, next, kin, history)
}

/// Implements `dda_core::ContactLaw` for types that implement
/// [`StrengthLaw`].
#[macro_export]
macro_rules! strength_law {
    ($($law:ty),+ $(,)?) => {$(
        impl $crate::core::ContactLaw for $law {
            type History = <$law as $crate::StrengthLaw>::History;

            fn initial_history(&self, at_start: bool) -> Self::History {
                $crate::StrengthLaw::new_history(self, at_start)
            }

            fn response(
                &self,
                state: $crate::core::ContactState,
                kin: &$crate::core::LocalKinematics,
                history: &Self::History,
            ) -> $crate::core::ContactResponse {
                $crate::strength::response(self, state, kin, history)
            }

            fn next_state(
                &self,
                state: $crate::core::ContactState,
                kin: &$crate::core::LocalKinematics,
                history: &Self::History,
            ) -> $crate::core::ContactState {
                $crate::strength::next_state(self, state, kin, history)
            }

            fn commit(
                &self,
                state: $crate::core::ContactState,
                kin: &$crate::core::LocalKinematics,
                history: &mut Self::History,
            ) {
                $crate::StrengthLaw::update_history(self, state, kin, history)
            }

            fn check(&self) -> Result<(), $crate::core::DdaError> {
                $crate::StrengthLaw::check(self)
            }

            fn yields_at_strength(&self) -> bool {
                $crate::StrengthLaw::yields_at_strength(self)
            }
        }
    )+};
}
