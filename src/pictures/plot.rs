//! `dda plot DIR`: time-series charts of a run as SVG and PNG: the chosen
//! blocks' displacement, speed and rotation, with `contacts.csv` the
//! contacts' normal forces, and with `steps.csv` each step's wall time,
//! where it went (the phases stacked), work and length; or those step
//! charts alone of a lone steps file (`dda bench --step-log`'s).

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

/// One chart: lines of (time, value); `stacked`, each drawn as a band
/// on the ones before it (the parts of a whole).
struct Chart {
    name: &'static str,
    title: String,
    y_label: String,
    lines: Vec<(String, Vec<(f64, f64)>)>,
    stacked: bool,
}

/// Writes the charts of the run in `dir`; returns the files written.
/// `dir` may also be a lone `steps.csv` (as `dda bench --step-log` writes
/// one per wall): its step charts go beside it, into `plots/`, each named
/// after the file (`40x40_rigid_2d_step_time.png`; plain `step_time.png`
/// for a file named `steps.csv`).
pub fn plot(dir: &Path, options: &PlotOptions) -> anyhow::Result<Vec<PathBuf>> {
    if dir.is_file() {
        return plot_steps(dir, options);
    }
    if !dir.exists() && dir.extension().is_some_and(|e| e == "csv") {
        bail!(
            "{} not found: give a run's folder, or a steps file (`dda run --steps` writes steps.csv, `dda bench --step-log DIR` one a wall)",
            dir.display()
        );
    }
    let run = RunData::load(dir)?;
    let blocks = choose_blocks(&run, &options.blocks)?;
    let out = options.out.clone().unwrap_or_else(|| dir.join("plots"));
    create_dir(&out)?;

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
            stacked: false,
        },
        Chart {
            name: "velocity",
            title: "Speed of the centroid".into(),
            y_label: "|v| (m/s)".into(),
            lines: per_block(&|k, i| norm(run.blocks[k][i].velocity)),
            stacked: false,
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
            stacked: false,
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
            stacked: false,
        });
    }
    let steps_path = dir.join("steps.csv");
    if steps_path.exists() {
        charts.extend(step_charts(&crate::step_log::read_steps(&steps_path)?));
    }

    write_charts(&charts, &out, "")
}

/// The step charts of a lone `steps.csv` (see [`plot`]).
fn plot_steps(file: &Path, options: &PlotOptions) -> anyhow::Result<Vec<PathBuf>> {
    if !options.blocks.is_empty() {
        bail!(
            "--blocks chooses blocks of a run's folder; {} is a steps file, which has none",
            file.display()
        );
    }
    let rows = crate::step_log::read_steps(file)?;
    if rows.is_empty() {
        bail!(
            "{} has no step yet, only its header: nothing to chart",
            file.display()
        );
    }
    let beside = file.parent().unwrap_or(Path::new("."));
    let out = options.out.clone().unwrap_or_else(|| beside.join("plots"));
    create_dir(&out)?;
    let prefix = match file.file_stem().and_then(|s| s.to_str()) {
        Some("steps") | None => String::new(),
        Some(stem) => format!("{stem}_"),
    };
    write_charts(&step_charts(&rows), &out, &prefix)
}

/// Each chart as SVG and PNG into `out`, named `prefix` and its name.
fn write_charts(charts: &[Chart], out: &Path, prefix: &str) -> anyhow::Result<Vec<PathBuf>> {
    register_font();
    let mut written = Vec::new();
    for chart in charts {
        let svg = out.join(format!("{prefix}{}.svg", chart.name));
        draw(SVGBackend::new(&svg, SIZE).into_drawing_area(), chart)?;
        let png = out.join(format!("{prefix}{}.png", chart.name));
        draw(BitMapBackend::new(&png, SIZE).into_drawing_area(), chart)?;
        written.extend([svg, png]);
    }
    Ok(written)
}

/// Points drawn of `steps.csv` at most: a longer run's steps are averaged
/// over runs of consecutive steps, each drawn at its last step's time.
const STEP_POINTS: usize = 400;

/// `steps.csv` as four charts: the wall time, where it went (the
/// phases, stacked), the work (passes, moves, factorisations, cuts) and
/// the length of each step.
fn step_charts(rows: &[crate::step_log::StepRow]) -> Vec<Chart> {
    if rows.is_empty() {
        // A run stopped before its first step: nothing to chart.
        return Vec::new();
    }
    let per = rows.len().div_ceil(STEP_POINTS).max(1);
    let over = if per > 1 {
        format!(", mean over each {per} steps")
    } else {
        String::new()
    };
    let line = |f: &dyn Fn(&crate::step_log::StepRow) -> f64| -> Vec<(f64, f64)> {
        (rows.chunks(per))
            .map(|c| {
                let mean = c.iter().map(f).sum::<f64>() / c.len() as f64;
                (c[c.len() - 1].time, mean)
            })
            .collect()
    };
    vec![
        Chart {
            name: "step_time",
            title: format!("Wall time of each step{over}"),
            y_label: "wall time (ms)".into(),
            lines: vec![("step".into(), line(&|r| r.wall_ms))],
            stacked: false,
        },
        Chart {
            name: "step_phases",
            title: format!("Where each step's wall time went{over}"),
            y_label: "wall time (ms)".into(),
            lines: vec![
                ("contact search".into(), line(&|r| r.search_ms)),
                ("assembly".into(), line(&|r| r.assembly_ms)),
                ("factorisation".into(), line(&|r| r.factorization_ms)),
                ("substitutions".into(), line(&|r| r.solve_ms)),
                ("open-close decisions".into(), line(&|r| r.open_close_ms)),
                ("commit".into(), line(&|r| r.commit_ms)),
                ("other".into(), line(&|r| r.other_ms())),
            ],
            stacked: true,
        },
        Chart {
            name: "step_work",
            title: format!("Work of each step{over}"),
            y_label: "count per step".into(),
            lines: vec![
                ("open-close passes".into(), line(&|r| r.passes as f64)),
                ("Newton-Raphson moves".into(), line(&|r| r.moves as f64)),
                ("factorisations".into(), line(&|r| r.factorizations as f64)),
                ("cuts".into(), line(&|r| r.cuts as f64)),
            ],
            stacked: false,
        },
        Chart {
            name: "step_length",
            title: format!("Length of each step{over}"),
            y_label: "dt (s)".into(),
            lines: vec![("step".into(), line(&|r| r.dt))],
            stacked: false,
        },
    ]
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
    // A stacked chart draws each line's running sum with the ones before.
    let lines = if chart.stacked {
        stack(&chart.lines)
    } else {
        chart.lines.clone()
    };
    let points = lines.iter().flat_map(|(_, p)| p.iter());
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
    // No point at all (a chart of nothing) gets a unit span, not an
    // infinite one, which the axis would never finish dividing.
    let (t0, t1) = if t0.is_finite() { (t0, t1) } else { (0.0, 1.0) };
    let t1 = if t1 > t0 { t1 } else { t0 + 1.0 };
    let (y0, y1) = if chart.stacked {
        // Bands start at zero; room above for the legend.
        (0.0, padded(y0, y1).1.max(f64::MIN_POSITIVE))
    } else {
        padded(y0, y1)
    };

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
    if chart.stacked {
        // The last band first, so each lower one is drawn over it; the
        // legend lists them bottom band first, as read up the chart.
        for (i, (name, points)) in lines.iter().enumerate().rev() {
            let (r, g, b) = palette(i);
            let colour = RGBColor(r, g, b);
            // Opaque, lightened: a translucent band would darken the
            // lower bands drawn over it.
            let light = |v: u8| v + ((255 - v) as f64 * 0.3) as u8;
            let fill = RGBColor(light(r), light(g), light(b));
            c.draw_series(
                AreaSeries::new(points.iter().copied(), 0.0, fill.filled())
                    .border_style(colour.stroke_width(1)),
            )
            .map_err(fail)?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill.filled()));
        }
    }
    for (i, (name, points)) in lines.iter().enumerate().filter(|_| !chart.stacked) {
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

/// Each line's points summed with those of the lines before it (the lines
/// share their times).
fn stack(lines: &[(String, Vec<(f64, f64)>)]) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut below: Vec<f64> = Vec::new();
    lines
        .iter()
        .map(|(name, points)| {
            below.resize(points.len(), 0.0);
            let summed = (points.iter().zip(&mut below))
                .map(|(&(t, v), b)| {
                    *b += v;
                    (t, *b)
                })
                .collect();
            (name.clone(), summed)
        })
        .collect()
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
        // Four significant digits: ticks 1e-5 apart near 1e-3 differ.
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            // A whole number keeps its zeros: 1200, not 12.
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::step_log::StepRow;

    fn step(step: usize, moves: usize) -> StepRow {
        StepRow {
            step,
            time: step as f64 * 1e-3,
            dt: 1e-3,
            passes: 1,
            moves,
            factorizations: 0,
            cuts: 0,
            unconverged: 0,
            whole_tangent_moves: 0,
            products: 0,
            energy: 0.0,
            wall_ms: 0.5,
            search_ms: 0.1,
            assembly_ms: 0.2,
            factorization_ms: 0.0,
            solve_ms: 0.1,
            open_close_ms: 0.0,
            commit_ms: 0.05,
        }
    }

    /// The phases chart stacks each band on the ones before it, the last
    /// band ("other") the rest of the step's wall time.
    #[test]
    fn phases_are_stacked_up_to_the_wall_time() {
        let rows: Vec<StepRow> = (1..=4).map(|i| step(i, 1)).collect();
        let charts = step_charts(&rows);
        let phases = charts.iter().find(|c| c.name == "step_phases").unwrap();
        assert!(phases.stacked);
        let stacked = stack(&phases.lines);
        assert_eq!(stacked.len(), 7);
        let top = &stacked[6].1;
        assert!(top.iter().all(|&(_, v)| (v - 0.5).abs() < 1e-12), "{top:?}");
        // Search 0.1, then assembly 0.2 on it, factorisation none.
        assert!((stacked[1].1[0].1 - 0.3).abs() < 1e-12);
        assert_eq!(stacked[2].1[0].1, stacked[1].1[0].1);
        assert!((rows[0].other_ms() - 0.05).abs() < 1e-12);
    }

    /// A long run's steps are drawn as means over runs of consecutive
    /// steps, at most `STEP_POINTS` of them, each at its last step's time.
    #[test]
    fn long_runs_are_charted_as_means_of_their_steps() {
        let rows: Vec<StepRow> = (1..=1000).map(|i| step(i, i % 3)).collect();
        let charts = step_charts(&rows);
        let work = charts.iter().find(|c| c.name == "step_work").unwrap();
        assert!(
            work.title.ends_with("mean over each 3 steps"),
            "{}",
            work.title
        );
        let moves = &work.lines[1].1;
        assert_eq!(moves.len(), 334);
        // Steps 1, 2, 3 make 1, 2, 0 moves; the last run is step 1000 alone.
        assert_eq!(moves[0], (3e-3, 1.0));
        assert_eq!(moves[333], (1.0, 1.0));
        let short: Vec<StepRow> = (1..=10).map(|i| step(i, 2)).collect();
        let charts = step_charts(&short);
        assert_eq!(charts[0].title, "Wall time of each step");
        assert_eq!(charts[0].lines[0].1.len(), 10);
    }

    /// A chart with no point draws on a unit span (its axis was infinite,
    /// and dividing it never ended).
    #[test]
    fn a_chart_of_nothing_is_drawn() {
        register_font();
        let chart = Chart {
            name: "empty",
            title: "nothing".into(),
            y_label: "y".into(),
            lines: vec![("none".into(), Vec::new())],
            stacked: false,
        };
        let mut buffer = vec![0; (SIZE.0 * SIZE.1 * 3) as usize];
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        draw(root, &chart).unwrap();
    }

    #[test]
    fn ticks_keep_four_significant_digits() {
        assert_eq!(tick(1.02e-3), "0.00102");
        assert_eq!(tick(0.13), "0.13");
        assert_eq!(tick(12.5), "12.5");
        assert_eq!(tick(2.0), "2");
        assert_eq!(tick(1200.0), "1200");
        assert_eq!(tick(1000.0), "1000");
        assert_eq!(tick(-20.0), "-20");
        assert_eq!(tick(3.5e-5), "3.50e-5");
    }
}
