//! Output files written as the run goes, as [`Observer`]s: `history.csv`
//! and, when the scene asks, `contacts.csv`; and their readers.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use anyhow::{bail, Context};
use dda_core::ContactState;
use serde::Serialize;

use crate::observe::{Observer, RunView};

/// The header line of a 2D scene's `history.csv`.
pub const HISTORY_HEADER: &str = "step,time,block,x,y,rotation,vx,vy,omega,sxx,syy,sxy";

/// The header line of a 3D scene's `history.csv`: centroid, accumulated
/// rotation as a rotation vector (axis · angle, radians), velocity and
/// angular velocity, stress.
pub const HISTORY_HEADER_3D: &str =
    "step,time,block,x,y,z,rx,ry,rz,vx,vy,vz,wx,wy,wz,sxx,syy,szz,syz,szx,sxy";

/// One row of `history.csv`: a block's state at an output time.
#[derive(Debug, Clone, Copy, PartialEq)]
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
    out: BufWriter<File>,
}

impl HistoryWriter {
    /// A file with `header` as its first line ([`HISTORY_HEADER`] or
    /// [`HISTORY_HEADER_3D`]).
    pub fn create(path: &Path, header: &str) -> anyhow::Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut out = BufWriter::new(file);
        writeln!(out, "{header}")?;
        out.flush()?;
        Ok(Self { out })
    }

    /// One row per block at the run's current time.
    pub fn write(&mut self, driver: &dyn RunView) -> anyhow::Result<()> {
        let step = driver.statistics().steps;
        let time = round_time(driver.time());
        for i in 0..driver.block_count() {
            write!(self.out, "{step},{},{i}", num(time))?;
            for value in driver.history_values(i) {
                write!(self.out, ",{}", num(value))?;
            }
            writeln!(self.out)?;
        }
        self.out.flush()?;
        Ok(())
    }
}

impl Observer for HistoryWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
    }
}

/// The header line of `contacts.csv`.
pub const CONTACTS_HEADER: &str = "step,time,contact,block_a,block_b,state,fn,fs,slip";

/// One row of `contacts.csv`: a contact at an output time.
#[derive(Debug, Clone, PartialEq)]
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
    pub state: ContactState,
    /// Normal force of the last step, compression positive (force per unit
    /// thickness in 2D); 0 when open.
    pub normal_force: f64,
    /// Shear force magnitude of the last step.
    pub shear_force: f64,
    /// Accumulated slip path.
    pub slip: f64,
}

/// Writes `contacts.csv` a time at a time: one row per contact the last
/// step considered, open ones included (none at time 0, before the first
/// contact search).
pub struct ContactWriter {
    out: BufWriter<File>,
}

impl ContactWriter {
    pub fn create(path: &Path) -> anyhow::Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut out = BufWriter::new(file);
        writeln!(out, "{CONTACTS_HEADER}")?;
        out.flush()?;
        Ok(Self { out })
    }

    /// One row per contact at the run's current time.
    pub fn write(&mut self, driver: &dyn RunView) -> anyhow::Result<()> {
        let step = driver.statistics().steps;
        let time = num(round_time(driver.time()));
        for c in driver.contact_lines() {
            writeln!(
                self.out,
                "{step},{time},{},{},{},{},{},{},{}",
                c.label,
                c.blocks[0],
                c.blocks[1],
                c.state.name(),
                num(c.normal_force),
                num(c.shear_force),
                num(c.slip)
            )?;
        }
        self.out.flush()?;
        Ok(())
    }
}

impl Observer for ContactWriter {
    fn on_output(&mut self, run: &dyn RunView) -> anyhow::Result<()> {
        self.write(run)
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
fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-4..1e15).contains(&a) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Reads a 2D scene's `history.csv` written by [`HistoryWriter`].
pub fn read_history(path: impl AsRef<Path>) -> anyhow::Result<Vec<HistoryRow>> {
    read_rows(path.as_ref(), "history", HISTORY_HEADER, parse_row)
}

/// Reads a 3D scene's `history.csv` written by [`HistoryWriter`].
pub fn read_history_3d(path: impl AsRef<Path>) -> anyhow::Result<Vec<HistoryRow3>> {
    read_rows(path.as_ref(), "history", HISTORY_HEADER_3D, parse_row_3d)
}

fn read_rows<T>(
    path: &Path,
    what: &str,
    expected: &str,
    parse: impl Fn(&str) -> anyhow::Result<T>,
) -> anyhow::Result<Vec<T>> {
    let file = File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
    let mut lines = BufReader::new(file).lines();
    let header = lines.next().transpose()?.unwrap_or_default();
    let header = header.trim_end();
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
    let mut rows = Vec::new();
    for (n, line) in lines.enumerate() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let row = parse(&line)
            .with_context(|| format!("{}:{}: bad {what} row", path.display(), n + 2))?;
        rows.push(row);
    }
    Ok(rows)
}

fn parse_row_3d(line: &str) -> anyhow::Result<HistoryRow3> {
    let fields: Vec<&str> = line.trim_end().split(',').collect();
    if fields.len() != 21 {
        bail!("expected 21 fields, found {}", fields.len());
    }
    let f = |i: usize| -> anyhow::Result<f64> {
        fields[i]
            .parse()
            .with_context(|| format!("field {i} is not a number: {:?}", fields[i]))
    };
    let three = |i: usize| -> anyhow::Result<[f64; 3]> { Ok([f(i)?, f(i + 1)?, f(i + 2)?]) };
    Ok(HistoryRow3 {
        step: fields[0].parse().context("step is not an integer")?,
        time: f(1)?,
        block: fields[2].parse().context("block is not an integer")?,
        position: three(3)?,
        rotation: three(6)?,
        velocity: three(9)?,
        spin: three(12)?,
        stress: [f(15)?, f(16)?, f(17)?, f(18)?, f(19)?, f(20)?],
    })
}

fn parse_row(line: &str) -> anyhow::Result<HistoryRow> {
    let fields: Vec<&str> = line.trim_end().split(',').collect();
    if fields.len() != 12 {
        bail!("expected 12 fields, found {}", fields.len());
    }
    let f = |i: usize| -> anyhow::Result<f64> {
        fields[i]
            .parse()
            .with_context(|| format!("field {i} is not a number: {:?}", fields[i]))
    };
    Ok(HistoryRow {
        step: fields[0].parse().context("step is not an integer")?,
        time: f(1)?,
        block: fields[2].parse().context("block is not an integer")?,
        x: f(3)?,
        y: f(4)?,
        rotation: f(5)?,
        vx: f(6)?,
        vy: f(7)?,
        omega: f(8)?,
        sxx: f(9)?,
        syy: f(10)?,
        sxy: f(11)?,
    })
}

/// Reads a `contacts.csv` written by [`ContactWriter`].
pub fn read_contacts(path: impl AsRef<Path>) -> anyhow::Result<Vec<ContactRow>> {
    read_rows(path.as_ref(), "contacts", CONTACTS_HEADER, parse_contact)
}

fn parse_contact(line: &str) -> anyhow::Result<ContactRow> {
    let fields: Vec<&str> = line.trim_end().split(',').collect();
    if fields.len() != 9 {
        bail!("expected 9 fields, found {}", fields.len());
    }
    let f = |i: usize| -> anyhow::Result<f64> {
        fields[i]
            .parse()
            .with_context(|| format!("field {i} is not a number: {:?}", fields[i]))
    };
    let int = |i: usize| -> anyhow::Result<usize> {
        fields[i]
            .parse()
            .with_context(|| format!("field {i} is not an integer: {:?}", fields[i]))
    };
    let state = match fields[5] {
        "open" => ContactState::Open,
        "locked" => ContactState::Locked,
        "sliding" => ContactState::Sliding,
        other => bail!("unknown contact state {other:?}"),
    };
    Ok(ContactRow {
        step: int(0)?,
        time: f(1)?,
        contact: fields[2].to_string(),
        block_a: int(3)?,
        block_b: int(4)?,
        state,
        normal_force: f(6)?,
        shear_force: f(7)?,
        slip: f(8)?,
    })
}

/// Writes pretty JSON to `path`.
pub fn write_json<T: Serialize>(path: &Path, value: &T) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    std::fs::write(path, text + "\n").with_context(|| format!("cannot write {}", path.display()))
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
