//! Turns a validated scene into a driver ready to run.

use dda_2d::{Block, Driver2d, FixedPoint, Force, PlaneElastic, PointLoad, Polygons};
use dda_contact::Coulomb;
use dda_core::{ConstitutiveLaw, DynContactLaw, Settings};
use nalgebra::{Point2, Vector2, Vector3, Vector6};

use super::validate::{polygon_message, to_points, Place};
use super::{JointLaw, Load, Scene, SceneError};

/// A scene ready to run.
pub struct Model {
    pub driver: Driver2d,
    /// Simulated time to reach, in seconds.
    pub duration: f64,
    /// Time between outputs; `None` writes every step.
    pub output_interval: Option<f64>,
}

impl Scene {
    /// Validates the scene and builds the blocks, laws and driver.
    pub fn build(&self) -> Result<Model, SceneError> {
        self.validate()?;
        let blocks_at = Place::root().field("blocks");
        let materials: Vec<Box<dyn ConstitutiveLaw<3>>> = self
            .materials
            .iter()
            .map(|(_, m)| {
                Box::new(PlaneElastic {
                    young: m.young,
                    poisson: m.poisson,
                    plane: self.analysis.plane,
                }) as Box<dyn ConstitutiveLaw<3>>
            })
            .collect();
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for (k, spec) in self.blocks.iter().enumerate() {
            let at = blocks_at.index(k);
            let material = self
                .material_index(spec)
                .ok_or_else(|| self.error(&at, "the block's material is not defined"))?;
            let density = self.materials[material].1.density;
            let mut block = Block::new(&to_points(&spec.vertices()), material, density)
                .map_err(|e| self.error(&at, polygon_message(&e)))?;
            block.stress = Vector3::from(spec.stress());
            blocks.push(block);
        }

        let mut system = Polygons::new(blocks, materials);
        let a = &self.analysis;
        system.gravity = Vector2::from(a.gravity);
        system.rotation_update = a.rotation_update;
        system.length_scale = a.length_scale;
        // Fixed points are ten times stiffer than the contacts (A3.6), so a
        // held base does not sag into its supports.
        system.fixed_penalty = a
            .fixed_penalty
            .unwrap_or_else(|| 10.0 * a.penalty.unwrap_or(system.fixed_penalty));
        let (laws, table) = self.law_table();
        system.joint_laws = table;
        for load in &self.loads {
            match load {
                Load::PointLoad {
                    block,
                    point,
                    force,
                    history,
                } => {
                    let force = match (force, history) {
                        (Some(f), _) => Force::Constant(Vector2::from(*f)),
                        (None, Some(h)) => Force::History(
                            h.iter().map(|s| (s[0], Vector2::new(s[1], s[2]))).collect(),
                        ),
                        (None, None) => Force::Constant(Vector2::zeros()),
                    };
                    system.loads.push(PointLoad {
                        block: *block,
                        point: Point2::from(*point),
                        force,
                    });
                }
            }
        }
        for fp in &self.fixed_points {
            let p = Point2::from(fp.point);
            system.fixed.push(FixedPoint::at(fp.block, p));
        }
        for (k, spec) in self.blocks.iter().enumerate() {
            if spec.fixed() {
                system.fix_block(k);
            }
        }

        let settings = Settings {
            velocity_ratio: a.velocity_ratio.unwrap_or(a.mode.velocity_ratio()),
            dt: a.dt,
            min_dt_ratio: a.min_dt_ratio,
            open_close_limit: a.open_close_limit,
            max_displacement_ratio: a.max_displacement_ratio,
            max_penetration_ratio: a.max_penetration_ratio,
            penalty: a.penalty,
            raise_penalty: a.raise_penalty,
            length_scale: a.length_scale,
            ..Settings::default()
        };
        let laws: Vec<Box<dyn DynContactLaw>> = laws.iter().map(contact_law).collect();
        let mut driver = Driver2d::new(system, laws, settings)
            .map_err(|e| self.error(&Place::root().field("analysis"), e.to_string()))?;
        for (k, spec) in self.blocks.iter().enumerate() {
            let [vx, vy, w] = spec.velocity();
            driver.set_velocity(k, Vector6::new(vx, vy, w, 0.0, 0.0, 0.0));
        }
        let interval = self.output.interval;
        Ok(Model {
            driver,
            duration: a.duration,
            output_interval: (interval > 0.0).then_some(interval),
        })
    }

    /// The distinct joint laws (the default first) and, for each pair of
    /// materials, the index of its law.
    pub fn law_table(&self) -> (Vec<JointLaw>, Vec<Vec<usize>>) {
        let n = self.materials.len();
        let mut laws = vec![self.default_joint.clone()];
        let mut table = vec![vec![0; n]; n];
        for joint in &self.joints {
            let index = match laws.iter().position(|l| *l == joint.law) {
                Some(i) => i,
                None => {
                    laws.push(joint.law.clone());
                    laws.len() - 1
                }
            };
            let find = |name: &str| self.materials.iter().position(|(m, _)| m == name);
            if let (Some(a), Some(b)) = (find(&joint.between.0), find(&joint.between.1)) {
                table[a][b] = index;
                table[b][a] = index;
            }
        }
        (laws, table)
    }
}

fn contact_law(law: &JointLaw) -> Box<dyn DynContactLaw> {
    match law {
        JointLaw::Coulomb {
            friction_angle,
            cohesion,
            tensile_strength,
            normal_stiffness,
            shear_stiffness,
        } => Box::new(Coulomb {
            friction_angle: *friction_angle,
            cohesion: *cohesion,
            tensile_strength: *tensile_strength,
            normal_stiffness: *normal_stiffness,
            shear_stiffness: *shear_stiffness,
        }),
    }
}
