//! Analysis settings of the driver.

use serde::{Deserialize, Serialize};

use crate::error::DdaError;

/// Declares a struct of the fields given (each with its default), then the
/// driver's settings: those of [`Settings`] but `velocity_ratio` and
/// `mass_damping`, each with its doc and default. With `Default`, and
/// `settings_with`, the [`Settings`] of its values. One flat struct, so a
/// serde derive on it refuses unknown fields (`flatten` cannot): a scene's
/// `analysis` section is one.
#[macro_export]
macro_rules! with_settings {
    ($(#[$meta:meta])* pub struct $name:ident { $($own:tt)* }) => {
        $crate::with_settings! { @declare $(#[$meta])* $name { $($own)* }
            /// Nominal time step, s; default `None`: automatic. Under gravity
            /// with the implicit integrator the step then follows the motion,
            /// as long as keeps each contact's relative motion, each block's
            /// points' motion against each other, and a block in flight's
            /// whole motion below 2.5e-4 of the median block size a step, at
            /// most 1/20 of sqrt(block size / g) (a wall at rest or ringing
            /// steps at that ceiling, a rocking column at about a
            /// millisecond); without gravity, 0.2·sqrt(lightest block
            /// mass / penalty), which resolves contact oscillations.
            dt: Option<f64> = None,
            /// Smallest time step as a fraction of the nominal one, the floor
            /// of recursive cuts; default 1e-3.
            min_dt_ratio: f64 = 1e-3,
            /// Open-close passes before the step is cut to a third; default
            /// 20 (Shi's codes stop at 6). A pass that returns to the states
            /// of two passes before is a cycle and is broken at once, so
            /// the limit only stops states that keep changing: as a
            /// 70-course wall rebounds, joints open one course of bricks per
            /// pass; at 6 its first 0.1 s cut 8 steps (758 factorisations,
            /// against none cut and 420 at 20), and with contact damping it
            /// failed.
            open_close_limit: usize = 20,
            /// Largest step displacement of any boundary point, as a fraction
            /// of w0 (Shi's g2); default 0.01. In a model more than about 10
            /// blocks wide the bound is also at most a tenth of the median
            /// block size (or twice the last step's motion, if larger). The
            /// contact search range is 2.5 times the bound.
            max_displacement_ratio: f64 = 0.01,
            /// Deepest penetration allowed, as a fraction of w0 (2.5·g3 in
            /// Shi); default 1e-3.
            max_penetration_ratio: f64 = 1e-3,
            /// Normal contact stiffness per unit contact length (2D, per unit
            /// thickness) or area (3D), N/m³; a contact's springs are this
            /// times the length or area they stand for. Default `None`: twice
            /// the stiffest block's Young's modulus over the median block size
            /// (stiff enough that penetration under self-weight is a tiny
            /// fraction of the block size, soft enough to keep the system well
            /// conditioned).
            penalty: Option<f64> = None,
            /// Multiply the penalty by 10 and redo the step when a step
            /// penetrates too deep (Shi's remedy); default `false`: a global
            /// raise multiplies the force of every existing overlap and can
            /// throw blocks apart, so the step is cut to a third instead.
            raise_penalty: bool = false,
            /// Newton-Raphson iterations per open-close pass, at most; default
            /// 25.
            newton_limit: usize = 25,
            /// Newton-Raphson stops when the residual falls below this fraction
            /// of the step's first one, at its start (a later open-close pass's
            /// own first where that is larger), default 1e-10 ...
            residual_tolerance: f64 = 1e-10,
            /// ... or the increment below this fraction of w0 (default 1e-14):
            /// on a factor kept from an earlier iterate, the increments still
            /// to come, the last one's times ρ / (1 − ρ), ρ the residual's
            /// contraction over it.
            increment_tolerance: f64 = 1e-14,
            /// Open-close distance tolerance, as a fraction of w0; default
            /// 1e-7.
            contact_tolerance: f64 = 1e-7,
            /// Model length scale w0, m; default `None`: the system's.
            length_scale: Option<f64> = None,
            /// Contact damping as a share of critical; default 0 (off), 1 is
            /// critical. A dashpot beside each closed contact's normal spring,
            /// and beside its shear spring while locked, of coefficient
            /// 2ζ·sqrt(k·m) with k the spring and m the contact's effective
            /// mass along it. At 1 an impact ends without rebound of the
            /// striking point (Housner's inelastic impact, which a rocking
            /// rigid block assumes) and a block released onto its contacts
            /// settles without bouncing, so a block near its friction limit
            /// does not slide off during the first bounces; 0 gives Shi's
            /// undamped springs, whose rebound depends on the step.
            contact_damping: f64 = 0.0,
            /// Whether a closed contact opens at its tensile strength;
            /// default `false`: a contact tolerance past it, a band that
            /// keeps passes from opening and closing it by turns. The
            /// spring over that band pulls, up to the spring's stiffness
            /// times contact_tolerance·w0, so uplift waits for a pull that
            /// grows with the penalty: a rigid 1 m × 4 m column under a
            /// slowly rising base acceleration lifted at 0.267 g at a
            /// penalty of 2e10 and not by 0.28 g at 2e11, where its
            /// threshold is 0.25 g (`tests/uplift.rs`); and a static step,
            /// with no inertia to carry a block across the band, lets a
            /// block stand 1 mm beyond its ledge (`tests/static_steps.rs`).
            /// With `true`, a contact that ends a step pulling past its
            /// strength is committed open, so the next step starts without
            /// it: the column lifts at 0.255 g at both penalties, in 2D and
            /// 3D, and the block tips. It costs a ringing wall passes (the
            /// 10,051-block wall at dt 1 ms: 11.2 moves a step instead of
            /// 7, twice the time). A settling's static steps keep the band
            /// (with no inertia, a block would cross a contact opened
            /// between them and back, and never end still); the run then
            /// opens what pulls. A running-bond wall near its toppling
            /// limit stands on the band's pull: a tilted 68-brick wall
            /// whose joints can carry at most 0.994 of its load stands
            /// with the band and topples with `true` (`tests/settle.rs`).
            /// Implicit integrator only: the explicit one keeps the band.
            open_at_strength: bool = false,
            /// Coefficient of restitution e of impacts, in [0, 1]; default
            /// `None` (off: the springs and dashpots alone decide a rebound,
            /// which then follows dt and the penalty). With a value, a contact
            /// that closes in a step strikes: before the step is solved, an
            /// impulse on the two blocks turns its approach speed u into a
            /// rebound of e·u (and stops its slip if it closes locked), as
            /// rigid-body impacts do. 0 is Housner's inelastic impact; implicit
            /// integrator only.
            restitution: Option<f64> = None,
            /// How each step is integrated in time; default `Implicit` (Shi's
            /// Newmark steps with open-close iterations). `Explicit` is central
            /// differences on the same blocks and contact laws, with steps
            /// below the critical one.
            integrator: $crate::Integrator = $crate::Integrator::Implicit,
            /// Local (non-viscous) damping of the explicit integrator, as in
            /// 3DEC/UDEC: each DOF's unbalanced force is reduced by this share
            /// of its size, against the DOF's velocity; in [0, 1), default 0
            /// (off). 0.8 relaxes a model to rest (a static solution); dynamic
            /// runs keep 0. The implicit integrator takes none.
            local_damping: f64 = 0.0,
            /// How the step's linear systems are solved; default `Direct`
            /// (sparse Cholesky). `Iterative` is preconditioned conjugate
            /// gradients with a tolerance and an iteration cap
            /// (`docs/solvers.md`).
            solver: $crate::Solver = $crate::Solver::Direct,
        }
    };
    (@declare $(#[$meta:meta])* $name:ident {
        $($(#[$own_doc:meta])* $own:ident: $own_ty:ty = $own_default:expr,)*
    } $($(#[$doc:meta])* $field:ident: $ty:ty = $default:expr,)*) => {
        $(#[$meta])*
        pub struct $name {
            $($(#[$own_doc])* pub $own: $own_ty,)*
            $($(#[$doc])* pub $field: $ty,)*
        }

        impl Default for $name {
            fn default() -> Self {
                Self { $($own: $own_default,)* $($field: $default,)* }
            }
        }

        impl $name {
            /// The driver's settings: these, with the velocity ratio and the
            /// mass damping given.
            pub fn settings_with(&self, velocity_ratio: f64, mass_damping: f64) -> $crate::Settings {
                $crate::Settings {
                    velocity_ratio,
                    mass_damping,
                    $($field: self.$field.clone(),)*
                }
            }
        }
    };
}

with_settings! {
    /// Settings of one analysis. Lengths are fractions of the model length
    /// scale w0 where noted (Shi's control ratios). Each field's line says its
    /// unit and default; a field left out of a serialised form takes its
    /// default.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    #[serde(default, deny_unknown_fields)]
    pub struct Settings {
        /// Velocity carry-over ratio k_dyn, in [0, 1]; default 1. 1 is fully
        /// dynamic, 0 static (each step starts at rest), in between bleeds
        /// kinetic energy.
        velocity_ratio: f64 = 1.0,
        /// Mass-proportional viscous damping coefficient α, 1/s; default 0
        /// (off). A force −αM·v on every block; a damping ratio ξ at angular
        /// frequency ω is α = 2ξω.
        mass_damping: f64 = 0.0,
    }
}

/// The linear solver of the implicit step.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Solver {
    /// Sparse Cholesky with a fill-reducing ordering: exact to rounding,
    /// one factorisation per change of the matrix.
    #[default]
    Direct,
    /// Conjugate gradients preconditioned by each block's own diagonal
    /// block (block Jacobi), started from the last solution.
    Iterative {
        /// Relative residual ‖b − Ax‖ / ‖b‖ at which the iterations stop,
        /// in (0, 1); default 1e-11, a tenth of the Newton-Raphson
        /// `residual_tolerance` default, so a linear pass still converges
        /// in one Newton-Raphson iteration.
        #[serde(default = "default_iterative_tolerance")]
        tolerance: f64,
        /// Iterations, at most, before the system is solved by sparse
        /// Cholesky instead (counted in the statistics); at least 1,
        /// default 1000.
        #[serde(default = "default_iterative_cap")]
        max_iterations: usize,
    },
}

impl Solver {
    /// `Iterative` with its default tolerance and iteration cap.
    pub fn iterative() -> Self {
        Solver::Iterative {
            tolerance: default_iterative_tolerance(),
            max_iterations: default_iterative_cap(),
        }
    }
}

fn default_iterative_tolerance() -> f64 {
    1e-11
}

fn default_iterative_cap() -> usize {
    1000
}

/// Time integration of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Integrator {
    /// Shi's Newmark (β = 1/2, γ = 1) step, solved with the contact states
    /// held fixed and repeated until they agree (open-close iterations):
    /// unconditionally stable, any step the displacement bound allows.
    #[default]
    Implicit,
    /// Central differences (velocities at half steps): no matrix, no
    /// iterations, but a step below the critical one, 2/ω_max, which the
    /// driver bounds from the penalty springs and the block masses at every
    /// step and enforces.
    Explicit,
}

impl Settings {
    /// Checks every value; the first bad one is named by its field, with
    /// what to write instead.
    pub fn validate(&self) -> Result<(), DdaError> {
        let auto = "give a value or leave it out for an automatic one";
        let ratio = "it is a fraction of the model size, like 0.01";
        let tolerance = "it is a small fraction, like the default";
        if let Some(dt) = self.dt {
            positive(
                "dt",
                "the time step dt",
                dt,
                "give a time step in seconds or leave dt out for an automatic one",
            )?;
        }
        finite("velocity_ratio", "velocity_ratio", self.velocity_ratio)?;
        if !(0.0..=1.0).contains(&self.velocity_ratio) {
            return Err(invalid(
                "velocity_ratio",
                format!(
                    "velocity_ratio must lie in [0, 1] (1 dynamic, 0 static), got {}",
                    self.velocity_ratio
                ),
            ));
        }
        if self.open_close_limit == 0 {
            return Err(invalid(
                "open_close_limit",
                "open_close_limit must be at least 1 (the default is 20)".into(),
            ));
        }
        if self.newton_limit == 0 {
            return Err(invalid(
                "newton_limit",
                "newton_limit must be at least 1 (25 is usual)".into(),
            ));
        }
        positive(
            "max_displacement_ratio",
            "max_displacement_ratio",
            self.max_displacement_ratio,
            ratio,
        )?;
        positive(
            "max_penetration_ratio",
            "max_penetration_ratio",
            self.max_penetration_ratio,
            ratio,
        )?;
        positive(
            "min_dt_ratio",
            "min_dt_ratio",
            self.min_dt_ratio,
            "it is a fraction of dt, like 0.001",
        )?;
        if self.min_dt_ratio > 1.0 {
            return Err(invalid(
                "min_dt_ratio",
                format!(
                    "min_dt_ratio is a fraction of dt and must not exceed 1, got {}",
                    self.min_dt_ratio
                ),
            ));
        }
        non_negative(
            "contact_damping",
            "contact_damping",
            self.contact_damping,
            "it is a share of critical damping: 0 off, 1 critical",
        )?;
        non_negative(
            "mass_damping",
            "mass_damping",
            self.mass_damping,
            "it is a coefficient in 1/s: 0 off",
        )?;
        non_negative(
            "local_damping",
            "local_damping",
            self.local_damping,
            "it is a share of the unbalanced force: 0 off, 0.8 to relax to rest",
        )?;
        if self.local_damping >= 1.0 {
            return Err(invalid(
                "local_damping",
                format!(
                    "local_damping must be below 1 (at 1 no unbalanced force would move a block), got {}; 0.8 relaxes a model to rest",
                    self.local_damping
                ),
            ));
        }
        if self.local_damping > 0.0 && self.integrator == Integrator::Implicit {
            return Err(invalid(
                "local_damping",
                "local damping belongs to the explicit integrator; write integrator: Explicit, or use contact_damping or mass damping with the implicit one".into(),
            ));
        }
        if let Some(e) = self.restitution {
            if !(0.0..=1.0).contains(&e) {
                return Err(invalid(
                    "restitution",
                    format!("restitution must lie in [0, 1], got {e}; 0 is an inelastic impact (Housner's), 1 an elastic one"),
                ));
            }
            if self.integrator == Integrator::Explicit {
                return Err(invalid(
                    "restitution",
                    "impacts with a restitution coefficient belong to the implicit integrator; leave restitution out, or use contact_damping with the explicit one".into(),
                ));
            }
        }
        if let Solver::Iterative {
            tolerance,
            max_iterations,
        } = self.solver
        {
            finite("solver", "the solver's tolerance", tolerance)?;
            if !(tolerance > 0.0 && tolerance < 1.0) {
                return Err(invalid(
                    "solver",
                    format!("the iterative solver's tolerance is a relative residual in (0, 1), got {tolerance}; 1e-11 is the default"),
                ));
            }
            if max_iterations == 0 {
                return Err(invalid(
                    "solver",
                    "the iterative solver's max_iterations must be at least 1 (1000 is the default)".into(),
                ));
            }
            if self.integrator == Integrator::Explicit {
                return Err(invalid(
                    "solver",
                    "the explicit integrator solves no system; leave solver out, or use integrator: Implicit".into(),
                ));
            }
        }
        if let Some(p) = self.penalty {
            positive("penalty", "the penalty", p, auto)?;
        }
        if let Some(w) = self.length_scale {
            positive("length_scale", "the length scale", w, auto)?;
        }
        positive(
            "residual_tolerance",
            "residual_tolerance",
            self.residual_tolerance,
            tolerance,
        )?;
        positive(
            "increment_tolerance",
            "increment_tolerance",
            self.increment_tolerance,
            tolerance,
        )?;
        positive(
            "contact_tolerance",
            "contact_tolerance",
            self.contact_tolerance,
            tolerance,
        )
    }
}

fn invalid(field: &'static str, message: String) -> DdaError {
    DdaError::Setting { field, message }
}

/// `value` is a finite number.
pub fn finite(field: &'static str, what: &str, value: f64) -> Result<(), DdaError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("{what} is {value}, not a finite number; write a finite value"),
        ))
    }
}

/// `value` is finite and above zero; `hint` says what to write.
pub fn positive(field: &'static str, what: &str, value: f64, hint: &str) -> Result<(), DdaError> {
    finite(field, what, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("{what} must be positive, got {value}; {hint}"),
        ))
    }
}

/// `value` is finite and zero or above; `hint` says what to write.
pub fn non_negative(
    field: &'static str,
    what: &str,
    value: f64,
    hint: &str,
) -> Result<(), DdaError> {
    finite(field, what, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("{what} must not be negative, got {value}; {hint}"),
        ))
    }
}
