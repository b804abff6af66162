fn main() -> std::process::ExitCode {
    osim_tune::cli::run()
}
