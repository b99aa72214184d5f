//! Contact laws: what a contact does, seen in its local frame.
//!
//! A law never sees blocks, matrices or the dimension. The driver hands it the
//! contact's normal gap and tangential displacement (scalars along the current
//! shear or slip direction) and asks two questions:
//!
//! 1. [`ContactLaw::response`]: with the contact held in a given state, what are
//!    the normal and shear forces and their stiffnesses at this trial
//!    displacement? (Called at every Newton iteration of an open-close pass.)
//! 2. [`ContactLaw::next_state`]: after the pass has converged, which state is
//!    consistent with the result? (The open-close check.)
//!
//! A law may keep its own per-contact history (`ContactLaw::History`). It is
//! read during trial passes and changed only in [`ContactLaw::commit`], which the
//! driver calls once per accepted step: a rejected pass or step leaves no trace.

use std::any::Any;
use std::fmt;

use serde::de::DeserializeOwned;
use serde::Serialize;

/// The three contact states of DDA.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
pub enum ContactState {
    /// No springs: the blocks are apart.
    #[default]
    Open,
    /// Normal and shear springs: no relative tangential motion.
    Locked,
    /// Normal spring and a friction force opposing the slip.
    Sliding,
}

impl ContactState {
    /// Whether the normal spring is on.
    pub fn is_closed(self) -> bool {
        self != ContactState::Open
    }

    /// The name used in output files.
    pub fn name(self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Locked => "locked",
            ContactState::Sliding => "sliding",
        }
    }
}

impl fmt::Display for ContactState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The contact's motion in its local frame at the trial displacement of a step.
///
/// Lengths are in the model's units; signs: `gap < 0` is penetration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalKinematics {
    /// Normal gap at the trial displacement (negative: penetration).
    pub gap: f64,
    /// Normal gap at the start of the step.
    pub gap_start: f64,
    /// Magnitude of the elastic shear displacement: the stretch of the shear
    /// spring carried over from earlier steps plus this step's tangential
    /// motion. While sliding, the carried stretch is the one that carries the
    /// friction force, so a contact that locks again keeps its force.
    pub shear: f64,
    /// This step's relative tangential displacement projected on the current
    /// slip direction (negative: the slip has reversed).
    pub slip: f64,
    /// Sum of |slip| over accepted steps in which the contact slid.
    pub slip_path: f64,
    /// Slip rate of the last accepted step (length per time), so rate laws do
    /// not chatter between open-close passes.
    pub slip_rate: f64,
    /// Boundary length (2D, per unit thickness) or area (3D) the contact
    /// stands for: what cohesion and tensile strength act over.
    pub length: f64,
    /// Boundary length (2D) or area (3D) the contact's springs stand for:
    /// a spring's stiffness is its stiffness per unit length or area times
    /// this, so a 2D model and its extruded prism settle alike.
    pub spring_length: f64,
    /// The driver's normal penalty per unit contact length (2D, per unit
    /// thickness) or area (3D), in N/m³ (automatic or from the scene, raised
    /// when penetration is too deep). Laws use it unless they set their own.
    pub penalty: f64,
    /// Distance tolerance for open-close decisions.
    pub tolerance: f64,
    /// Time step.
    pub dt: f64,
}

/// Forces and stiffnesses of a contact in a given state.
///
/// Sign convention: `normal_force > 0` pushes the blocks apart (compression);
/// a bonded contact may carry tension (`normal_force < 0`). `shear_force` is a
/// magnitude that opposes the shear displacement (locked) or the slip (sliding).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactResponse {
    pub normal_force: f64,
    /// −d(normal_force)/d(gap): the normal spring stiffness.
    pub normal_stiffness: f64,
    pub shear_force: f64,
    /// d(shear_force)/d(shear): the shear spring stiffness (zero when sliding).
    pub shear_stiffness: f64,
}

/// A contact law. Implement this (one file is enough) and register it by name
/// to use it from scenes.
///
/// * `response` and `next_state` must be pure: they may be called many times
///   per step with trial kinematics that are later thrown away.
/// * `commit` is called once per accepted step, with the accepted state and
///   kinematics; it is the only place history changes.
pub trait ContactLaw: Send + Sync + 'static {
    /// What the law remembers about one contact between steps; saved with
    /// the run in a checkpoint, so it derives serde.
    type History: Clone + Send + Sync + Serialize + DeserializeOwned + 'static;

    /// History of a new contact. `at_start` is true for contacts found at the
    /// first step of a run (joints that exist in the initial geometry, which is
    /// where bonds such as cohesion and tensile strength live).
    fn initial_history(&self, at_start: bool) -> Self::History;

    /// Forces and stiffnesses with the contact held in `state`.
    fn response(
        &self,
        state: ContactState,
        kin: &LocalKinematics,
        history: &Self::History,
    ) -> ContactResponse;

    /// The state consistent with the trial result of a pass that assumed `state`.
    fn next_state(
        &self,
        state: ContactState,
        kin: &LocalKinematics,
        history: &Self::History,
    ) -> ContactState;

    /// Updates the history at the end of an accepted step.
    fn commit(&self, state: ContactState, kin: &LocalKinematics, history: &mut Self::History);

    /// Whether the parameters make sense: the first bad one is a
    /// [`DdaError::Setting`](crate::DdaError::Setting) naming its field.
    fn check(&self) -> Result<(), crate::DdaError> {
        Ok(())
    }

    /// Whether a locked contact yields exactly where its shear spring's
    /// force reaches the friction `response` gives when sliding (the
    /// elastoplastic return map), with no other rule between the two
    /// states. Then the driver applies that limit to locked contacts
    /// within each pass, and a contact passing between locked and sliding
    /// costs no open-close pass. Default `false`: a law with a static
    /// strength above its sliding one, or a bond, must keep it so.
    fn yields_at_strength(&self) -> bool {
        false
    }
}

/// Type-erased contact history, stored per contact by the driver.
pub type History = Box<dyn Any + Send + Sync>;

/// Object-safe form of [`ContactLaw`], so laws of different types can sit in one
/// table. Implemented for every `ContactLaw`; users never implement it.
pub trait DynContactLaw: Send + Sync {
    fn initial_history(&self, at_start: bool) -> History;
    fn response(&self, state: ContactState, kin: &LocalKinematics, h: &History) -> ContactResponse;
    fn next_state(&self, state: ContactState, kin: &LocalKinematics, h: &History) -> ContactState;
    /// A closed contact's responses for its load, read off the history
    /// once: in `state`, and in the state the elastoplastic return map
    /// weighs it against, where there is one (a sliding contact's locked
    /// spring; a locked one's friction where `may_yield` and the law
    /// [yields at its strength](ContactLaw::yields_at_strength)).
    fn load_responses(
        &self,
        state: ContactState,
        may_yield: bool,
        kin: &LocalKinematics,
        h: &History,
    ) -> (ContactResponse, Option<ContactResponse>);
    fn commit(&self, state: ContactState, kin: &LocalKinematics, h: &mut History);
    fn check(&self) -> Result<(), crate::DdaError>;
    /// [`ContactLaw::yields_at_strength`].
    fn yields_at_strength(&self) -> bool;
    /// A contact's history as a checkpoint keeps it.
    fn save_history(&self, h: &History) -> Result<Vec<u8>, crate::DdaError>;
    /// A history saved by [`DynContactLaw::save_history`] of this law.
    fn load_history(&self, bytes: &[u8]) -> Result<History, crate::DdaError>;
}

impl<L: ContactLaw> DynContactLaw for L {
    fn initial_history(&self, at_start: bool) -> History {
        Box::new(ContactLaw::initial_history(self, at_start))
    }

    fn response(&self, state: ContactState, kin: &LocalKinematics, h: &History) -> ContactResponse {
        ContactLaw::response(self, state, kin, downcast::<L>(h))
    }

    fn next_state(&self, state: ContactState, kin: &LocalKinematics, h: &History) -> ContactState {
        ContactLaw::next_state(self, state, kin, downcast::<L>(h))
    }

    fn load_responses(
        &self,
        state: ContactState,
        may_yield: bool,
        kin: &LocalKinematics,
        h: &History,
    ) -> (ContactResponse, Option<ContactResponse>) {
        let h = downcast::<L>(h);
        let weighed = match state {
            ContactState::Sliding => Some(ContactState::Locked),
            ContactState::Locked if may_yield && ContactLaw::yields_at_strength(self) => {
                Some(ContactState::Sliding)
            }
            _ => None,
        };
        (
            ContactLaw::response(self, state, kin, h),
            weighed.map(|s| ContactLaw::response(self, s, kin, h)),
        )
    }

    fn commit(&self, state: ContactState, kin: &LocalKinematics, h: &mut History) {
        let h = h
            .downcast_mut::<L::History>()
            .expect("contact history belongs to another law");
        ContactLaw::commit(self, state, kin, h)
    }

    fn check(&self) -> Result<(), crate::DdaError> {
        ContactLaw::check(self)
    }

    fn yields_at_strength(&self) -> bool {
        ContactLaw::yields_at_strength(self)
    }

    fn save_history(&self, h: &History) -> Result<Vec<u8>, crate::DdaError> {
        postcard::to_stdvec(downcast::<L>(h)).map_err(|e| {
            crate::DdaError::Checkpoint(format!("cannot save a contact's history: {e}"))
        })
    }

    fn load_history(&self, bytes: &[u8]) -> Result<History, crate::DdaError> {
        let h: L::History = postcard::from_bytes(bytes).map_err(|e| {
            crate::DdaError::Checkpoint(format!(
                "a contact's history does not read as its law's: {e}"
            ))
        })?;
        Ok(Box::new(h))
    }
}

fn downcast<L: ContactLaw>(h: &History) -> &L::History {
    // A contact keeps the law it was created with (the law index is part of the
    // contact), so a mismatch is a programming error, not bad input.
    h.downcast_ref::<L::History>()
        .expect("contact history belongs to another law")
}
