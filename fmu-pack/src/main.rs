//! `fmu-pack`: packs one hydrofmu FMU archive per hull geometry.
//!
//! ```text
//! fmu-pack                                  pack the built-in semicircle into Semicircle.fmu
//! fmu-pack pack HULL [--network FILE] [--fmi 3] ... -o X.fmu
//! fmu-pack inspect X.fmu
//! fmu-pack sweep ...                        coefficient table of a hull
//! fmu-pack fit ...                          equivalent network of a hull
//! ```
//!
//! Exit codes: 0 on success; 1 on any error, with one line `fmu-pack: error: ...` on standard
//! error (also when standard output cannot be written, see [`output`]); 2 for command-line
//! syntax errors (clap's usage message).

mod args;
mod body;
mod database_cmd;
mod fit_cmd;
mod fit_report;
mod floating;
mod hull_arg;
mod output;
mod pack;
mod packing;
mod pipeline;
mod progress;
mod ship_cmd;
mod sweep_cmd;
mod viscous_args;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "fmu-pack",
    version,
    about = "Packs hydrofmu FMI 2.0 (or 3.0) co-simulation units, one per hull",
    long_about = "Packs hydrofmu FMI 2.0 co-simulation units, one per hull. \
                  Without a subcommand, packs the built-in semicircle into Semicircle.fmu."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Pack a hull (or a given network) into an .fmu archive.
    Pack(pack::PackArgs),
    /// Print the model description summary, DOFs, network order and state size.
    Inspect(pack::InspectArgs),
    /// Compute the complex added mass table of a hull (CSV).
    Sweep(sweep_cmd::SweepArgs),
    /// Identify the equivalent mass-spring-damper network of a hull.
    Fit(fit_cmd::FitArgs),
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Some(Command::Pack(args)) => {
            let summary = pack::pack(&args).map_err(|e| e.to_string())?;
            output::stdout(format!("{summary}\n").as_bytes())?;
        }
        Some(Command::Inspect(args)) => {
            let found = pack::inspect(&args.fmu).map_err(|e| e.to_string())?;
            output::stdout(found.to_string().as_bytes())?;
        }
        Some(Command::Sweep(args)) => sweep_cmd::run(&args)?,
        Some(Command::Fit(args)) => fit_cmd::run(&args)?,
        None => {
            // The defaults of `fmu-pack pack semicircle -o Semicircle.fmu`.
            let args =
                Cli::try_parse_from(["fmu-pack", "pack", "semicircle", "-o", "Semicircle.fmu"])
                    .map_err(|e| e.to_string())?;
            let Some(Command::Pack(args)) = args.command else {
                return Err("the default pack arguments did not parse".into());
            };
            let summary = pack::pack(&args).map_err(|e| e.to_string())?;
            output::stdout(format!("{summary}\n").as_bytes())?;
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help and --version: the text is the product, so a failed write is an error.
        Err(e) if !e.use_stderr() => {
            if std::io::IsTerminal::is_terminal(&std::io::stdout()) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            return match output::stdout(e.render().to_string().as_bytes()) {
                Ok(()) => ExitCode::SUCCESS,
                Err(message) => {
                    output::stderr_line(&format!("fmu-pack: error: {message}"));
                    ExitCode::FAILURE
                }
            };
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            output::stderr_line(&format!("fmu-pack: error: {message}"));
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn pack_help_names_every_input_kind_and_the_order() {
        let mut cli = Cli::command();
        let help = cli
            .find_subcommand_mut("pack")
            .unwrap()
            .render_long_help()
            .to_string();
        for words in [
            "semicircle",
            "circle",
            "hull file",
            "ship file",
            "NAME.1",
            "NetCDF-3",
            "NAME.nc",
            "--order",
            "poles per invariant block",
        ] {
            assert!(help.contains(words), "{words} missing from:\n{help}");
        }
    }
}
