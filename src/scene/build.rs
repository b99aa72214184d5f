//! Turns a validated scene into a driver ready to run.

use std::collections::HashMap;

use dda_2d::{Block, Driver2d};
use dda_3d::Driver3d;
use dda_contact::LawRegistry;
use dda_core::{BlockSet, BlockSystem, Driver, Element, Settings};
use nalgebra::SVector;

use super::dimension::SceneElement;
use super::locate::{place_of, Place};
use super::{JointLaw, Scene, SceneError, SetLaws};

/// A scene ready to run: a 2D one by default ([`Driver2d`]), a 3D one as
/// [`Model3`].
pub struct Model<D = Driver2d> {
    pub driver: D,
    /// Simulated time to reach, in seconds.
    pub duration: f64,
    /// Time between outputs; `None` writes every step.
    pub output_interval: Option<f64>,
    /// Whether to write `contacts.csv`.
    pub write_contacts: bool,
    /// Whether to write `steps.csv` (the scene's `output.steps`, or `dda
    /// run --steps`).
    pub write_steps: bool,
    /// Why the scene's automatic values were chosen (the driver keeps its
    /// own: see [`Model::all_notes`]).
    pub notes: Vec<String>,
    /// The settings the driver was made with.
    pub settings: Settings,
    /// What the run does when a guard trips.
    pub on_failure: crate::guard::OnFailure,
}

impl<D: crate::Simulation> Model<D> {
    /// The driver's notes on automatic choices, then the scene's.
    pub fn all_notes(&self) -> Vec<String> {
        let mut notes = self.driver.notes().to_vec();
        notes.extend(self.notes.iter().cloned());
        notes
    }
}

/// A 3D scene ready to run.
pub type Model3 = Model<Driver3d>;

/// A scene of either dimension ready to run.
pub enum AnyModel {
    Plane(Model),
    Space(Model3),
}

impl AnyModel {
    /// 2 or 3.
    pub fn dimension(&self) -> u32 {
        match self {
            AnyModel::Plane(_) => 2,
            AnyModel::Space(_) => 3,
        }
    }
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
    /// Validates a 2D scene and builds the blocks, laws and driver, with the
    /// built-in contact laws for `Custom` joints. A 3D scene is an error
    /// here: see [`Scene::build_3d`] and [`Scene::build_any`].
    pub fn build(&self) -> Result<Model, SceneError> {
        self.build_with(&LawRegistry::with_builtin())
    }

    /// Validates and builds a scene of either dimension.
    pub fn build_any(&self) -> Result<AnyModel, SceneError> {
        self.build_any_with(&LawRegistry::with_builtin())
    }

    /// [`Scene::build_any`] with `Custom` joint laws built through `registry`.
    pub fn build_any_with(&self, registry: &LawRegistry) -> Result<AnyModel, SceneError> {
        match self.dimension {
            3 => self.build_3d_with(registry).map(AnyModel::Space),
            _ => self.build_with(registry).map(AnyModel::Plane),
        }
    }

    /// Validates a 3D scene and builds its polyhedra, laws and driver.
    pub fn build_3d(&self) -> Result<Model3, SceneError> {
        self.build_3d_with(&LawRegistry::with_builtin())
    }

    /// [`Scene::build`] with `Custom` joint laws built through `registry`, so
    /// scenes can name laws written elsewhere.
    pub fn build_with(&self, registry: &LawRegistry) -> Result<Model, SceneError> {
        self.build_as::<Block, 2, 6, 1, 3>(registry)
    }

    /// Validates a 3D scene and builds it with `Custom` joint laws built
    /// through `registry`.
    pub fn build_3d_with(&self, registry: &LawRegistry) -> Result<Model3, SceneError> {
        self.build_as::<dda_3d::Block, 3, 12, 2, 6>(registry)
    }

    /// Validates the scene as one of `D` dimensions and builds its blocks
    /// of type `B`, laws and driver; a scene of the other dimension is
    /// refused once it is valid.
    #[allow(clippy::type_complexity)]
    fn build_as<B, const D: usize, const N: usize, const T: usize, const S: usize>(
        &self,
        registry: &LawRegistry,
    ) -> Result<Model<Driver<BlockSet<B, D, N, T, S>, N, T>>, SceneError>
    where
        B: SceneElement<D, S> + Element<D, N, T, S>,
    {
        if self.dimension != D as u32 {
            self.validate()?;
            let (builder, other) = if D == 2 {
                ("Scene::build", "Scene::build_3d")
            } else {
                ("Scene::build_3d", "Scene::build")
            };
            return Err(self.error(
                &Place::root().field("dimension"),
                format!(
                    "this is a {}D scene, and {builder} builds {D}D ones; use {other} or Scene::build_any",
                    self.dimension
                ),
            ));
        }
        let mut checked = self.checked::<B, D, S>()?;
        B::share(&mut checked.shapes);
        let plane = self.analysis.plane;
        let materials = self.materials.iter().map(|(_, m)| B::elastic(m, plane));
        let mut blocks = Vec::with_capacity(checked.blocks.len());
        for (spec, shape) in checked.blocks.iter().zip(checked.shapes) {
            let entry = &self.blocks[spec.entry];
            let material = self.material_index(entry.material()).expect("checked");
            let density = self.materials[material].1.density;
            let block = B::block(shape, material, density, self.kind_of(entry), spec.stress);
            let at = place_of(spec.entry, spec.part.as_deref());
            blocks.push(block.map_err(|e| self.error(&at, e))?);
        }
        let mut system = BlockSet::new(blocks, materials.collect());
        let a = &self.analysis;
        system.gravity = SVector::<f64, D>::from_column_slice(&self.gravity());
        system.rotation_update = a.rotation_update;
        system.length_scale = a.length_scale;
        // Fixed points are ten times stiffer than a typical contact, whose
        // springs stand for half a block's side in 2D and a quarter of a
        // face in 3D (A3.6), so a held base does not sag into its supports.
        let contact = a.penalty.unwrap_or_else(|| system.automatic_penalty())
            * (system.block_size() / 2.0).powi(D as i32 - 1);
        system.fixed_penalty = a.fixed_penalty.unwrap_or(10.0 * contact);
        system.joint_laws = checked.laws.materials;
        system.pair_laws = checked.laws.pairs;
        system.loads = checked.loads;
        system.fixed = checked.fixed;
        system.measured = checked.measured;
        for (k, block) in checked.blocks.iter().enumerate() {
            if block.fixed {
                system.fix_block(k);
            }
        }
        // The ground moves the fixed points of its blocks, those of fixed
        // blocks included.
        let mut notes = Vec::new();
        if let Some((driven, motion, note)) = checked.ground {
            let driven = system
                .fixed
                .iter_mut()
                .filter(|f| driven.contains(&f.block));
            driven.for_each(|fp| fp.ground = Some(motion.clone()));
            notes.extend(note);
        }
        let settings = self.analysis.settings();
        // The contact laws, `Custom` ones built by the registry.
        let laws = checked.laws.laws.iter().map(|law| {
            law.build(registry)
                .map_err(|message| self.error(&self.law_place(law), message))
        });
        let mut driver = Driver::new(system, laws.collect::<Result<_, _>>()?, settings.clone())
            .map_err(|e| self.error(&Place::root().field("analysis"), e.to_string()))?;
        // The velocity (translation, then rotation) is a block's leading
        // DOFs; its strain rates start at zero.
        for (k, block) in checked.blocks.iter().enumerate() {
            let v = SVector::from_fn(|i, _| block.velocity.get(i).copied().unwrap_or(0.0));
            driver.set_velocity(k, v);
        }
        // An automatic step shortens itself to land on the output times, so
        // only an interval below its floor means every step.
        let (output_interval, note) = self.output_interval(driver.shortest_dt());
        notes.extend(note);
        Ok(Model {
            driver,
            duration: self.analysis.duration,
            output_interval,
            write_contacts: self.output.contacts,
            write_steps: self.output.steps,
            on_failure: self.analysis.on_failure,
            settings,
            notes,
        })
    }

    /// Where `law` is first written: the default joint or a joint set's law.
    fn law_place(&self, law: &JointLaw) -> Place {
        let root = Place::root();
        let joints = self.joints.iter().enumerate();
        let joints = joints.map(|(k, j)| (root.field("joints").index(k), Some(&j.law)));
        let sets = self.blocks.iter().enumerate().flat_map(|(k, spec)| {
            let at = root.field("blocks").index(k).field("sets");
            let sets = spec.joint_sets().iter().enumerate();
            sets.map(move |(s, set)| (at.index(s), set.law.as_ref()))
        });
        match joints.chain(sets).find(|(_, l)| *l == Some(law)) {
            Some((at, _)) if *law != self.default_joint => at.field("law"),
            _ => root.field("default_joint"),
        }
    }

    /// The distinct joint laws (the default first) and which joints use
    /// which.
    pub fn law_table(&self) -> LawTable {
        let set_laws = match self.dimension {
            3 => self.expanded::<dda_3d::Block, 3, 6>().1,
            _ => self.expanded::<Block, 2, 3>().1,
        };
        self.laws_of(set_laws)
    }

    /// The law table with the laws a jointed domain's sets give its block
    /// pairs.
    pub(super) fn laws_of(&self, set_laws: SetLaws<'_>) -> LawTable {
        // Each distinct law once: its index, added when new.
        let index_of = |laws: &mut Vec<JointLaw>, law: &JointLaw| {
            laws.iter().position(|l| l == law).unwrap_or_else(|| {
                laws.push(law.clone());
                laws.len() - 1
            })
        };
        let n = self.materials.len();
        let mut laws = vec![self.default_joint.clone()];
        let mut materials = vec![vec![0; n]; n];
        // Joints made by a jointed domain's sets first; the scene's own
        // block pairs override them.
        let mut pairs: HashMap<_, _> = set_laws
            .into_iter()
            .map(|(pair, law)| (pair, index_of(&mut laws, law)))
            .collect();
        for joint in &self.joints {
            let index = index_of(&mut laws, &joint.law);
            if let Some((a, b)) = &joint.between {
                let find = |name: &String| self.material_index(Some(name));
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
