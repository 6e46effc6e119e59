//! The Debian package (packaging/build-deb, packaging/check-deb). The
//! package itself is built only where cargo-deb is installed (it takes a
//! release build); the check of its contents runs everywhere, on small
//! packages made here with dpkg-deb.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(program).is_file()))
}

/// Every file check-deb asks for, as the package holds it.
const CONTENTS: &[&str] = &[
    "usr/bin/axterm",
    "usr/share/man/man1/axterm.1.gz",
    "usr/share/man/man1/axterm-run.1",
    "usr/share/bash-completion/completions/axterm",
    "usr/share/zsh/vendor-completions/_axterm",
    "usr/share/fish/vendor_completions.d/axterm.fish",
    "usr/share/doc/axterm/examples/cmd4cr/4.3.1-jog.txt",
    "usr/share/doc/axterm/LICENSE",
    "usr/share/doc/axterm/copyright",
];

/// A package holding `files` (each a line of text), built by dpkg-deb.
fn package(dir: &Path, files: &[&str]) -> PathBuf {
    let root = dir.join("root");
    std::fs::create_dir_all(root.join("DEBIAN")).expect("DEBIAN");
    std::fs::write(
        root.join("DEBIAN/control"),
        "Package: axterm\nVersion: 0.1.0-1\nArchitecture: all\n\
         Maintainer: the axterm developers\nDescription: a test package\n",
    )
    .expect("control");
    for file in files {
        let path = root.join(file);
        std::fs::create_dir_all(path.parent().expect("folder")).expect("folder");
        std::fs::write(&path, "x\n").expect("file");
    }
    let deb = dir.join("axterm.deb");
    let out = Command::new("dpkg-deb")
        .args(["--root-owner-group", "--build"])
        .arg(&root)
        .arg(&deb)
        .output()
        .expect("dpkg-deb");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    deb
}

fn check_deb(deb: &Path) -> std::process::Output {
    Command::new(repository().join("packaging/check-deb"))
        .arg(deb)
        .output()
        .expect("run packaging/check-deb")
}

#[test]
fn check_deb_passes_a_whole_package_and_names_what_one_lacks() {
    if !on_path("dpkg-deb") {
        eprintln!("no dpkg-deb here: packaging/check-deb not tried");
        return;
    }
    let whole = tempfile::tempdir().expect("temp dir");
    let out = check_deb(&package(whole.path(), CONTENTS));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let lacking = tempfile::tempdir().expect("temp dir");
    let without_fish: Vec<&str> = CONTENTS
        .iter()
        .copied()
        .filter(|file| !file.ends_with(".fish"))
        .collect();
    let out = check_deb(&package(lacking.path(), &without_fish));
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no ./usr/share/fish/vendor_completions.d/axterm.fish"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn the_package_built_by_build_deb_holds_what_a_line_pc_needs() {
    if !on_path("cargo-deb") {
        eprintln!("cargo-deb is not on the PATH: packaging/build-deb not tried");
        return;
    }
    let out = Command::new(repository().join("packaging/build-deb"))
        .output()
        .expect("run packaging/build-deb");
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let deb = said.lines().last().expect("the .deb's path").trim();
    assert!(deb.ends_with(".deb"), "{said}");
    let out = check_deb(Path::new(deb));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
