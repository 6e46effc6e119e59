//! Files of the user's: a file axterm writes on request (`params export`,
//! `upload -o`, `asm -o`) never replaces an existing one without
//! `--force`, and a folder that is not there is bad input (exit 2) found
//! before the module is asked anything, on every family.

mod cli_support;

use std::path::Path;
use std::process::Output;

use axterm::families::FAMILIES;
use cli_support::{axterm, stderr, stdout};

fn text(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

fn assert_refused(out: &Output, what: &str, expected: &str) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{what}: {err}");
    assert!(
        err.contains(expected),
        "{what}: `{expected}` not in:\n{err}"
    );
}

const EXISTS: &str = "it exists: give --force to replace it (nothing was overwritten)";

#[test]
fn params_export_refuses_a_missing_folder_and_an_existing_file_in_every_family() {
    let dir = tempfile::tempdir().expect("temp dir");
    for family in FAMILIES {
        let Some(kind) = family.simulators.first().map(|k| k.name) else {
            continue;
        };
        let missing = dir
            .path()
            .join("no-such-folder")
            .join(format!("{kind}.toml"));
        for force in [&[][..], &["--force"][..]] {
            let mut args = vec!["params", "export", "--sim", kind];
            args.extend(force);
            let missing = text(&missing);
            args.push(&missing);
            let out = axterm(&args);
            assert_refused(&out, kind, "there is no folder");
            assert!(
                stderr(&out).contains("nothing was sent"),
                "{}",
                stderr(&out)
            );
        }

        let existing = dir.path().join(format!("{kind}.toml"));
        std::fs::write(&existing, "# the technician's own file\n").expect("write");
        let out = axterm(&["params", "export", "--sim", kind, &text(&existing)]);
        assert_refused(&out, kind, EXISTS);
        assert_eq!(
            std::fs::read_to_string(&existing).expect("read"),
            "# the technician's own file\n",
            "{kind}: the file was left as it was"
        );
        let out = axterm(&[
            "params",
            "export",
            "--force",
            "--sim",
            kind,
            &text(&existing),
        ]);
        // SIXpack 2 settings cannot be read back: exported commented out.
        assert!(out.status.code() != Some(2), "{kind}: {}", stderr(&out));
        let replaced = std::fs::read_to_string(&existing).expect("read");
        assert!(replaced.contains("family = "), "{kind}: {replaced}");
    }
}

#[test]
fn upload_and_asm_refuse_an_existing_output_without_force() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut tried = 0;
    for family in FAMILIES {
        let Some(kind) = family.simulators.first().map(|k| k.name) else {
            continue;
        };
        let Some(tool) = family.console.program() else {
            continue;
        };
        // Only a tool with an upload plan reads a module's program.
        if tool
            .upload(family.console.default_address(), Default::default())
            .is_err()
        {
            continue;
        }
        tried += 1;
        let existing = dir.path().join(format!("{kind}.up"));
        std::fs::write(&existing, "kept\n").expect("write");
        let out = axterm(&["upload", "--sim", kind, "-o", &text(&existing)]);
        assert_refused(&out, kind, EXISTS);
        assert!(
            stderr(&out).contains("nothing was sent"),
            "{}",
            stderr(&out)
        );
        assert_eq!(std::fs::read_to_string(&existing).expect("read"), "kept\n");
        let out = axterm(&["upload", "--sim", kind, "--force", "-o", &text(&existing)]);
        assert_eq!(out.status.code(), Some(0), "{kind}: {}", stderr(&out));
        assert_ne!(std::fs::read_to_string(&existing).expect("read"), "kept\n");
        let missing = dir.path().join("gone").join("x.up");
        let out = axterm(&["upload", "--sim", kind, "-o", &text(&missing)]);
        assert_refused(&out, kind, "there is no folder");
    }
    assert!(tried > 0, "no family uploads");

    let source = dir.path().join("p.tmc");
    std::fs::write(&source, "MVP ABS, 0, 1000\nSTOP\n").expect("write");
    let image = dir.path().join("p.hex");
    std::fs::write(&image, "kept\n").expect("write");
    let out = axterm(&["asm", &text(&source), "-o", &text(&image)]);
    assert_refused(&out, "asm", EXISTS);
    assert_eq!(stdout(&out), "");
    assert_eq!(std::fs::read_to_string(&image).expect("read"), "kept\n");
    let out = axterm(&["asm", &text(&source), "-o", &text(&image), "--force"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_ne!(std::fs::read_to_string(&image).expect("read"), "kept\n");
}
