//! `dda plot DIR`: time-series charts of a run as SVG and PNG: the chosen
//! blocks' displacement, speed and rotation, and with `contacts.csv` the
//! contacts' normal forces.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{create_dir, norm, palette, register_font, RunData, FAMILY};

/// Blocks drawn when none are chosen: all of them up to this many, else the
/// ones that moved farthest.
pub const DEFAULT_BLOCKS: usize = 6;

/// Chart size in pixels (PNG) or user units (SVG).
const SIZE: (u32, u32) = (900, 540);

/// What `dda plot` is asked for.
#[derive(Debug, Clone, Default)]
pub struct PlotOptions {
    /// Block indices; empty: see [`DEFAULT_BLOCKS`].
    pub blocks: Vec<usize>,
    /// Where the charts go; `None`: `DIR/plots`.
    pub out: Option<PathBuf>,
}

/// One chart: lines of (time, value).
struct Chart {
    name: &'static str,
    title: String,
    y_label: String,
    lines: Vec<(String, Vec<(f64, f64)>)>,
}

/// Writes the charts of the run in `dir`; returns the files written.
pub fn plot(dir: &Path, options: &PlotOptions) -> anyhow::Result<Vec<PathBuf>> {
    let run = RunData::load(dir)?;
    let blocks = choose_blocks(&run, &options.blocks)?;
    let out = options.out.clone().unwrap_or_else(|| dir.join("plots"));
    create_dir(&out)?;
    register_font();

    let per_block = |f: &dyn Fn(usize, usize) -> f64| -> Vec<(String, Vec<(f64, f64)>)> {
        blocks
            .iter()
            .map(|&i| {
                let points = (0..run.times.len())
                    .map(|k| (run.times[k], f(k, i)))
                    .collect();
                (format!("block {i}"), points)
            })
            .collect()
    };
    let rotation_label = if run.dimension == 2 {
        "rotation θ (°, counter-clockwise)"
    } else {
        "rotation |θ| (°, about the block's axis)"
    };
    let mut charts = vec![
        Chart {
            name: "displacement",
            title: "Displacement of the centroid".into(),
            y_label: "|u| (m)".into(),
            lines: per_block(&|k, i| run.displacement(k, i)),
        },
        Chart {
            name: "velocity",
            title: "Speed of the centroid".into(),
            y_label: "|v| (m/s)".into(),
            lines: per_block(&|k, i| norm(run.blocks[k][i].velocity)),
        },
        Chart {
            name: "rotation",
            title: "Rotation".into(),
            y_label: rotation_label.into(),
            lines: per_block(&|k, i| {
                let r = run.blocks[k][i].rotation;
                let angle = if run.dimension == 2 { r[2] } else { norm(r) };
                angle.to_degrees()
            }),
        },
    ];
    if let Some(contacts) = &run.contacts {
        let unit = if run.dimension == 2 { "N/m" } else { "N" };
        let total = contacts
            .iter()
            .map(|c| c.iter().map(|c| c.normal_force).sum());
        let largest = contacts
            .iter()
            .map(|c| c.iter().map(|c| c.normal_force).fold(0.0, f64::max));
        let along = |v: Vec<f64>| run.times.iter().copied().zip(v).collect();
        charts.push(Chart {
            name: "contact_forces",
            title: "Contact normal forces".into(),
            y_label: format!("normal force ({unit})"),
            lines: vec![
                ("sum over contacts".into(), along(total.collect())),
                ("largest contact".into(), along(largest.collect())),
            ],
        });
    }

    let mut written = Vec::new();
    for chart in &charts {
        let svg = out.join(format!("{}.svg", chart.name));
        draw(SVGBackend::new(&svg, SIZE).into_drawing_area(), chart)?;
        let png = out.join(format!("{}.png", chart.name));
        draw(BitMapBackend::new(&png, SIZE).into_drawing_area(), chart)?;
        written.extend([svg, png]);
    }
    Ok(written)
}

/// The chosen blocks, checked; or the default choice.
fn choose_blocks(run: &RunData, chosen: &[usize]) -> anyhow::Result<Vec<usize>> {
    let n = run.block_count();
    if let Some(&bad) = chosen.iter().find(|&&i| i >= n) {
        bail!(
            "--blocks names block {bad}, but the run has {n} blocks (0 to {})",
            n - 1
        );
    }
    if !chosen.is_empty() {
        return Ok(chosen.to_vec());
    }
    if n <= DEFAULT_BLOCKS {
        return Ok((0..n).collect());
    }
    let last = run.times.len() - 1;
    let mut by_move: Vec<usize> = (0..n).collect();
    by_move.sort_by(|&a, &b| {
        run.displacement(last, b)
            .total_cmp(&run.displacement(last, a))
    });
    by_move.truncate(DEFAULT_BLOCKS);
    by_move.sort_unstable();
    Ok(by_move)
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, chart: &Chart) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let fail =
        |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("cannot draw {}: {e:?}", chart.name);
    root.fill(&WHITE).map_err(fail)?;
    let points = chart.lines.iter().flat_map(|(_, p)| p.iter());
    let (t0, t1) = points
        .clone()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    let (y0, y1) = points
        .filter(|p| p.1.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let t1 = if t1 > t0 { t1 } else { t0 + 1.0 };
    let (y0, y1) = padded(y0, y1);

    let mut c = ChartBuilder::on(&root)
        .caption(&chart.title, (FAMILY, 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(fail)?;
    c.configure_mesh()
        .x_desc("time (s)")
        .y_desc(&chart.y_label)
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 17))
        .y_label_formatter(&|v| tick(*v))
        .x_label_formatter(&|v| tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(fail)?;
    for (i, (name, points)) in chart.lines.iter().enumerate() {
        let (r, g, b) = palette(i);
        let colour = RGBColor(r, g, b);
        c.draw_series(LineSeries::new(
            points.iter().copied(),
            colour.stroke_width(2),
        ))
        .map_err(fail)?
        .label(name.as_str())
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FAMILY, 15))
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(fail)?;
    root.present().map_err(fail)?;
    Ok(())
}

/// A y range around [lo, hi] with a margin; a flat line gets a unit span.
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - half, hi + half);
    }
    (lo - 0.05 * span, hi + 0.15 * span)
}

/// A tick label: short, with an exponent for very large or small values.
fn tick(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.2e}")
    }
}
