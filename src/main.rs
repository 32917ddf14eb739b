fn main() -> std::process::ExitCode {
    nostencil::cli::main()
}
