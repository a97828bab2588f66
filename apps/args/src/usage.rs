//! clap's errors as Phosphor's programs report them: a usage error is one line naming the flag
//! ([`usage_line`]) and exit status 2; `--help` and `--version` go to stdout, checked
//! ([`parse_or_exit`]).

use clap::error::{ContextKind, ContextValue, ErrorKind};
use phosphor_output::term::{finish_stdout, one_line, say, tell};

/// One line for a clap error that is a usage error, without the `error: ` prefix, the flag
/// first: `--size: invalid value '0x10': each side must be between 1 and 16384`,
/// `-o/--output: required`, `--shading: invalid value 'shiny' (expected flat, gouraud, ...)`.
/// `command` is the application's whole command (to spell a flag with its short form).
#[must_use]
pub fn usage_line(err: &clap::Error, command: &clap::Command) -> String {
    let text = |kind| match err.get(kind) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        Some(ContextValue::Strings(v)) => Some(v.join(", ")),
        Some(ContextValue::StyledStr(s)) => Some(s.to_string()),
        Some(ContextValue::Number(n)) => Some(n.to_string()),
        _ => None,
    };
    let list = |kind| match err.get(kind) {
        Some(ContextValue::Strings(v)) => v.clone(),
        Some(ContextValue::String(s)) => vec![s.clone()],
        _ => Vec::new(),
    };
    let args: Vec<String> = list(ContextKind::InvalidArg)
        .iter()
        .map(|a| flag_name(a, command))
        .collect();
    let value = text(ContextKind::InvalidValue).unwrap_or_default();
    let suggestion = |kind| {
        text(kind)
            .map(|s| format!(" (did you mean {s}?)"))
            .unwrap_or_default()
    };
    let detail = match err.kind() {
        ErrorKind::MissingRequiredArgument => "required".to_owned(),
        ErrorKind::InvalidValue if value.is_empty() => "needs a value".to_owned(),
        ErrorKind::InvalidValue => {
            let valid = list(ContextKind::ValidValue);
            if valid.is_empty() {
                format!("invalid value '{value}'")
            } else {
                format!("invalid value '{value}' (expected {})", valid.join(", "))
            }
        }
        ErrorKind::ValueValidation => {
            let why = std::error::Error::source(err)
                .map_or_else(String::new, |s| format!(": {}", one_line(&s.to_string())));
            format!("invalid value '{value}'{why}")
        }
        ErrorKind::UnknownArgument => {
            format!("unknown argument{}", suggestion(ContextKind::SuggestedArg))
        }
        ErrorKind::ArgumentConflict => match text(ContextKind::PriorArg) {
            Some(prior) => format!("cannot be used with {}", flag_name(&prior, command)),
            None => "cannot be used with another argument given".to_owned(),
        },
        ErrorKind::InvalidSubcommand => {
            let name = text(ContextKind::InvalidSubcommand).unwrap_or_default();
            return format!(
                "{name}: unknown command{}",
                suggestion(ContextKind::SuggestedSubcommand)
            );
        }
        ErrorKind::MissingSubcommand | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let names: Vec<String> = command
                .get_subcommands()
                .map(|c| c.get_name().to_owned())
                .collect();
            return format!(
                "a command is required: {} (see {} --help)",
                names.join(", "),
                command.get_name()
            );
        }
        ErrorKind::TooManyValues if !value.is_empty() => {
            format!("unexpected value '{value}'")
        }
        _ => first_line_of(err),
    };
    if args.is_empty() {
        detail
    } else {
        format!("{}: {detail}", args.join(", "))
    }
}

/// clap's own message, first line, without its `error: ` prefix.
fn first_line_of(err: &clap::Error) -> String {
    let rendered = err.render().to_string();
    let first = rendered.lines().next().unwrap_or_default().trim();
    first.strip_prefix("error: ").unwrap_or(first).to_owned()
}

/// `--size <WxH>` as `--size`, `--output <FILE>` as `-o/--output` when it has a short form,
/// `[SCENE.toml]` as `SCENE.toml`.
fn flag_name(arg: &str, command: &clap::Command) -> String {
    let name = arg.split([' ', '=']).next().unwrap_or(arg);
    let name = name.trim_matches(['[', ']', '<', '>']);
    if let Some(long) = name.strip_prefix("--") {
        if let Some(short) = find_short(command, long) {
            return format!("-{short}/--{long}");
        }
    }
    name.to_owned()
}

/// The short form of the flag `--long` anywhere in `command` or its subcommands.
fn find_short(command: &clap::Command, long: &str) -> Option<char> {
    command
        .get_arguments()
        .find(|a| a.get_long() == Some(long))
        .and_then(clap::Arg::get_short)
        .or_else(|| {
            command
                .get_subcommands()
                .find_map(|sub| find_short(sub, long))
        })
}

/// Handles the result of clap's parsing for an application's `main`: the parsed value; or,
/// for `--help` and `--version`, the text on stdout (checked) and exit 0; or one usage line on
/// stderr and exit status 2.
pub fn parse_or_exit<T>(parsed: Result<T, clap::Error>, command: &clap::Command) -> T {
    match parsed {
        Ok(v) => v,
        Err(e) if !e.use_stderr() => {
            say(e.render().to_string().trim_end());
            finish_stdout();
            std::process::exit(0);
        }
        Err(e) => {
            tell(&format!("error: {}", usage_line(&e, command)));
            std::process::exit(2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn command() -> clap::Command {
        clap::Command::new("tool")
            .subcommand(
                clap::Command::new("render")
                    .arg(
                        clap::Arg::new("output")
                            .short('o')
                            .long("output")
                            .value_name("FILE")
                            .required(true),
                    )
                    .arg(
                        clap::Arg::new("size")
                            .long("size")
                            .value_name("WxH")
                            .value_parser(|s: &str| {
                                if s == "ok" {
                                    Ok(1u32)
                                } else {
                                    Err("expected WxH".to_owned())
                                }
                            }),
                    )
                    .arg(
                        clap::Arg::new("mode")
                            .long("mode")
                            .value_parser(["flat", "phong"]),
                    ),
            )
            .subcommand(clap::Command::new("info"))
            .subcommand_required(true)
    }

    fn line_for(args: &[&str]) -> String {
        let err = command()
            .try_get_matches_from(args)
            .expect_err("a usage error");
        usage_line(&err, &command())
    }

    #[test]
    fn usage_errors_are_one_line_naming_the_flag_first() {
        assert_eq!(line_for(&["tool", "render"]), "-o/--output: required");
        assert_eq!(
            line_for(&["tool", "render", "-o", "x", "--size", "big"]),
            "--size: invalid value 'big': expected WxH"
        );
        assert_eq!(
            line_for(&["tool", "render", "-o", "x", "--mode", "shiny"]),
            "--mode: invalid value 'shiny' (expected flat, phong)"
        );
        assert!(line_for(&["tool", "render", "-o", "x", "--wat"]).starts_with("--wat: unknown"));
        assert!(line_for(&["tool", "rendr"]).starts_with("rendr: unknown command"));
        assert_eq!(
            line_for(&["tool"]),
            "a command is required: render, info (see tool --help)"
        );
    }
}
