//! Charts of a study, SVG and PNG, drawn from its rows: error against wall
//! time with the Pareto front, stability maps, the figure against a swept
//! field, and a bisection's bracket. Axes spanning a factor of 4 or more
//! of positive values are logarithmic (drawn as log10, labelled in the
//! values themselves).

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::outcome::Outcome;
use super::spec::Boundary;
use super::table::Row;
use crate::pictures::{palette, register_font, FAMILY};

/// Picture size in pixels (PNG) or user units (SVG).
const SIZE: (u32, u32) = (900, 600);

/// An axis: its title and whether its values are drawn as log10.
#[derive(Clone)]
struct Axis {
    title: String,
    log: bool,
    /// Names of the whole-number positions, for categories.
    names: Option<Vec<String>>,
}

impl Axis {
    fn new(title: String, values: impl Iterator<Item = f64>) -> Self {
        let v: Vec<f64> = values.filter(|v| v.is_finite()).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        let log = !v.is_empty() && lo > 0.0 && hi / lo >= 4.0;
        Self {
            title,
            log,
            names: None,
        }
    }

    fn logarithmic(title: String) -> Self {
        Self {
            title,
            log: true,
            names: None,
        }
    }

    fn linear(title: String) -> Self {
        Self {
            title,
            log: false,
            names: None,
        }
    }

    fn at(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// A tick label with enough digits to tell ticks `span` apart.
    fn label(&self, v: f64, span: f64) -> String {
        if let Some(names) = &self.names {
            let k = v.round();
            return match names.get(k as usize) {
                Some(n) if (v - k).abs() < 1e-6 && k >= 0.0 => n.clone(),
                _ => String::new(),
            };
        }
        if self.log {
            let x = 10f64.powf(v);
            // Only round values are labelled (ticks fall evenly in log10).
            let e = x.log10().floor();
            let m = x / 10f64.powf(e);
            let round = [1.0, 2.0, 2.5, 5.0, 10.0]
                .into_iter()
                .find(|r| (m / r - 1.0).abs() < 0.03);
            if let Some(r) = round.filter(|_| span >= 0.3) {
                return tick(r * 10f64.powf(e));
            }
            if span >= 0.3 {
                return String::new();
            }
            let digits = if span < 1.0 { 2 } else { 1 };
            let s = format!("{x:.digits$e}");
            match s.split_once('e') {
                Some((m, e)) => {
                    let m = m.trim_end_matches('0').trim_end_matches('.');
                    format!("{m}e{e}")
                }
                None => s,
            }
        } else {
            let a = v.abs().max(span);
            if v != 0.0 && !(1e-3..1e5).contains(&a) {
                return format!("{v:.2e}");
            }
            let decimals = (-(span / 10.0).log10().floor()).clamp(0.0, 9.0) as usize;
            let s = format!("{v:.decimals$}");
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            }
        }
    }
}

/// One set of marks on a chart.
/// One series of squares per outcome, in its colour, at the points `at`
/// gives each row (its index and the row).
fn outcome_series(rows: &[Row], at: impl Fn(usize, &Row) -> Option<(f64, f64)>) -> Vec<Series> {
    Outcome::ALL
        .into_iter()
        .filter_map(|o| {
            let points: Vec<(f64, f64)> = (rows.iter().enumerate())
                .filter(|(_, r)| r.outcome == o)
                .filter_map(|(k, r)| at(k, r))
                .collect();
            let (r, g, b) = o.colour();
            (!points.is_empty()).then(|| Series {
                name: o.name().into(),
                colour: RGBColor(r, g, b),
                points,
                line: false,
                mark: Mark::Square,
                dashed: false,
            })
        })
        .collect()
}

struct Series {
    name: String,
    colour: RGBColor,
    points: Vec<(f64, f64)>,
    /// Joined by a line (in the given order).
    line: bool,
    mark: Mark,
    dashed: bool,
}

#[derive(Clone, Copy, PartialEq)]
enum Mark {
    Dot,
    Square,
    /// A hollow ring around other marks.
    Ring,
    /// A bar from zero, 0.6 wide in x.
    Bar,
    /// None: a line alone, named in the legend by its stroke.
    None,
}

struct Chart {
    title: String,
    x: Axis,
    y: Axis,
    series: Vec<Series>,
    /// Vertical or horizontal reference lines: (value, on x?, label).
    rules: Vec<(f64, bool, String)>,
    /// The x range, when not from the marks.
    x_span: Option<(f64, f64)>,
}

/// Draws `chart` as `stem.svg` and `stem.png` in `dir`.
fn save(chart: &Chart, dir: &Path, stem: &str) -> anyhow::Result<Vec<PathBuf>> {
    register_font();
    let svg = dir.join(format!("{stem}.svg"));
    draw(SVGBackend::new(&svg, SIZE).into_drawing_area(), chart)?;
    let png = dir.join(format!("{stem}.png"));
    draw(BitMapBackend::new(&png, SIZE).into_drawing_area(), chart)?;
    Ok(vec![svg, png])
}

/// Draws `chart` into `path`, SVG or PNG by its extension.
fn save_as(chart: &Chart, path: &Path) -> anyhow::Result<()> {
    register_font();
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("svg") => {
            draw(SVGBackend::new(path, SIZE).into_drawing_area(), chart)
        }
        Some(e) if e.eq_ignore_ascii_case("png") => {
            draw(BitMapBackend::new(path, SIZE).into_drawing_area(), chart)
        }
        _ => Err(anyhow!(
            "{}: a chart is written as .png or .svg; name the file so",
            path.display()
        )),
    }
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &Chart) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let fail =
        |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("cannot draw {}: {e:?}", chart.title);
    root.fill(&WHITE).map_err(fail)?;
    // Bars stand on zero.
    let pts = || {
        chart.series.iter().flat_map(|s| {
            let base = (s.mark == Mark::Bar).then_some(s.points.iter().map(|p| (p.0, 0.0)));
            s.points.iter().copied().chain(base.into_iter().flatten())
        })
    };
    let legend_rows = chart.series.len() + chart.rules.len();
    let (mut x0, mut x1) = range(pts().map(|p| chart.x.at(p.0)));
    let (mut y0, mut y1) = range(pts().map(|p| chart.y.at(p.1)));
    for (v, on_x, _) in &chart.rules {
        if *on_x {
            (x0, x1) = (x0.min(chart.x.at(*v)), x1.max(chart.x.at(*v)));
        } else {
            (y0, y1) = (y0.min(chart.y.at(*v)), y1.max(chart.y.at(*v)));
        }
    }
    let categories = chart.x.names.as_ref().map(|n| (-0.5, n.len() as f64 - 0.5));
    let (x0, x1) = chart
        .x_span
        .or(categories)
        .unwrap_or_else(|| pad(x0, x1, 0.06, 0.06));
    // Room at the top for the legend, above the marks.
    let (y0, y1) = pad(y0, y1, 0.08, 0.1 + 0.07 * legend_rows as f64);
    let mut c = ChartBuilder::on(&root)
        .caption(&chart.title, (FAMILY, 22))
        .margin(18)
        .x_label_area_size(50)
        .y_label_area_size(85)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(fail)?;
    c.configure_mesh()
        .x_desc(chart.x.title.as_str())
        .y_desc(chart.y.title.as_str())
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .x_label_formatter(&|v| chart.x.label(*v, x1 - x0))
        .y_label_formatter(&|v| chart.y.label(*v, y1 - y0))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(fail)?;
    for (v, on_x, label) in &chart.rules {
        let ends = if *on_x {
            let x = chart.x.at(*v);
            vec![(x, y0), (x, y1)]
        } else {
            let y = chart.y.at(*v);
            vec![(x0, y), (x1, y)]
        };
        let style = BLACK.stroke_width(2);
        c.draw_series(DashedLineSeries::new(ends, 8, 5, style))
            .map_err(fail)?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
    }
    for s in &chart.series {
        let at: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|p| (chart.x.at(p.0), chart.y.at(p.1)))
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .collect();
        let colour = s.colour;
        let name = s.name.as_str();
        if s.line && at.len() > 1 {
            let style = colour.stroke_width(2);
            let drawn = if s.dashed {
                c.draw_series(DashedLineSeries::new(at.clone(), 6, 4, style))
                    .map_err(fail)?
            } else {
                c.draw_series(LineSeries::new(at.clone(), style))
                    .map_err(fail)?
            };
            if s.mark == Mark::None {
                let dashes = if s.dashed {
                    [(0, 6), (9, 15)]
                } else {
                    [(0, 10), (10, 20)]
                };
                drawn.label(name).legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(dashes[0].0, 0), (dashes[0].1, 0)], style)
                        + PathElement::new(vec![(dashes[1].0, 0), (dashes[1].1, 0)], style)
                });
            }
        }
        match s.mark {
            Mark::None => {}
            Mark::Bar => {
                let bars = at
                    .iter()
                    .map(|&(x, y)| Rectangle::new([(x - 0.3, 0.0), (x + 0.3, y)], colour.filled()));
                c.draw_series(bars)
                    .map_err(fail)?
                    .label(name)
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 6), (x + 12, y + 6)], colour.filled())
                    });
            }
            Mark::Square => {
                let marks = at.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(-9, -9), (9, 9)], colour.filled())
                });
                c.draw_series(marks)
                    .map_err(fail)?
                    .label(name)
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 6), (x + 12, y + 6)], colour.filled())
                    });
            }
            Mark::Dot | Mark::Ring => {
                let (radius, style) = if s.mark == Mark::Dot {
                    (5, colour.filled())
                } else {
                    (9, colour.stroke_width(2))
                };
                let marks = at
                    .iter()
                    .map(move |&p| EmptyElement::at(p) + Circle::new((0, 0), radius, style));
                let drawn = c.draw_series(marks).map_err(fail)?;
                if !name.is_empty() {
                    drawn
                        .label(name)
                        .legend(move |(x, y)| Circle::new((x + 6, y), radius.min(6), style));
                }
            }
        }
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FAMILY, 14))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(fail)?;
    root.present().map_err(fail)?;
    Ok(())
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        })
}

/// A range around [lo, hi] with a margin; a point gets a unit span.
fn pad(lo: f64, hi: f64, below: f64, above: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - half, hi + half);
    }
    (lo - below * span, hi + above * span)
}

fn tick(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

/// The column of `field` among the swept fields.
fn column(fields: &[String], field: &str) -> anyhow::Result<usize> {
    fields.iter().position(|f| f == field).ok_or_else(|| {
        anyhow!(
            "study.csv has no column `{field}`; its swept fields are {}",
            fields.join(", ")
        )
    })
}

/// Groups rows by the value of `series` (one group without it), in first-seen order.
fn groups<'a>(
    fields: &[String],
    rows: &'a [Row],
    series: Option<&str>,
) -> anyhow::Result<Vec<(String, Vec<&'a Row>)>> {
    let k = series.map(|s| column(fields, s)).transpose()?;
    let mut out: Vec<(String, Vec<&Row>)> = Vec::new();
    for r in rows {
        let key = k.map_or_else(String::new, |k| r.values[k].clone());
        match out.iter_mut().find(|(n, _)| *n == key) {
            Some((_, g)) => g.push(r),
            None => out.push((key, vec![r])),
        }
    }
    Ok(out)
}

/// The error a chart shows: relative where the reference is not zero.
fn shown_error(r: &Row) -> Option<f64> {
    r.relative_error.or(r.error).filter(|e| *e > 0.0)
}

/// Error against wall time; the Pareto front (no other run both faster and
/// more accurate) is joined by a dashed black line.
pub fn error_vs_time(
    title: &str,
    fields: &[String],
    rows: &[Row],
    series: Option<&str>,
    dir: &Path,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let relative = rows.iter().any(|r| r.relative_error.is_some());
    let mut all = Vec::new();
    let mut out = Vec::new();
    for (i, (name, g)) in groups(fields, rows, series)?.into_iter().enumerate() {
        let mut pts: Vec<(f64, f64)> = g
            .iter()
            .filter_map(|r| shown_error(r).map(|e| (r.wall_time.max(1e-6), e)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        all.extend(pts.iter().copied());
        let (r, gr, b) = palette(i);
        out.push(Series {
            name: match series {
                Some(s) => format!("{} = {name}", short(s)),
                None => "runs".into(),
            },
            colour: RGBColor(r, gr, b),
            points: pts,
            line: true,
            mark: Mark::Dot,
            dashed: false,
        });
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in all.iter() {
        if front.last().is_none_or(|q| p.1 < q.1) {
            front.push(*p);
        }
    }
    out.push(Series {
        name: "Pareto front".into(),
        colour: BLACK,
        points: front,
        line: true,
        mark: Mark::Ring,
        dashed: true,
    });
    let chart = Chart {
        title: title.into(),
        x: Axis::new("wall time (s)".into(), all.iter().map(|p| p.0)),
        y: Axis::new(
            if relative { "relative error" } else { "error" }.into(),
            all.iter().map(|p| p.1),
        ),
        series: out,
        rules: vec![],
        x_span: None,
    };
    save(&chart, dir, stem)
}

/// The distinct texts of column `k` when any of them is not a number.
fn categories(rows: &[Row], k: usize) -> Option<Vec<String>> {
    if rows.iter().all(|r| r.values[k].parse::<f64>().is_ok()) {
        return None;
    }
    let mut names: Vec<String> = Vec::new();
    for r in rows {
        if !names.contains(&r.values[k]) {
            names.push(r.values[k].clone());
        }
    }
    Some(names)
}

/// A swept value as a number (its position among the values when they
/// are text).
fn numeric(rows: &[Row], k: usize) -> impl Fn(&Row) -> f64 + '_ {
    let names = categories(rows, k);
    move |r: &Row| match &names {
        Some(names) => names.iter().position(|n| *n == r.values[k]).unwrap_or(0) as f64,
        None => r.values[k].parse().unwrap_or(f64::NAN),
    }
}

/// The axis of a swept field: named positions for text values.
fn field_axis(title: &str, rows: &[Row], k: usize) -> Axis {
    match categories(rows, k) {
        Some(names) => Axis {
            names: Some(names),
            ..Axis::linear(title.into())
        },
        None => Axis::new(title.into(), rows.iter().map(numeric(rows, k))),
    }
}

/// Each run's outcome over two swept fields, with the boundary.
#[allow(clippy::too_many_arguments)]
pub fn stability_map(
    title: &str,
    fields: &[String],
    rows: &[Row],
    x: &str,
    y: &str,
    boundary: Option<&Boundary>,
    dir: &Path,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let (kx, ky) = (column(fields, x)?, column(fields, y)?);
    let (fx, fy) = (numeric(rows, kx), numeric(rows, ky));
    let mut series = outcome_series(rows, |_, r| Some((fx(r), fy(r))));
    let mut rules = Vec::new();
    match boundary {
        Some(Boundary::FactorOfSafety { slope }) => {
            let label = "factor of safety 1".to_string();
            if x.ends_with("friction_angle") {
                rules.push((*slope, true, label));
            } else if y.ends_with("friction_angle") {
                rules.push((*slope, false, label));
            }
        }
        Some(Boundary::Points(p)) => series.push(Series {
            name: "boundary".into(),
            colour: BLACK,
            points: p.clone(),
            line: true,
            mark: Mark::Dot,
            dashed: true,
        }),
        None => {}
    }
    let chart = Chart {
        title: title.into(),
        x: field_axis(x, rows, kx),
        y: field_axis(y, rows, ky),
        series,
        rules,
        x_span: None,
    };
    save(&chart, dir, stem)
}

/// The figure against a swept field, one series per value of another, the
/// reference as black dashes.
#[allow(clippy::too_many_arguments)]
pub fn figure_against(
    title: &str,
    figure: &str,
    fields: &[String],
    rows: &[Row],
    x: &str,
    series: Option<&str>,
    dir: &Path,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let kx = column(fields, x)?;
    let fx = numeric(rows, kx);
    let mut out = Vec::new();
    let mut xs = Vec::new();
    for (i, (name, g)) in groups(fields, rows, series)?.into_iter().enumerate() {
        let mut pts: Vec<(f64, f64)> = g
            .iter()
            .filter_map(|r| r.figure.map(|f| (fx(r), f)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        xs.extend(pts.iter().map(|p| p.0));
        let (r, gr, b) = palette(i);
        out.push(Series {
            name: match series {
                Some(s) => format!("{} = {name}", short(s)),
                None => "dda".into(),
            },
            colour: RGBColor(r, gr, b),
            points: pts,
            line: true,
            mark: Mark::Dot,
            dashed: false,
        });
    }
    let mut refs: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| r.reference.map(|v| (fx(r), v)))
        .collect();
    refs.sort_by(|a, b| a.0.total_cmp(&b.0));
    refs.dedup();
    let mut rules = Vec::new();
    if !refs.is_empty() {
        if refs.iter().all(|p| p.1 == refs[0].1) {
            rules.push((refs[0].1, false, format!("reference {}", tick(refs[0].1))));
        } else {
            out.push(Series {
                name: "reference".into(),
                colour: BLACK,
                points: refs,
                line: true,
                mark: Mark::Dot,
                dashed: true,
            });
        }
    }
    let chart = Chart {
        title: title.into(),
        x: match categories(rows, kx) {
            Some(_) => field_axis(x, rows, kx),
            None => Axis::new(x.into(), xs.into_iter()),
        },
        y: Axis::linear(figure.into()),
        series: out,
        rules,
        x_span: None,
    };
    save(&chart, dir, stem)
}

/// A bisection: each run's value of the field against its order, coloured
/// by outcome, the bracket's ends after each run, and the expected value.
#[allow(clippy::too_many_arguments)]
pub fn bracket(
    title: &str,
    field: &str,
    rows: &[Row],
    brackets: &[(f64, f64)],
    expected: Option<f64>,
    dir: &Path,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut series = Vec::new();
    let n = |k: usize| (k + 1) as f64;
    let lo: Vec<(f64, f64)> = brackets
        .iter()
        .enumerate()
        .map(|(k, b)| (n(k), b.0))
        .collect();
    let hi: Vec<(f64, f64)> = brackets
        .iter()
        .enumerate()
        .map(|(k, b)| (n(k), b.1))
        .collect();
    for (name, pts, colour) in [
        ("bracket, low end", lo, RGBColor(120, 120, 120)),
        ("bracket, high end", hi, RGBColor(60, 60, 60)),
    ] {
        series.push(Series {
            name: name.into(),
            colour,
            points: pts,
            line: true,
            mark: Mark::Dot,
            dashed: true,
        });
    }
    series.extend(outcome_series(rows, |k, r| {
        r.values[0].parse().ok().map(|v| (n(k), v))
    }));
    let rules = expected
        .map(|e| vec![(e, false, format!("expected {}", tick(e)))])
        .unwrap_or_default();
    let chart = Chart {
        title: title.into(),
        x: Axis::linear("run".into()),
        y: Axis::linear(field.into()),
        series,
        rules,
        x_span: None,
    };
    save(&chart, dir, stem)
}

/// A field's last segment, for legends.
fn short(path: &str) -> &str {
    path.rsplit('.').next().unwrap_or(path)
}

/// The figure of each value of `by` side by side as bars (the first run of
/// each value), the wall time in the legend, the reference as a line.
pub fn bars(
    title: &str,
    figure: &str,
    fields: &[String],
    rows: &[Row],
    by: &str,
    dir: &Path,
    stem: &str,
) -> anyhow::Result<Vec<PathBuf>> {
    let mut series = Vec::new();
    let mut names = Vec::new();
    for (i, (name, g)) in groups(fields, rows, Some(by))?.into_iter().enumerate() {
        let r = g[0];
        let (cr, cg, cb) = palette(i);
        let value = r.figure.map_or("failed".into(), |f| {
            if (1e-3..1e5).contains(&f.abs()) {
                format!("{f:.4}")
            } else {
                format!("{f:.3e}")
            }
        });
        series.push(Series {
            name: format!("{} = {name}: {value}, {:.2} s", short(by), r.wall_time),
            colour: RGBColor(cr, cg, cb),
            points: r.figure.map(|f| (i as f64, f)).into_iter().collect(),
            line: false,
            mark: Mark::Bar,
            dashed: false,
        });
        names.push(format!("{} = {name}", short(by)));
    }
    let rules = rows
        .iter()
        .find_map(|r| r.reference)
        .map(|v| vec![(v, false, format!("reference {}", tick(v)))])
        .unwrap_or_default();
    let n = names.len();
    let chart = Chart {
        title: title.into(),
        x: Axis {
            names: Some(names),
            ..Axis::linear(String::new())
        },
        y: Axis::linear(figure.into()),
        series,
        rules,
        x_span: None,
    };
    let mut chart = chart;
    chart.x_span = Some((-0.6, n as f64 - 0.4));
    save(&chart, dir, stem)
}

/// One line of a [`log_log`] chart: its legend name, points (x, y), both
/// positive, and colour; `dashed` lines carry no marks.
pub struct Line {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub colour: (u8, u8, u8),
    pub dashed: bool,
}

/// A chart of `lines` with both axes logarithmic, into `path` (`.png` or
/// `.svg`, by its extension).
pub fn log_log(
    title: &str,
    x_title: &str,
    y_title: &str,
    lines: Vec<Line>,
    path: &Path,
) -> anyhow::Result<()> {
    let series = lines
        .into_iter()
        .map(|l| Series {
            name: l.name,
            colour: RGBColor(l.colour.0, l.colour.1, l.colour.2),
            points: l.points,
            line: true,
            mark: if l.dashed { Mark::None } else { Mark::Dot },
            dashed: l.dashed,
        })
        .collect();
    let chart = Chart {
        title: title.into(),
        x: Axis::logarithmic(x_title.into()),
        y: Axis::logarithmic(y_title.into()),
        series,
        rules: Vec::new(),
        x_span: None,
    };
    save_as(&chart, path)
}
