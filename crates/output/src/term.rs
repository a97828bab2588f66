//! Lines for the terminal whose loss is never silent: a write to stdout or stderr that fails
//! (a full disk behind `>`, a closed pipe, a revoked terminal) ends the process with exit
//! status 1, with a message on stderr when stderr still works, and never with a panic or 0.
//!
//! Also the shapes of those lines: warnings are one line of at most [`WARNING_CHARS`]
//! characters, and clap's usage errors become one line naming the flag ([`usage_line`]).

use std::io::{self, Write};

use clap::error::{ContextKind, ContextValue, ErrorKind};

/// Exit status when stdout or stderr cannot be written.
pub const STREAM_FAILURE_EXIT: i32 = 1;

/// Longest warning line, in characters, `warning: ` included: a warning quoting a long name
/// or a whole file must not flood the terminal.
pub const WARNING_CHARS: usize = 200;

/// Writes `line` and a newline to stdout, flushed. On failure: an `error: stdout: ...` line on
/// stderr (if it can be written) and exit status 1.
pub fn say(line: &str) {
    let line = visible(line, &['\n', '\t']);
    let mut out = io::stdout().lock();
    let result = out
        .write_all(line.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    if let Err(e) = result {
        stdout_failed(&e);
    }
}

/// Flushes stdout at the end of a command; on failure as [`say`].
pub fn finish_stdout() {
    if let Err(e) = io::stdout().flush() {
        stdout_failed(&e);
    }
}

fn stdout_failed(e: &io::Error) -> ! {
    let _ = writeln!(io::stderr(), "error: stdout: {e}");
    std::process::exit(STREAM_FAILURE_EXIT);
}

/// Writes `text` to stderr as it is (no newline added), flushed. If stderr cannot be written
/// there is nowhere left to report to: exit status 1.
pub fn tell_raw(text: &str) {
    let mut err = io::stderr().lock();
    if err
        .write_all(text.as_bytes())
        .and_then(|()| err.flush())
        .is_err()
    {
        std::process::exit(STREAM_FAILURE_EXIT);
    }
}

/// Writes one line to stderr (newlines inside become spaces); on failure as [`tell_raw`].
pub fn tell(line: &str) {
    tell_raw(&format!("{}\n", one_line(line)));
}

/// Writes a warning to stderr: one line starting `warning: ` (added if missing), cut to
/// [`WARNING_CHARS`] characters; on failure as [`tell_raw`].
pub fn warn(text: &str) {
    tell(&warning_line(text));
}

/// The line [`warn`] writes for `text`.
#[must_use]
pub fn warning_line(text: &str) -> String {
    let line = one_line(text);
    let line = if line.starts_with("warning:") {
        line
    } else {
        format!("warning: {line}")
    };
    cut(&line, WARNING_CHARS)
}

/// `text` on one line: line breaks and tabs become single spaces, and every other control
/// character (and the invisible characters that reorder text) an escape, so that a message
/// quoting a file or a file name cannot clear or recolour the terminal (`ESC[2J` is shown as
/// `\e[2J`).
#[must_use]
pub fn one_line(text: &str) -> String {
    let text = if text.contains(['\n', '\r', '\t']) {
        text.split(['\n', '\r', '\t'])
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join(" ")
    } else {
        text.to_owned()
    };
    visible(&text, &[])
}

/// Whether `c` must not reach a terminal as it is: a control character, or a format
/// character that changes the direction or visibility of the text around it.
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}'
        )
}

/// `text` with the characters [`hidden`] refuses, other than those in `keep`, escaped:
/// `\e`, `\0`, `\r`, else `\u{XX}`.
fn visible(text: &str, keep: &[char]) -> String {
    if !text.chars().any(|c| hidden(c) && !keep.contains(&c)) {
        return text.to_owned();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            c if !hidden(c) || keep.contains(&c) => out.push(c),
            '\u{1b}' => out.push_str("\\e"),
            '\0' => out.push_str("\\0"),
            '\r' => out.push_str("\\r"),
            c => out.push_str(&format!("\\u{{{:x}}}", u32::from(c))),
        }
    }
    out
}

/// `text` cut to at most `chars` characters, the last one `…` when anything was cut.
#[must_use]
pub fn cut(text: &str, chars: usize) -> String {
    match text.char_indices().nth(chars.saturating_sub(1)) {
        Some((at, _)) if text[at..].chars().nth(1).is_some() => format!("{}…", &text[..at]),
        _ => text.to_owned(),
    }
}

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

    #[test]
    fn long_warnings_are_cut_to_one_line_of_200_characters() {
        let long = format!("a mesh named {}\nand more", "x".repeat(500));
        let line = warning_line(&long);
        assert_eq!(line.chars().count(), WARNING_CHARS);
        assert!(line.starts_with("warning: a mesh named xxx"), "{line}");
        assert!(line.ends_with('…') && !line.contains('\n'));
        assert_eq!(warning_line("warning: short"), "warning: short");
        assert_eq!(warning_line("short"), "warning: short");
    }

    #[test]
    fn terminal_controls_in_lines_are_shown_not_obeyed() {
        assert_eq!(
            one_line("bad \u{1b}[2J\u{1b}[31mname\0\u{202e}"),
            "bad \\e[2J\\e[31mname\\0\\u{202e}"
        );
        assert_eq!(warning_line("x\u{7}"), "warning: x\\u{7}");
        assert_eq!(visible("a\nb\u{1b}", &['\n']), "a\nb\\e");
    }

    #[test]
    fn cutting_respects_character_boundaries() {
        assert_eq!(cut("ééééé", 3), "éé…");
        assert_eq!(cut("ééé", 3), "ééé");
        assert_eq!(cut("", 3), "");
    }

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
