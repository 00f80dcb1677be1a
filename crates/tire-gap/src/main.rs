//! The `tire-gap` command line: a thin `main` over the library.

use std::process::ExitCode;

fn main() -> ExitCode {
    ExitCode::from(tire_gap::exit::OK)
}
