//! `ftwire`: sense and steer an elastic wire with a dual-arm robot from one wrist F/T sensor.
//!
//! The binary is thin: clap types live in [`cli`], each subcommand's logic in its own module
//! under [`commands`], the shared argument groups in the `ftwire` library, the error type and
//! the output writer in `ftwire-app`, and the libraries do the work. Exit codes are mapped here, in one place
//! ([`ftwire_lab::error::LabError::exit_code`]): 0 success, 1 valid input but no answer, 2 bad input.

/// `println!` with the line's control characters escaped ([`ftwire_core::text::printable`]):
/// a folder, a file or a name the user gave is shown, never acted on by the terminal.
macro_rules! outln {
    ($($arg:tt)*) => {
        println!("{}", ftwire_core::text::printable(&format!($($arg)*)))
    };
}

/// `print!` with control characters escaped, as [`outln!`].
macro_rules! out {
    ($($arg:tt)*) => {
        print!("{}", ftwire_core::text::printable(&format!($($arg)*)))
    };
}

/// `eprintln!` with control characters escaped, as [`outln!`].
macro_rules! errln {
    ($($arg:tt)*) => {
        eprintln!("{}", ftwire_core::text::printable(&format!($($arg)*)))
    };
}

mod cli;
mod commands;

use std::process::ExitCode;

use clap::Parser;

/// Ends the process cleanly on SIGINT, SIGTERM or SIGHUP (exit 128 + the signal's number):
/// the temporary results folders it is writing are removed, and a folder moving into place
/// finishes its move first ([`ftwire_lab::results::abandon_all_and_exit`]).
#[cfg(unix)]
fn end_cleanly_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                ftwire_lab::results::abandon_all_and_exit(128 + signal);
            }
        });
    }
}

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    #[cfg(unix)]
    {
        // A ROS 2 node ends on a signal by itself, printing its summary.
        #[cfg(feature = "ros2")]
        let own_signals = matches!(cli.command, cli::Command::Ros2(_));
        #[cfg(not(feature = "ros2"))]
        let own_signals = false;
        if !own_signals {
            end_cleanly_on_signals();
        }
        // An experiment that `ftwire reproduce` started ends once that process is gone.
        ftwire_lab::reproduce::end_with_parent();
    }
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Errors may quote the user's input (a log's line, a key): its control
            // characters are escaped, so that no input can drive the terminal.
            eprintln!(
                "error: {}",
                ftwire_core::text::printable(&error.to_string())
            );
            ExitCode::from(error.exit_code())
        }
    }
}
