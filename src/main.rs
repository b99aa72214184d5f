//! The `dda` command: run or check scene files.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use dda::run::{run_with, RunOptions};
use dda::Scene;

#[derive(Parser)]
#[command(
    name = "dda",
    version,
    about = "Discontinuous Deformation Analysis of block systems"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene, writing DIR/history.csv (and DIR/contacts.csv if asked) as it goes and DIR/summary.json at the end
    Run {
        /// The scene file (RON)
        scene: PathBuf,
        /// Output directory (created if missing)
        #[arg(long, short, value_name = "DIR")]
        out: PathBuf,
    },
    /// Load, validate and build a scene without running it
    Check {
        /// The scene file (RON)
        scene: PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match execute(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn execute(command: Command) -> anyhow::Result<()> {
    use std::io::IsTerminal;
    match command {
        Command::Run { scene, out } => {
            let options = RunOptions {
                progress: std::io::stderr().is_terminal(),
                notes: true,
            };
            let summary = run_with(&scene, &out, options)?;
            let files: Vec<String> = summary
                .outputs
                .iter()
                .map(|f| out.join(f).display().to_string())
                .collect();
            println!("wrote {}", list(&files));
        }
        Command::Check { scene: path } => {
            let scene = Scene::load(&path)?;
            let model = scene.build()?;
            let laws = scene.law_table().laws;
            let dt = model.driver.dt();
            let auto = if scene.analysis.dt.is_none() {
                " (automatic)"
            } else {
                ""
            };
            println!(
                "{}: ok ({}, {}, {}, duration {} s, dt {dt:.4e} s{auto})",
                path.display(),
                count(model.driver.system.blocks.len(), "block"),
                count(scene.materials.len(), "material"),
                count(laws.len(), "joint law"),
                model.duration,
            );
            for note in model.driver.notes() {
                eprintln!("note: {note}");
            }
        }
    }
    Ok(())
}

/// "a", "a and b", "a, b and c".
fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

fn count(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
