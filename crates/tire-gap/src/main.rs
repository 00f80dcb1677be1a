//! The `tire-gap` command line: a thin `main` over [`tire_gap::cli::run`].

use std::process::ExitCode;

use clap::Parser;
use tire_gap::cli::{Cli, run};
use tire_gap::io::output::FailureKind;

/// The exit code of each kind of failure (0 is success; argument errors exit with 2, clap's
/// own code for usage errors, help and version with 0).
fn exit_code(kind: FailureKind) -> u8 {
    match kind {
        // An output could not be made or written.
        FailureKind::Output => 1,
        // Unreadable file, missing column, bad value, bad arguments, data that cannot
        // support a diagnosis.
        FailureKind::BadInput => 2,
        // The report is printed, but an output asked for (parameter file, figures) could not
        // be written; the report says which and why.
        FailureKind::Incomplete => 3,
        // Stopped on request (the shell's code for an interrupt).
        FailureKind::Cancelled => 130,
    }
}

/// Gives freed memory back to the system: glibc keeps the free pieces of its heaps mapped,
/// and what reading millions of rows freed would otherwise count against the diagnosis.
fn release_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim takes no pointer and only returns the allocator's own free pages;
    // glibc allows it at any time, from any thread.
    unsafe {
        libc::malloc_trim(0);
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut stdout = std::io::stdout().lock();
    match run(cli, &mut stdout, release_freed) {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("tire-gap: {}", f.message);
            ExitCode::from(exit_code(f.kind))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_has_the_documented_exit_code() {
        // docs/tire-gap.md: bad input 2, a report whose outputs were not all written 3; an
        // output that could not be written 1.
        assert_eq!(exit_code(FailureKind::BadInput), 2);
        assert_eq!(exit_code(FailureKind::Incomplete), 3);
        assert_eq!(exit_code(FailureKind::Output), 1);
        assert_eq!(exit_code(FailureKind::Cancelled), 130);
    }
}
