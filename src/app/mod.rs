//! The glue behind each subcommand: load, build, run, write, report.

pub mod baseline;
pub mod cli;
mod compare;
pub mod limits;
pub mod method;
pub mod method_args;
pub(crate) mod output;
pub mod profile;
pub mod progress;
mod reference;
pub mod render;
pub mod report;
mod scene;
mod view;

pub use cli::{Cli, Command};

/// Run one subcommand.
pub fn run(command: &Command) -> anyhow::Result<()> {
    match command {
        Command::Render(args) => render::run(args),
        Command::View(args) => view::run(args),
        Command::Reference(args) => reference::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Profile(args) => profile::run_command(args),
        Command::Report(args) => report::run_command(args),
        Command::Scene(args) => scene::run(args),
        Command::CaveMaster(args) => crate::cave::master::run(args),
        Command::CaveNode(args) => crate::cave::node::run(args),
    }
}

/// True when the error (or anything it wraps) is the user's bad input (exit code 2).
pub fn is_input_error(error: &anyhow::Error) -> bool {
    error.chain().any(|e| {
        e.downcast_ref::<crate::error::InputError>().is_some()
            || matches!(
                e.downcast_ref::<crate::gpu::GpuError>(),
                Some(crate::gpu::GpuError::NoSuchDevice(_))
            )
    })
}
