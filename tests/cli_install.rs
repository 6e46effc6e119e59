//! What an install puts beside the binary, made by the binary itself:
//! shell completions (`axterm completions SHELL`) and manual pages
//! (`axterm man`), checked by the tools that will read them: bash itself,
//! and groff with every warning on.

mod cli_support;

use std::path::Path;
use std::process::{Command, Stdio};

use axterm::cli::Cli;
use clap::CommandFactory;
use cli_support::{axterm, stderr, stdout};

/// The subcommands as typed, from the same definitions the binary uses.
fn subcommands() -> Vec<String> {
    Cli::command()
        .get_subcommands()
        .map(|sub| sub.get_name().to_string())
        .filter(|name| name != "help")
        .collect()
}

fn bash(script: &str) -> std::process::Output {
    Command::new("bash")
        .arg("--norc")
        .arg("--noprofile")
        .arg("-c")
        .arg(script)
        .stdin(Stdio::null())
        .output()
        .expect("run bash")
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    path.display().to_string()
}

#[test]
fn the_bash_script_parses_registers_and_completes_subcommands() {
    let out = axterm(&["completions", "bash"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let dir = tempfile::tempdir().expect("temp dir");
    let file = write(dir.path(), "axterm.bash", &out.stdout);

    let syntax = bash(&format!("bash -n '{file}'"));
    assert!(syntax.status.success(), "bash -n: {}", stderr(&syntax));

    let registered = bash(&format!(". '{file}' && complete -p axterm"));
    assert!(registered.status.success(), "{}", stderr(&registered));
    assert!(
        stdout(&registered).contains("axterm"),
        "{}",
        stdout(&registered)
    );

    // What bash offers after `axterm ru<TAB>`: the function the script
    // registered, called as bash calls it.
    let offered = bash(&format!(
        ". '{file}'
         COMP_WORDS=(axterm ru); COMP_CWORD=1; COMP_LINE='axterm ru'; COMP_POINT=9
         $(complete -p axterm | sed -n 's/.*-F \\([^ ]*\\) .*/\\1/p') axterm ru axterm
         printf '%s\\n' \"${{COMPREPLY[@]}}\""
    ));
    assert!(offered.status.success(), "{}", stderr(&offered));
    let mut words: Vec<String> = stdout(&offered).lines().map(str::to_string).collect();
    words.sort();
    assert_eq!(words, ["run", "run-ascript", "run-macro"]);
}

#[test]
fn zsh_and_fish_scripts_name_every_subcommand() {
    let names = subcommands();
    assert!(names.contains(&"completions".to_string()), "{names:?}");
    for (shell, opening) in [("zsh", "#compdef axterm"), ("fish", "complete -c axterm")] {
        let out = axterm(&["completions", shell]);
        assert_eq!(out.status.code(), Some(0), "{shell}: {}", stderr(&out));
        let text = stdout(&out);
        assert!(text.contains(opening), "{shell}: no `{opening}`:\n{text}");
        for name in &names {
            assert!(text.contains(name.as_str()), "{shell}: no {name}");
        }
    }
}

#[test]
fn an_unknown_shell_is_bad_usage_naming_the_shells_there_are() {
    let out = axterm(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = stderr(&out);
    assert!(err.contains("invalid value 'tcsh'"), "{err}");
    assert!(err.contains("bash, zsh, fish"), "{err}");
}

/// groff's complaints about a page, every warning category on, laid out
/// for a terminal as man(1) does.
fn groff_warnings(page: &Path) -> String {
    let out = Command::new("groff")
        .args(["-man", "-Tutf8", "-z", "-ww"])
        .arg(page)
        .output()
        .expect("groff (apt-get install groff) checks the manual pages");
    assert!(
        out.status.success(),
        "groff {}: {}",
        page.display(),
        stderr(&out)
    );
    stderr(&out)
}

#[test]
fn every_page_is_written_and_reads_without_a_groff_warning() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().display().to_string();
    let out = axterm(&["man", "--dir", &folder]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let written: Vec<String> = stdout(&out).lines().map(str::to_string).collect();
    let mut expected = vec!["axterm.1".to_string()];
    expected.extend(subcommands().iter().map(|name| format!("axterm-{name}.1")));
    expected.push("axterm-params-diff.1".to_string());
    for name in &expected {
        let path = dir.path().join(name).display().to_string();
        assert!(written.contains(&path), "{name} not written: {written:?}");
    }
    for path in &written {
        let path = Path::new(path);
        let text = std::fs::read_to_string(path).expect("read page");
        assert!(text.is_ascii(), "{}", path.display());
        assert!(!text.contains("[`"), "rustdoc markup in {}", path.display());
        assert_eq!(groff_warnings(path), "", "{}", path.display());
    }
    let top = std::fs::read_to_string(dir.path().join("axterm.1")).expect("axterm.1");
    for name in subcommands() {
        assert!(
            top.contains(&name.replace('-', "\\-")),
            "axterm.1 lists no {name}"
        );
    }
}

#[test]
fn without_a_folder_the_program_page_or_a_subcommand_page_is_printed() {
    let out = axterm(&["man"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains(".TH AXTERM 1"), "{}", stdout(&out));

    let out = axterm(&["man", "params", "diff"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains(".TH AXTERM-PARAMS-DIFF 1"));

    let out = axterm(&["man", "params", "nosuch"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = stderr(&out);
    assert!(
        err.contains("no subcommand 'axterm params nosuch'"),
        "{err}"
    );
    assert!(err.contains("params diff"), "{err}");
}

#[test]
fn pages_already_there_are_replaced_only_with_force() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = dir.path().display().to_string();
    let mine = dir.path().join("axterm-run.1");
    std::fs::write(&mine, "mine\n").expect("write");

    let out = axterm(&["man", "--dir", &folder]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("give --force"), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&mine).expect("read"), "mine\n");
    // Checked before anything is written: no page beside it either.
    assert_eq!(std::fs::read_dir(dir.path()).expect("list").count(), 1);

    let out = axterm(&["man", "--dir", &folder, "--force"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let page = std::fs::read_to_string(&mine).expect("read");
    assert!(page.contains(".TH AXTERM-RUN 1"), "{page}");

    let missing = dir.path().join("nosuch").display().to_string();
    let out = axterm(&["man", "--dir", &missing]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no such folder"), "{}", stderr(&out));
}
