//! The `verity` command-line tool; all of it lives in [`compare::cli`].

fn main() -> std::process::ExitCode {
    compare::cli::main()
}
