//! Guards: checks after every accepted step that stop a run whose results
//! can no longer be trusted, with a report naming the time, the blocks and
//! the contacts, and what to change. `analysis.on_failure: Continue` runs
//! on instead (the summary still warns).

use anyhow::bail;
use dda_core::Statistics;
use serde::{Deserialize, Serialize};

use crate::observe::RunView;

/// What a run does when a guard trips.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum OnFailure {
    /// End the run there, status "failed", with the report (default).
    #[default]
    Stop,
    /// Run on; the summary lists what happened as warnings.
    Continue,
}

/// The guards of one run.
pub struct Guards {
    on_failure: OnFailure,
    /// Deepest penetration allowed (m): the driver's bound.
    penetration_limit: f64,
    /// Whether the contacts have dashpots (`analysis.contact_damping`),
    /// so the advice does not ask for what is already there.
    damped: bool,
    /// The counts of the last step.
    seen: Seen,
    /// Each block's velocity after the last step, for a closing speed.
    velocities: Vec<[f64; 3]>,
}

#[derive(Default)]
struct Seen {
    unconverged: usize,
    deep: usize,
    energy: usize,
}

impl Seen {
    fn of(stats: &Statistics) -> Self {
        Self {
            unconverged: stats.unconverged_steps,
            deep: stats.deep_penetration_steps,
            energy: stats.energy_growth_steps,
        }
    }
}

impl Guards {
    /// Guards for a run now at `run`'s state (a resumed run's earlier
    /// reports are not reported again).
    pub fn new(
        on_failure: OnFailure,
        penetration_limit: f64,
        damped: bool,
        run: &dyn RunView,
    ) -> Self {
        Self {
            on_failure,
            penetration_limit,
            damped,
            seen: Seen::of(run.statistics()),
            velocities: (0..run.block_count()).map(|i| run.velocity(i)).collect(),
        }
    }

    /// After an accepted step: an error that stops the run if a guard
    /// tripped (a non-finite number always stops it).
    pub fn after_step(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        let t = run.time();
        let blown: Vec<usize> = (0..run.block_count())
            .filter(|&i| !run.is_finite(i))
            .collect();
        if !blown.is_empty() {
            bail!(
                "at t = {t} s, {} a non-finite position or velocity: the model is unstable; {}",
                blocks(&blown, "has", "have"),
                dda_core::error::OVERFLOW_ADVICE
            );
        }
        let stats = run.statistics();
        let before = std::mem::replace(&mut self.seen, Seen::of(stats));
        let stop = self.on_failure == OnFailure::Stop;
        if stop && stats.deep_penetration_steps > before.deep {
            if let Some((key, depth)) = stats.last_deep {
                let [a, b] = [key.block_a as usize, key.block_b as usize];
                let speed = self.closing_speed(a, b);
                let travel = speed * run.dt();
                let advice = if travel > self.penetration_limit {
                    format!(
                        "the blocks closed at {speed:.3e} m/s, {travel:.3e} m in one step of {:.3e} s: a dt below {:.3e} s lets the contact springs catch them",
                        run.dt(),
                        self.penetration_limit / speed
                    )
                } else {
                    format!(
                        "the springs are too soft for the load they carry: raise analysis.penalty (now {:.3e} N/m³)",
                        run.penalty()
                    )
                };
                bail!(
                    "at t = {t} s, contact {} (block {a} into block {b}) penetrated {depth:.3e} m, beyond the bound of {:.3e} m (analysis.max_penetration_ratio × the length scale) even at the smallest step; {advice}{}",
                    run.contact_label(&key),
                    self.penetration_limit,
                    CONTINUE
                );
            }
        }
        if stop && stats.unconverged_steps > before.unconverged {
            let contacts: Vec<String> = stats
                .last_unsettled
                .iter()
                .take(5)
                .map(|k| {
                    format!(
                        "{} (block {} on block {})",
                        run.contact_label(k),
                        k.block_a,
                        k.block_b
                    )
                })
                .collect();
            bail!(
                "at t = {t} s, the step could not reach open-close agreement even at the smallest time step (analysis.min_dt_ratio × dt); still changing: {}; {}{}",
                if contacts.is_empty() { "no contact named".into() } else { contacts.join(", ") },
                if self.damped {
                    "a smaller dt or a larger analysis.open_close_limit lets the contacts settle"
                } else {
                    "a smaller dt, analysis.contact_damping: 1.0 or a larger analysis.open_close_limit lets the contacts settle"
                },
                CONTINUE
            );
        }
        if stop && stats.energy_growth_steps > before.energy {
            let mut fastest: Vec<(usize, f64)> = (0..run.block_count())
                .map(|i| (i, norm(run.velocity(i))))
                .collect();
            fastest.sort_by(|x, y| y.1.total_cmp(&x.1));
            let named: Vec<String> = fastest
                .iter()
                .take(3)
                .map(|(i, v)| format!("block {i} ({v:.3e} m/s)"))
                .collect();
            bail!(
                "at t = {t} s, the total energy rose {:.3e} J above its lowest value although nothing does work on the blocks; the fastest are {}; {}{}",
                stats.energy_growth,
                named.join(", "),
                crate::summary::energy_advice(
                    stats,
                    dda_core::error::stiff_penalty(run.penalty(), run.automatic_penalty())
                ),
                CONTINUE
            );
        }
        self.velocities = (0..run.block_count()).map(|i| run.velocity(i)).collect();
        Ok(())
    }

    /// The speed at which blocks a and b approached each other at the start
    /// of the step (translations only).
    fn closing_speed(&self, a: usize, b: usize) -> f64 {
        let (va, vb) = (self.velocities[a], self.velocities[b]);
        norm([va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]])
    }
}

const CONTINUE: &str = " (analysis.on_failure: Continue runs on regardless)";

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// "block 3 has" or "blocks 3, 4 and 7 have".
fn blocks(list: &[usize], one: &str, many: &str) -> String {
    let names: Vec<String> = list.iter().take(10).map(|i| i.to_string()).collect();
    match names.as_slice() {
        [only] => format!("block {only} {one}"),
        [rest @ .., last] => format!("blocks {} and {last} {many}", rest.join(", ")),
        [] => String::new(),
    }
}
