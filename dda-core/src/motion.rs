//! Prescribed motion of the ground: acceleration, velocity or displacement
//! records, sinusoids and pulses, integrated exactly to the displacement
//! that drives the base blocks. `D` is the number of components.

mod file;

use nalgebra::{DMatrix, DVector, SVector};

pub use file::{read_samples, Layout, Sample};

use crate::settings::{finite, positive};
use crate::DdaError;

/// Degree of the polynomial a baseline correction takes out of an
/// acceleration record (so of degree + 2 from its displacement).
pub const BASELINE_DEGREE: usize = 3;

/// What the samples of a recorded motion are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Quantity {
    #[default]
    Acceleration,
    Velocity,
    Displacement,
}

/// A ground motion starting from rest at t = 0.
#[derive(Debug, Clone, PartialEq)]
pub enum GroundMotion<const D: usize> {
    /// a(t) = A sin(2π f t) for t < `duration`, then 0. Whole cycles end at
    /// rest; otherwise the ground keeps its final velocity.
    Sine {
        amplitude: SVector<f64, D>,
        frequency: f64,
        duration: f64,
    },
    /// One sine pulse: a(t) = A sin(2π t / T) for 0 ≤ t ≤ T, then 0.
    Pulse {
        amplitude: SVector<f64, D>,
        period: f64,
    },
    /// Samples (time, value), linear between samples, zero acceleration (or
    /// constant velocity or displacement) after the last one.
    Record(Record<D>),
}

/// A sampled motion, integrated exactly sample to sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Record<const D: usize> {
    times: Vec<f64>,
    acceleration: Vec<SVector<f64, D>>,
    velocity: Vec<SVector<f64, D>>,
    displacement: Vec<SVector<f64, D>>,
    quantity: Quantity,
}

impl<const D: usize> Record<D> {
    /// A record from samples in increasing time; the motion is at rest
    /// before the first sample. Returns the reason if the samples are unusable.
    pub fn new(quantity: Quantity, samples: &[(f64, SVector<f64, D>)]) -> Result<Self, String> {
        if samples.is_empty() {
            return Err("a ground-motion record needs at least one sample".into());
        }
        for (k, w) in samples.windows(2).enumerate() {
            if w[1].0 <= w[0].0 || w[1].0.is_nan() {
                return Err(format!(
                    "sample times must increase (samples {} and {})",
                    k,
                    k + 1
                ));
            }
        }
        if let Some(k) = samples
            .iter()
            .position(|(t, v)| !t.is_finite() || v.iter().any(|x| !x.is_finite()))
        {
            return Err(format!("sample {k} is not a finite number"));
        }
        let times: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let values: Vec<SVector<f64, D>> = samples.iter().map(|s| s.1).collect();
        let n = times.len();
        let zero = SVector::<f64, D>::zeros();
        let (mut acceleration, mut velocity, mut displacement) =
            (vec![zero; n], vec![zero; n], vec![zero; n]);
        match quantity {
            Quantity::Acceleration => acceleration = values,
            Quantity::Velocity => velocity = values,
            Quantity::Displacement => displacement = values,
        }
        match quantity {
            Quantity::Acceleration => {
                (velocity, displacement) = integrate(&times, &acceleration);
            }
            Quantity::Velocity => {
                // Integrate piecewise-linear data exactly, segment by segment.
                for k in 1..n {
                    let h = times[k] - times[k - 1];
                    let (v0, v1) = (velocity[k - 1], velocity[k]);
                    displacement[k] = displacement[k - 1] + (v0 + v1) * (h / 2.0);
                    acceleration[k - 1] = (v1 - v0) / h;
                }
            }
            Quantity::Displacement => {}
        }
        Ok(Self {
            times,
            acceleration,
            velocity,
            displacement,
            quantity,
        })
    }

    /// What the samples are.
    pub fn quantity(&self) -> Quantity {
        self.quantity
    }

    /// Displacement at the last sample (where the ground stays, up to a
    /// constant velocity, after the record ends).
    pub fn end_displacement(&self) -> SVector<f64, D> {
        self.displacement[self.times.len() - 1]
    }

    /// Velocity at the last sample, kept after the record ends.
    pub fn end_velocity(&self) -> SVector<f64, D> {
        self.velocity[self.times.len() - 1]
    }

    /// The record with its baseline corrected, as is usual for
    /// accelerograms: a polynomial of degree [`BASELINE_DEGREE`] in time is
    /// taken out of the acceleration, the one whose doubly integrated
    /// displacement is nearest (least squares over the samples) to the
    /// record's own, with the ground ending at rest where it started
    /// (displacement and velocity zero at the last sample). Small offsets
    /// of the zero line, which integrate to metres of drift, go; the
    /// shaking stays. Records of velocity or displacement, and records of
    /// fewer than [`BASELINE_DEGREE`] + 3 samples, are returned unchanged.
    pub fn baseline_corrected(&self) -> Record<D> {
        let n = self.times.len();
        let m = BASELINE_DEGREE + 1;
        if self.quantity != Quantity::Acceleration || n < m + 2 {
            return self.clone();
        }
        let (t0, t1) = (self.times[0], self.times[n - 1]);
        // Powers of the time scaled to [0, 1], for a well-conditioned fit.
        let basis: Vec<(Vec<f64>, Vec<f64>)> = (0..m)
            .map(|j| {
                let a: Vec<SVector<f64, 1>> = self
                    .times
                    .iter()
                    .map(|t| SVector::<f64, 1>::new(((t - t0) / (t1 - t0)).powi(j as i32)))
                    .collect();
                let (v, u) = integrate(&self.times, &a);
                (
                    u.iter().map(|x| x[0]).collect(),
                    v.iter().map(|x| x[0]).collect(),
                )
            })
            .collect();
        // Least squares with the two end conditions as constraints
        // (Lagrange multipliers): [2AᵀA Cᵀ; C 0].
        let a = DMatrix::from_fn(n, m, |k, j| basis[j].0[k]);
        let mut kkt = DMatrix::zeros(m + 2, m + 2);
        kkt.view_mut((0, 0), (m, m))
            .copy_from(&(a.transpose() * &a * 2.0));
        for j in 0..m {
            let (u_end, v_end) = (basis[j].0[n - 1], basis[j].1[n - 1]);
            kkt[(m, j)] = u_end;
            kkt[(j, m)] = u_end;
            kkt[(m + 1, j)] = v_end;
            kkt[(j, m + 1)] = v_end;
        }
        let Some(lu) = Some(kkt.lu()).filter(|lu| lu.is_invertible()) else {
            return self.clone();
        };
        let mut acceleration = self.acceleration.clone();
        #[allow(clippy::needless_range_loop)] // c is a component of every sample
        for c in 0..D {
            let u = DVector::from_fn(n, |k, _| self.displacement[k][c]);
            let mut rhs = DVector::zeros(m + 2);
            rhs.rows_mut(0, m).copy_from(&(a.transpose() * &u * 2.0));
            rhs[m] = self.displacement[n - 1][c];
            rhs[m + 1] = self.velocity[n - 1][c];
            let Some(b) = lu.solve(&rhs) else {
                return self.clone();
            };
            for (k, t) in self.times.iter().enumerate() {
                let s = (t - t0) / (t1 - t0);
                let trend: f64 = (0..m).map(|j| b[j] * s.powi(j as i32)).sum();
                acceleration[k][c] -= trend;
            }
        }
        let (velocity, displacement) = integrate(&self.times, &acceleration);
        Record {
            times: self.times.clone(),
            acceleration,
            velocity,
            displacement,
            quantity: Quantity::Acceleration,
        }
    }

    /// (segment start index, time into it), or None before the first sample.
    fn locate(&self, t: f64) -> Option<(usize, f64)> {
        if t < self.times[0] {
            return None;
        }
        let k = self.times.partition_point(|&s| s <= t).saturating_sub(1);
        Some((k, t - self.times[k]))
    }

    fn displacement(&self, t: f64) -> SVector<f64, D> {
        let Some((k, tau)) = self.locate(t) else {
            return SVector::zeros();
        };
        let last = k + 1 == self.times.len();
        match self.quantity {
            Quantity::Acceleration => {
                let slope = if last {
                    SVector::zeros()
                } else {
                    (self.acceleration[k + 1] - self.acceleration[k])
                        / (self.times[k + 1] - self.times[k])
                };
                let a = if last {
                    SVector::zeros()
                } else {
                    self.acceleration[k]
                };
                self.displacement[k]
                    + self.velocity[k] * tau
                    + a * (tau * tau / 2.0)
                    + slope * (tau.powi(3) / 6.0)
            }
            Quantity::Velocity => {
                let a = if last {
                    SVector::zeros()
                } else {
                    self.acceleration[k]
                };
                self.displacement[k] + self.velocity[k] * tau + a * (tau * tau / 2.0)
            }
            Quantity::Displacement => {
                if last {
                    self.displacement[k]
                } else {
                    let s = tau / (self.times[k + 1] - self.times[k]);
                    self.displacement[k] * (1.0 - s) + self.displacement[k + 1] * s
                }
            }
        }
    }

    fn acceleration(&self, t: f64) -> SVector<f64, D> {
        match (self.quantity, self.locate(t)) {
            (Quantity::Acceleration, Some((k, tau))) if k + 1 < self.times.len() => {
                let s = tau / (self.times[k + 1] - self.times[k]);
                self.acceleration[k] * (1.0 - s) + self.acceleration[k + 1] * s
            }
            (Quantity::Velocity, Some((k, _))) if k + 1 < self.times.len() => self.acceleration[k],
            _ => SVector::zeros(),
        }
    }

    /// Largest |acceleration| component magnitude of the samples (PGA).
    pub fn peak_acceleration(&self) -> f64 {
        self.acceleration
            .iter()
            .map(|a| a.norm())
            .fold(0.0, f64::max)
    }
}

/// Velocities and displacements of piecewise-linear accelerations, from
/// rest at the first sample, integrated exactly segment by segment.
#[allow(clippy::type_complexity)]
fn integrate<const D: usize>(
    times: &[f64],
    acceleration: &[SVector<f64, D>],
) -> (Vec<SVector<f64, D>>, Vec<SVector<f64, D>>) {
    let n = times.len();
    let zero = SVector::<f64, D>::zeros();
    let (mut velocity, mut displacement) = (vec![zero; n], vec![zero; n]);
    for k in 1..n {
        let h = times[k] - times[k - 1];
        let (a0, a1) = (acceleration[k - 1], acceleration[k]);
        velocity[k] = velocity[k - 1] + (a0 + a1) * (h / 2.0);
        displacement[k] =
            displacement[k - 1] + velocity[k - 1] * h + (a0 * 2.0 + a1) * (h * h / 6.0);
    }
    (velocity, displacement)
}

impl<const D: usize> GroundMotion<D> {
    /// Whether a sine's or pulse's values make a motion: the first field at
    /// fault and what to change (a record's samples are checked by
    /// [`Record::new`]).
    pub fn check(&self) -> Result<(), DdaError> {
        let amplitude = |a: &SVector<f64, D>| {
            a.iter()
                .try_for_each(|v| finite("amplitude", "the amplitude", *v))
        };
        match self {
            GroundMotion::Sine {
                amplitude: a,
                frequency,
                duration,
            } => {
                amplitude(a)?;
                positive("frequency", "the frequency", *frequency, "give it in Hz")?;
                let hint = "give how long the shaking lasts, in s";
                positive("duration", "the duration", *duration, hint)
            }
            GroundMotion::Pulse {
                amplitude: a,
                period,
            } => {
                amplitude(a)?;
                positive(
                    "period",
                    "the period",
                    *period,
                    "give the pulse's length in s",
                )
            }
            GroundMotion::Record(_) => Ok(()),
        }
    }

    /// Ground displacement at time t.
    pub fn displacement(&self, t: f64) -> SVector<f64, D> {
        use std::f64::consts::TAU;
        match self {
            GroundMotion::Sine {
                amplitude,
                frequency,
                duration,
            } => {
                // u = A (t/ω − sin ωt / ω²) while shaking, then drifting at v(end).
                let w = TAU * frequency;
                let u = |t: f64| t / w - (w * t).sin() / (w * w);
                let v = |t: f64| (1.0 - (w * t).cos()) / w;
                if t <= 0.0 {
                    SVector::zeros()
                } else if t <= *duration {
                    amplitude * u(t)
                } else {
                    amplitude * (u(*duration) + v(*duration) * (t - duration))
                }
            }
            GroundMotion::Pulse { amplitude, period } => {
                let w = TAU / period;
                let t = t.clamp(0.0, *period);
                // v(T) = 0: the ground ends at rest, displaced by A T / ω.
                amplitude * (t / w - (w * t).sin() / (w * w))
            }
            GroundMotion::Record(r) => r.displacement(t),
        }
    }

    /// Ground acceleration at time t (for reporting and tests).
    pub fn acceleration(&self, t: f64) -> SVector<f64, D> {
        use std::f64::consts::TAU;
        match self {
            GroundMotion::Sine {
                amplitude,
                frequency,
                duration,
            } if t > 0.0 && t <= *duration => amplitude * (TAU * frequency * t).sin(),
            GroundMotion::Pulse { amplitude, period } if t > 0.0 && t <= *period => {
                amplitude * (TAU * t / period).sin()
            }
            GroundMotion::Record(r) => r.acceleration(t),
            _ => SVector::zeros(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    /// Second difference of the displacement: the acceleration, to O(h²).
    fn check_acceleration(m: &GroundMotion<2>, times: &[f64]) {
        let h = 1e-4;
        for &t in times {
            let fd =
                (m.displacement(t + h) - m.displacement(t) * 2.0 + m.displacement(t - h)) / (h * h);
            let a = m.acceleration(t);
            assert!(
                (fd - a).norm() < 1e-5 * (1.0 + a.norm()),
                "t = {t}: {fd} vs {a}"
            );
        }
    }

    #[test]
    fn sine_and_pulse_integrate_to_their_displacements() {
        let sine = GroundMotion::Sine {
            amplitude: Vector2::new(2.0, -1.0),
            frequency: 1.5,
            duration: 2.0,
        };
        check_acceleration(&sine, &[0.1, 0.37, 1.2, 1.9, 2.5]);
        let pulse = GroundMotion::Pulse {
            amplitude: Vector2::new(3.0, 0.0),
            period: 0.4,
        };
        check_acceleration(&pulse, &[0.05, 0.2, 0.35, 0.8]);
        // A pulse ends at rest, displaced by A T² / (2π).
        let end = pulse.displacement(1.0);
        assert!((end.x - 3.0 * 0.16 / std::f64::consts::TAU).abs() < 1e-15);
        assert_eq!(pulse.displacement(1.0), pulse.displacement(2.0));
    }

    #[test]
    fn baseline_correction_takes_out_drift_and_keeps_the_shaking() {
        // A 2 Hz shaking on a zero line offset by 0.01 m/s², which alone
        // integrates to 0.5 m of drift over 10 s.
        let samples: Vec<(f64, Vector2<f64>)> = (0..=1000)
            .map(|k| {
                let t = k as f64 * 0.01;
                let shake = (std::f64::consts::TAU * 2.0 * t).sin() * (t * (10.0 - t) / 25.0);
                (t, Vector2::new(shake + 0.01, 0.5 * shake - 0.02))
            })
            .collect();
        let raw = Record::new(Quantity::Acceleration, &samples).unwrap();
        assert!(raw.end_displacement().x > 0.4, "{}", raw.end_displacement());
        let fixed = raw.baseline_corrected();
        assert!(fixed.end_displacement().norm() < 1e-9);
        assert!(fixed.end_velocity().norm() < 1e-9);
        // The offset goes, the shaking stays.
        let m = GroundMotion::Record(fixed.clone());
        let peak = (0..1000)
            .map(|k| m.displacement(k as f64 * 0.01).x.abs())
            .fold(0.0, f64::max);
        assert!(peak < 0.02, "peak displacement {peak}");
        let change = (fixed.peak_acceleration() - raw.peak_acceleration()).abs();
        assert!(change < 0.05 * raw.peak_acceleration(), "{change}");
        // After the record the ground stays where it is.
        assert!((m.displacement(10.0) - m.displacement(20.0)).norm() < 1e-9);
        // Other quantities are left alone.
        let v = Record::new(Quantity::Velocity, &samples).unwrap();
        assert_eq!(v.baseline_corrected(), v);
    }

    #[test]
    fn records_integrate_piecewise_linear_samples_exactly() {
        // A triangle of acceleration, then nothing: compare with the sine-free
        // closed form at the peak and the end.
        let samples = [
            (0.0, Vector2::new(0.0, 0.0)),
            (1.0, Vector2::new(2.0, 0.0)),
            (2.0, Vector2::new(0.0, 0.0)),
        ];
        let m = GroundMotion::Record(Record::new(Quantity::Acceleration, &samples).unwrap());
        // a = 2t on [0, 1]: u(1) = t³/3 = 1/3; v(1) = 1; v(2) = 2, u(2) = 2.
        assert!((m.displacement(1.0).x - 1.0 / 3.0).abs() < 1e-14);
        assert!((m.displacement(2.0).x - 2.0).abs() < 1e-14);
        // Then constant velocity 2.
        assert!((m.displacement(3.0).x - 4.0).abs() < 1e-14);
        check_acceleration(&m, &[0.3, 1.5]);
        let v = GroundMotion::Record(
            Record::new(
                Quantity::Velocity,
                &[(0.0, Vector2::zeros()), (1.0, Vector2::new(1.0, 0.0))],
            )
            .unwrap(),
        );
        assert!((v.displacement(1.0).x - 0.5).abs() < 1e-15);
        assert!(Record::<2>::new(
            Quantity::Acceleration,
            &[(1.0, Vector2::zeros()), (1.0, Vector2::zeros())]
        )
        .is_err());
        assert!(Record::<2>::new(Quantity::Acceleration, &[]).is_err());
    }
}
