//! Ground-motion record files: `time, ax, ay` (2D) or `time, ax, ay, az`
//! (3D) CSV rows, or the columns a [`Layout`] names.

use std::path::Path;

use nalgebra::SVector;

use super::{Quantity, Record, BASELINE_DEGREE};
use crate::settings::finite;
use crate::DdaError;

/// One line of a record, 1-based, and its sample (time, values as written).
pub type Sample = (usize, f64, Vec<f64>);

/// The value columns a record's rows have after the time.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The axis of each column (0 for x), in order.
    pub axes: Vec<usize>,
    /// One more column is accepted if it is zero throughout (az in a 2D
    /// scene's default layout).
    pub zero_extra: bool,
}

impl Layout {
    /// The columns `components` names, like "xz", or every axis of a space
    /// of `dimension` when it is `None`; the error says what to write.
    pub fn new(components: Option<&str>, dimension: u32) -> Result<Self, String> {
        let axes = if dimension == 3 { "xyz" } else { "xy" };
        let Some(c) = components else {
            return Ok(Self {
                axes: (0..axes.len()).collect(),
                zero_extra: dimension == 2,
            });
        };
        let mut out = Vec::new();
        for ch in c.chars() {
            match axes.find(ch) {
                Some(k) if !out.contains(&k) => out.push(k),
                _ => {
                    let like = if dimension == 3 { "xz" } else { "x" };
                    return Err(format!("components {c:?} must name axes of this {dimension}D scene ({axes}), each once, in the order of the record's columns, like {like:?}"));
                }
            }
        }
        if out.is_empty() {
            return Err(format!("components is empty; name the axes of the record's columns, like {axes:?}, or leave it out for all of them"));
        }
        Ok(Self {
            axes: out,
            zero_extra: false,
        })
    }

    /// What a row is, like "`time, ax, ay`".
    pub fn row(&self) -> String {
        let names: Vec<String> = self
            .axes
            .iter()
            .map(|&k| format!("a{}", ["x", "y", "z"][k]))
            .collect();
        format!("`time, {}`", names.join(", "))
    }
}

/// The samples of a record file, each with its line, as written (not
/// scaled). Blank lines and lines starting with `#` are skipped, and so is a
/// first line that does not start with a number (a header). Fields are
/// separated by commas, or by spaces when a line has no comma. Errors name
/// the file and line and say what to change.
///
/// Rows are split by the `csv` crate, which knows quoting, comments and line
/// ends (`\r\n` as well as `\n`), rather than by hand; only the rules of a
/// record (a header row, space-separated rows, the layout) are this
/// function's own.
pub fn read_samples(path: &Path, layout: &Layout) -> Result<Vec<Sample>, String> {
    let row = layout.row();
    let width = 1 + layout.axes.len();
    let file = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| {
        format!("cannot read the record file {file}: {e}; check the path (relative to the scene file's folder)")
    })?;
    // Spreadsheets often start a CSV with a byte-order mark, which would
    // make the first row look like a header and drop it.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut samples: Vec<Sample> = Vec::new();
    let mut first = true;
    for record in reader.records() {
        // The text is read whole and valid UTF-8 already, so the crate has
        // nothing left to fail on; its message is passed on all the same.
        let record = record.map_err(|e| format!("{file}: {e}; correct the record file"))?;
        let (line, start) = record.position().map_or((0, 0), |p| (p.line(), p.byte()));
        // The crate's position is where it began to read, before the blank
        // and comment lines it passed over: the record's own line, as
        // written, is the first line from there that is neither.
        let mut line = usize::try_from(line).unwrap_or(usize::MAX);
        let mut rest = usize::try_from(start)
            .ok()
            .and_then(|start| text.get(start..))
            .unwrap_or_default();
        let content = loop {
            let (first_line, tail) = rest.split_once('\n').unwrap_or((rest, ""));
            let trimmed = first_line.trim();
            if !(trimmed.is_empty() || trimmed.starts_with('#')) || tail.is_empty() {
                break trimmed;
            }
            rest = tail;
            line += 1;
        };
        // Blank lines, and comments indented past the crate's notice.
        if record.iter().all(str::is_empty) || record[0].starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = if record.len() == 1 {
            record[0].split_whitespace().collect()
        } else {
            record.iter().collect()
        };
        let header = first && fields[0].parse::<f64>().is_err();
        first = false;
        if header {
            continue;
        }
        let numbers: Vec<f64> = fields
            .iter()
            .map(|f| f.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                format!(
                    "{file}:{line}: {content:?} is not a row of numbers {row}; correct the line or comment it out with #"
                )
            })?;
        let extra = usize::from(layout.zero_extra);
        if !(width..=width + extra).contains(&numbers.len()) {
            return Err(format!(
                "{file}:{line}: {content:?} has {} columns; a row is {row}",
                numbers.len()
            ));
        }
        if let Some(v) = numbers.iter().find(|v| !v.is_finite()) {
            return Err(format!(
                "{file}:{line}: {v} is not a finite number; write finite values"
            ));
        }
        if let Some(&z) = numbers.get(width).filter(|_| layout.zero_extra) {
            if z != 0.0 {
                return Err(format!(
                    "{file}:{line}: the third component is {z}: a 3D record in a 2D scene; give `time, ax, ay` (a third column is accepted only if it is zero throughout)"
                ));
            }
        }
        let t = numbers[0];
        if let Some(&(previous_line, t0, _)) = samples.last() {
            if t <= t0 {
                return Err(format!(
                    "{file}:{line}: the time {t} does not come after the previous sample's ({t0}, line {previous_line}); times must increase"
                ));
            }
        }
        samples.push((line, t, numbers[1..width].to_vec()));
    }
    if samples.is_empty() {
        return Err(format!("{file} has no samples; give rows {row}"));
    }
    Ok(samples)
}

impl<const D: usize> Record<D> {
    /// Reads a record file of rows `layout` gives (see [`read_samples`]),
    /// its values times `scale` (9.81 for a record in g); the error names
    /// the file and, for a bad row, its line.
    pub fn read(
        path: &Path,
        layout: &Layout,
        quantity: Quantity,
        scale: f64,
    ) -> Result<Self, String> {
        let samples: Vec<(f64, SVector<f64, D>)> = read_samples(path, layout)?
            .iter()
            .map(|(_, t, v)| {
                let mut a = SVector::<f64, D>::zeros();
                for (value, &axis) in v.iter().zip(&layout.axes) {
                    a[axis] = value * scale;
                }
                (*t, a)
            })
            .collect();
        Record::new(quantity, &samples).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// A record as a scene names it: [`Record::read`], an acceleration
    /// record baseline corrected unless `correct` is `Some(false)`, and a
    /// note on how far it drifts. The error names the field at fault
    /// (`scale`, `baseline_correction`, `path`; none for the file's rows).
    pub fn load(
        path: &Path,
        layout: &Layout,
        quantity: Quantity,
        scale: f64,
        correct: Option<bool>,
    ) -> Result<(Self, Option<String>), DdaError> {
        let fault = |field, message| DdaError::Setting { field, message };
        finite("scale", "the scale", scale)?;
        if correct == Some(true) && quantity != Quantity::Acceleration {
            return Err(fault("baseline_correction", "baseline correction applies to acceleration records only; remove baseline_correction or give quantity: Acceleration".into()));
        }
        if path.as_os_str().is_empty() || path.is_dir() {
            let row = layout.row();
            return Err(fault(
                "path",
                format!("the record's path names no file; name a CSV file of rows {row}"),
            ));
        }
        let record = Record::read(path, layout, quantity, scale)
            .map_err(|m| fault(if path.is_file() { "" } else { "path" }, m))?;
        if quantity != Quantity::Acceleration {
            return Ok((record, None));
        }
        let short = |x: f64| match x {
            x if x >= 1e-3 => format!("{x:.3}"),
            x => format!("{x:.1e}"),
        };
        let drift = format!(
            "as recorded it ends {} m from where it started, moving at {} m/s",
            short(record.end_displacement().norm()),
            short(record.end_velocity().norm())
        );
        if correct == Some(false) {
            return Ok((
                record,
                Some(format!(
                    "no baseline correction (baseline_correction: false); {drift}"
                )),
            ));
        }
        let fixed = record.baseline_corrected();
        let note = format!(
            "baseline corrected (a polynomial of degree {BASELINE_DEGREE} fitted by least squares taken out of the acceleration, so the ground ends at rest where it started; baseline_correction: false turns this off); {drift}; corrected, {} m and {} m/s",
            short(fixed.end_displacement().norm()),
            short(fixed.end_velocity().norm()),
        );
        Ok((fixed, Some(note)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(name: &str, text: &str) -> Result<Vec<Sample>, String> {
        read_as(name, text, &Layout::new(None, 2).unwrap())
    }

    fn read_as(name: &str, text: &str, layout: &Layout) -> Result<Vec<Sample>, String> {
        let path =
            std::env::temp_dir().join(format!("dda-record-{}-{name}.csv", std::process::id()));
        std::fs::write(&path, text).unwrap();
        let result = read_samples(&path, layout);
        let _ = std::fs::remove_file(&path);
        result
    }

    #[test]
    fn headers_comments_and_separators() {
        let samples = read(
            "good",
            "time, ax, ay\n# comment\n\n0.0, 1.0, 2.0\n0.5 3.0 4.0\n1.0,5.0,6.0,0.0\n",
        )
        .unwrap();
        assert_eq!(
            samples,
            [
                (4, 0.0, vec![1.0, 2.0]),
                (5, 0.5, vec![3.0, 4.0]),
                (6, 1.0, vec![5.0, 6.0])
            ]
        );
    }

    /// Windows line ends, a quoted header, indented comments and tabs read
    /// as plain ones do, and errors still name the line as written.
    #[test]
    fn line_ends_quotes_and_indented_comments() {
        let samples = read(
            "crlf",
            "\"time\", \"ax\", \"ay\"\r\n  # comment\r\n\r\n0.0,1.0,2.0\r\n0.5\t3.0  4.0\r\n",
        )
        .unwrap();
        assert_eq!(
            samples,
            [(4, 0.0, vec![1.0, 2.0]), (5, 0.5, vec![3.0, 4.0])]
        );
        let e = read(
            "crlf-bad",
            "# t, ax, ay\r\n\r\n0.0, 1.0, 2.0\r\n# gap\r\n0.1, y, 2.0\r\n",
        )
        .unwrap_err();
        assert!(
            e.contains(":5: \"0.1, y, 2.0\" is not a row of numbers"),
            "{e}"
        );
    }

    /// Bad rows, 3D records and partial layouts are read through scenes in
    /// the root package's `tests/bad_input.rs` and `tests/bad_input_3d.rs`;
    /// rows too long for a 3D layout are not, so they are here.
    #[test]
    fn three_and_partial_layouts() {
        let e = read_as(
            "xyzw",
            "0.0, 1.0, 2.0, 0.0, 0.0\n",
            &Layout::new(None, 3).unwrap(),
        )
        .unwrap_err();
        assert!(e.contains("has 5 columns"), "{e}");
        let e = read_as(
            "xz4",
            "0.0, 1.0, 2.0, 0.0\n",
            &Layout::new(Some("xz"), 3).unwrap(),
        )
        .unwrap_err();
        assert!(e.contains("a row is `time, ax, az`"), "{e}");
    }

    /// A record reads its columns into the axes it names, scaled.
    #[test]
    fn a_record_is_read_scaled_into_its_axes() {
        let path = std::env::temp_dir().join(format!("dda-record-{}-xz.csv", std::process::id()));
        std::fs::write(&path, "t, ax, az\n0.0, 1.0, 2.0\n1.0, 1.0, 2.0\n").unwrap();
        let layout = Layout::new(Some("xz"), 3).unwrap();
        let record = Record::<3>::read(&path, &layout, Quantity::Velocity, 9.81);
        let _ = std::fs::remove_file(&path);
        let v = record.unwrap().end_velocity();
        assert_eq!(v, SVector::<f64, 3>::new(9.81, 0.0, 2.0 * 9.81));
        let missing = Record::<2>::read(
            &path,
            &Layout::new(None, 2).unwrap(),
            Quantity::Velocity,
            1.0,
        );
        assert!(missing.unwrap_err().contains("cannot read the record file"));
    }

    /// A record saved with a byte-order mark keeps its first row.
    #[test]
    fn a_byte_order_mark_does_not_eat_the_first_row() {
        let rows = "0.0, 0.5, 0.0\n0.01, 0.25, 0.0\n0.02, 0.0, 0.0\n";
        let with_mark = read("bom", &format!("\u{feff}{rows}")).unwrap();
        assert_eq!(with_mark.len(), 3);
        assert_eq!(with_mark, read("plain", rows).unwrap());
    }
}
