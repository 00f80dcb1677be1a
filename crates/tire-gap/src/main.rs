//! The `tire-gap` command line: a thin `main` over [`tire_gap::cli::run`].

use std::process::ExitCode;

use clap::Parser;
use tire_gap::cli::{Cli, Host, run};
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

/// Has glibc map every block of a MiB or more on its own, and unmap it when freed. By default glibc
/// raises that threshold to the size of each large block freed (up to 32 MiB), after which
/// the columns and residual series of millions of rows are carved from its heaps, and their
/// freed space stays mapped: a 10M-row diagnosis then peaks about 0.4 GiB above what it holds.
fn map_large_blocks() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt takes no pointer; setting M_MMAP_THRESHOLD before any thread starts
    // only changes where glibc places later blocks.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20);
    }
}

/// The CPU time the process has used on all its threads, in seconds.
fn cpu_seconds() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `t` is a valid, writable timespec for the call to fill in.
        let ok = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
        ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

fn main() -> ExitCode {
    map_large_blocks();
    let cli = Cli::parse();
    let mut stdout = std::io::stdout().lock();
    let host = Host {
        release_freed,
        cpu_seconds,
    };
    match run(cli, &mut stdout, host) {
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
