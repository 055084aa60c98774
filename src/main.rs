//! The vkgi command line: parse, call the library, map errors to exit codes
//! (0 success, 1 failure, 2 bad input or usage). A panic anywhere (vkgi's or a library's) is
//! caught here as a last resort and reported as one line with exit code 1, never a backtrace.

use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;

use clap::Parser;
use clap::error::ErrorKind;

use vkgi::app::{self, Cli};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            return match e.kind() {
                ErrorKind::DisplayHelp
                | ErrorKind::DisplayVersion
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
                    let _ = e.print();
                    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                        ExitCode::from(2)
                    } else {
                        ExitCode::SUCCESS
                    }
                }
                _ => {
                    let rendered = e.render().to_string();
                    let line = rendered.lines().next().unwrap_or("invalid arguments");
                    eprintln!("{} (see vkgi --help)", line.trim());
                    ExitCode::from(2)
                }
            };
        }
    };
    let level = match cli.verbose {
        0 => "warn",
        1 => "info",
        _ => "debug",
    };
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or(level))
        .format_timestamp(None)
        .init();
    // Panics are reported once, below, as one line (with their place when -v is given).
    let verbose = cli.verbose > 0;
    panic::set_hook(Box::new(move |info| {
        if verbose && let Some(place) = info.location() {
            eprintln!("panic at {}:{}", place.file(), place.line());
        }
    }));
    match panic::catch_unwind(AssertUnwindSafe(|| app::run(&cli.command))) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("error: {e:#}");
            if app::is_input_error(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
        Err(payload) => {
            eprintln!(
                "error: internal error (a bug in vkgi or a library it uses; please report it): {}",
                vkgi::error::panic_message(payload.as_ref())
            );
            ExitCode::FAILURE
        }
    }
}
