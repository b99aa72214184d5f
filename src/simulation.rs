//! What a run needs of a driver, in either dimension: [`Driver2d`] and
//! [`Driver3d`] both implement [`Simulation`], so `run` is written once;
//! the outputs see a simulation as a [`RunView`].

use dda_2d::Driver2d;
use dda_3d::Driver3d;
use dda_core::{ContactKey, DdaError, Settling, Statistics};

use crate::observe::{BlockShape, ContactLine, PointLine, RunView};

/// A driver a scene run can step and record.
pub trait Simulation {
    /// 2 or 3.
    const DIMENSION: u32;
    /// The header line of its `history.csv`.
    const HISTORY_HEADER: &'static str;

    fn time(&self) -> f64;
    /// The nominal time step.
    fn dt(&self) -> f64;
    /// The normal penalty now (after any raises).
    fn penalty(&self) -> f64;
    /// The model's automatic penalty, whatever the one in use.
    fn automatic_penalty(&self) -> f64;
    fn statistics(&self) -> &Statistics;
    /// Why automatic values were chosen.
    fn notes(&self) -> &[String];
    fn block_count(&self) -> usize;
    fn advance_to(&mut self, time: f64) -> Result<(), DdaError>;
    /// [`Simulation::advance_to`], showing each accepted step to `observe`.
    fn advance_observed(
        &mut self,
        time: f64,
        observe: &mut dyn FnMut(&Self),
    ) -> Result<(), DdaError>;
    /// [`Simulation::advance_observed`] that stops after a step where
    /// `go_on` says false; returns whether `time` was reached.
    fn advance_while(
        &mut self,
        time: f64,
        go_on: &mut dyn FnMut(&Self) -> bool,
    ) -> Result<bool, DdaError>;
    /// One step of at most `dt_limit`.
    fn step(&mut self, dt_limit: f64) -> Result<(), DdaError>;
    /// The values of a block's history row after `step,time,block`.
    fn history_values(&self, block: usize) -> Vec<f64>;
    /// Block `block`'s boundary now.
    fn block_shape(&self, block: usize) -> BlockShape;
    /// Whether the block's position and velocity are finite numbers.
    fn is_finite(&self, block: usize) -> bool;
    /// The contacts the last step considered, open ones included.
    fn contact_lines(&self) -> Vec<ContactLine>;
    /// A contact's name, like `1:v0/0:e2`.
    fn contact_label(&self, key: &ContactKey) -> String;
    /// A block's velocity (z = 0 in 2D), m/s.
    fn velocity(&self, block: usize) -> [f64; 3];
    /// The scene's measured points, in order.
    fn measured_points(&self) -> Vec<PointLine>;
    /// The model's length scale w0, m.
    fn length_scale(&self) -> f64;
    /// The whole state, for a checkpoint.
    fn save(&self) -> Result<Vec<u8>, DdaError>;
    /// Back to a state [`Simulation::save`] gave.
    fn restore(&mut self, bytes: &[u8]) -> Result<(), DdaError>;
    /// Brings the model to rest under its loads now in at most
    /// `most_steps` static steps ([`dda_core::Driver::settle`]); the
    /// measured points' displacements then start from there.
    fn settle(&mut self, most_steps: usize) -> Result<Settling, DdaError>;
}

macro_rules! delegate {
    () => {
        fn time(&self) -> f64 {
            dda_core::Driver::time(self)
        }
        fn dt(&self) -> f64 {
            dda_core::Driver::dt(self)
        }
        fn penalty(&self) -> f64 {
            dda_core::Driver::penalty(self)
        }
        fn automatic_penalty(&self) -> f64 {
            dda_core::Driver::automatic_penalty(self)
        }
        fn statistics(&self) -> &Statistics {
            dda_core::Driver::statistics(self)
        }
        fn notes(&self) -> &[String] {
            dda_core::Driver::notes(self)
        }
        fn block_count(&self) -> usize {
            self.system.blocks.len()
        }
        fn advance_to(&mut self, time: f64) -> Result<(), DdaError> {
            dda_core::Driver::advance_to(self, time)
        }
        fn advance_observed(
            &mut self,
            time: f64,
            observe: &mut dyn FnMut(&Self),
        ) -> Result<(), DdaError> {
            dda_core::Driver::advance_observed(self, time, observe)
        }
        fn advance_while(
            &mut self,
            time: f64,
            go_on: &mut dyn FnMut(&Self) -> bool,
        ) -> Result<bool, DdaError> {
            dda_core::Driver::advance_while(self, time, go_on)
        }
        fn step(&mut self, dt_limit: f64) -> Result<(), DdaError> {
            dda_core::Driver::step(self, dt_limit)
        }
        fn velocity(&self, block: usize) -> [f64; 3] {
            let v = self.velocities()[block];
            let mut out = [0.0; 3];
            let d = Self::DIMENSION as usize;
            out[..d].copy_from_slice(&v.as_slice()[..d]);
            out
        }
        fn measured_points(&self) -> Vec<PointLine> {
            let three = |v: &[f64]| {
                let mut out = [0.0; 3];
                out[..v.len()].copy_from_slice(v);
                out
            };
            self.system
                .measured
                .iter()
                .map(|m| PointLine {
                    block: m.block,
                    position: three(m.point.coords.as_slice()),
                    displacement: three(m.displacement().as_slice()),
                })
                .collect()
        }
        fn length_scale(&self) -> f64 {
            dda_core::Driver::length_scale(self)
        }
        fn save(&self) -> Result<Vec<u8>, DdaError> {
            dda_core::Driver::save(self)
        }
        fn restore(&mut self, bytes: &[u8]) -> Result<(), DdaError> {
            dda_core::Driver::restore(self, bytes)
        }
        fn settle(&mut self, most_steps: usize) -> Result<Settling, DdaError> {
            let settling = dda_core::Driver::settle(self, most_steps)?;
            for m in &mut self.system.measured {
                m.start = m.point;
            }
            Ok(settling)
        }
        fn is_finite(&self, block: usize) -> bool {
            let c = self.system.blocks[block].centroid();
            c.coords.iter().all(|x| x.is_finite())
                && self.velocities()[block].iter().all(|x| x.is_finite())
        }
    };
}

impl Simulation for Driver2d {
    const DIMENSION: u32 = 2;
    const HISTORY_HEADER: &'static str = crate::output::HISTORY_HEADER;

    delegate!();

    /// x, y, rotation, vx, vy, omega, sxx, syy, sxy.
    fn history_values(&self, block: usize) -> Vec<f64> {
        let b = &self.system.blocks[block];
        let v = self.velocities()[block];
        let (c, s) = (b.centroid(), b.stress);
        vec![c.x, c.y, b.rotation, v[0], v[1], v[2], s.x, s.y, s.z]
    }

    fn block_shape(&self, block: usize) -> BlockShape {
        let b = &self.system.blocks[block];
        let vertices: Vec<[f64; 3]> = b.vertices().iter().map(|p| [p.x, p.y, 0.0]).collect();
        BlockShape {
            faces: vec![(0..vertices.len()).collect()],
            vertices,
            material: b.material,
            rigid: b.kind == dda_core::BlockKind::Rigid,
        }
    }

    fn contact_label(&self, key: &ContactKey) -> String {
        dda_2d::contact::contact_label(key)
    }

    fn contact_lines(&self) -> Vec<ContactLine> {
        self.contacts()
            .iter()
            .map(|c| {
                let p = self.system.blocks[c.blocks[0]].vertices()[c.key.feature_a as usize];
                ContactLine {
                    label: dda_2d::contact::contact_label(&c.key),
                    blocks: c.blocks,
                    state: c.record.state,
                    normal_force: c.record.normal_force,
                    shear_force: c.record.shear_force,
                    slip: c.record.slip_path,
                    point: [p.x, p.y, 0.0],
                    normal: entrance_normal(&c.entrances, c.record.entrance, 2),
                }
            })
            .collect()
    }
}

impl Simulation for Driver3d {
    const DIMENSION: u32 = 3;
    const HISTORY_HEADER: &'static str = crate::output::HISTORY_HEADER_3D;

    delegate!();

    /// x, y, z, rx, ry, rz, vx, vy, vz, wx, wy, wz, sxx, syy, szz, syz,
    /// szx, sxy.
    fn history_values(&self, block: usize) -> Vec<f64> {
        let b = &self.system.blocks[block];
        let v = self.velocities()[block];
        let mut row = Vec::with_capacity(18);
        row.extend(b.centroid().coords.iter());
        row.extend(b.rotation.iter());
        row.extend(v.iter().take(6));
        row.extend(b.stress.iter());
        row
    }

    fn block_shape(&self, block: usize) -> BlockShape {
        let b = &self.system.blocks[block];
        BlockShape {
            vertices: b.vertices().iter().map(|p| [p.x, p.y, p.z]).collect(),
            faces: b.faces().to_vec(),
            material: b.material,
            rigid: b.kind == dda_core::BlockKind::Rigid,
        }
    }

    fn contact_label(&self, key: &ContactKey) -> String {
        dda_3d::contact_label(key)
    }

    fn contact_lines(&self) -> Vec<ContactLine> {
        let shapes: Vec<_> = self.system.blocks.iter().map(|b| b.shape()).collect();
        self.contacts()
            .iter()
            .map(|c| {
                let label = dda_3d::contact_label(&c.key);
                let point = crate::features::contact_point_3d(&label, &shapes)
                    .map(|p| [p.x, p.y, p.z])
                    .unwrap_or([f64::NAN; 3]);
                ContactLine {
                    label,
                    blocks: c.blocks,
                    state: c.record.state,
                    normal_force: c.record.normal_force,
                    shear_force: c.record.shear_force,
                    slip: c.record.slip_path,
                    point,
                    normal: entrance_normal(&c.entrances, c.record.entrance, 3),
                }
            })
            .collect()
    }
}

/// The contact normal of the entrance in use: the translation rows of
/// block a's normal row are the normal itself (the T-matrix starts with the
/// identity), pointing from block b towards block a.
fn entrance_normal<const N: usize, const T: usize>(
    entrances: &[impl dda_core::EntranceRows<N, T>],
    used: usize,
    dimension: usize,
) -> [f64; 3] {
    let Some(e) = entrances.get(used).or(entrances.first()) else {
        return [0.0; 3];
    };
    let mut n = [0.0; 3];
    n[..dimension].copy_from_slice(&e.normal()[0].as_slice()[..dimension]);
    let length = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    if length > 0.0 {
        n.iter_mut().for_each(|x| *x /= length);
    }
    n
}

impl<S: Simulation> RunView for S {
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn dt(&self) -> f64 {
        Simulation::dt(self)
    }
    fn penalty(&self) -> f64 {
        Simulation::penalty(self)
    }
    fn automatic_penalty(&self) -> f64 {
        Simulation::automatic_penalty(self)
    }
    fn statistics(&self) -> &Statistics {
        Simulation::statistics(self)
    }
    fn notes(&self) -> &[String] {
        Simulation::notes(self)
    }
    fn block_count(&self) -> usize {
        Simulation::block_count(self)
    }
    fn dimension(&self) -> u32 {
        S::DIMENSION
    }
    fn block_shape(&self, block: usize) -> BlockShape {
        Simulation::block_shape(self, block)
    }
    fn history_values(&self, block: usize) -> Vec<f64> {
        Simulation::history_values(self, block)
    }
    fn is_finite(&self, block: usize) -> bool {
        Simulation::is_finite(self, block)
    }
    fn contact_lines(&self) -> Vec<ContactLine> {
        Simulation::contact_lines(self)
    }
    fn contact_label(&self, key: &ContactKey) -> String {
        Simulation::contact_label(self, key)
    }
    fn velocity(&self, block: usize) -> [f64; 3] {
        Simulation::velocity(self, block)
    }
    fn measured_points(&self) -> Vec<PointLine> {
        Simulation::measured_points(self)
    }
}
