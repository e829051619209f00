//! The command line as a whole (`Cli`): every flag explained, every
//! number refused in words.

use clap::{CommandFactory, Parser};

use super::Cli;

/// Every flag of every command, with its command's name.
fn flags() -> Vec<(String, clap::Arg)> {
    let cli = Cli::command();
    let mut all = Vec::new();
    for command in cli.get_subcommands() {
        for arg in command.get_arguments() {
            let id = arg.get_id().as_str();
            if id != "help" && id != "version" {
                all.push((command.get_name().to_string(), arg.clone()));
            }
        }
    }
    all
}

#[test]
fn every_flag_of_every_command_has_a_description() {
    let missing: Vec<String> = flags()
        .into_iter()
        .filter(|(_, arg)| arg.get_help().is_none() && arg.get_long_help().is_none())
        .map(|(command, arg)| format!("meadow {command} --{}", arg.get_id()))
        .collect();
    assert!(
        missing.is_empty(),
        "flags without a description: {missing:#?}"
    );
}

/// Every flag that takes a number (those that refuse "abc" and list no
/// possible values): a negative, a fraction, text and a value past any
/// integer type are refused naming the flag, with what to use in words.
#[test]
fn every_numeric_flag_refuses_in_words() {
    let jargon = [
        "4294967295",
        "i128",
        "invalid digit",
        "unexpected argument",
        "too large to fit",
        "float literal",
        "not in ",
    ];
    let mut numeric = 0;
    for (command, arg) in flags() {
        let Some(long) = arg.get_long() else { continue };
        if !arg.get_action().takes_values() || !arg.get_possible_values().is_empty() {
            continue;
        }
        let flag = format!("--{long}");
        let parse = |value: &str| {
            Cli::try_parse_from(["meadow", command.as_str(), flag.as_str(), value])
                .err()
                .map(|e| e.render().to_string())
        };
        if parse("abc").is_none() {
            continue; // text (a scene, a path, a count like 200k)
        }
        numeric += 1;
        for value in ["-1", "1.5e99", "abc", "99999999999999999999999", "NaN"] {
            let Some(error) = parse(value) else { continue };
            let first = error.lines().next().unwrap_or_default();
            assert!(
                first.contains(&flag) && first.contains("use a "),
                "meadow {command} {flag} {value}: {error}"
            );
            for word in jargon {
                assert!(
                    !error.contains(word),
                    "meadow {command} {flag} {value}: {error}"
                );
            }
        }
    }
    eprintln!("{numeric} numeric flags");
    assert!(numeric >= 20, "only {numeric} numeric flags found");
}
