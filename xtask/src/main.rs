//! Project tasks, run as `cargo xtask <task>`.

mod docs;
mod fmu;
mod platforms;

use std::process::ExitCode;

const USAGE: &str = "usage: cargo xtask <task>

tasks:
  fmu          build the binaries (linux64; win64 when its cross tools are installed) and
               package them as target/fmu/<modelIdentifier>.fmu (FMI 2.0) and
               target/fmu/<modelIdentifier>-fmi3.fmu (FMI 3.0)
  fmu --host   the same FMU with the linux64 binary only, built with plain cargo against
               this machine's glibc (no cargo-zigbuild, no cross tools; scripts/demo.sh)
  test-win64   run the FMU crate's tests compiled for Windows, under Wine
  help         show this message";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["fmu"] => finish(fmu::run(fmu::Build::Release)),
        ["fmu", "--host"] => finish(fmu::run(fmu::Build::Host)),
        ["test-win64"] => finish(platforms::test_win64(&fmu::workspace())),
        ["help" | "-h" | "--help"] => {
            println!("{USAGE}");
            ExitCode::SUCCESS
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

fn finish(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
