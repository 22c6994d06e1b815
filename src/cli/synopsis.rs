//! `traxer synopsis` (hidden): every subcommand with all its arguments, one block,
//! generated from the clap definitions — the "Command line" section of
//! docs/scene-format.md is this output (a test checks that they agree).

use clap::builder::ArgAction;
use clap::Arg;

/// Longest line before an argument goes on the next one.
const WIDTH: usize = 88;

/// One argument as the synopsis writes it: `SCENE`, `--photons N`, `-D NAME=VALUE...`.
fn word(arg: &Arg) -> Option<String> {
    let id = arg.get_id().as_str();
    if matches!(id, "help" | "version") || arg.is_hide_set() {
        return None;
    }
    let value = || {
        let names = arg
            .get_value_names()
            .map(|v| v.join(" "))
            .unwrap_or_else(|| id.to_uppercase());
        let values: Vec<String> = arg
            .get_possible_values()
            .iter()
            .map(|v| v.get_name().to_string())
            .collect();
        if values.is_empty() {
            names
        } else {
            values.join("|")
        }
    };
    let takes_value = !matches!(
        arg.get_action(),
        ArgAction::SetTrue | ArgAction::SetFalse | ArgAction::Count
    );
    let mut w = match (arg.get_long(), arg.get_short()) {
        (Some(long), _) if takes_value => format!("--{long} {}", value()),
        (Some(long), _) => format!("--{long}"),
        (None, Some(short)) if takes_value => format!("-{short} {}", value()),
        (None, Some(short)) => format!("-{short}"),
        (None, None) => value(),
    };
    if matches!(arg.get_action(), ArgAction::Append) {
        w.push_str("...");
    }
    Some(if arg.is_required_set() {
        w
    } else {
        format!("[{w}]")
    })
}

/// The synopsis of every visible subcommand of `cli`.
pub fn synopsis(cli: &clap::Command) -> String {
    let mut out = String::new();
    for sub in cli.get_subcommands().filter(|s| !s.is_hide_set()) {
        let head = format!("{} {}", cli.get_name(), sub.get_name());
        let indent = " ".repeat(head.len() + 1);
        let mut line = head;
        // Positionals first, then the options in the order of `--help`.
        let mut options: Vec<&Arg> = sub.get_arguments().filter(|a| !a.is_positional()).collect();
        options.sort_by_key(|a| a.get_display_order());
        let args: Vec<&Arg> = sub
            .get_arguments()
            .filter(|a| a.is_positional())
            .chain(options)
            .collect();
        for w in args.into_iter().filter_map(word) {
            if line.chars().count() + 1 + w.chars().count() > WIDTH && line != indent {
                out.push_str(line.trim_end());
                out.push('\n');
                line = indent.clone();
            } else {
                line.push(' ');
            }
            line.push_str(&w);
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

pub fn run(cli: &clap::Command) -> anyhow::Result<()> {
    say!("{}", synopsis(cli).trim_end());
    Ok(())
}
