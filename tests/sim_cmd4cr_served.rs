//! `axterm sim cmd4cr --pty` as a served process: its ID and flash kept
//! between runs, `--program FILE` loaded and started over the wire, a
//! program that does not compile refused before serving. (The §4.3 worked
//! sequences run from `examples/cmd4cr/` in `tests/cmd4cr_examples.rs`.)
//!
//! The simulator runs on the wall clock here, so run files wait for
//! states with `:wait-until` (polling the controller), never for time.

mod served_support;

use std::process::{Command, Output};

use served_support::Served;

fn run_file(pty: &str, name: &str, text: &str, extra: &[&str]) -> Output {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write the run file");
    Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["run", "--port", pty, "--protocol", "cmd4cr"])
        .args(extra)
        .arg(&path)
        .output()
        .expect("run axterm run")
}

#[test]
fn the_served_simulator_keeps_its_id_and_flash() {
    let dir = tempfile::tempdir().expect("temp dir");
    let flash = dir.path().join("flash.json");
    let flash = flash.to_string_lossy().into_owned();
    {
        let served = Served::start("cmd4cr", &["--address", "7", "--eeprom", &flash]);
        let out = run_file(
            &served.pty,
            "store.txt",
            "POLX=5\nSTORE\n:expect POLX == 5\n",
            &["--address", "7"],
        );
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let served = Served::start("cmd4cr", &["--address", "7", "--eeprom", &flash]);
    let out = run_file(
        &served.pty,
        "read.txt",
        ":expect POLX == 5\n",
        &["--address", "7"],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_program_given_with_program_runs_when_started_over_the_wire() {
    // §5.4.1, loaded by the simulator-side option and started with SACTRL.
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("example1.txt");
    std::fs::write(
        &program,
        "PRG 0\n    HSPD=20000\n    LSPD=1000\n    ACC=300\n    EO=1\n    X1000\n    WAITX\n    X0\n    WAITX\nEND\n",
    )
    .expect("write the program");
    let served = Served::start("cmd4cr", &["--program", &program.to_string_lossy()]);
    let out = run_file(
        &served.pty,
        "start.txt",
        ":expect SASTAT0 == 0\nSYNCX=1\nSYNPX=1000\nSYNOX\nSACTRL0=1\n\
         :wait-until SASTAT0 == 0 timeout 30s\n:expect SYNSX == 2\n:expect PX == 0\n:expect HSPD == 20000\n",
        &[],
    );
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_program_that_does_not_compile_is_refused_before_serving() {
    let dir = tempfile::tempdir().expect("temp dir");
    let program = dir.path().join("bad.txt");
    std::fs::write(&program, "PRG 0\n    V200=1\nEND\n").expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "cmd4cr", "--pty", "--program"])
        .arg(&program)
        .output()
        .expect("run axterm sim");
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty(), "nothing served");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.txt") && err.contains("Var Range Error"),
        "{err}"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["sim", "tmcm1110", "--pty", "--program"])
        .arg(&program)
        .output()
        .expect("run axterm sim");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("runs no A-Script"));
}
