//! `axterm completions SHELL`: the shell's completion script for axterm,
//! printed on standard output, generated from the same clap definitions
//! as `--help` (so it cannot list a subcommand or option that is not
//! there). Where to put it for each shell: docs/install.md.

use std::io::Write;

use clap::{Args, CommandFactory, ValueEnum};

use super::{Cli, EXIT_DEVICE, EXIT_OK};

/// The shells a completion script can be made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Shell {
    Bash,
    Zsh,
    Fish,
    Elvish,
    #[value(name = "powershell")]
    PowerShell,
}

impl Shell {
    fn generator(self) -> clap_complete::Shell {
        match self {
            Shell::Bash => clap_complete::Shell::Bash,
            Shell::Zsh => clap_complete::Shell::Zsh,
            Shell::Fish => clap_complete::Shell::Fish,
            Shell::Elvish => clap_complete::Shell::Elvish,
            Shell::PowerShell => clap_complete::Shell::PowerShell,
        }
    }
}

#[derive(Debug, Clone, Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// The completion script for `shell`, naming the program `axterm`.
pub fn script(shell: Shell) -> Vec<u8> {
    let mut command = Cli::command();
    let mut bytes = Vec::new();
    clap_complete::generate(shell.generator(), &mut command, "axterm", &mut bytes);
    bytes
}

/// `axterm completions SHELL`.
pub fn run(args: &CompletionsArgs) -> i32 {
    let mut out = std::io::stdout().lock();
    match out
        .write_all(&script(args.shell))
        .and_then(|()| out.flush())
    {
        Ok(()) => EXIT_OK,
        Err(e) => {
            eprintln!("axterm completions: cannot write the script: {e}");
            EXIT_DEVICE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shell_gets_a_script_naming_every_subcommand() {
        let names: Vec<String> = Cli::command()
            .get_subcommands()
            .map(|sub| sub.get_name().to_string())
            .collect();
        assert!(names.contains(&"run-ascript".to_string()), "{names:?}");
        for shell in Shell::value_variants() {
            let text = String::from_utf8(script(*shell)).expect("utf-8");
            for name in &names {
                assert!(text.contains(name.as_str()), "{shell:?}: no {name}");
            }
        }
    }
}
