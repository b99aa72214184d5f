//! VTK frames for ParaView, as an [`Observer`]: at each output time the
//! blocks (`vtk/blocks_NNNNNN.vtu`: polygons in the z = 0 plane in 2D,
//! `VTK_POLYHEDRON` cells with their faces in 3D) and the contacts
//! (`vtk/contacts_NNNNNN.vtu`: one vertex cell per contact), tied by
//! `blocks.pvd` and `contacts.pvd`, which ParaView opens as animations.
//!
//! The files are VTK's XML unstructured grids written here in ASCII with
//! every number as it reads back: vtkio (0.6) has no way to give a
//! polyhedron's faces in the XML format and writes no `.pvd` collections.
//! Each `.pvd` is written whole after each frame, to a temporary file that
//! is then renamed over it, so a run that is killed leaves a valid
//! collection of the frames it finished.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::observe::{Cursor, Observer, RunView};
use crate::output::{num, round_time};

/// The folder of the frames inside the run's folder.
pub const FRAMES_DIR: &str = "vtk";

/// `VTK_VERTEX`, `VTK_POLYGON`, `VTK_POLYHEDRON`.
const VERTEX: u8 = 1;
const POLYGON: u8 = 7;
const POLYHEDRON: u8 = 42;

/// Writes the frames and the two collections as the run goes.
pub struct VtkWriter {
    dir: PathBuf,
    /// (time, frame number) of the frames written.
    frames: Vec<(f64, usize)>,
    /// The blocks' centroids at the first frame, for their displacement.
    start: Vec<[f64; 3]>,
}

impl VtkWriter {
    /// Frames into `dir/vtk/`, collections `dir/blocks.pvd` and
    /// `dir/contacts.pvd`.
    pub fn create(dir: &Path) -> anyhow::Result<Self> {
        let frames = dir.join(FRAMES_DIR);
        std::fs::create_dir_all(&frames)
            .with_context(|| format!("cannot create {}", frames.display()))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            frames: Vec::new(),
            start: Vec::new(),
        })
    }

    /// Frames into `dir` after those a checkpoint found ([`Cursor::Frames`]);
    /// the collections are written again at the next frame.
    pub fn resume(dir: &Path, cursor: &Cursor) -> anyhow::Result<Self> {
        let Cursor::Frames { frames, start } = cursor else {
            anyhow::bail!("the checkpoint's VTK frames are not recorded as frames");
        };
        let mut writer = Self::create(dir)?;
        writer.frames = frames.clone();
        writer.start = start.clone();
        Ok(writer)
    }

    /// The file names, relative to the run's folder, that a run with VTK
    /// frames lists among its outputs.
    pub fn outputs() -> [&'static str; 2] {
        ["blocks.pvd", "contacts.pvd"]
    }

    /// One frame of blocks and contacts at the run's current time.
    pub fn write(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        let frame = self.frames.len();
        let values: Vec<Vec<f64>> = (0..run.block_count())
            .map(|i| run.history_values(i))
            .collect();
        let layout = Layout::of(run.dimension());
        if self.start.is_empty() {
            self.start = values.iter().map(|v| layout.position(v)).collect();
        }
        let blocks = blocks_vtu(run, &values, &self.start, layout);
        save(&self.dir.join(frame_name("blocks", frame)), &blocks)?;
        save(
            &self.dir.join(frame_name("contacts", frame)),
            &contacts_vtu(run),
        )?;
        self.frames.push((round_time(run.time()), frame));
        for what in ["blocks", "contacts"] {
            let pvd = collection(what, &self.frames);
            crate::output::write_atomically(&self.dir.join(format!("{what}.pvd")), pvd.as_bytes())?;
        }
        Ok(())
    }
}

impl Observer for VtkWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
    }

    fn cursor(&self) -> Option<Cursor> {
        Some(Cursor::Frames {
            frames: self.frames.clone(),
            start: self.start.clone(),
        })
    }
}

/// `vtk/blocks_000012.vtu`, relative to the run's folder.
pub fn frame_name(what: &str, frame: usize) -> String {
    format!("{FRAMES_DIR}/{what}_{frame:06}.vtu")
}

/// Where a history row keeps what a frame shows.
#[derive(Clone, Copy)]
struct Layout {
    dimension: u32,
}

impl Layout {
    fn of(dimension: u32) -> Self {
        Self { dimension }
    }

    fn position(&self, v: &[f64]) -> [f64; 3] {
        match self.dimension {
            2 => [v[0], v[1], 0.0],
            _ => [v[0], v[1], v[2]],
        }
    }

    /// Rotation as a rotation vector (2D: about z).
    fn rotation(&self, v: &[f64]) -> [f64; 3] {
        match self.dimension {
            2 => [0.0, 0.0, v[2]],
            _ => [v[3], v[4], v[5]],
        }
    }

    fn velocity(&self, v: &[f64]) -> [f64; 3] {
        match self.dimension {
            2 => [v[3], v[4], 0.0],
            _ => [v[6], v[7], v[8]],
        }
    }

    fn angular_velocity(&self, v: &[f64]) -> [f64; 3] {
        match self.dimension {
            2 => [0.0, 0.0, v[5]],
            _ => [v[9], v[10], v[11]],
        }
    }

    /// Stress in VTK's symmetric-tensor order: xx, yy, zz, xy, yz, xz
    /// (2D: plane components, the others zero).
    fn stress(&self, v: &[f64]) -> [f64; 6] {
        match self.dimension {
            2 => [v[6], v[7], 0.0, v[8], 0.0, 0.0],
            // The history's order is xx, yy, zz, yz, zx, xy.
            _ => [v[12], v[13], v[14], v[17], v[15], v[16]],
        }
    }
}

/// The blocks' unstructured grid: each block its own points and one cell.
fn blocks_vtu(run: &dyn RunView, values: &[Vec<f64>], start: &[[f64; 3]], l: Layout) -> String {
    let shapes: Vec<_> = (0..run.block_count()).map(|i| run.block_shape(i)).collect();
    let points: usize = shapes.iter().map(|s| s.vertices.len()).sum();
    let mut x = String::new();
    header(&mut x, points, shapes.len(), run.time());

    x.push_str("<CellData Scalars=\"block\" Vectors=\"displacement\" Tensors=\"stress\">\n");
    let ints = |f: &dyn Fn(usize) -> usize| (0..shapes.len()).map(f).collect::<Vec<_>>();
    int_array(&mut x, "Int32", "block", &ints(&|i| i));
    int_array(&mut x, "Int32", "material", &ints(&|i| shapes[i].material));
    // 0 deformable, 1 rigid.
    int_array(
        &mut x,
        "Int32",
        "rigid",
        &ints(&|i| shapes[i].rigid as usize),
    );
    let displacement: Vec<[f64; 3]> = values
        .iter()
        .zip(start)
        .map(|(v, s)| {
            let p = l.position(v);
            [p[0] - s[0], p[1] - s[1], p[2] - s[2]]
        })
        .collect();
    float_array(&mut x, "displacement", 3, displacement.iter().flatten());
    let each = |f: fn(&Layout, &[f64]) -> [f64; 3]| values.iter().map(move |v| f(&l, v));
    float_array(
        &mut x,
        "velocity",
        3,
        each(Layout::velocity).flatten().collect::<Vec<_>>().iter(),
    );
    float_array(
        &mut x,
        "rotation",
        3,
        each(Layout::rotation).flatten().collect::<Vec<_>>().iter(),
    );
    let spin: Vec<f64> = each(Layout::angular_velocity).flatten().collect();
    float_array(&mut x, "angular_velocity", 3, spin.iter());
    let stress: Vec<f64> = values.iter().flat_map(|v| l.stress(v)).collect();
    float_array(&mut x, "stress", 6, stress.iter());
    x.push_str("</CellData>\n<Points>\n");
    float_array(
        &mut x,
        "Points",
        3,
        shapes.iter().flat_map(|s| s.vertices.iter().flatten()),
    );
    x.push_str("</Points>\n<Cells>\n");

    let mut connectivity = Vec::with_capacity(points);
    let mut offsets = Vec::with_capacity(shapes.len());
    let (mut faces, mut face_offsets) = (Vec::new(), Vec::new());
    let mut first = 0;
    for s in &shapes {
        connectivity.extend(first..first + s.vertices.len());
        offsets.push(connectivity.len());
        if l.dimension == 3 {
            // Per cell: the face count, then each face's size and points.
            faces.push(s.faces.len());
            for f in &s.faces {
                faces.push(f.len());
                faces.extend(f.iter().map(|v| first + v));
            }
            face_offsets.push(faces.len());
        }
        first += s.vertices.len();
    }
    int_array(&mut x, "Int64", "connectivity", &connectivity);
    int_array(&mut x, "Int64", "offsets", &offsets);
    let cell = if l.dimension == 3 {
        POLYHEDRON
    } else {
        POLYGON
    };
    int_array(&mut x, "UInt8", "types", &vec![cell as usize; shapes.len()]);
    if l.dimension == 3 {
        int_array(&mut x, "Int64", "faces", &faces);
        int_array(&mut x, "Int64", "faceoffsets", &face_offsets);
    }
    x.push_str("</Cells>\n");
    footer(&mut x);
    x
}

/// The contacts' unstructured grid: one point and vertex cell per contact
/// the last step considered, open ones included.
fn contacts_vtu(run: &dyn RunView) -> String {
    let contacts = run.contact_lines();
    let n = contacts.len();
    let mut x = String::new();
    header(&mut x, n, n, run.time());
    x.push_str("<PointData Scalars=\"normal_force\" Vectors=\"force\">\n");
    let map = |f: &dyn Fn(&crate::observe::ContactLine) -> f64| -> Vec<f64> {
        contacts.iter().map(f).collect()
    };
    float_array(&mut x, "normal_force", 1, map(&|c| c.normal_force).iter());
    float_array(&mut x, "shear_force", 1, map(&|c| c.shear_force).iter());
    float_array(&mut x, "slip", 1, map(&|c| c.slip).iter());
    // 0 open, 1 locked (sticking), 2 sliding.
    let state: Vec<usize> = contacts
        .iter()
        .map(|c| match c.state {
            dda_core::ContactState::Open => 0,
            dda_core::ContactState::Locked => 1,
            dda_core::ContactState::Sliding => 2,
        })
        .collect();
    int_array(&mut x, "Int32", "state", &state);
    int_array(
        &mut x,
        "Int32",
        "block_a",
        &contacts.iter().map(|c| c.blocks[0]).collect::<Vec<_>>(),
    );
    int_array(
        &mut x,
        "Int32",
        "block_b",
        &contacts.iter().map(|c| c.blocks[1]).collect::<Vec<_>>(),
    );
    float_array(
        &mut x,
        "normal",
        3,
        contacts.iter().flat_map(|c| c.normal.iter()),
    );
    // The normal force on block a as a vector, for glyphs.
    let force: Vec<f64> = contacts
        .iter()
        .flat_map(|c| c.normal.map(|n| n * c.normal_force))
        .collect();
    float_array(&mut x, "force", 3, force.iter());
    x.push_str("</PointData>\n<Points>\n");
    float_array(
        &mut x,
        "Points",
        3,
        contacts.iter().flat_map(|c| c.point.iter()),
    );
    x.push_str("</Points>\n<Cells>\n");
    let ids: Vec<usize> = (0..n).collect();
    int_array(&mut x, "Int64", "connectivity", &ids);
    int_array(&mut x, "Int64", "offsets", &(1..=n).collect::<Vec<_>>());
    int_array(&mut x, "UInt8", "types", &vec![VERTEX as usize; n]);
    x.push_str("</Cells>\n");
    footer(&mut x);
    x
}

fn header(x: &mut String, points: usize, cells: usize, time: f64) {
    x.push_str("<?xml version=\"1.0\"?>\n");
    x.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n");
    // The time also as field data, for readers of a single frame.
    let _ = writeln!(
        x,
        "<FieldData>\n<DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n</FieldData>",
        num(round_time(time))
    );
    let _ = writeln!(
        x,
        "<Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    );
}

fn footer(x: &mut String) {
    x.push_str("</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

fn int_array(x: &mut String, kind: &str, name: &str, values: &[usize]) {
    let _ = writeln!(
        x,
        "<DataArray type=\"{kind}\" Name=\"{name}\" format=\"ascii\">"
    );
    let text: Vec<String> = values.iter().map(|v| v.to_string()).collect();
    for line in text.chunks(20) {
        x.push_str(&line.join(" "));
        x.push('\n');
    }
    x.push_str("</DataArray>\n");
}

fn float_array<'a>(
    x: &mut String,
    name: &str,
    components: usize,
    values: impl Iterator<Item = &'a f64>,
) {
    let _ = writeln!(
        x,
        "<DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
    );
    let text: Vec<String> = values.map(|&v| num(v)).collect();
    for line in text.chunks(components.max(3)) {
        x.push_str(&line.join(" "));
        x.push('\n');
    }
    x.push_str("</DataArray>\n");
}

/// A `.pvd` collection of the frames of `what`, one dataset per time.
fn collection(what: &str, frames: &[(f64, usize)]) -> String {
    let mut x = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for &(time, frame) in frames {
        let _ = writeln!(
            x,
            "<DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>",
            num(time),
            frame_name(what, frame)
        );
    }
    x.push_str("</Collection>\n</VTKFile>\n");
    x
}

fn save(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}
