//! Every command the README and `docs/` show runs here, against the
//! built-in simulators, so the documentation cannot drift from the program.
//!
//! The rules, also written in `docs/README.md` for whoever edits a page:
//!
//! - A fenced block whose info string is `sh` is run, line by line, in a
//!   fresh folder per page (blocks of one page share it, in order), with
//!   the `axterm` just built first on the PATH. Lines that are not `axterm`
//!   (`cat > file <<'EOF'` … `EOF`, `printf`, `mkdir`) are run too, by
//!   `sh`, and must succeed: they set up what the next commands read.
//! - In a block with `$ ` prompts only the prompted lines are commands; the
//!   lines under one are its expected output, each of which must be a line
//!   of what it printed (standard output and standard error together; a
//!   line with `…` in it stands for something elided and is not compared).
//! - An `axterm` command must exit 0, unless its line ends with a comment
//!   `# exit N` (`# exit 2: nothing sent`): then it must exit N.
//! - A block that cannot run here (the console needs a terminal, a real
//!   serial port, a simulator served on a pty whose path differs each
//!   time) says so in its info string with a reason: `sh not-run: REASON`.
//!   A line starting with `axterm` in a fenced block of any other kind is
//!   an error: every command shown is either run or says why not.
//!
//! The page's folder holds links to the repository's `examples/` and
//! `tests/` folders, so a page can name `examples/cmd4cr/…` as written.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A command longer than this is taken as hung: simulators are in-process
/// and every documented command ends in well under a second.
const COMMAND_LIMIT: Duration = Duration::from_secs(30);

/// One fenced block of a page.
#[derive(Debug)]
struct Block {
    /// The line of the page where the block's opening fence is (1-based).
    line: usize,
    info: String,
    body: Vec<String>,
}

/// One thing to run: a command (maybe spanning lines, a here-document or
/// continued lines), what it must print and how it must end.
#[derive(Debug, PartialEq)]
struct Step {
    /// The page line of its first line.
    line: usize,
    script: String,
    /// An `axterm` command (its exit code is what the page says), or a
    /// setup line (must succeed).
    is_axterm: bool,
    expected_exit: i32,
    expected_output: Vec<String>,
}

fn fenced_blocks(page: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    // (first line, info string, fence, indent of the fence, body)
    let mut open: Option<(usize, String, String, usize, Vec<String>)> = None;
    for (index, line) in page.lines().enumerate() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        match &mut open {
            None => {
                if let Some(rest) = trimmed.strip_prefix("```") {
                    let fence = "```".to_string()
                        + &rest.chars().take_while(|c| *c == '`').collect::<String>();
                    let info = rest.trim_start_matches('`').trim().to_string();
                    open = Some((index + 1, info, fence, indent, Vec::new()));
                }
            }
            Some((start, info, fence, fence_indent, body)) => {
                if trimmed.starts_with(fence.as_str()) && trimmed.trim_end() == fence.as_str() {
                    blocks.push(Block {
                        line: *start,
                        info: std::mem::take(info),
                        body: std::mem::take(body),
                    });
                    open = None;
                } else {
                    // A block inside a list item is indented with it.
                    body.push(line[indent.min(*fence_indent)..].to_string());
                }
            }
        }
    }
    blocks
}

/// The exit code a command line's trailing comment asks for (`# exit 2`).
fn expected_exit(line: &str) -> Option<i32> {
    let comment = line.rsplit_once("# exit ")?.1;
    let digits: String = comment.chars().take_while(|c| c.is_ascii_digit()).collect();
    digits.parse().ok()
}

/// The terminator of a here-document the line opens (`<<'EOF'`, `<<EOF`).
fn heredoc_end(line: &str) -> Option<String> {
    let after = line
        .split_once("<<")?
        .1
        .trim_start_matches('-')
        .trim_start();
    let word: String = after
        .trim_start_matches(['\'', '"'])
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
        .collect();
    (!word.is_empty()).then_some(word)
}

fn steps(block: &Block) -> Vec<Step> {
    let prompted = block.body.iter().any(|l| l.starts_with("$ "));
    let mut steps: Vec<Step> = Vec::new();
    let mut lines = block.body.iter().enumerate().peekable();
    while let Some((offset, line)) = lines.next() {
        let command = if prompted {
            match line.strip_prefix("$ ") {
                Some(command) => command,
                None => {
                    if let Some(step) = steps.last_mut()
                        && !line.contains('…')
                        && !line.trim().is_empty()
                    {
                        step.expected_output.push(line.trim_end().to_string());
                    }
                    continue;
                }
            }
        } else {
            line.as_str()
        };
        if command.trim().is_empty() || command.trim_start().starts_with('#') {
            continue;
        }
        let mut script = command.to_string();
        // Continued lines and here-documents belong to the same step.
        while script.ends_with('\\') {
            match lines.next() {
                Some((_, next)) => {
                    script.push('\n');
                    script.push_str(next.strip_prefix("> ").unwrap_or(next));
                }
                None => break,
            }
        }
        if let Some(end) = heredoc_end(&script) {
            for (_, next) in lines.by_ref() {
                script.push('\n');
                script.push_str(next);
                if next.trim() == end {
                    break;
                }
            }
        }
        let first = script.lines().next().unwrap_or_default();
        let is_axterm = first == "axterm" || first.starts_with("axterm ");
        steps.push(Step {
            line: block.line + 1 + offset,
            expected_exit: if is_axterm {
                expected_exit(first).unwrap_or(0)
            } else {
                0
            },
            script,
            is_axterm,
            expected_output: Vec::new(),
        });
    }
    steps
}

/// What a block's info string says: run it, or not and why.
enum Verdict {
    Run,
    NotRun,
    /// Not a shell block: it must show no command.
    Other,
}

fn verdict(info: &str) -> Result<Verdict, String> {
    let mut words = info.splitn(2, char::is_whitespace);
    let language = words.next().unwrap_or_default();
    let rest = words.next().unwrap_or_default().trim();
    if language != "sh" {
        return Ok(Verdict::Other);
    }
    if rest.is_empty() {
        return Ok(Verdict::Run);
    }
    match rest.strip_prefix("not-run:") {
        Some(reason) if !reason.trim().is_empty() => Ok(Verdict::NotRun),
        Some(_) => Err(format!(
            "`{info}`: a block not run must say why (`sh not-run: REASON`)"
        )),
        None => Err(format!(
            "`{info}`: a sh block is `sh` or `sh not-run: REASON`"
        )),
    }
}

fn shows_a_command(block: &Block) -> bool {
    block.body.iter().any(|l| {
        let l = l.trim_start();
        let l = l.strip_prefix("$ ").unwrap_or(l);
        l == "axterm" || l.starts_with("axterm ")
    })
}

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The README and every page of `docs/`, as (name, text).
fn pages() -> Vec<(String, String)> {
    let root = repository();
    let mut names = vec![PathBuf::from("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("a docs folder")
        .map(|entry| entry.expect("docs entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .map(|path| Path::new("docs").join(path.file_name().expect("a name")))
        .collect();
    docs.sort();
    names.extend(docs);
    names
        .into_iter()
        .map(|name| {
            let text = std::fs::read_to_string(root.join(&name)).expect("read page");
            (name.display().to_string(), text)
        })
        .collect()
}

/// A folder for one page: `axterm` on the PATH, the repository's examples
/// and test data beside it, a home of its own (no user's profiles, themes
/// or history leak in).
struct PageFolder {
    _dir: tempfile::TempDir,
    work: PathBuf,
    path: String,
}

impl PageFolder {
    fn new() -> PageFolder {
        let dir = tempfile::tempdir().expect("temp dir");
        let bin = dir.path().join("bin");
        let work = dir.path().join("work");
        let home = dir.path().join("home");
        for folder in [&bin, &work, &home] {
            std::fs::create_dir(folder).expect("folder");
        }
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_axterm"), bin.join("axterm"))
            .expect("link axterm");
        for shared in ["examples", "tests"] {
            std::os::unix::fs::symlink(repository().join(shared), work.join(shared))
                .expect("link a repository folder");
        }
        let path = format!(
            "{}:{}",
            bin.display(),
            std::env::var("PATH").unwrap_or_default()
        );
        PageFolder {
            _dir: dir,
            work,
            path,
        }
    }

    fn home(&self) -> PathBuf {
        self.work.parent().expect("parent").join("home")
    }

    /// Run one step with `sh`; its exit code and what it printed.
    fn run(&self, script: &str) -> Result<(i32, String), String> {
        let home = self.home();
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(script)
            .current_dir(&self.work)
            .env_clear()
            .env("PATH", &self.path)
            .env("HOME", &home)
            .env("XDG_CONFIG_HOME", home.join(".config"))
            .env("XDG_DATA_HOME", home.join(".local/share"))
            .env("LANG", "C.UTF-8")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start sh: {e}"))?;
        let started = Instant::now();
        loop {
            match child.try_wait().map_err(|e| e.to_string())? {
                Some(_) => break,
                None if started.elapsed() > COMMAND_LIMIT => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(format!("still running after {COMMAND_LIMIT:?}"));
                }
                None => std::thread::sleep(Duration::from_millis(5)),
            }
        }
        let output = child.wait_with_output().map_err(|e| e.to_string())?;
        let mut printed = String::from_utf8_lossy(&output.stdout).into_owned();
        printed.push_str(&String::from_utf8_lossy(&output.stderr));
        Ok((output.status.code().unwrap_or(-1), printed))
    }
}

/// Run every runnable block of one page; the failures, each naming its
/// page line.
fn run_page(name: &str, text: &str) -> (usize, Vec<String>) {
    let folder = PageFolder::new();
    let mut failures = Vec::new();
    let mut commands = 0;
    for block in fenced_blocks(text) {
        let verdict = match verdict(&block.info) {
            Ok(verdict) => verdict,
            Err(message) => {
                failures.push(format!("{name}:{}: {message}", block.line));
                continue;
            }
        };
        match verdict {
            Verdict::NotRun => continue,
            Verdict::Other => {
                if shows_a_command(&block) {
                    failures.push(format!(
                        "{name}:{}: a `{}` block shows an axterm command: make it `sh` (run) or `sh not-run: REASON`",
                        block.line, block.info
                    ));
                }
                continue;
            }
            Verdict::Run => {}
        }
        for step in steps(&block) {
            if step.is_axterm {
                commands += 1;
            }
            let place = format!("{name}:{}", step.line);
            match folder.run(&step.script) {
                Err(message) => failures.push(format!("{place}: `{}`: {message}", step.script)),
                Ok((code, printed)) => {
                    if code != step.expected_exit {
                        failures.push(format!(
                            "{place}: `{}` exited {code}, the page says {}; it printed:\n{printed}",
                            step.script, step.expected_exit
                        ));
                        continue;
                    }
                    let printed_lines: Vec<&str> = printed.lines().map(str::trim_end).collect();
                    for expected in &step.expected_output {
                        if !printed_lines.contains(&expected.as_str()) {
                            failures.push(format!(
                                "{place}: `{}` did not print the line `{expected}`; it printed:\n{printed}",
                                step.script
                            ));
                        }
                    }
                }
            }
        }
    }
    (commands, failures)
}

#[test]
fn every_documented_command_runs_as_the_page_says() {
    let pages = pages();
    assert!(pages.len() > 1, "docs/ holds no page");
    let results: Vec<(String, usize, Vec<String>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = pages
            .iter()
            .map(|(name, text)| {
                scope.spawn(move || {
                    let started = Instant::now();
                    let (commands, failures) = run_page(name, text);
                    eprintln!(
                        "{name}: {commands} axterm command(s) in {:.1} s",
                        started.elapsed().as_secs_f64()
                    );
                    (name.clone(), commands, failures)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("page thread"))
            .collect()
    });
    let failures: Vec<String> = results.iter().flat_map(|r| r.2.clone()).collect();
    assert!(
        failures.is_empty(),
        "{} documented command(s) failed:\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
    let readme = results
        .iter()
        .find(|r| r.0 == "README.md")
        .expect("the README");
    assert!(
        readme.1 >= 4,
        "the README's tour runs {} axterm command(s): one family at least each",
        readme.1
    );
}

#[test]
fn no_page_shows_rustdoc_link_markup() {
    // "[`Name`]" with no "(target)" after it is rustdoc's, not Markdown's.
    for (name, text) in pages() {
        for (index, line) in text.lines().enumerate() {
            let mut rest = line;
            while let Some(start) = rest.find("[`") {
                let after = &rest[start + 2..];
                let Some(end) = after.find("`]") else { break };
                let follows = &after[end + 2..];
                assert!(
                    follows.starts_with('('),
                    "{name}:{}: rustdoc link markup `{}`",
                    index + 1,
                    &rest[start..start + 2 + end + 2]
                );
                rest = follows;
            }
        }
    }
}

#[test]
fn every_page_says_what_it_is_for_under_its_title() {
    for (name, text) in pages() {
        let mut lines = text.lines();
        let title = lines.next().unwrap_or_default();
        assert!(
            title.starts_with("# "),
            "{name}: the first line is its title"
        );
        let purpose = lines.find(|l| !l.trim().is_empty()).unwrap_or_default();
        assert!(
            !purpose.starts_with('#') && !purpose.starts_with("```") && !purpose.starts_with('|'),
            "{name}: the title is followed by what the page is for, not `{purpose}`"
        );
    }
}

#[cfg(test)]
mod rules {
    use super::*;

    fn block(info: &str, body: &str) -> Block {
        Block {
            line: 10,
            info: info.to_string(),
            body: body.lines().map(str::to_string).collect(),
        }
    }

    #[test]
    fn a_block_not_run_must_say_why() {
        assert!(matches!(verdict("sh"), Ok(Verdict::Run)));
        assert!(matches!(
            verdict("sh not-run: needs a real serial port"),
            Ok(Verdict::NotRun)
        ));
        assert!(verdict("sh not-run:").is_err());
        assert!(verdict("sh norun").is_err());
        assert!(matches!(verdict("toml"), Ok(Verdict::Other)));
    }

    #[test]
    fn prompted_lines_are_commands_and_the_rest_their_output() {
        let steps = steps(&block(
            "sh",
            "$ axterm encode tmcl 'ROR 0, 500'\n01 01 00\n$ axterm exec --sim cmd4cr X  # exit 1\nsomething … elided\n",
        ));
        assert_eq!(steps.len(), 2);
        assert_eq!(steps[0].line, 11);
        assert_eq!(steps[0].expected_output, vec!["01 01 00".to_string()]);
        assert_eq!(steps[0].expected_exit, 0);
        assert_eq!(steps[1].expected_exit, 1);
        assert!(steps[1].expected_output.is_empty());
    }

    #[test]
    fn a_here_document_is_one_step_with_its_command() {
        let steps = steps(&block(
            "sh",
            "cat > run.txt <<'EOF'\nSAP 4, 0, 1000\n# a comment in the file\nEOF\naxterm run --sim tmcm1110 run.txt\n",
        ));
        assert_eq!(steps.len(), 2);
        assert!(!steps[0].is_axterm);
        assert!(steps[0].script.ends_with("EOF"));
        assert!(steps[0].script.contains("# a comment in the file"));
        assert!(steps[1].is_axterm);
    }

    #[test]
    fn a_command_shown_outside_a_sh_block_is_found() {
        assert!(shows_a_command(&block("", "axterm --sim tmcm1110")));
        assert!(shows_a_command(&block("text", "$ axterm ports")));
        assert!(!shows_a_command(&block(
            "toml",
            "[bench]\nsim = \"tmcm1110\""
        )));
    }

    #[test]
    fn blocks_in_list_items_are_found_unindented() {
        let blocks = fenced_blocks("- item\n\n  ```sh\n  axterm ports\n  ```\n");
        assert_eq!(blocks.len(), 1);
        assert_eq!(blocks[0].body, vec!["axterm ports".to_string()]);
        assert_eq!(blocks[0].line, 3);
    }
}
