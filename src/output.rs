//! Output files written as the run goes, as [`Observer`]s: `history.csv`
//! and, when the scene asks, `contacts.csv` and `points.csv`; and their
//! readers.

use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use dda_core::ContactState;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Deserializer, Serialize};

use crate::observe::{Cursor, Observer, RunView};

/// The header line of a 2D scene's `history.csv`.
pub const HISTORY_HEADER: &str = "step,time,block,x,y,rotation,vx,vy,omega,sxx,syy,sxy";

/// The header line of a 3D scene's `history.csv`: centroid, accumulated
/// rotation as a rotation vector (axis · angle, radians), velocity and
/// angular velocity, stress.
pub const HISTORY_HEADER_3D: &str =
    "step,time,block,x,y,z,rx,ry,rz,vx,vy,vz,wx,wy,wz,sxx,syy,szz,syz,szx,sxy";

/// One row of `history.csv`: a block's state at an output time.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct HistoryRow {
    pub step: usize,
    pub time: f64,
    pub block: usize,
    /// Centroid.
    pub x: f64,
    pub y: f64,
    /// Accumulated rotation, radians counter-clockwise.
    pub rotation: f64,
    pub vx: f64,
    pub vy: f64,
    pub omega: f64,
    /// Stress, tension positive.
    pub sxx: f64,
    pub syy: f64,
    pub sxy: f64,
}

/// One row of a 3D scene's `history.csv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryRow3 {
    pub step: usize,
    pub time: f64,
    pub block: usize,
    /// Centroid (x, y, z).
    pub position: [f64; 3],
    /// Accumulated rotation as a rotation vector (axis · angle, radians,
    /// angle in [0, π]).
    pub rotation: [f64; 3],
    pub velocity: [f64; 3],
    /// Angular velocity (ωx, ωy, ωz).
    pub spin: [f64; 3],
    /// (σx, σy, σz, τyz, τzx, τxy), tension positive.
    pub stress: [f64; 6],
}

/// Writes `history.csv` a time at a time, flushing each so an interrupted
/// run keeps what it reached.
pub struct HistoryWriter {
    out: CsvFile,
}

/// A CSV file written a batch of rows at a time: each batch goes out in one
/// write and is flushed, and a batch the disk refuses is cut off again, so
/// the file always ends with a whole line and an error names the file.
pub struct CsvFile {
    path: PathBuf,
    file: File,
    /// Bytes of whole batches in the file.
    written: u64,
}

impl CsvFile {
    /// A new file with `header` as its first line.
    pub fn create(path: &Path, header: &str) -> anyhow::Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut out = Self {
            path: path.to_path_buf(),
            file,
            written: 0,
        };
        out.write_batch(|w| w.write_record(header.split(',')))?;
        Ok(out)
    }

    /// An existing file cut back to its first `length` bytes, to be written
    /// on from there (a run resumed from a checkpoint taken at that length).
    pub fn resume(path: &Path, length: u64) -> anyhow::Result<Self> {
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .with_context(|| format!("cannot open {} to continue it", path.display()))?;
        let found = file.metadata()?.len();
        if found < length {
            bail!(
                "{} has {found} bytes, fewer than the {length} it had at the checkpoint: it was changed since; run the scene again from the start",
                path.display()
            );
        }
        file.set_len(length)
            .and_then(|_| file.seek(SeekFrom::Start(length)))
            .with_context(|| format!("cannot cut {} back to the checkpoint", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            file,
            written: length,
        })
    }

    /// Bytes written so far, whole lines only.
    pub fn len(&self) -> u64 {
        self.written
    }

    /// Whether nothing, not even the header, was written.
    pub fn is_empty(&self) -> bool {
        self.written == 0
    }

    /// The rows `rows` writes, as one write.
    pub fn write_batch(
        &mut self,
        rows: impl FnOnce(&mut csv::Writer<&mut Vec<u8>>) -> csv::Result<()>,
    ) -> anyhow::Result<()> {
        let mut bytes = Vec::new();
        {
            let mut w = csv::Writer::from_writer(&mut bytes);
            rows(&mut w)?;
            w.flush()?;
        }
        let result = self.file.write_all(&bytes).and_then(|_| self.file.flush());
        if let Err(e) = result {
            // Cut a torn batch off; if even that fails the error still stands.
            let _ = self.file.set_len(self.written);
            let _ = self.file.seek(SeekFrom::Start(self.written));
            return Err(e).with_context(|| format!("cannot write {}", self.path.display()));
        }
        self.written += bytes.len() as u64;
        Ok(())
    }
}

impl HistoryWriter {
    /// A file with `header` as its first line ([`HISTORY_HEADER`] or
    /// [`HISTORY_HEADER_3D`]).
    pub fn create(path: &Path, header: &str) -> anyhow::Result<Self> {
        Ok(Self {
            out: CsvFile::create(path, header)?,
        })
    }

    /// Writes on after the first `length` bytes of `path`.
    pub fn resume(path: &Path, length: u64) -> anyhow::Result<Self> {
        Ok(Self {
            out: CsvFile::resume(path, length)?,
        })
    }

    /// Bytes written so far.
    pub fn len(&self) -> u64 {
        self.out.len()
    }

    /// Whether nothing was written.
    pub fn is_empty(&self) -> bool {
        self.out.is_empty()
    }

    /// One row per block at the run's current time.
    pub fn write(&mut self, driver: &dyn RunView) -> anyhow::Result<()> {
        let step = driver.statistics().steps.to_string();
        let time = num(round_time(driver.time()));
        self.out.write_batch(|w| {
            for i in 0..driver.block_count() {
                let values = driver.history_values(i).into_iter().map(num);
                let row = [step.clone(), time.clone(), i.to_string()];
                w.write_record(row.into_iter().chain(values))?;
            }
            Ok(())
        })
    }
}

impl Observer for HistoryWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
    }

    fn cursor(&self) -> Option<Cursor> {
        Some(Cursor::File {
            name: "history.csv".into(),
            length: self.len(),
        })
    }
}

/// The header line of `contacts.csv`.
pub const CONTACTS_HEADER: &str = "step,time,contact,block_a,block_b,state,fn,fs,slip";

/// One row of `contacts.csv`: a contact at an output time.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ContactRow {
    pub step: usize,
    pub time: f64,
    /// The contact's name, like `1:v0/0:e2` (vertex 0 of block 1 against
    /// edge 2 of block 0; see `dda_2d::contact::contact_label`) or
    /// `1:v3/0:f1` in 3D (vertex 3 of block 1 against face 1 of block 0; see
    /// `dda_3d::contact_label`).
    pub contact: String,
    /// The block whose vertex touches.
    pub block_a: usize,
    /// The block whose edge (or vertex, or face) is touched.
    pub block_b: usize,
    #[serde(deserialize_with = "state_by_name")]
    pub state: ContactState,
    /// Normal force of the last step, compression positive (force per unit
    /// thickness in 2D); 0 when open.
    #[serde(rename = "fn")]
    pub normal_force: f64,
    /// Shear force magnitude of the last step.
    #[serde(rename = "fs")]
    pub shear_force: f64,
    /// Accumulated slip path.
    pub slip: f64,
}

/// Writes `contacts.csv` a time at a time: one row per contact the last
/// step considered, open ones included (none at time 0, before the first
/// contact search).
pub struct ContactWriter {
    out: CsvFile,
}

impl ContactWriter {
    pub fn create(path: &Path) -> anyhow::Result<Self> {
        Ok(Self {
            out: CsvFile::create(path, CONTACTS_HEADER)?,
        })
    }

    /// Writes on after the first `length` bytes of `path`.
    pub fn resume(path: &Path, length: u64) -> anyhow::Result<Self> {
        Ok(Self {
            out: CsvFile::resume(path, length)?,
        })
    }

    /// Bytes written so far.
    pub fn len(&self) -> u64 {
        self.out.len()
    }

    /// Whether nothing was written.
    pub fn is_empty(&self) -> bool {
        self.out.is_empty()
    }

    /// One row per contact at the run's current time.
    pub fn write(&mut self, driver: &dyn RunView) -> anyhow::Result<()> {
        let step = driver.statistics().steps.to_string();
        let time = num(round_time(driver.time()));
        self.out.write_batch(|w| {
            for c in driver.contact_lines() {
                w.write_record([
                    step.clone(),
                    time.clone(),
                    c.label,
                    c.blocks[0].to_string(),
                    c.blocks[1].to_string(),
                    c.state.name().to_string(),
                    num(c.normal_force),
                    num(c.shear_force),
                    num(c.slip),
                ])?;
            }
            Ok(())
        })
    }
}

impl Observer for ContactWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
    }

    fn cursor(&self) -> Option<Cursor> {
        Some(Cursor::File {
            name: "contacts.csv".into(),
            length: self.len(),
        })
    }
}

/// The header line of a 2D scene's `points.csv`: the time, the measured
/// point's index and block, where it is and how far it has moved since the
/// start (m).
pub const POINTS_HEADER: &str = "time,point,block,x,y,dx,dy";

/// The header line of a 3D scene's `points.csv`.
pub const POINTS_HEADER_3D: &str = "time,point,block,x,y,z,dx,dy,dz";

/// One row of `points.csv`: a measured point at an output time (z = 0 in
/// 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointRow {
    pub time: f64,
    /// Index into the scene's `measured_points`.
    pub point: usize,
    pub block: usize,
    /// Where it is, m.
    pub position: [f64; 3],
    /// How far it has moved since the start, m.
    pub displacement: [f64; 3],
}

/// Writes `points.csv` a time at a time: one row per measured point.
pub struct PointsWriter {
    out: CsvFile,
    /// 2 or 3: the coordinates written.
    dimension: usize,
}

impl PointsWriter {
    /// A new file for a scene of `dimension` (2 or 3).
    pub fn create(path: &Path, dimension: u32) -> anyhow::Result<Self> {
        let header = if dimension == 3 {
            POINTS_HEADER_3D
        } else {
            POINTS_HEADER
        };
        Ok(Self {
            out: CsvFile::create(path, header)?,
            dimension: dimension as usize,
        })
    }

    /// Writes on after the first `length` bytes of `path`.
    pub fn resume(path: &Path, length: u64, dimension: u32) -> anyhow::Result<Self> {
        Ok(Self {
            out: CsvFile::resume(path, length)?,
            dimension: dimension as usize,
        })
    }

    /// One row per measured point at the run's current time.
    pub fn write(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        let time = num(round_time(run.time()));
        let d = self.dimension;
        self.out.write_batch(|w| {
            for (k, p) in run.measured_points().into_iter().enumerate() {
                let row = [time.clone(), k.to_string(), p.block.to_string()];
                let values = p.position[..d].iter().chain(&p.displacement[..d]);
                w.write_record(row.into_iter().chain(values.copied().map(num)))?;
            }
            Ok(())
        })
    }
}

impl Observer for PointsWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
    }

    fn cursor(&self) -> Option<Cursor> {
        Some(Cursor::File {
            name: "points.csv".into(),
            length: self.out.len(),
        })
    }
}

/// The first line of the file at `path`, its line ending left off (the
/// header of a CSV file, read without its rows).
pub(crate) fn first_line(path: &Path) -> anyhow::Result<String> {
    let mut first = String::new();
    File::open(path)
        .map(std::io::BufReader::new)
        .and_then(|mut r| std::io::BufRead::read_line(&mut r, &mut first))
        .with_context(|| format!("cannot open {}", path.display()))?;
    Ok(first.trim_end().to_string())
}

/// Reads a `points.csv` written by [`PointsWriter`], of either dimension.
pub fn read_points(path: impl AsRef<Path>) -> anyhow::Result<Vec<PointRow>> {
    let path = path.as_ref();
    let three = first_line(path)? == POINTS_HEADER_3D;
    let (header, d) = if three {
        (POINTS_HEADER_3D, 3)
    } else {
        (POINTS_HEADER, 2)
    };
    let rows: Vec<(f64, usize, usize, Vec<f64>)> = read_rows(path, "points", header)?;
    let three = |v: &[f64]| {
        let mut out = [0.0; 3];
        out[..d].copy_from_slice(v);
        out
    };
    Ok(rows
        .into_iter()
        .map(|(time, point, block, v)| PointRow {
            time,
            point,
            block,
            position: three(&v[..d]),
            displacement: three(&v[d..]),
        })
        .collect())
}

/// A number as a person writes it: plainly from 1e-3 to 1e5 (and 0), with
/// an exponent beyond (1e300 is "1e300", not 301 digits).
pub fn plain_number(x: f64) -> String {
    if x != 0.0 && !(1e-3..1e5).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A time as written: a sum of steps within two units of round-off of a
/// 15-digit decimal is written as that decimal, so 2000 steps of 0.001 s
/// read 2, not 1.9999999999999998; any other time (a duration of 2π, a
/// step cut to a third) as it is.
pub fn round_time(t: f64) -> f64 {
    let Ok(short) = format!("{t:.14e}").parse::<f64>() else {
        return t;
    };
    if (short - t).abs() <= 2.0 * f64::EPSILON * t.abs() {
        short
    } else {
        t
    }
}

/// Shortest text that reads back to the same number; exponent form for very
/// large or small magnitudes so rows stay short.
pub(crate) fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Reads a 2D scene's `history.csv` written by [`HistoryWriter`].
pub fn read_history(path: impl AsRef<Path>) -> anyhow::Result<Vec<HistoryRow>> {
    read_rows(path.as_ref(), "history", HISTORY_HEADER)
}

/// Reads a 3D scene's `history.csv` written by [`HistoryWriter`].
pub fn read_history_3d(path: impl AsRef<Path>) -> anyhow::Result<Vec<HistoryRow3>> {
    let rows: Vec<(usize, f64, usize, Vec<f64>)> =
        read_rows(path.as_ref(), "history", HISTORY_HEADER_3D)?;
    let three = |v: &[f64]| [v[0], v[1], v[2]];
    Ok(rows
        .into_iter()
        .map(|(step, time, block, v)| HistoryRow3 {
            step,
            time,
            block,
            position: three(&v[0..]),
            rotation: three(&v[3..]),
            velocity: three(&v[6..]),
            spin: three(&v[9..]),
            stress: [v[12], v[13], v[14], v[15], v[16], v[17]],
        })
        .collect())
}

/// Reads a `contacts.csv` written by [`ContactWriter`].
pub fn read_contacts(path: impl AsRef<Path>) -> anyhow::Result<Vec<ContactRow>> {
    read_rows(path.as_ref(), "contacts", CONTACTS_HEADER)
}

/// The rows of a CSV file whose header is `expected`, each with as many
/// fields as the header.
pub(crate) fn read_rows<T: DeserializeOwned>(
    path: &Path,
    what: &str,
    expected: &str,
) -> anyhow::Result<Vec<T>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .with_context(|| format!("cannot open {}", path.display()))?;
    let header: Vec<&str> = reader.headers()?.iter().collect();
    let header = header.join(",");
    if header != expected {
        let hint = if header == HISTORY_HEADER {
            " (it is a 2D history: read it with read_history)"
        } else if header == HISTORY_HEADER_3D {
            " (it is a 3D history: read it with read_history_3d)"
        } else {
            ""
        };
        bail!(
            "{}: the first line is not the {what} header {expected:?}{hint}",
            path.display()
        );
    }
    reader
        .deserialize()
        .map(|row| row.with_context(|| format!("{}: bad {what} row", path.display())))
        .collect()
}

/// A contact state by its name in `contacts.csv`.
fn state_by_name<'de, D: Deserializer<'de>>(d: D) -> Result<ContactState, D::Error> {
    let name = String::deserialize(d)?;
    [
        ContactState::Open,
        ContactState::Locked,
        ContactState::Sliding,
    ]
    .into_iter()
    .find(|s| s.name() == name)
    .ok_or_else(|| serde::de::Error::custom(format!("unknown contact state {name:?}")))
}

/// Writes pretty JSON to `path`, whole or not at all ([`write_atomically`]).
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    write_atomically(path, (text + "\n").as_bytes())
}

/// Writes beside `path`, syncs, and renames over it, so `path` is always
/// whole: the old contents or the new, even if the run is killed.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = PathBuf::from(partial);
    let write = || -> std::io::Result<()> {
        let mut file = File::create(&partial)?;
        file.write_all(bytes)?;
        file.sync_all()
    };
    if let Err(e) = write() {
        let _ = std::fs::remove_file(&partial);
        return Err(e).with_context(|| format!("cannot write {}", path.display()));
    }
    std::fs::rename(&partial, path).with_context(|| format!("cannot replace {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn times_lose_round_off_only() {
        use super::round_time;
        assert_eq!(round_time(1.9999999999999998), 2.0);
        assert_eq!(round_time(0.009000000000000001), 0.009);
        // Times that are what they are stay.
        let cut = 1.0 + 1e-3 / 729.0;
        assert_eq!(round_time(cut), cut);
        assert_eq!(round_time(std::f64::consts::TAU), std::f64::consts::TAU);
        assert_eq!(round_time(0.0), 0.0);
        assert!(round_time(f64::NAN).is_nan());
    }

    /// Plain within [1e-3, 1e5), and 0; an exponent beyond, never 301
    /// digits.
    #[test]
    fn plain_numbers_are_short() {
        use super::plain_number;
        assert_eq!(plain_number(0.25), "0.25");
        assert_eq!(plain_number(1.0), "1");
        assert_eq!(plain_number(0.0), "0");
        assert_eq!(plain_number(0.001), "0.001");
        assert_eq!(plain_number(1e5), "1e5");
        assert_eq!(plain_number(1e300), "1e300");
        assert_eq!(plain_number(-1e-300), "-1e-300");
    }

    #[test]
    fn numbers_round_trip() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1 + 0.2,
            -9.81e-3,
            1e-20,
            6.02e23,
            1.0 / 3.0,
            -123456.789,
        ] {
            let s = num(v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
        }
    }
}
