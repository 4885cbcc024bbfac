//! The `acs` host tool; see `docs/cli.md` and [`acs::host::cli`].

fn main() -> std::process::ExitCode {
    acs::host::cli::main()
}
