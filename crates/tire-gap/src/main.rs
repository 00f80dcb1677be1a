//! The `tire-gap` command line: a thin `main` over [`tire_gap::cli::run`].

use std::process::ExitCode;

use clap::Parser;
use tire_gap::cli::{Cli, run};
use tire_gap::exit;

fn main() -> ExitCode {
    // Argument errors exit with 2 (clap's own code for usage errors), help and version with 0.
    let cli = Cli::parse();
    let mut stdout = std::io::stdout().lock();
    match run(cli, &mut stdout) {
        Ok(()) => ExitCode::from(exit::OK),
        Err(f) => {
            eprintln!("tire-gap: {}", f.message);
            ExitCode::from(f.code)
        }
    }
}
