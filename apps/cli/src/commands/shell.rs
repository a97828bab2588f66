//! `phosphor completions SHELL` and `phosphor man`: the shell completion script and the manual
//! page, both made from the command-line definition itself (clap_complete, clap_mangen), so
//! they list exactly the subcommands and flags `phosphor` takes.
//!
//! Each is made whole in memory and then written to stdout through `say!`, so that a stdout
//! that cannot be written ends the command with exit status 1 and a message, never a panic.

use clap::CommandFactory;
use clap_complete::Shell;

use crate::CliError;
use crate::args::{Cli, CompletionsArgs, ShellArg};

/// The completion script for `shell`.
#[must_use]
pub fn completion_script(shell: ShellArg) -> Vec<u8> {
    let shell = match shell {
        ShellArg::Bash => Shell::Bash,
        ShellArg::Zsh => Shell::Zsh,
        ShellArg::Fish => Shell::Fish,
        ShellArg::Powershell => Shell::PowerShell,
    };
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut Cli::command(), "phosphor", &mut script);
    script
}

/// The manual page, in roff.
///
/// # Errors
/// The page cannot be rendered (an input error, exit 1).
pub fn man_page() -> Result<Vec<u8>, CliError> {
    let mut page = Vec::new();
    clap_mangen::Man::new(Cli::command())
        .render(&mut page)
        .map_err(|e| CliError::Input(format!("manual page: {e}")))?;
    Ok(page)
}

/// Writes `bytes` (UTF-8 text ending in a newline) to stdout.
fn print(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    say!("{}", text.strip_suffix('\n').unwrap_or(&text));
}

/// Runs `phosphor completions`.
pub fn completions(args: &CompletionsArgs) -> Result<(), CliError> {
    print(&completion_script(args.shell));
    Ok(())
}

/// Runs `phosphor man`.
pub fn man() -> Result<(), CliError> {
    print(&man_page()?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shell_gets_a_script_naming_the_subcommands() {
        for shell in [
            ShellArg::Bash,
            ShellArg::Zsh,
            ShellArg::Fish,
            ShellArg::Powershell,
        ] {
            let script = String::from_utf8(completion_script(shell)).unwrap_or_default();
            for word in ["render", "accuracy", "turntable", "ortho", "completions"] {
                assert!(script.contains(word), "{shell:?}: no {word}");
            }
        }
    }

    #[test]
    fn the_manual_page_is_roff_naming_the_subcommands() {
        let page = man_page().map(String::from_utf8);
        let Ok(Ok(page)) = page else {
            panic!("no manual page");
        };
        assert!(page.starts_with(".ie") || page.starts_with(".TH"), "{page}");
        assert!(page.contains(".TH phosphor"), "{page}");
        assert!(page.contains("render"), "{page}");
    }
}
