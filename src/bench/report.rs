//! The tables `dda bench` prints.

use super::scaling::{series_name, Fit};
use super::simulate::SimulateRow;
use super::{BenchRow, PerStep, SHAKE_FREQUENCY};
use crate::output::plain_number;
use crate::scene::BlockKind;

/// The step-timing table, then where each step's time goes.
pub fn print_steps(rows: &[BenchRow], steps: usize, repeats: usize) {
    println!(
        "running-bond walls of n × n bricks, {steps} steps timed per run, median of {}",
        runs(repeats)
    );
    println!(
        "{:>4} {:>15} {:>7} {:>9} {:>8} {:>10} {:>7} {:>8} {:>7} {:>5} {:>7} {:>7} {:>5} {:>9} {:>9} {:>7}",
        "n", "bricks", "blocks", "contacts", "unknowns", "ms/step", "× base", "s/sim s", "passes",
        "most", "newton", "factor.", "cuts", "drift m", "analyses", "MB"
    );
    for r in rows {
        println!(
            "{:>4} {:>15} {:>7} {:>9} {:>8} {:>10.2} {:>7.2} {:>8.2} {:>7.2} {:>5} {:>7.2} {:>7.2} {:>5} {:>9.2e} {:>9.2} {:>7.0}",
            r.courses,
            series_name(r.dimension, r.kind),
            r.blocks,
            r.contacts,
            r.unknowns,
            r.median_ms_per_step,
            r.ratio_to_baseline,
            r.seconds_per_simulated_second,
            r.per_step.passes_per_step,
            r.most_passes,
            r.per_step.newton_per_step,
            r.per_step.factorizations_per_step,
            r.cuts,
            r.drift,
            r.per_step.analyses_per_step,
            r.peak_memory_mb,
        );
    }
    let labelled: Vec<_> = (rows.iter())
        .map(|r| (label(r.courses, r.dimension, r.kind, None), &r.per_step))
        .collect();
    print_phases(&labelled, false);
}

/// A row's wall, and its step where given: "  20   rigid 2D".
fn label(courses: usize, dimension: u32, kind: BlockKind, dt: Option<f64>) -> String {
    let wall = format!("{courses:>4} {:>15}", series_name(dimension, kind));
    match dt {
        Some(dt) => format!("{wall} {dt:>10.3e}"),
        None => wall,
    }
}

/// Where each labelled row's step time goes; `dt_column`: the labels
/// carry the step.
fn print_phases(rows: &[(String, &PerStep)], dt_column: bool) {
    let Some((_, per_step)) = rows.first() else {
        return;
    };
    println!("where the time goes, ms per step (median run):");
    let names: String = (per_step.phase_ms_per_step.iter())
        .map(|(name, _)| format!("{name:>13}"))
        .collect();
    let mut head = format!("{:>4} {:>15}", "n", "bricks");
    if dt_column {
        head += &format!(" {:>10}", "dt s");
    }
    println!("{head} {names}");
    for (label, per_step) in rows {
        let cells: String = (per_step.phase_ms_per_step.iter())
            .map(|(_, ms)| format!("{ms:>13.3}"))
            .collect();
        println!("{label} {cells}");
    }
    // What the solve phase holds where sliding contacts couple friction
    // to the normal force: each product is a solve on the factor.
    if rows
        .iter()
        .any(|(_, p)| p.whole_tangent_moves_per_step > 0.0)
    {
        println!("moves on the whole tangent (friction coupled to the normal force), per step (median run):");
        println!(
            "{head} {:>9} {:>9} {:>9} {:>9}",
            "moves", "products", "factor.", "searched"
        );
        for (label, p) in rows {
            println!(
                "{label} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
                p.whole_tangent_moves_per_step,
                p.whole_tangent_products_per_step,
                p.whole_tangent_factorizations_per_step,
                p.line_search_residuals_per_step
            );
        }
    }
}

/// The simulated-time table.
pub fn print_simulate(rows: &[SimulateRow], repeats: usize) {
    let seconds = rows.first().map_or(0.0, |r| r.seconds);
    let given = rows.iter().any(|r| r.dt_given);
    let stepping = if given {
        "the dt given and automatic penalty"
    } else {
        "automatic dt and penalty"
    };
    println!(
        "running-bond walls of n × n bricks, {} s simulated with {stepping}, median of {}",
        plain_number(seconds),
        runs(repeats)
    );
    if rows.first().is_some_and(|r| r.settle_s.is_some()) {
        println!("each wall settled under its weight first (--settle)");
    }
    if let Some(a) = rows.first().and_then(|r| r.shake) {
        println!(
            "the bases shaken along the walls by a {SHAKE_FREQUENCY} Hz sine of {a} m/s² (drift includes the base's motion)"
        );
    }
    println!(
        "{:>4} {:>15} {:>7} {:>10} {:>9} {:>9} {:>9} {:>10} {:>8} {:>9} {:>7} {:>5} {:>7} {:>7} {:>6} {:>11} {:>10} {:>10} {:>7}",
        "n",
        "bricks",
        "blocks",
        "dt s",
        "penalty",
        "reached",
        "wall s",
        "s/sim s",
        "steps",
        "ms/step",
        "passes",
        "most",
        "newton",
        "factor.",
        "cuts",
        "unconverged",
        "drift m",
        "at end m",
        "MB"
    );
    for r in rows {
        println!(
            "{:>4} {:>15} {:>7} {:>10.3e} {:>9.2e} {:>9.4} {:>9.2} {:>10.3} {:>8} {:>9.2} {:>7.2} {:>5} {:>7.2} {:>7.2} {:>6} {:>11} {:>10.3e} {:>10.3e} {:>7.0}",
            r.courses,
            series_name(r.dimension, r.kind),
            r.blocks,
            r.dt,
            r.penalty,
            r.reached,
            r.wall_s,
            r.seconds_per_simulated_second,
            r.steps,
            r.ms_per_step,
            r.per_step.passes_per_step,
            r.most_passes,
            r.per_step.newton_per_step,
            r.per_step.factorizations_per_step,
            r.cuts,
            r.unconverged_steps,
            r.drift,
            r.end_drift,
            r.peak_memory_mb,
        );
    }
    let labelled: Vec<_> = (rows.iter())
        .map(|r| {
            let dt = given.then_some(r.dt);
            (label(r.courses, r.dimension, r.kind, dt), &r.per_step)
        })
        .collect();
    print_phases(&labelled, given);
    for r in rows {
        let Some(settle_s) = r.settle_s else { continue };
        let how = match r.settled {
            Some(true) => "settled",
            _ => "did not settle",
        };
        println!(
            "the {n} × {n} {} wall {how} before its run in {settle_s:.2} s of wall time, {} static steps, {} passes and {} factorisations (not in wall s; drift is from where it settled)",
            series_name(r.dimension, r.kind),
            r.settle_steps.unwrap_or(0),
            r.settle_passes.unwrap_or(0),
            r.settle_factorizations.unwrap_or(0),
            n = r.courses,
        );
    }
    for r in rows.iter().filter(|r| !r.completed) {
        println!(
            "the {n} × {n} {} wall stopped at the wall-clock cap, at t = {:.4} of {} s",
            series_name(r.dimension, r.kind),
            r.reached,
            plain_number(r.seconds),
            n = r.courses,
        );
    }
}

/// The exponent of time per step against blocks, per series.
pub fn print_fits(fits: &[Fit]) {
    if fits.is_empty() {
        return;
    }
    println!("time per step grows as N^p with the blocks N:");
    for f in fits {
        println!(
            "  {}: p = {:.2} from {} to {} blocks (least squares over all sizes {:.2})",
            series_name(f.dimension, f.kind),
            f.exponent,
            f.from_blocks,
            f.to_blocks,
            f.least_squares
        );
    }
}

/// "1 run", "3 runs".
fn runs(n: usize) -> String {
    if n == 1 {
        "1 run".into()
    } else {
        format!("{n} runs")
    }
}
