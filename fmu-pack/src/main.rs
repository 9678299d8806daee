//! `fmu-pack`: computes, fits and packs one hydrofmu FMU archive per hull geometry.

mod fit_cmd;
mod hull_arg;
mod pipeline;
mod progress;
mod sweep_cmd;

use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "fmu-pack",
    version,
    about = "Packs one hydrofmu FMU archive per hull geometry"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Compute the complex added mass table of a hull (CSV).
    Sweep(sweep_cmd::SweepArgs),
    /// Identify the equivalent mass-spring-damper network of a hull.
    Fit(fit_cmd::FitArgs),
}

fn main() {
    let cli = Cli::parse();
    let outcome = match &cli.command {
        Some(Command::Sweep(args)) => sweep_cmd::run(args),
        Some(Command::Fit(args)) => fit_cmd::run(args),
        None => Err("packing is not available in this build; try `fmu-pack sweep --help`".into()),
    };
    if let Err(message) = outcome {
        eprintln!("error: {message}");
        std::process::exit(2);
    }
}
