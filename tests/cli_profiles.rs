//! `axterm @NAME`: named connections from a profile file, on the real
//! binary: expanded wherever connection options go, an unknown name
//! refused with the names there are, `axterm profiles` listing them.

mod cli_support;

use std::process::{Command, Output};

use cli_support::{stderr, stdout};

const PROFILES: &str = r#"
[bench]
sim = "tmcm1110"

[stepper]
sim = "cmd4cr"
address = 1

[two]
links = [{ sim = "tmcm1110" }, { sim = "cmd4cr" }]
"#;

/// Run axterm with the profile file named by AXTERM_PROFILES.
fn axterm_with(file: &std::path::Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(args)
        .env("AXTERM_PROFILES", file)
        .output()
        .expect("run axterm")
}

fn profile_file() -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("profiles.toml");
    std::fs::write(&file, PROFILES).expect("write");
    (dir, file)
}

#[test]
fn a_profile_stands_for_its_connection_with_any_subcommand() {
    let (_dir, file) = profile_file();
    let out = axterm_with(&file, &["exec", "@bench", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "1000\n", "{}", stderr(&out));
    let out = axterm_with(&file, &["exec", "@stepper", "--input", "DI4=1", "DI"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "8\n");
    // --profiles names the file too, before the environment.
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["exec", "--profiles"])
        .arg(&file)
        .args(["@bench", "GAP 4, 0"])
        .env("AXTERM_PROFILES", "/nonexistent/profiles.toml")
        .output()
        .expect("run axterm");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}

#[test]
fn an_unknown_name_is_a_usage_error_listing_the_names() {
    let (_dir, file) = profile_file();
    let out = axterm_with(&file, &["exec", "@line4", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no profile `line4` in ")
            && stderr(&out).contains("(profiles there: bench, stepper, two)"),
        "{}",
        stderr(&out)
    );
    assert_eq!(stdout(&out), "");
}

#[test]
fn profiles_are_listed_with_the_options_they_stand_for() {
    let (_dir, file) = profile_file();
    let out = axterm_with(&file, &["profiles"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        "@bench  --sim tmcm1110\n@stepper  --sim cmd4cr --address 1\n\
         @two  --sim tmcm1110 --sim cmd4cr\n"
    );
}

#[test]
fn a_bad_profile_file_says_what_is_wrong() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("profiles.toml");
    std::fs::write(&file, "[bench]\nsimulator = \"tmcm1110\"\n").expect("write");
    let out = axterm_with(&file, &["exec", "@bench", "GAP 4, 0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("profile `bench`: unknown key `simulator`"),
        "{}",
        stderr(&out)
    );
}
