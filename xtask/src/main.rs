//! Project tasks, run as `cargo xtask <task>`.

mod docs;
mod fmu;

use std::process::ExitCode;

const USAGE: &str = "usage: cargo xtask <task>

tasks:
  fmu    build the release library and package it as target/fmu/<modelIdentifier>.fmu
  help   show this message";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["fmu"] => match fmu::run() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        ["help" | "-h" | "--help"] => {
            println!("{USAGE}");
            ExitCode::from(2)
        }
        _ => {
            if !args.is_empty() {
                eprintln!("unknown task: {}", args.join(" "));
            }
            eprintln!("{USAGE}");
            ExitCode::from(2)
        }
    }
}
