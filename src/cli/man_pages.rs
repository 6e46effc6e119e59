//! `axterm man [COMMAND…] [--dir DIR [--force]]`: manual pages in roff,
//! generated from the same clap definitions as `--help`. One page per
//! subcommand at any depth, named as man(1) expects: axterm.1,
//! axterm-run.1, axterm-params-diff.1 … Without `--dir` one page is
//! printed on standard output (the program's, or the subcommand's
//! named), ready for `man -l -`; with `--dir` every page is written
//! there, under the one rule for files axterm writes (an existing page
//! is replaced only with `--force`, the folder must be there), checked
//! for every page before any is written.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, CommandFactory};

use super::{Cli, EXIT_DEVICE, EXIT_OK, EXIT_USAGE};
use crate::files::{self, Existing};

/// The manual section of every page: user commands.
const SECTION: &str = "1";

#[derive(Debug, Clone, Args)]
pub struct ManArgs {
    /// The subcommand whose page to print, e.g. `run` or `params diff`
    /// (default: the program's page, which lists the subcommands).
    #[arg(value_name = "COMMAND", conflicts_with = "dir")]
    pub command: Vec<String>,
    /// Write every page into this folder (it must exist) as NAME.1, each
    /// written path printed on its own line.
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
    /// Replace pages already in the --dir folder (without it an existing
    /// page is refused, exit 2, and nothing is written).
    #[arg(long, requires = "dir")]
    pub force: bool,
}

/// One manual page: the words that name it (`["params", "diff"]`; none
/// for the program's) and its page.
pub struct Page {
    pub words: Vec<String>,
    pub man: clap_mangen::Man,
}

impl Page {
    /// Its file name: axterm.1, axterm-params-diff.1.
    pub fn file_name(&self) -> String {
        self.man.get_filename()
    }

    /// The page in roff, in ASCII: groff reads a page as Latin-1 unless
    /// told otherwise, so the help text's `…` and `−` are written as
    /// groff's Unicode escapes (`\[u2026]`), which man-db and mandoc read
    /// too.
    pub fn render(&self) -> Vec<u8> {
        let mut bytes = Vec::new();
        self.man
            .render(&mut bytes)
            .expect("rendering into memory does not fail");
        ascii_roff(&String::from_utf8_lossy(&bytes)).into_bytes()
    }
}

/// `text` with every character outside ASCII as a groff escape.
fn ascii_roff(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            out.push_str(&format!("\\[u{:04X}]", u32::from(c)));
        }
    }
    out
}

/// Every page: the program's first, then each subcommand's, depth first
/// in the order `--help` lists them. clap's own `help` subcommand has
/// none (`--help` is on every page).
pub fn pages() -> Vec<Page> {
    let mut command = Cli::command().disable_help_subcommand(true);
    // Building names each subcommand after its parents (axterm-params-diff).
    command.build();
    let mut pages = Vec::new();
    collect(&command, Vec::new(), &mut pages);
    pages
}

fn collect(command: &clap::Command, words: Vec<String>, pages: &mut Vec<Page>) {
    let source = format!("axterm {}", env!("CARGO_PKG_VERSION"));
    let title = command
        .get_display_name()
        .unwrap_or_else(|| command.get_name())
        .to_uppercase();
    let man = clap_mangen::Man::new(command.clone())
        .title(title)
        .section(SECTION)
        .source(source)
        .manual("axterm manual");
    pages.push(Page {
        words: words.clone(),
        man,
    });
    for sub in command.get_subcommands().filter(|sub| !sub.is_hide_set()) {
        let mut words = words.clone();
        words.push(sub.get_name().to_string());
        collect(sub, words, pages);
    }
}

/// `axterm man`.
pub fn run(args: &ManArgs) -> i32 {
    let pages = pages();
    match &args.dir {
        Some(dir) => write_pages(&pages, dir, Existing::from_force(args.force)),
        None => print_page(&pages, &args.command),
    }
}

fn print_page(pages: &[Page], words: &[String]) -> i32 {
    let Some(page) = pages.iter().find(|page| page.words == words) else {
        let known: Vec<String> = pages
            .iter()
            .filter(|page| !page.words.is_empty())
            .map(|page| page.words.join(" "))
            .collect();
        eprintln!(
            "axterm man: no subcommand 'axterm {}' (pages: {})",
            words.join(" "),
            known.join(", ")
        );
        return EXIT_USAGE;
    };
    let mut out = std::io::stdout().lock();
    match out.write_all(&page.render()).and_then(|()| out.flush()) {
        Ok(()) => EXIT_OK,
        Err(e) => {
            eprintln!("axterm man: cannot write the page: {e}");
            EXIT_DEVICE
        }
    }
}

/// Every page into `dir`: all checked first, so a refused page leaves
/// the folder as it was.
fn write_pages(pages: &[Page], dir: &Path, existing: Existing) -> i32 {
    if !dir.is_dir() {
        eprintln!(
            "axterm man: --dir {}: there is no such folder (nothing written)",
            dir.display()
        );
        return EXIT_USAGE;
    }
    let paths: Vec<PathBuf> = pages.iter().map(|p| dir.join(p.file_name())).collect();
    for path in &paths {
        if let Err(e) = files::check_destination(path, existing) {
            eprintln!("axterm man: cannot write {}: {e}", path.display());
            return if e.is_usage() {
                EXIT_USAGE
            } else {
                EXIT_DEVICE
            };
        }
    }
    for (page, path) in pages.iter().zip(&paths) {
        if let Err(e) = files::save(path, &page.render(), existing) {
            eprintln!("axterm man: cannot write {}: {e}", path.display());
            return if e.is_usage() {
                EXIT_USAGE
            } else {
                EXIT_DEVICE
            };
        }
        // A closed standard output (`| head`) is no reason to stop writing.
        let _ = writeln!(std::io::stdout(), "{}", path.display());
    }
    EXIT_OK
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn characters_outside_ascii_become_groff_escapes() {
        assert_eq!(ascii_roff("a … b −1 \\fB"), "a \\[u2026] b \\[u2212]1 \\fB");
        assert_eq!(ascii_roff("\u{1F600}"), "\\[u1F600]");
    }

    #[test]
    fn a_page_for_the_program_and_each_subcommand_at_any_depth() {
        let names: Vec<String> = pages().iter().map(Page::file_name).collect();
        for expected in [
            "axterm.1",
            "axterm-run.1",
            "axterm-run-ascript.1",
            "axterm-params.1",
            "axterm-params-diff.1",
            "axterm-completions.1",
            "axterm-man.1",
        ] {
            assert!(names.iter().any(|n| n == expected), "{expected}: {names:?}");
        }
        assert!(!names.iter().any(|n| n.contains("help")), "{names:?}");
        let top = Cli::command();
        assert_eq!(
            pages().iter().filter(|p| p.words.len() == 1).count(),
            top.get_subcommands()
                .filter(|s| s.get_name() != "help")
                .count()
        );
    }

    #[test]
    fn a_subcommand_page_names_itself_and_its_options() {
        let pages = pages();
        let diff = pages
            .iter()
            .find(|p| p.words == ["params", "diff"])
            .expect("params diff");
        let text = String::from_utf8(diff.render()).expect("utf-8");
        assert!(text.contains(".TH AXTERM-PARAMS-DIFF 1"), "{text}");
        assert!(text.contains("axterm\\-params\\-diff"), "{text}");
        assert!(text.contains("addresses"), "{text}");
    }
}
