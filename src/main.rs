//! `kanestop`: simulate a ship-restraining system with Kane's method.
//!
//! `cargo run --release` runs the paper's case 1 (embedded); see `--help` for the rest.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use kanestop_runtime::eval::{evaluate, StateFile};
use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::DEFAULT_SCENE;
use kanestop_runtime::reference::ReferenceKernel;
use kanestop_runtime::report;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, Stop};

#[derive(Parser)]
#[command(
    name = "kanestop",
    version,
    about = "Kane-method simulator for ship-restraining systems (anchor, chain, cable, rod, ship)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run one scene and print a summary (default: the paper's case 1).
    Run {
        /// Scene TOML file; omitted: the embedded case 1.
        scene: Option<PathBuf>,
        /// Write the time history as CSV to this file (written whole or not at all).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Which Kane kernel evaluates the equations of motion.
        #[arg(long, value_enum, default_value_t = KernelChoice::Reference)]
        kernel: KernelChoice,
    },
    /// Evaluate the equations of motion once and print JSON (M, f, qdd, body states).
    Eval {
        /// Scene TOML file; omitted: the embedded case 1.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// State JSON {"q": [...], "u": [...], "anchor": "free"|"stuck"}; omitted: the
        /// scene's initial state.
        #[arg(long)]
        state: Option<PathBuf>,
        #[arg(long, value_enum, default_value_t = KernelChoice::Reference)]
        kernel: KernelChoice,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum KernelChoice {
    /// The generic formulation of the paper's Eqs. 1–27 (slow, the oracle).
    Reference,
}

fn kernel(choice: KernelChoice, model: &Model) -> Box<dyn Kernel> {
    match choice {
        KernelChoice::Reference => Box::new(ReferenceKernel::new(&model.chain)),
    }
}

fn load_model(scene: Option<&PathBuf>) -> Result<Model> {
    let scene = match scene {
        Some(path) => Scene::load(path)?,
        None => Scene::from_toml(DEFAULT_SCENE, "embedded case01.toml")?,
    };
    Ok(Model::new(&scene)?)
}

/// Exit code of a run that ended in a numerical failure.
const EXIT_NUMERICAL_FAILURE: u8 = 3;

fn main() -> ExitCode {
    match try_main() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn try_main() -> Result<ExitCode> {
    let cli = Cli::parse();
    let command = cli.command.unwrap_or(Command::Run { scene: None, out: None, kernel: KernelChoice::Reference });
    match command {
        Command::Run { scene, out, kernel: choice } => {
            let model = load_model(scene.as_ref())?;
            let result = simulate::run(&model, kernel(choice, &model));
            print!("{}", report::summary(&model, &result));
            if let Some(path) = out {
                report::write_csv(&result, &path).with_context(|| format!("cannot write {}", path.display()))?;
                println!("{:<10}{} ({} samples)", "written", path.display(), result.samples.len());
            }
            Ok(if matches!(result.stop, Stop::Failed(_)) {
                ExitCode::from(EXIT_NUMERICAL_FAILURE)
            } else {
                ExitCode::SUCCESS
            })
        }
        Command::Eval { scene, state, kernel: choice } => {
            let model = load_model(scene.as_ref())?;
            let state = match state {
                Some(path) => {
                    let text =
                        std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
                    let s: StateFile = serde_json::from_str(&text)
                        .with_context(|| format!("state file {} is not valid", path.display()))?;
                    Some(s)
                }
                None => None,
            };
            let out = evaluate(&model, kernel(choice, &model), state.as_ref())?;
            println!("{}", serde_json::to_string_pretty(&out)?);
            Ok(ExitCode::SUCCESS)
        }
    }
}
