//! The `acs` host tool; see `../shared/cli.md` and [`acs::host::cli`].

fn main() -> std::process::ExitCode {
    acs::host::cli::main()
}
