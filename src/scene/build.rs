//! Turns a validated scene into a driver ready to run.

use std::collections::HashMap;

use dda_2d::{Block, Driver2d, FixedPoint, Force, PlaneElastic, PointLoad, Polygons};
use dda_contact::{Coulomb, LawRegistry, Params, RateFriction, SlipWeakening, ThresholdBond};
use dda_core::{ConstitutiveLaw, DynContactLaw, Settings};
use nalgebra::{Point2, Vector2, Vector3, Vector6};

use super::validate::{polygon_message, to_points, unit_axis, Place};
use super::{JointLaw, Load, Scene, SceneError};

/// A scene ready to run.
pub struct Model {
    pub driver: Driver2d,
    /// Simulated time to reach, in seconds.
    pub duration: f64,
    /// Time between outputs; `None` writes every step.
    pub output_interval: Option<f64>,
    /// Whether to write `contacts.csv`.
    pub write_contacts: bool,
    /// The settings the driver was made with.
    pub settings: Settings,
}

/// Which law each joint uses: the distinct laws of a scene (the default
/// first) and indices into them.
#[derive(Debug, Clone, PartialEq)]
pub struct LawTable {
    pub laws: Vec<JointLaw>,
    /// For each pair of materials, the index of its law (symmetric).
    pub materials: Vec<Vec<usize>>,
    /// For block pairs in joint sets, keyed (lower, higher), the index of
    /// their law.
    pub pairs: HashMap<(usize, usize), usize>,
}

impl Scene {
    /// Validates the scene and builds the blocks, laws and driver, with the
    /// built-in contact laws for `Custom` joints.
    pub fn build(&self) -> Result<Model, SceneError> {
        self.build_with(&LawRegistry::with_builtin())
    }

    /// [`Scene::build`] with `Custom` joint laws built through `registry`, so
    /// scenes can name laws written elsewhere.
    pub fn build_with(&self, registry: &LawRegistry) -> Result<Model, SceneError> {
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
        let specs = self.expanded_blocks();
        let mut blocks = Vec::with_capacity(specs.len());
        for spec in &specs {
            let at = self.block_place(spec);
            let material = self
                .material_index(&self.blocks[spec.entry])
                .ok_or_else(|| {
                    self.error(
                        &blocks_at.index(spec.entry),
                        "the block's material is not defined",
                    )
                })?;
            let density = self.materials[material].1.density;
            let mut block = Block::new(&to_points(&spec.vertices), material, density)
                .map_err(|e| self.error(&at, polygon_message(&e)))?;
            block.stress = Vector3::from(spec.stress);
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
        let table = self.law_table();
        system.joint_laws = table.materials;
        system.pair_laws = table.pairs;
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
            system.fixed.push(FixedPoint {
                velocity: Vector2::from(fp.velocity),
                axis: fp.axis.and_then(unit_axis),
                ..FixedPoint::at(fp.block, Point2::from(fp.point))
            });
        }
        for (k, spec) in specs.iter().enumerate() {
            if spec.fixed {
                system.fix_block(k);
            }
        }
        if let Some((driven, motion)) = self.ground_motion(&specs)? {
            for fp in system
                .fixed
                .iter_mut()
                .filter(|f| driven.contains(&f.block))
            {
                fp.ground = Some(motion.clone());
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
            mass_damping: a.damping.map_or(0.0, |d| d.mass_coefficient()),
            ..Settings::default()
        };
        let laws = table
            .laws
            .iter()
            .map(|law| {
                contact_law(law, registry)
                    .map_err(|message| self.error(&self.law_place(law), message))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut driver = Driver2d::new(system, laws, settings.clone())
            .map_err(|e| self.error(&Place::root().field("analysis"), e.to_string()))?;
        for (k, spec) in specs.iter().enumerate() {
            let [vx, vy, w] = spec.velocity;
            driver.set_velocity(k, Vector6::new(vx, vy, w, 0.0, 0.0, 0.0));
        }
        let interval = self.output.interval;
        Ok(Model {
            driver,
            duration: a.duration,
            output_interval: (interval > 0.0).then_some(interval),
            write_contacts: self.output.contacts,
            settings,
        })
    }

    /// Where `law` is first written: the default joint or a joint set's law.
    fn law_place(&self, law: &JointLaw) -> Place {
        let root = Place::root();
        if *law == self.default_joint {
            return root.field("default_joint");
        }
        match self.joints.iter().position(|j| j.law == *law) {
            Some(k) => root.field("joints").index(k).field("law"),
            None => root.field("default_joint"),
        }
    }

    /// The distinct joint laws (the default first) and which joints use
    /// which.
    pub fn law_table(&self) -> LawTable {
        let n = self.materials.len();
        let mut laws = vec![self.default_joint.clone()];
        let mut materials = vec![vec![0; n]; n];
        let mut pairs = HashMap::new();
        for joint in &self.joints {
            let index = match laws.iter().position(|l| *l == joint.law) {
                Some(i) => i,
                None => {
                    laws.push(joint.law.clone());
                    laws.len() - 1
                }
            };
            if let Some((a, b)) = &joint.between {
                let find = |name: &str| self.materials.iter().position(|(m, _)| m == name);
                if let (Some(a), Some(b)) = (find(a), find(b)) {
                    materials[a][b] = index;
                    materials[b][a] = index;
                }
            }
            for &[a, b] in joint.blocks.iter().flatten() {
                pairs.insert((a.min(b), a.max(b)), index);
            }
        }
        LawTable {
            laws,
            materials,
            pairs,
        }
    }
}

/// The law a scene names; typed laws are built directly, `Custom` ones by
/// the registry.
fn contact_law(law: &JointLaw, registry: &LawRegistry) -> Result<Box<dyn DynContactLaw>, String> {
    Ok(match law.clone() {
        JointLaw::Coulomb {
            friction_angle,
            cohesion,
            tensile_strength,
            normal_stiffness,
            shear_stiffness,
        } => Box::new(Coulomb {
            friction_angle,
            cohesion,
            tensile_strength,
            normal_stiffness,
            shear_stiffness,
        }),
        JointLaw::ThresholdBond {
            friction_angle,
            max_opening,
            max_shear,
            normal_stiffness,
            shear_stiffness,
        } => Box::new(ThresholdBond {
            friction_angle,
            max_opening,
            max_shear,
            normal_stiffness,
            shear_stiffness,
        }),
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
        JointLaw::RateFriction {
            static_friction_angle,
            dynamic_friction_angle,
            characteristic_rate,
            normal_stiffness,
            shear_stiffness,
        } => Box::new(RateFriction {
            static_friction_angle,
            dynamic_friction_angle,
            characteristic_rate,
            normal_stiffness,
            shear_stiffness,
        }),
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
