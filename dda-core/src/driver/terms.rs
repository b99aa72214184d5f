//! One contact's kinematics and forces at a trial. They read the step's
//! contacts and laws and write nothing, so the contacts' loads are computed
//! in parallel and gathered in contact order (the sums are those of one
//! thread, bit for bit).

use nalgebra::SVector;

use super::chosen::Chosen;
use super::{block, widest_entrance, Trial, ROUND_OFF_FORCE};
use crate::contact::{ContactResponse, ContactState, DynContactLaw, LocalKinematics};
use crate::contacts::{BlockVector, Contact, Entrance, EntranceRows};
use crate::system::BlockMatrix;

/// What a closed contact adds to a step's equations at a trial.
#[derive(Clone, Copy)]
pub(super) struct ContactLoad<const N: usize, const T: usize> {
    /// The contact's forces on its two blocks' unknowns.
    pub force: [BlockVector<N>; 2],
    /// The normal spring's stiffness, with its dashpot's share.
    pub normal_stiffness: f64,
    /// Each shear row's stiffness, with its dashpot's share.
    pub shear_stiffness: SVector<f64, T>,
    /// A sliding contact's friction over its stretch (3D): how fast its
    /// force turns with the stretch across the slip direction (0 if none).
    pub turning: f64,
    /// The slip direction in the entrance's tangent frame.
    pub direction: SVector<f64, T>,
    /// A sliding contact's d(friction)/d(gap) (computed only for coupled
    /// solves; 0 otherwise).
    pub slope: f64,
    /// Whether its shear force is its strength's at the trial: sliding
    /// beyond its elastic limit, or locked and past its strength (the
    /// return map's friction branch either way).
    pub slipping: bool,
}

/// One contact's open-close decision at a trial.
pub(super) struct Decision<const T: usize> {
    pub state: ContactState,
    /// The trial stretch's direction (`None` at no stretch: keep the last).
    pub direction: Option<SVector<f64, T>>,
    /// Opened because its dashpot pulled.
    pub pulled: bool,
    /// Sliding, found within its strength, and kept sliding for the passes.
    pub within: bool,
    pub entrance: usize,
    /// Whether the decision differs from what the pass assumed.
    pub changed: bool,
}

/// What a contact keeps of an accepted step.
pub(super) struct Kept<const T: usize> {
    pub state: ContactState,
    pub kin: LocalKinematics,
    pub entrance: usize,
    /// The shear spring's stretch carried into the next step.
    pub shear: SVector<f64, T>,
    pub direction: SVector<f64, T>,
    /// The step's slip distance (counted only if sliding).
    pub slip: f64,
    pub normal_force: f64,
    pub shear_force: f64,
    /// Elastic energy stored in the normal and the shear spring.
    pub energy: [f64; 2],
}

/// The step's contacts as one contact's terms read them.
pub(super) struct ContactTerms<'a, const N: usize, const T: usize, E = Entrance<N, T>> {
    pub contacts: &'a [Contact<N, T, E>],
    pub laws: &'a [Box<dyn DynContactLaw>],
    /// Inverse mass matrices of the blocks in the step.
    pub inverse_masses: &'a [BlockMatrix<N>],
    /// Contacts struck in the attempt: no dashpots.
    pub striking: &'a [usize],
    /// `Settings::contact_damping`.
    pub damping: f64,
    /// The contact tolerance (m).
    pub tolerance: f64,
    /// Whether a closed contact pulling past its tensile strength at the
    /// step's end is committed open (`Settings::open_at_strength`).
    pub commit_open: bool,
    pub penalty: f64,
    /// Each contact's chosen entrance, side by side (where held).
    pub chosen: &'a Chosen<N, T, E>,
}

impl<const N: usize, const T: usize, E: EntranceRows<N, T>> ContactTerms<'_, N, T, E> {
    /// Contact `i`'s entrance `e`: its copy where held.
    pub fn entrance(&self, i: usize, e: usize) -> &E {
        self.chosen.of(self.contacts, i, e)
    }

    /// Elastic shear displacement carried from earlier steps, valid only on
    /// the entrance it was measured on.
    pub fn carried_shear(&self, c: &Contact<N, T, E>, entrance: usize) -> SVector<f64, T> {
        if c.record.state.is_closed() && c.record.entrance == entrance {
            c.record.shear
        } else {
            SVector::zeros()
        }
    }

    /// Whether contact `i` has dashpots this pass: with contact damping,
    /// unless it strikes (its impulse is the impact's loss).
    pub fn damped(&self, i: usize) -> bool {
        self.damping > 0.0 && !self.striking.contains(&i)
    }

    /// Whether contact `i`, held in `state`, takes the return map when
    /// locked: its law yields at its sliding strength, and no shear dashpot
    /// (which locking adds) makes the two states load the blocks
    /// differently.
    pub fn yields(&self, i: usize, state: ContactState) -> bool {
        state == ContactState::Locked
            && !self.damped(i)
            && self.laws[self.contacts[i].law].yields_at_strength()
    }

    /// The coefficient of the dashpot beside a spring of stiffness `k`
    /// along a contact's rows: `contact_damping` × 2·sqrt(k·m), with m the
    /// two blocks' effective mass along the rows, 1 / (gₐᵀ Mₐ⁻¹ gₐ + g_bᵀ
    /// M_b⁻¹ g_b) (rotation and strain included).
    pub fn dashpot(&self, a: usize, b: usize, [ga, gb]: &[BlockVector<N>; 2], k: f64) -> f64 {
        let compliance =
            ga.dot(&(self.inverse_masses[a] * ga)) + gb.dot(&(self.inverse_masses[b] * gb));
        if compliance > 0.0 && k > 0.0 {
            self.damping * 2.0 * (k / compliance).sqrt()
        } else {
            0.0
        }
    }

    pub fn kinematics(&self, i: usize, e: usize, trial: &Trial<T>, dt: f64) -> LocalKinematics {
        self.kinematics_on(i, e, self.entrance(i, e), trial, dt).0
    }

    /// Contact `i`'s kinematics on `entrance` (its `e`-th), and the shear
    /// spring's trial stretch.
    #[inline(always)]
    fn kinematics_on(
        &self,
        i: usize,
        e: usize,
        entrance: &impl EntranceRows<N, T>,
        trial: &Trial<T>,
        dt: f64,
    ) -> (LocalKinematics, SVector<f64, T>) {
        let c = &self.contacts[i];
        let da = block(&trial.d, c.blocks[0]);
        let db = block(&trial.d, c.blocks[1]);
        let (gap, ds) = entrance.gap_and_shear_at(&da, &db);
        let stretch = self.carried_shear(c, e) + ds;
        let kin = LocalKinematics {
            gap,
            gap_start: entrance.gap(),
            shear: stretch.norm(),
            slip: ds.dot(&trial.directions[i]),
            slip_path: c.record.slip_path,
            slip_rate: c.record.slip_rate,
            length: c.length,
            spring_length: c.spring_length,
            penalty: self.penalty,
            tolerance: self.tolerance,
            dt,
        };
        (kin, stretch)
    }

    /// Contact `i`'s load at the trial (`None` where it is open). The
    /// dashpots act on `moving`, the step's motion (or an explicit step's
    /// approach); `couple` asks for the friction's slope. Made inline, so
    /// a caller that reads only part of the load makes only that part.
    #[inline(always)]
    pub fn load(
        &self,
        i: usize,
        trial: &Trial<T>,
        dt: f64,
        moving: &[f64],
        couple: bool,
    ) -> Option<ContactLoad<N, T>> {
        let state = trial.states[i];
        if !state.is_closed() {
            return None;
        }
        let e = trial.entrances[i];
        let entrance = self.entrance(i, e);
        Some(if self.damped(i) {
            // The dashpots read its rows several times over: made once.
            entrance.with_rows(|rows| self.load_on(i, rows, trial, dt, moving, couple))
        } else {
            // Only its motion and its forces: read through the entrance,
            // which in 3D makes two points' products where rows make six.
            self.load_on(i, entrance, trial, dt, moving, couple)
        })
    }

    /// Contact `i`'s forces on its two blocks at the trial (`None` where
    /// it is open): [`ContactTerms::load`]'s without the rest, for a move
    /// on a kept factor (on the 10,051-block wall 14–17 % less time than
    /// the forces read off a load made out of line, the same bits).
    #[inline(always)]
    pub fn force(
        &self,
        i: usize,
        trial: &Trial<T>,
        dt: f64,
        moving: &[f64],
    ) -> Option<[BlockVector<N>; 2]> {
        self.load(i, trial, dt, moving, false).map(|l| l.force)
    }

    /// [`ContactTerms::load`] of closed contact `i`, read on `entrance`
    /// (its trial entrance, as kept or with its rows made).
    #[inline(always)]
    fn load_on(
        &self,
        i: usize,
        entrance: &impl EntranceRows<N, T>,
        trial: &Trial<T>,
        dt: f64,
        moving: &[f64],
        couple: bool,
    ) -> ContactLoad<N, T> {
        let (state, e) = (trial.states[i], trial.entrances[i]);
        let c = &self.contacts[i];
        let (kin, stretch) = self.kinematics_on(i, e, entrance, trial, dt);
        let history = c.record.history.as_ref().expect("history set at search");
        let law = &self.laws[c.law];
        let damped = self.damped(i);
        // With a shear dashpot (which locking adds) the two states load
        // the blocks differently: no return map for a locked contact.
        let (mut response, weighed) = law.load_responses(state, !damped, &kin, history);
        let [a, b] = c.blocks;
        if damped {
            // A dashpot beside the normal spring, a share of critical for
            // the contact's own effective mass: impacts end in a few steps
            // instead of ringing on the penalty springs, and a block
            // released onto its contacts does not bounce. Its force on the
            // step's approach dissipates only.
            let c = self.dashpot(a, b, &entrance.normal(), response.normal_stiffness);
            let approached = entrance.gap_at(&block(moving, a), &block(moving, b)) - entrance.gap();
            response.normal_force -= c * approached / dt;
            response.normal_stiffness += c / dt;
        }
        // Shear: a spring when locked; when sliding, the friction force
        // along the trial stretch (the radial return of an elastoplastic
        // spring), whose tangent turns the force with the stretch in 3D.
        let length = kin.shear;
        // A sliding contact's force is the return map's, min(k_s·|s|,
        // strength) along the stretch s: within the elastic limit (an
        // iterate that reverses the slip) it is the spring's, so the force
        // stays continuous and Newton-Raphson does not jump between
        // opposite friction forces. A locked contact of a law that yields
        // at its sliding strength takes the same return map, so passing
        // between the two states changes no force.
        let mut slipping = state == ContactState::Sliding;
        if let Some(weighed) = weighed {
            if slipping {
                // Within the elastic limit, the locked spring's.
                let spring = weighed;
                if spring.shear_stiffness > 0.0 && spring.shear_force < response.shear_force {
                    response.shear_force = spring.shear_force;
                    response.shear_stiffness = spring.shear_stiffness;
                    slipping = false;
                }
            } else {
                // Past the strength, the friction's.
                let friction = weighed;
                if response.shear_force > friction.shear_force {
                    response.shear_force = friction.shear_force;
                    response.shear_stiffness = friction.shear_stiffness;
                    slipping = true;
                }
            }
        }
        let direction = stretch.try_normalize(1e-300).unwrap_or(trial.directions[i]);
        let step_shear = if damped {
            entrance.shear_at(&block(moving, a), &block(moving, b))
        } else {
            SVector::zeros()
        };
        let mut shear_stiffness = SVector::<f64, T>::zeros();
        let mut shear_force = SVector::<f64, T>::zeros();
        for k in 0..T {
            let mut stiffness = response.shear_stiffness;
            let mut f = -response.shear_force * direction[k];
            if damped && state == ContactState::Locked {
                // The shear spring's dashpot, as the normal one's.
                let c = self.dashpot(a, b, &entrance.tangent(k), stiffness);
                f -= c * step_shear[k] / dt;
                stiffness += c / dt;
            }
            shear_stiffness[k] = stiffness;
            shear_force[k] = f;
        }
        // The normal spring's force along the gap gradient, the shear's
        // along the tangents.
        let force = entrance.spread(response.normal_force, &shear_force);
        let slope = if couple && slipping {
            // d(friction)/d(gap), by central differences: laws are pure.
            // The friction's, also for a locked contact past its strength:
            // its own (locked) response is the spring's, which no gap moves.
            let h = 1e-6 * kin.gap.abs().max(kin.tolerance);
            let at = |gap: f64| {
                let kin = LocalKinematics { gap, ..kin };
                law.response(ContactState::Sliding, &kin, history)
                    .shear_force
            };
            (at(kin.gap + h) - at(kin.gap - h)) / (2.0 * h)
        } else {
            0.0
        };
        let turning = if slipping && T > 1 && length > 0.0 {
            response.shear_force / length
        } else {
            0.0
        };
        ContactLoad {
            force,
            normal_stiffness: response.normal_stiffness,
            shear_stiffness,
            turning,
            direction,
            slope,
            slipping,
        }
    }

    /// Contact `i`'s open-close decision at the trial: its next state, slip
    /// direction and entrance. The shear dashpots act on `moving`.
    pub fn decision(&self, i: usize, trial: &Trial<T>, dt: f64, moving: &[f64]) -> Decision<T> {
        let c = &self.contacts[i];
        let e = trial.entrances[i];
        // Read off the contact, not its copy: read there, the
        // 10,051-block walls' decisions took 30-60 % longer (measured, 2D
        // and 3D), and a group's entrances are all read below anyway.
        let entrance = &c.entrances[e];
        let (mut kin, stretch) = self.kinematics_on(i, e, entrance, trial, dt);
        let law = &self.laws[c.law];
        let history = c.record.history.as_ref().expect("history set at search");
        let state = trial.states[i];
        let mut pulled = false;
        if self.damped(i) {
            // Friction bounds the whole tangential force, the shear
            // dashpot's too: test the spring stretch that carries
            // it, so locked and sliding stay complementary.
            let k = law
                .response(ContactState::Locked, &kin, history)
                .shear_stiffness;
            if k > 0.0 {
                let [a, b] = c.blocks;
                let ds = entrance.shear_at(&block(&trial.d, a), &block(&trial.d, b));
                let rate = entrance.shear_at(&block(moving, a), &block(moving, b));
                let carried = self.carried_shear(c, e);
                let loaded = SVector::<f64, T>::from_fn(|r, _| {
                    let damper = self.dashpot(a, b, &entrance.tangent(r), k);
                    carried[r] + ds[r] + rate[r] * damper / (k * dt)
                });
                kin.shear = loaded.norm();
            }
        }
        let mut next = law.next_state(state, &kin, history);
        if self.damped(i) && state.is_closed() && next.is_closed() {
            // The normal dashpot pushes only: a contact whose spring
            // and dashpot together pull (a corner leaving its base
            // faster than its spring unloads) opens, as the spring
            // alone would at that gap, instead of holding on.
            let k = law
                .response(ContactState::Locked, &kin, history)
                .normal_stiffness;
            if k > 0.0 {
                let [a, b] = c.blocks;
                let damper = self.dashpot(a, b, &entrance.normal(), k);
                let approached =
                    entrance.gap_at(&block(moving, a), &block(moving, b)) - entrance.gap();
                let loaded = LocalKinematics {
                    gap: kin.gap + approached * damper / (k * dt),
                    ..kin
                };
                if law.next_state(state, &loaded, history) == ContactState::Open {
                    next = ContactState::Open;
                    pulled = true;
                }
            }
        }
        if state.is_closed() && next.is_closed() && next != state {
            // Where the contact can carry almost no shear and carries
            // almost none (a wall's head joint, at no normal force),
            // locked and sliding differ by round-off: with a shear
            // dashpot it would pass between them at every pass.
            let locked = law.response(ContactState::Locked, &kin, history);
            let floor = ROUND_OFF_FORCE * locked.normal_stiffness * kin.tolerance;
            let friction = law.response(ContactState::Sliding, &kin, history);
            if friction.shear_force.abs() < floor && locked.shear_stiffness * kin.shear < floor {
                next = state;
            }
        }
        // The slip direction is the trial spring stretch's (the
        // return map's), so a sliding contact's friction opposes
        // where the stretch points now, never a stale direction.
        let direction = stretch.try_normalize(1e-300);
        // A sliding contact found within its strength carried the
        // locked spring's force and tangent in this pass already (the
        // return map's min(k_s·|s|, strength)): it stays sliding for the
        // passes and commits locked, so no pass is spent locking it and
        // it cannot flip back and forth between the two (a wall's head
        // joints, at almost no normal force, would). Not so where
        // locking adds its shear dashpot.
        let within = state == ContactState::Sliding
            && next == ContactState::Locked
            && !self.damped(i)
            && !self.laws[c.law].yields_at_strength();
        if within {
            next = ContactState::Sliding;
        }
        // Where both states take the return map they load the blocks
        // alike: the pass's forces stand whichever is recorded.
        let alike = state.is_closed() && next.is_closed() && self.yields(i, ContactState::Locked);
        let entrance = widest_entrance(c, &trial.d, e, self.tolerance);
        Decision {
            state: next,
            direction,
            pulled,
            within,
            entrance,
            changed: (next != state && !alike) || entrance != e,
        }
    }

    /// What contact `i` keeps of the accepted trial.
    pub fn kept(&self, i: usize, trial: &Trial<T>, dt: f64) -> Kept<T> {
        let c = &self.contacts[i];
        let e = trial.entrances[i];
        let kin = self.kinematics(i, e, trial, dt);
        let history = c.record.history.as_ref().expect("history set at search");
        let law = &self.laws[c.law];
        let mut state = if trial.within[i] {
            ContactState::Locked
        } else {
            trial.states[i]
        };
        if self.commit_open && state.is_closed() {
            // Opened where the law would open it a contact tolerance
            // further open: at its strength, not past the band.
            let further = LocalKinematics {
                gap: kin.gap + kin.tolerance,
                ..kin
            };
            if law.next_state(state, &further, history) == ContactState::Open {
                state = ContactState::Open;
            }
        }
        let response = if state.is_closed() {
            law.response(state, &kin, history)
        } else {
            ContactResponse::default()
        };
        let ds = (self.entrance(i, e))
            .shear_at(&block(&trial.d, c.blocks[0]), &block(&trial.d, c.blocks[1]));
        let shear = self.carried_shear(c, e) + ds;
        let sliding_stiffness = if state == ContactState::Sliding {
            law.response(ContactState::Locked, &kin, history)
                .shear_stiffness
        } else {
            0.0
        };
        let shear_energy = match state {
            ContactState::Locked => stored(response.shear_force, response.shear_stiffness),
            ContactState::Sliding => {
                let kept = response.shear_force.min(sliding_stiffness * shear.norm());
                stored(kept, sliding_stiffness)
            }
            ContactState::Open => 0.0,
        };
        Kept {
            state,
            kin,
            entrance: e,
            shear: match state {
                ContactState::Locked => shear,
                // The spring keeps the stretch that carries the friction
                // force, so a contact that locks again starts from the force
                // it had instead of from zero (no stick-slip creep).
                // Never more than the trial stretch: with a shear dashpot
                // a contact may slide before its spring alone reaches the
                // strength, and a stretch it never had would be energy
                // from nowhere.
                ContactState::Sliding if sliding_stiffness > 0.0 => {
                    trial.directions[i]
                        * (response.shear_force / sliding_stiffness).min(shear.norm())
                }
                _ => SVector::zeros(),
            },
            direction: trial.directions[i],
            slip: ds.norm(),
            normal_force: response.normal_force,
            shear_force: response.shear_force,
            energy: [
                stored(response.normal_force, response.normal_stiffness),
                shear_energy,
            ],
        }
    }
}

/// Energy of a linear spring carrying `force` with stiffness `k`.
fn stored(force: f64, k: f64) -> f64 {
    if k > 0.0 {
        0.5 * force * force / k
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{ContactLaw, DynContactLaw};
    use crate::contacts::ContactRecord;

    /// Penalty springs with Coulomb friction, yielding at its strength.
    struct Friction;

    const PENALTY: f64 = 1e9;
    const SHEAR: f64 = 4e8;
    const MU: f64 = 0.6;

    impl ContactLaw for Friction {
        type History = ();

        fn initial_history(&self, _: bool) {}

        fn response(&self, state: ContactState, kin: &LocalKinematics, _: &()) -> ContactResponse {
            let normal_force = -PENALTY * kin.gap;
            let (shear_force, shear_stiffness) = match state {
                ContactState::Sliding => (MU * normal_force.max(0.0), 0.0),
                _ => (SHEAR * kin.shear, SHEAR),
            };
            ContactResponse {
                normal_force,
                normal_stiffness: PENALTY,
                shear_force,
                shear_stiffness,
            }
        }

        fn next_state(&self, state: ContactState, _: &LocalKinematics, _: &()) -> ContactState {
            state
        }

        fn commit(&self, _: ContactState, _: &LocalKinematics, _: &mut ()) {}

        fn yields_at_strength(&self) -> bool {
            true
        }
    }

    /// A contact of `Friction` between blocks 0 and 1 (3 DOF each), 1e-5
    /// deep, standing for a boundary of `length`.
    fn frictional_contact(length: f64) -> [Contact<3, 1>; 1] {
        let n = |v: [f64; 3]| BlockVector::<3>::from(v);
        let entrance = Entrance {
            gap: -1e-5,
            normal: [n([0.0, 1.0, 0.2]), n([0.0, -1.0, 0.1])],
            tangents: [[n([1.0, 0.0, -0.3]), n([-1.0, 0.0, 0.05])]],
        };
        [Contact {
            length,
            record: ContactRecord {
                history: Some(DynContactLaw::initial_history(&Friction, true)),
                ..ContactRecord::default()
            },
            ..Contact::between_first_two(vec![entrance])
        }]
    }

    /// A trial holding the one contact in `state` at the blocks' DOF `d`.
    fn trial_of(state: ContactState, d: Vec<f64>) -> Trial<1> {
        Trial {
            d,
            states: vec![state],
            entrances: vec![0],
            directions: vec![SVector::<f64, 1>::from([1.0])],
            converged: false,
            solved: true,
            unsettled: Vec::new(),
            pulled: vec![false],
            within: vec![false],
            load_scale: 0.0,
            rest_norm: 0.0,
            end_norm: 0.0,
            foreseen: Vec::new(),
            first_moves: 0,
        }
    }

    /// A closed contact takes the return map, min(spring, friction): a
    /// locked contact past its strength slides unless a shear dashpot
    /// holds it, a sliding one within it rides its spring; and a move's
    /// forces are its loads' to the last bit.
    #[test]
    fn a_contacts_load_takes_the_return_map_and_a_moves_forces_are_its_loads() {
        let contacts = frictional_contact(1.0);
        let laws: Vec<Box<dyn DynContactLaw>> = vec![Box::new(Friction)];
        let masses = [BlockMatrix::<3>::identity(); 2];
        let chosen = Chosen::default();
        use ContactState::{Locked, Sliding};
        // The friction is 0.6 · 1e4 N; a stretch of 1e-5 carries 4e3 N on
        // the spring, one of 1e-4 4e4 N.
        for (state, stretch, damping, slips) in [
            (Locked, 1e-5, 0.0, false),
            (Locked, 1e-4, 0.0, true),
            (Sliding, 1e-5, 0.0, false),
            (Sliding, 1e-4, 0.0, true),
            (Locked, 1e-4, 0.1, false),
            (Sliding, 1e-5, 0.1, false),
            (Sliding, 1e-4, 0.1, true),
        ] {
            let terms = ContactTerms {
                contacts: &contacts,
                laws: &laws,
                inverse_masses: &masses,
                striking: &[],
                damping,
                tolerance: 1e-7,
                commit_open: false,
                penalty: PENALTY,
                chosen: &chosen,
            };
            let at = trial_of(state, vec![stretch, 0.0, 0.0, 0.0, 0.0, 0.0]);
            let case = format!("{state:?}, stretch {stretch}, damping {damping}");
            let load = terms.load(0, &at, 1e-3, &at.d, false).expect("closed");
            assert_eq!(load.shear_stiffness[0] == 0.0, slips, "{case}");
            let force = terms.force(0, &at, 1e-3, &at.d).expect("closed");
            let bits = |v: &[BlockVector<3>; 2]| v.map(|v| v.map(f64::to_bits));
            assert_eq!(bits(&force), bits(&load.force), "{case}");
        }
    }

    /// The force of a slipping contact, locked and past its strength or
    /// sliding, changes with the blocks' DOF as the whole tangent says:
    /// −(k_n·n nᵀ + slope·u nᵀ), u the friction's direction (finite
    /// differences).
    #[test]
    fn the_whole_tangent_is_the_derivative_of_a_slipping_contacts_force() {
        let contacts = frictional_contact(0.0);
        let laws: Vec<Box<dyn DynContactLaw>> = vec![Box::new(Friction)];
        let masses = [BlockMatrix::<3>::identity(); 2];
        let terms = ContactTerms {
            contacts: &contacts,
            laws: &laws,
            inverse_masses: &masses,
            striking: &[],
            damping: 0.0,
            tolerance: 1e-7,
            commit_open: false,
            penalty: PENALTY,
            chosen: &Chosen::default(),
        };
        // A stretch of 1e-4 carries 4e4 N on the spring; the friction is
        // 0.6 · 1e4 N.
        let d = vec![1e-4, 0.0, 0.0, 0.0, 0.0, 0.0];
        for state in [ContactState::Locked, ContactState::Sliding] {
            let trial = |d: Vec<f64>| trial_of(state, d);
            let at = trial(d.clone());
            let load = terms.load(0, &at, 1e-3, &at.d, true).expect("closed");
            assert_eq!(load.shear_stiffness[0], 0.0, "{state:?} slips");
            let [na, nb] = &contacts[0].entrances[0].normal;
            let [ta, tb] = &contacts[0].entrances[0].tangents[0];
            let (v, u) = ([na, nb], [ta * load.direction[0], tb * load.direction[0]]);
            for j in 0..6 {
                let h = 1e-9;
                let moved = |s: f64| {
                    let mut d = d.clone();
                    d[j] += s * h;
                    let t = trial(d);
                    let l = terms.load(0, &t, 1e-3, &t.d, true).expect("closed");
                    [l.force[0], l.force[1]]
                };
                let (plus, minus) = (moved(1.0), moved(-1.0));
                // Column j of −(k_n·v vᵀ + slope·u vᵀ), block by block.
                let vj = v[j / 3][j % 3];
                let column = |side: usize| {
                    -(v[side] * (load.normal_stiffness * vj) + u[side] * (load.slope * vj))
                };
                for side in 0..2 {
                    let fd = (plus[side] - minus[side]) / (2.0 * h);
                    let exact = column(side);
                    assert!(
                        (fd - exact).norm() <= 1e-6 * exact.norm().max(1.0),
                        "{state:?}, DOF {j}, block {side}: {fd} against {exact}"
                    );
                }
            }
        }
    }
}
