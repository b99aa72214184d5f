//! Doolin's DDAML: the XML geometry (`.geo`) and analysis (`.ana`) files of
//! his DDA code, read into a scene.
//!
//! The geometry is a list of joint lines; the blocks are what they enclose,
//! cut by the same arrangement as `JointedDomain` ([`dda_2d::cut::cut_lines`]).
//! Each joint line's `type` names its joint properties (1-based, in file
//! order, as Doolin's reader takes them); a pair of blocks takes the
//! properties of the line between them. Numbers are copied as written: the
//! scene's units are the file's.

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::Point2;
use roxmltree::{Document, Node};

use crate::scene::{
    BlockSpec, Coulomb, FixedPointSpec, Joint, JointLaw, Load, Material, MeasuredPointSpec, Mode,
    Plane, RotationUpdate, Scene,
};

/// A scene made from DDAML files, with what was left out or changed.
#[derive(Debug, Clone)]
pub struct Imported {
    pub scene: Scene,
    /// The scene as RON, with a header saying where it came from.
    pub text: String,
    pub notes: Vec<String>,
}

/// Why DDAML files could not be imported: the file, the line and the fix.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{file}: cannot read: {error}")]
    Read { file: String, error: std::io::Error },
    #[error("{file}:{line}: {message}")]
    At {
        file: String,
        line: u32,
        message: String,
    },
    #[error("{file}: {message}")]
    File { file: String, message: String },
}

/// What the geometry file gives.
#[derive(Debug, Default)]
struct Geometry {
    /// (x1, y1, x2, y2, joint type, line).
    joints: Vec<([f64; 4], usize, u32)>,
    /// Fixed points, with the line they were written on.
    fixed: Vec<([f64; 2], u32)>,
    loads: Vec<([f64; 2], u32)>,
    measured: Vec<([f64; 2], u32)>,
    holes: Vec<([f64; 2], u32)>,
}

/// What the analysis file gives; `None` where it says nothing.
#[derive(Debug, Default)]
struct Analysis {
    dynamic: Option<bool>,
    linear_rotation: Option<bool>,
    gravity: Option<f64>,
    plane_strain: Option<bool>,
    steps: Option<f64>,
    dt: Option<f64>,
    min_dt: Option<f64>,
    max_displacement: Option<f64>,
    open_close: Option<usize>,
    save_every: Option<f64>,
    materials: Vec<BlockMaterial>,
    joints: Vec<Coulomb>,
    /// (t, fx, fy) samples of each load point, in file order.
    loads: Vec<(Vec<[f64; 3]>, u32)>,
}

#[derive(Debug, Default)]
struct BlockMaterial {
    density: f64,
    young: f64,
    poisson: f64,
    stress: [f64; 3],
    velocity: [f64; 3],
}

/// One file being read.
struct Reader<'a> {
    file: &'a str,
    doc: &'a Document<'a>,
    notes: Vec<String>,
}

impl<'a> Reader<'a> {
    fn line(&self, node: Node) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    fn at(&self, node: Node, message: impl Into<String>) -> ImportError {
        ImportError::At {
            file: self.file.to_string(),
            line: self.line(node),
            message: message.into(),
        }
    }

    fn note(&mut self, node: Node, message: &str) {
        let line = self.line(node);
        self.notes.push(format!("{}:{line}: {message}", self.file));
    }

    /// The element children of `node`, comments and blank text skipped;
    /// other text is an error.
    fn elements(&self, node: Node<'a, 'a>) -> Result<Vec<Node<'a, 'a>>, ImportError> {
        let mut out = Vec::new();
        for child in node.children() {
            if child.is_element() {
                out.push(child);
            } else if child.is_text() && !child.text().unwrap_or("").trim().is_empty() {
                return Err(self.at(
                    child,
                    format!(
                        "text directly inside <{}>; numbers belong inside its elements",
                        node.tag_name().name()
                    ),
                ));
            }
        }
        Ok(out)
    }

    /// The numbers in an element's text: exactly `n`, or (with `n` = 0) any.
    fn numbers(&self, node: Node, n: usize) -> Result<Vec<f64>, ImportError> {
        let text: String = node
            .descendants()
            .filter(|d| d.is_text())
            .filter_map(|d| d.text())
            .collect();
        let values = parse_numbers(&text).map_err(|word| {
            self.at(
                node,
                format!("<{}> holds {word:?}, not a number", node.tag_name().name()),
            )
        })?;
        if n > 0 && values.len() != n {
            return Err(self.at(
                node,
                format!(
                    "<{}> needs {n} numbers, it has {}",
                    node.tag_name().name(),
                    values.len()
                ),
            ));
        }
        Ok(values)
    }

    /// A required attribute as a number.
    fn attribute(&self, node: Node, name: &str) -> Result<f64, ImportError> {
        let tag = node.tag_name().name();
        let value = node
            .attribute(name)
            .ok_or_else(|| self.at(node, format!("<{tag}> needs the attribute {name}=\"...\"")))?;
        value
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                self.at(
                    node,
                    format!("<{tag} {name}=\"{value}\">: {value:?} is not a number"),
                )
            })
    }

    /// A yes/no flag attribute.
    fn flag(&self, node: Node, name: &str) -> Result<bool, ImportError> {
        match node.attribute(name).map(str::trim) {
            Some("yes") => Ok(true),
            Some("no") => Ok(false),
            other => Err(self.at(
                node,
                format!(
                    "<{} {name}=...> must be \"yes\" or \"no\", got {other:?}",
                    node.tag_name().name()
                ),
            )),
        }
    }

    fn unknown(&self, node: Node, parent: &str, known: &[&str]) -> ImportError {
        self.at(
            node,
            format!(
                "unknown tag <{}> in <{parent}>; DDAML has {} there",
                node.tag_name().name(),
                known
                    .iter()
                    .map(|k| format!("<{k}>"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    }

    fn unsupported(&self, node: Node, what: &str) -> ImportError {
        self.at(
            node,
            format!(
                "<{}> ({what}) cannot be imported yet; remove it from the file to import the rest",
                node.tag_name().name()
            ),
        )
    }
}

fn parse_numbers(text: &str) -> Result<Vec<f64>, String> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .map(|w| {
            w.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| w.to_string())
        })
        .collect()
}

const GEOMETRY: &[&str] = &[
    "Edgenodedist",
    "Jointlist",
    "Fixedpointlist",
    "Measuredpointlist",
    "Loadpointlist",
    "Holepointlist",
    "Seismicpointlist",
    "Boltlist",
    "Matlinelist",
    "Boundlist",
];

const ANALYSIS: &[&str] = &[
    "Analysistype",
    "Rotation",
    "Gravity",
    "Gravaccel",
    "Autotimestep",
    "Autopenalty",
    "Planestrain",
    "Numtimesteps",
    "Maxtimestep",
    "Mintimestep",
    "Maxdisplacement",
    "OCLimit",
    "Opencloselimit",
    "Saveinterval",
    "AConstants",
    "Blockmaterial",
    "Jointproperties",
    "Loadpointlist",
    "Writevertices",
    "ContactDamping",
    "Boltproperties",
    "Timehistory",
];

impl<'a> Reader<'a> {
    /// Reads the `<Geometry>` and `<Analysis>` sections of a document.
    fn read(
        &mut self,
        geometry: &mut Option<Geometry>,
        analysis: &mut Option<Analysis>,
    ) -> Result<(), ImportError> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "DDA" {
            return Err(self.at(
                root,
                format!(
                    "the document is <{}>, not <Berkeley:DDA>; is this a DDAML file?",
                    root.tag_name().name()
                ),
            ));
        }
        for section in self.elements(root)? {
            match section.tag_name().name() {
                "Geometry" => *geometry = Some(self.geometry(section)?),
                "Analysis" => *analysis = Some(self.analysis(section)?),
                _ => return Err(self.unknown(section, "Berkeley:DDA", &["Geometry", "Analysis"])),
            }
        }
        Ok(())
    }

    fn points(
        &self,
        list: Node<'a, 'a>,
        out: &mut Vec<([f64; 2], u32)>,
    ) -> Result<(), ImportError> {
        let name = list.tag_name().name();
        for p in self.elements(list)? {
            if p.tag_name().name() != "Point" {
                return Err(self.unknown(p, name, &["Point"]));
            }
            let v = self.numbers(p, 2)?;
            out.push(([v[0], v[1]], self.line(p)));
        }
        Ok(())
    }

    fn geometry(&mut self, section: Node<'a, 'a>) -> Result<Geometry, ImportError> {
        let mut g = Geometry::default();
        for list in self.elements(section)? {
            match list.tag_name().name() {
                "Edgenodedist" => self.note(
                    list,
                    "<Edgenodedist> (Shi's edge-node distance) is not needed: contacts are found from the blocks' shapes",
                ),
                "Jointlist" => {
                    for joint in self.elements(list)? {
                        if joint.tag_name().name() != "Joint" {
                            return Err(self.unknown(joint, "Jointlist", &["Joint"]));
                        }
                        let kind = self.attribute(joint, "type")?;
                        if !(kind >= 1.0 && kind.fract() == 0.0) {
                            return Err(self.at(joint, format!("<Joint type=\"{kind}\">: the type is the number of its joint properties, 1 or more")));
                        }
                        let v = self.numbers(joint, 4)?;
                        g.joints.push(([v[0], v[1], v[2], v[3]], kind as usize, self.line(joint)));
                    }
                }
                "Fixedpointlist" => {
                    for p in self.elements(list)? {
                        match p.tag_name().name() {
                            "Point" => {
                                let v = self.numbers(p, 2)?;
                                g.fixed.push(([v[0], v[1]], self.line(p)));
                            }
                            // A fixed line holds its two ends.
                            "Line" => {
                                let v = self.numbers(p, 4)?;
                                g.fixed.push(([v[0], v[1]], self.line(p)));
                                g.fixed.push(([v[2], v[3]], self.line(p)));
                            }
                            _ => return Err(self.unknown(p, "Fixedpointlist", &["Point", "Line"])),
                        }
                    }
                }
                "Measuredpointlist" => self.points(list, &mut g.measured)?,
                "Loadpointlist" => self.points(list, &mut g.loads)?,
                "Holepointlist" => self.points(list, &mut g.holes)?,
                "Seismicpointlist" => return Err(self.unsupported(list, "seismic input points")),
                "Boltlist" => return Err(self.unsupported(list, "rock bolts")),
                "Matlinelist" => return Err(self.unsupported(list, "material lines; every block takes <Blockmaterial> 1")),
                "Boundlist" => return Err(self.unsupported(list, "boundary lines")),
                _ => return Err(self.unknown(list, "Geometry", GEOMETRY)),
            }
        }
        Ok(g)
    }

    fn analysis(&mut self, section: Node<'a, 'a>) -> Result<Analysis, ImportError> {
        let mut a = Analysis::default();
        if let Some(kind) = section.attribute("type") {
            a.dynamic = Some(kind.trim() == "dynamic");
        }
        for item in self.elements(section)? {
            match item.tag_name().name() {
                "Analysistype" => {
                    a.dynamic = Some(match item.attribute("type").map(str::trim) {
                        Some("dynamic") => true,
                        Some("static") => false,
                        other => return Err(self.at(item, format!("<Analysistype type=...> must be \"dynamic\" or \"static\", got {other:?}"))),
                    })
                }
                "Rotation" => {
                    a.linear_rotation = Some(match item.attribute("type").map(str::trim) {
                        Some("linear") => true,
                        Some("exact") | Some("secondorder") => false,
                        other => return Err(self.at(item, format!("<Rotation type=...> must be \"linear\", \"secondorder\" or \"exact\", got {other:?}"))),
                    })
                }
                "Gravity" => {
                    if self.flag(item, "flag")? {
                        self.note(item, "<Gravity flag=\"yes\"> (Doolin's gravity turn-on phase) is not imported: gravity acts from the start");
                    }
                }
                "Gravaccel" => a.gravity = Some(self.attribute(item, "value")?),
                "Autotimestep" => {
                    if self.flag(item, "flag")? {
                        self.note(item, "<Autotimestep flag=\"yes\">: the step starts at <Maxtimestep> and is cut to a third where contacts do not settle");
                    }
                }
                "Autopenalty" => self.note(item, "<Autopenalty> is not imported: the penalty is automatic, twice the Young's modulus over the median block size"),
                "Planestrain" => a.plane_strain = Some(self.flag(item, "flag")?),
                "Numtimesteps" => a.steps = Some(self.attribute(item, "timesteps")?),
                "Maxtimestep" => a.dt = Some(self.attribute(item, "maxtimestep")?),
                "Mintimestep" => a.min_dt = Some(self.attribute(item, "mintimestep")?),
                "Maxdisplacement" => a.max_displacement = Some(self.attribute(item, "maxdisplacement")?),
                "OCLimit" | "Opencloselimit" => {
                    a.open_close = Some(self.attribute(item, "maxopenclose")?.max(1.0) as usize)
                }
                "Saveinterval" => a.save_every = Some(self.attribute(item, "step")?),
                "AConstants" => self.note(item, "<AConstants> (Shi's contact constants) are not imported: the scene's contact settings are automatic"),
                "Writevertices" | "ContactDamping" => self.note(item, &format!("<{}> is not imported", item.tag_name().name())),
                "Blockmaterial" => a.materials.push(self.block_material(item)?),
                "Jointproperties" => {
                    let mut law = Coulomb::frictional(0.0);
                    for p in self.elements(item)? {
                        let v = self.numbers(p, 1)?[0];
                        match p.tag_name().name() {
                            "Friction" => law.friction_angle = v,
                            "Cohesion" => law.cohesion = v,
                            "Tensile" => law.tensile_strength = v,
                            _ => return Err(self.unknown(p, "Jointproperties", &["Friction", "Cohesion", "Tensile"])),
                        }
                    }
                    a.joints.push(law);
                }
                "Loadpointlist" => {
                    for lp in self.elements(item)? {
                        if lp.tag_name().name() != "Loadpoint" {
                            return Err(self.unknown(lp, "Loadpointlist", &["Loadpoint"]));
                        }
                        let text: String = lp.children().filter_map(|c| c.text()).collect();
                        let mut samples = Vec::new();
                        for record in text.split(';').filter(|r| !r.trim().is_empty()) {
                            let v = parse_numbers(record).map_err(|w| self.at(lp, format!("<Loadpoint> holds {w:?}, not a number")))?;
                            if v.len() != 3 {
                                return Err(self.at(lp, format!("each <Loadpoint> record is \"time fx fy;\", got {record:?}")));
                            }
                            samples.push([v[0], v[1], v[2]]);
                        }
                        if let Some(n) = lp.attribute("numpoints") {
                            if n.trim().parse::<usize>().ok() != Some(samples.len()) {
                                return Err(self.at(lp, format!("<Loadpoint numpoints=\"{n}\"> but it holds {} records", samples.len())));
                            }
                        }
                        a.loads.push((samples, self.line(lp)));
                    }
                }
                "Boltproperties" => return Err(self.unsupported(item, "rock bolt properties")),
                "Timehistory" => return Err(self.unsupported(item, "an earthquake record; give it as the scene's ground_motion")),
                _ => return Err(self.unknown(item, "Analysis", ANALYSIS)),
            }
        }
        Ok(a)
    }

    fn block_material(&mut self, item: Node<'a, 'a>) -> Result<BlockMaterial, ImportError> {
        let mut m = BlockMaterial {
            poisson: 0.25,
            ..Default::default()
        };
        let (mut density, mut young) = (None, None);
        for p in self.elements(item)? {
            match p.tag_name().name() {
                "Unitmass" => density = Some(self.numbers(p, 1)?[0]),
                "Unitweight" => {} // the mass times gravity
                "Youngsmod" => young = Some(self.numbers(p, 1)?[0]),
                "Poissonratio" => m.poisson = self.numbers(p, 1)?[0],
                "Damping" => {
                    if self.numbers(p, 1)?[0] != 0.0 {
                        self.note(p, "<Damping> is not imported; give analysis.damping in the scene for viscous damping");
                    }
                }
                "Istress" => {
                    let v = self.numbers(p, 3)?;
                    m.stress = [v[0], v[1], v[2]];
                }
                "Ivelocity" => {
                    let v = self.numbers(p, 3)?;
                    m.velocity = [v[0], v[1], v[2]];
                }
                "Istrain" => {
                    if self.numbers(p, 3)?.iter().any(|v| *v != 0.0) {
                        self.note(p, "<Istrain> is not imported: blocks start unstrained");
                    }
                }
                _ => {
                    return Err(self.unknown(
                        p,
                        "Blockmaterial",
                        &[
                            "Unitmass",
                            "Unitweight",
                            "Youngsmod",
                            "Poissonratio",
                            "Damping",
                            "Istress",
                            "Ivelocity",
                            "Istrain",
                        ],
                    ))
                }
            }
        }
        m.density = density.ok_or_else(|| self.at(item, "<Blockmaterial> needs <Unitmass>"))?;
        m.young = young.ok_or_else(|| self.at(item, "<Blockmaterial> needs <Youngsmod>"))?;
        Ok(m)
    }
}

fn read_file(path: &Path) -> Result<String, ImportError> {
    std::fs::read_to_string(path).map_err(|error| ImportError::Read {
        file: path.display().to_string(),
        error,
    })
}

/// Reads one DDAML file into the sections it holds; returns its notes.
fn read_document(
    path: &Path,
    geometry: &mut Option<Geometry>,
    analysis: &mut Option<Analysis>,
) -> Result<Vec<String>, ImportError> {
    let file = path.display().to_string();
    let text = read_file(path)?;
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let doc = Document::parse_with_options(&text, options).map_err(|e| ImportError::At {
        file: file.clone(),
        line: e.pos().row,
        message: format!("not well-formed XML: {e}"),
    })?;
    let mut reader = Reader {
        file: &file,
        doc: &doc,
        notes: Vec::new(),
    };
    reader.read(geometry, analysis)?;
    Ok(reader.notes)
}

/// Reads a DDAML geometry file and (optionally) its analysis file, cuts
/// the joint lines into blocks and makes the scene.
pub fn import_ddaml(geo: &Path, ana: Option<&Path>) -> Result<Imported, ImportError> {
    let (mut geometry, mut analysis) = (None, None);
    let mut notes = read_document(geo, &mut geometry, &mut analysis)?;
    if let Some(ana) = ana {
        notes.extend(read_document(ana, &mut geometry, &mut analysis)?);
    }
    let file = geo.display().to_string();
    let fail = |message: String| ImportError::File {
        file: file.clone(),
        message,
    };
    let at = |line: u32, message: String| ImportError::At {
        file: file.clone(),
        line,
        message,
    };
    let g = geometry
        .ok_or_else(|| fail("no <Geometry> section; give the geometry file (.geo) first".into()))?;
    let a = analysis.ok_or_else(|| {
        fail("no <Analysis> section: the materials and joint properties are in the analysis file; give it after the geometry file".into())
    })?;
    if a.materials.is_empty() {
        return Err(fail("the analysis has no <Blockmaterial>; add one".into()));
    }

    // Shi's DC step on the joint lines.
    let mut traces = Vec::new();
    for (ends, kind, line) in &g.joints {
        if *kind > a.joints.len() {
            return Err(at(*line, format!("<Joint type=\"{kind}\"> but the analysis has {} <Jointproperties>; add them or correct the type", a.joints.len())));
        }
        traces.push(dda_2d::cut::Trace {
            a: Point2::new(ends[0], ends[1]),
            b: Point2::new(ends[2], ends[3]),
            set: kind - 1,
        });
    }
    // The model's size: its bounding box's diagonal, wherever it lies.
    let corners = traces.iter().flat_map(|t| [t.a, t.b]);
    let (lo, hi) = corners.fold(
        (
            Point2::from([f64::INFINITY; 2]),
            Point2::from([f64::NEG_INFINITY; 2]),
        ),
        |(lo, hi), p| (lo.inf(&p), hi.sup(&p)),
    );
    let size = if traces.is_empty() {
        0.0
    } else {
        (hi - lo).norm()
    };
    let cut = dda_2d::cut::cut_lines(&traces, 1e-9 * size * size)
        .map_err(|e| fail(format!("the joint lines: {e}")))?;
    if cut.dropped > 0 {
        notes.push(format!(
            "{file}: {} sliver blocks (area below 1e-9 of the model's size squared) were left out",
            cut.dropped
        ));
    }
    let contains = |outline: &[Point2<f64>], p: &Point2<f64>| dda_2d::polygon::contains(outline, p);
    // Hole points take out the blocks they lie in.
    let mut keep: Vec<bool> = vec![true; cut.blocks.len()];
    for (p, line) in &g.holes {
        let p = Point2::new(p[0], p[1]);
        match cut.blocks.iter().position(|b| contains(b, &p)) {
            Some(k) => keep[k] = false,
            None => {
                return Err(at(
                    *line,
                    format!("the hole point ({}, {}) lies in no block", p.x, p.y),
                ))
            }
        }
    }
    let mut index = vec![None; cut.blocks.len()];
    let mut outlines = Vec::new();
    for (k, b) in cut.blocks.iter().enumerate() {
        if keep[k] {
            index[k] = Some(outlines.len());
            outlines.push(b.clone());
        }
    }
    if outlines.is_empty() {
        return Err(fail(
            "the joint lines enclose no block; each block needs a closed outline of joint lines"
                .into(),
        ));
    }
    let block_of = |p: &[f64; 2], line: u32, what: &str| {
        let q = Point2::new(p[0], p[1]);
        outlines
            .iter()
            .position(|b| contains(b, &q))
            .ok_or_else(|| {
                at(
                    line,
                    format!(
                        "the {what} ({}, {}) lies in no block; move it inside one",
                        p[0], p[1]
                    ),
                )
            })
    };

    let m = &a.materials[0];
    if a.materials.len() > 1 {
        notes.push(format!("{file}: only <Blockmaterial> 1 is used: without material lines every block is of material 1"));
    }
    let mut scene: Scene = ron::Options::default()
        .from_str("Scene()")
        .expect("an empty scene parses");
    scene.materials = vec![(
        "material 1".to_string(),
        Material {
            density: m.density,
            young: m.young,
            poisson: m.poisson,
            kind: Default::default(),
        },
    )];
    scene.blocks = outlines
        .iter()
        .map(|b| BlockSpec::Polygon {
            material: None,
            kind: None,
            vertices: b.iter().map(|p| [p.x, p.y]).collect(),
            fixed: false,
            velocity: m.velocity,
            stress: m.stress,
        })
        .collect();
    for (p, line) in &g.fixed {
        scene.fixed_points.push(FixedPointSpec {
            block: block_of(p, *line, "fixed point")?,
            point: (*p).into(),
            velocity: Default::default(),
            axis: None,
        });
    }
    if g.loads.len() != a.loads.len() {
        return Err(fail(format!(
            "the geometry has {} load points and the analysis {} <Loadpoint> histories; give one history per point, in the same order",
            g.loads.len(),
            a.loads.len()
        )));
    }
    for (p, line) in &g.measured {
        scene.measured_points.push(MeasuredPointSpec {
            block: block_of(p, *line, "measured point")?,
            point: (*p).into(),
        });
    }
    for ((p, line), (history, _)) in g.loads.iter().zip(&a.loads) {
        scene.loads.push(Load::PointLoad {
            block: block_of(p, *line, "load point")?,
            point: (*p).into(),
            force: None,
            history: Some(history.iter().map(|s| (*s).into()).collect()),
        });
    }

    // Joint properties: the first is the default, each other type's block
    // pairs are listed with its law.
    let law = |c: &Coulomb| JointLaw::Coulomb(c.clone());
    if let Some(first) = a.joints.first() {
        scene.default_joint = law(first);
    }
    let mut pairs: BTreeMap<usize, Vec<[usize; 2]>> = BTreeMap::new();
    for j in &cut.joints {
        if let (Some(x), Some(y)) = (index[j.blocks.0], index[j.blocks.1]) {
            if j.set > 0 {
                pairs.entry(j.set).or_default().push([x, y]);
            }
        }
    }
    scene.joints = pairs
        .into_iter()
        .map(|(set, blocks)| Joint {
            between: None,
            blocks: Some(blocks),
            law: law(&a.joints[set]),
        })
        .collect();

    let s = &mut scene.analysis;
    let dt = a.dt.ok_or_else(|| {
        fail("the analysis has no <Maxtimestep>; add <Maxtimestep maxtimestep=\"...\"/>".into())
    })?;
    let steps = a.steps.ok_or_else(|| {
        fail("the analysis has no <Numtimesteps>; add <Numtimesteps timesteps=\"...\"/>".into())
    })?;
    s.dt = Some(dt);
    s.duration = steps * dt;
    s.mode = if a.dynamic.unwrap_or(true) {
        Mode::Dynamic
    } else {
        Mode::Static
    };
    s.rotation_update = if a.linear_rotation.unwrap_or(false) {
        RotationUpdate::Linear
    } else {
        RotationUpdate::Exact
    };
    // Doolin's default, like Shi's, is plane stress.
    s.plane = if a.plane_strain.unwrap_or(false) {
        Plane::Strain
    } else {
        Plane::Stress
    };
    s.gravity = Some([0.0, -a.gravity.unwrap_or(9.81)].into());
    if let Some(g2) = a.max_displacement {
        s.max_displacement_ratio = g2;
    }
    if let Some(n) = a.open_close {
        s.open_close_limit = n;
    }
    if let Some(min) = a.min_dt {
        s.min_dt_ratio = (min / dt).clamp(1e-9, 1.0);
    }
    scene.output.interval = Some(a.save_every.unwrap_or(1.0).max(1.0) * dt);

    let mut header = format!("// Imported from {}", geo.display());
    if let Some(ana) = ana {
        header += &format!(" and {}", ana.display());
    }
    header += " (DDAML) by `dda import`; the units are the files'.\n";
    let text = format!("{header}{}\n", scene.to_ron());
    let scene = Scene::from_str(&text, &file)
        .map_err(|e| fail(format!("the imported scene is not valid: {e}")))?;
    Ok(Imported { scene, text, notes })
}
