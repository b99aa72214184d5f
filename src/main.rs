//! The `dda` command: run, check or extrude scene files.

fn main() -> std::process::ExitCode {
    dda::cli::main_with(dda_contact::LawRegistry::with_builtin())
}
