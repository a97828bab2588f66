//! `phosphor`: the command line of the Phosphor engine.
//!
//! ```text
//! phosphor render [SCENE.toml] [--mesh FILE.obj] [--shading MODE] [--size WxH] [--threads N]
//!                 [--encoding srgb|linear] [--plan] [--turntable N [--frames A..B]]
//!                 -o OUT.png|OUT.exr|OUT_%04d.png|-
//! phosphor accuracy [SCENE.toml] [--mesh FILE.obj] [--size WxH] [--out-dir DIR] [--csv FILE.csv]
//! phosphor info FILE.obj
//! phosphor bench [SCENE.toml] [--mesh FILE.obj] [--shading MODE|all] [--size WxH] [--threads N] [--frames N]
//! phosphor completions bash|zsh|fish|powershell
//! phosphor man
//! ```
//!
//! `render`, `accuracy` and `bench` also take the camera flags `--eye X,Y,Z --target X,Y,Z
//! --up X,Y,Z --fov DEG` or the orbit form `--azimuth DEG --elevation DEG --distance D`, the
//! standard views `--view front|back|left|right|top|bottom|iso`, `--ortho`, and,
//! with `--mesh`, the normal flags `--crease-angle DEG --normals file|computed
//! --weighting uniform|area|angle --no-smoothing-groups --split-by-material`.
//!
//! Errors are one line on stderr, `error: FILE:LINE: what` or `error: FILE: FIELD: what` (the
//! libraries' error messages already name the file and line or field; usage errors name the
//! flag first). Exit codes: 0 success, 1 input error (a file that is missing or wrong, an
//! output that cannot be written, stdout or stderr that cannot be written), 2 usage error
//! (clap's, and an output extension other than `.png`/`.exr`).

/// `println!` whose failure is never silent: a line on stdout, and exit status 1 with a
/// message on stderr if it cannot be written (a full disk behind `>`, a closed pipe).
macro_rules! say {
    ($($arg:tt)*) => {
        phosphor_output::term::say(&format!($($arg)*))
    };
}

mod accuracy;
mod args;
mod commands;
mod folders;
mod font;
mod frames;
mod geometric;
mod limits;
mod mach;
mod output;
mod plot;
mod progress;
mod rgb8;
mod view;

use std::process::ExitCode;

use clap::{CommandFactory, Parser};
use phosphor_output::term;

use crate::args::{Cli, Command};

/// A failure, sorted by who has to fix it.
#[derive(Debug)]
pub enum CliError {
    /// The command line is wrong (exit 2).
    Usage(String),
    /// An input file is missing or wrong, or the output cannot be written (exit 1).
    Input(String),
}

impl CliError {
    /// The process exit code for this error.
    #[must_use]
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::Usage(_) => 2,
            CliError::Input(_) => 1,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::Usage(m) | CliError::Input(m) => f.write_str(m),
        }
    }
}

fn main() -> ExitCode {
    // Usage errors: one line naming the flag, exit 2; --help and --version: stdout, exit 0.
    let cli = phosphor_args::usage::parse_or_exit(Cli::try_parse(), &Cli::command());
    phosphor_mesh::allow_outside_assets(cli.allow_outside_assets);
    let result = match cli.command {
        Command::Render(a) => commands::render::run(&a),
        Command::Accuracy(a) => commands::accuracy::run(&a),
        Command::Info(a) => commands::info::run(&a),
        Command::Bench(a) => commands::bench::run(&a),
        Command::Completions(a) => commands::shell::completions(&a),
        Command::Man => commands::shell::man(),
    };
    match result {
        Ok(()) => {
            term::finish_stdout();
            ExitCode::SUCCESS
        }
        Err(e) => {
            // One line, whatever the library put in its message.
            term::tell(&format!("error: {e}"));
            ExitCode::from(e.exit_code())
        }
    }
}
