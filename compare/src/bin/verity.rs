//! The `verity` command-line tool; all of it lives in [`compare::cli`].

use std::io::Write;

fn main() -> std::process::ExitCode {
    let code = compare::cli::run();
    if realtime::gpu::device_abandoned() {
        // The abandoned device's work still runs on the driver's threads; returning would run
        // the C libraries' exit handlers (LLVM's and Mesa's static destructors) under them, which
        // crashed lavapipe after the error was printed (realtime::gpu::device_abandoned).
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
        // SAFETY: `_exit` only ends the process (POSIX.1-2017, _exit: no exit handlers, no
        // stdio flush); nothing of Rust's runs after it, so no invariant can be broken.
        unsafe { libc::_exit(i32::from(code)) }
    }
    std::process::ExitCode::from(code)
}
