//! The study file (RON): the base scene, what to sweep, the figure and its
//! reference, how runs are judged and which charts to draw. See
//! `docs/studies.md` for every field.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use serde::{Deserialize, Serialize};

use super::figure::Figure;
use crate::scene::dotted_path;

/// One study. Field order and names are the file format.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename = "Study", deny_unknown_fields)]
pub struct Study {
    /// A title for the charts; default the study file's name.
    #[serde(default)]
    pub title: Option<String>,
    /// The base scene: `File("path.ron")` (relative to the study file) or
    /// `Inline("Scene(...)")`.
    pub scene: SceneSource,
    /// Fields set in every run, by path: `{"analysis.duration": 0.5}`.
    #[serde(default)]
    pub set: BTreeMap<String, Value>,
    /// The grid: every combination of the swept values, the first sweep
    /// varying slowest.
    #[serde(default)]
    pub sweep: Vec<Sweep>,
    /// Instead of a grid: bisection on one field for where the outcome flips.
    #[serde(default)]
    pub search: Option<Search>,
    /// The quantity read from each run.
    pub figure: Figure,
    /// What the figure should be; default none (no error column).
    #[serde(default)]
    pub reference: Option<Reference>,
    /// When a run counts as held rather than slid; default none (runs that
    /// end well are `converged`).
    #[serde(default)]
    pub held: Option<Held>,
    /// Depth of the prisms, m, when `dimension` is swept to 3; default 1.
    #[serde(default = "one")]
    pub depth: f64,
    /// Charts drawn from study.csv.
    #[serde(default)]
    pub charts: Vec<Chart>,
}

fn one() -> f64 {
    1.0
}

/// Where the base scene comes from.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum SceneSource {
    /// A scene file, relative to the study file's folder.
    File(String),
    /// Scene text.
    Inline(String),
}

/// A swept or set value: a number, or RON text put in verbatim (`"Linear"`,
/// `"Rigid"`, `"\"rock\""` for a string).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    Number(f64),
    Text(String),
}

impl Value {
    /// As written in study.csv and folder names.
    pub fn label(&self) -> String {
        match self {
            Value::Number(x) => crate::output::plain_number(*x),
            Value::Text(s) => s.clone(),
        }
    }

    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Number(x) => Some(*x),
            Value::Text(s) => s.trim().parse().ok(),
        }
    }

    /// As RON text in place of `old` (a whole number replacing an integer
    /// stays one, so `open_close_limit` and `voussoirs` can be swept).
    pub fn ron(&self, old: Option<&str>) -> String {
        match self {
            Value::Number(x) => {
                let integer_field = old.is_some_and(|o| {
                    let o = o.trim();
                    !o.is_empty() && o.bytes().all(|c| c.is_ascii_digit() || c == b'-')
                });
                if integer_field && x.fract() == 0.0 && x.abs() < 1e15 {
                    format!("{}", *x as i64)
                } else {
                    format!("{x:?}")
                }
            }
            Value::Text(s) => s.clone(),
        }
    }
}

/// One swept field.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// The scene field's path (`analysis.dt`), or `dimension` (3 runs the
    /// 2D scene's extruded prism model).
    pub field: String,
    pub values: Vec<Value>,
}

/// Bisection for the value of `field` where the outcome flips.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Search {
    Bisect {
        field: String,
        /// Ends of the bracket; their outcomes must differ.
        low: f64,
        high: f64,
        /// Stop when the bracket is narrower than this (units of the field).
        tolerance: f64,
        /// Where the flip is expected (drawn on the chart); default none.
        #[serde(default)]
        expected: Option<f64>,
    },
}

/// The figure's expected value.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Reference {
    Number(f64),
    /// An analytical expression (see `expr`): swept fields by their paths, `t`.
    Expression(String),
    /// The run with the smallest value of this field among the runs that
    /// share the other swept values (e.g. the finest dt).
    Finest(String),
}

/// A run is held when `block` ends within `tolerance` (m) of its start;
/// else it slid.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Held {
    pub block: usize,
    pub tolerance: f64,
}

/// A chart of study.csv.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Chart {
    /// Error against wall time, one series per value of `series` (default
    /// one series), the Pareto front marked.
    ErrorVsTime {
        #[serde(default)]
        series: Option<String>,
    },
    /// The outcome of each run over two swept fields, with a boundary.
    StabilityMap {
        x: String,
        y: String,
        #[serde(default)]
        boundary: Option<Boundary>,
    },
    /// The figure of each value of a swept field side by side as bars,
    /// with each run's wall time (2D against 3D: `by: "dimension"`).
    Bars { by: String },
    /// The figure (and reference) against a swept field, one series per
    /// value of `series`.
    FigureAgainst {
        x: String,
        #[serde(default)]
        series: Option<String>,
    },
}

/// A known boundary between outcomes on a stability map.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Boundary {
    /// A block on a slope of `slope` degrees: factor of safety
    /// tan φ / tan θ = 1, at friction angle φ = θ, on the axis whose field
    /// ends in `friction_angle`.
    FactorOfSafety { slope: f64 },
    /// A polyline through (x, y) points in the map's units.
    Points(Vec<(f64, f64)>),
}

impl Study {
    /// Reads a study file; errors name the file, line and column.
    pub fn load(path: &Path) -> anyhow::Result<Study> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("{}: cannot read the study file", path.display()))?;
        Study::parse(&text, &path.display().to_string())
    }

    /// Parses study text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> anyhow::Result<Study> {
        let options = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let mut study: Study = options.from_str(text).map_err(|e| {
            anyhow::anyhow!(
                "{origin}:{}:{}: {}",
                e.span.start.line,
                e.span.start.col,
                e.code
            )
        })?;
        study.dot_paths();
        study.check(origin)?;
        Ok(study)
    }

    /// Every path written in dots: a place as the scene's errors name it
    /// (`blocks[1].width`, `materials["rock"].density`) is the same field
    /// as `blocks.1.width` and `materials.rock.density`, as in the Python
    /// package's `Scene`, so study.csv, run folders and charts name it one
    /// way.
    fn dot_paths(&mut self) {
        self.set = std::mem::take(&mut self.set)
            .into_iter()
            .map(|(k, v)| (dotted_path(&k), v))
            .collect();
        let mut paths: Vec<&mut String> = self.sweep.iter_mut().map(|s| &mut s.field).collect();
        if let Some(Search::Bisect { field, .. }) = &mut self.search {
            paths.push(field);
        }
        if let Some(Reference::Finest(f)) = &mut self.reference {
            paths.push(f);
        }
        for c in &mut self.charts {
            match c {
                Chart::ErrorVsTime { series } => paths.extend(series.as_mut()),
                Chart::StabilityMap { x, y, .. } => paths.extend([x, y]),
                Chart::Bars { by } => paths.push(by),
                Chart::FigureAgainst { x, series } => {
                    paths.push(x);
                    paths.extend(series.as_mut());
                }
            }
        }
        for path in paths {
            *path = dotted_path(path);
        }
    }

    /// What serde cannot check.
    fn check(&self, origin: &str) -> anyhow::Result<()> {
        for s in &self.sweep {
            if s.values.is_empty() {
                bail!(
                    "{origin}: sweep of `{}` has no values: list at least one",
                    s.field
                );
            }
        }
        let mut seen = std::collections::HashSet::new();
        for s in &self.sweep {
            if !seen.insert(s.field.as_str()) {
                bail!(
                    "{origin}: `{}` is swept twice: merge the two lists",
                    s.field
                );
            }
        }
        if let Some(Search::Bisect {
            low,
            high,
            tolerance,
            field,
            ..
        }) = &self.search
        {
            if !self.sweep.is_empty() {
                bail!("{origin}: a study has either `sweep` or `search`, not both: run the search in a study of its own");
            }
            if !(low < high && *tolerance > 0.0 && tolerance.is_finite()) {
                bail!("{origin}: search on `{field}`: give low < high and a tolerance above 0 (got low {low}, high {high}, tolerance {tolerance})");
            }
        }
        if self.search.is_none() && self.sweep.is_empty() {
            bail!("{origin}: nothing to run: give `sweep: [(field: \"analysis.dt\", values: [...])]` or a `search`");
        }
        if let Some(h) = &self.held {
            if h.tolerance.is_nan() || h.tolerance <= 0.0 {
                bail!(
                    "{origin}: held.tolerance must be above 0 m (got {})",
                    h.tolerance
                );
            }
        }
        if !(self.depth > 0.0 && self.depth.is_finite()) {
            bail!("{origin}: depth must be above 0 m (got {})", self.depth);
        }
        let swept: Vec<&str> = self.fields();
        let known = |f: &str| swept.contains(&f);
        let name_check = |what: &str, f: &str| -> anyhow::Result<()> {
            if known(f) {
                Ok(())
            } else {
                bail!(
                    "{origin}: {what} names `{f}`, which is not swept; swept fields: {}",
                    swept.join(", ")
                )
            }
        };
        for c in &self.charts {
            match c {
                Chart::ErrorVsTime { series } | Chart::FigureAgainst { series, .. } => {
                    if let Some(s) = series {
                        name_check("a chart's series", s)?;
                    }
                    if let Chart::FigureAgainst { x, .. } = c {
                        name_check("a chart's x", x)?;
                    }
                }
                Chart::Bars { by } => name_check("a bar chart's `by`", by)?,
                Chart::StabilityMap { x, y, .. } => {
                    name_check("a stability map's x", x)?;
                    name_check("a stability map's y", y)?;
                }
            }
            if matches!(c, Chart::ErrorVsTime { .. }) && self.reference.is_none() {
                bail!("{origin}: an ErrorVsTime chart needs a `reference` to measure the error against");
            }
        }
        if let Some(Reference::Finest(f)) = &self.reference {
            name_check("reference Finest", f)?;
        }
        Ok(())
    }

    /// The swept fields (or the searched one), in order.
    pub fn fields(&self) -> Vec<&str> {
        match &self.search {
            Some(Search::Bisect { field, .. }) => vec![field.as_str()],
            None => self.sweep.iter().map(|s| s.field.as_str()).collect(),
        }
    }

    /// The title: given, or the study file's name.
    pub fn title_or(&self, path: &Path) -> String {
        self.title.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "study".into())
        })
    }

    /// The base scene's file, if it is one.
    pub fn scene_file(&self, study_path: &Path) -> Option<PathBuf> {
        match &self.scene {
            SceneSource::File(f) => Some(
                study_path
                    .parent()
                    .filter(|d| !d.as_os_str().is_empty())
                    .map_or_else(|| PathBuf::from(f), |d| d.join(f)),
            ),
            SceneSource::Inline(_) => None,
        }
    }
}
