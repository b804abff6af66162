fn main() -> std::process::ExitCode {
    end_quietly_on_a_closed_pipe();
    osim_tune::cli::run()
}

/// Restores the default action of SIGPIPE, which the Rust runtime sets to "ignore": writing to
/// a pipe whose reader has gone (`osim-tune diff A B | head -1`) then ends the process quietly,
/// as it ends other Unix tools, instead of making `println!` panic on the EPIPE error.
#[cfg(unix)]
fn end_quietly_on_a_closed_pipe() {
    use std::os::raw::c_int;
    /// SIGPIPE's number and the default action's handler value (SIG_DFL) on Unix systems.
    const SIGPIPE: c_int = 13;
    const SIG_DFL: usize = 0;
    extern "C" {
        fn signal(signal: c_int, handler: usize) -> usize;
    }
    // SAFETY: the C library's `signal`, called before any other thread exists, installs the
    // default action; no handler code of ours runs.
    unsafe {
        signal(SIGPIPE, SIG_DFL);
    }
}

#[cfg(not(unix))]
fn end_quietly_on_a_closed_pipe() {}
