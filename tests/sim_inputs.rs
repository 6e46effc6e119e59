//! Simulator inputs driven from outside, on the real binary: `--input
//! SETTING` on the in-process `--sim` and on `axterm sim`, and a line on
//! the standard input of a served `axterm sim` applied while it serves
//! (synchronised on its answer on standard error, never on time).

mod cli_support;

mod served_support;

use std::process::Command;

use cli_support::axterm;
use served_support::Served;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn di4_on_reads_8_as_in_the_manuals_example() {
    // CMD-4CR manual §3.2.2: `@01DI` answers `8`, DI4 on.
    let out = axterm(&["exec", "--sim", "cmd4cr", "--input", "DI4=1", "DI"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert_eq!(text(&out.stdout), "8\n");
}

#[test]
fn several_inputs_are_set_in_order_on_the_tmcm1110_too() {
    let out = axterm(&[
        "exec", "--sim", "tmcm1110", "--input", "IN3=0", "--input", "AIN0=302", "GIO 3, 0",
        "GIO 0, 1", "GIO 2, 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    // IN2 is left open: its pull-up reads 1.
    assert_eq!(text(&out.stdout), "0\n302\n1\n");
}

#[test]
fn a_bad_setting_is_a_usage_error_naming_it() {
    let out = axterm(&["exec", "--sim", "cmd4cr", "--input", "IO5=2", "IO5"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(text(&out.stdout), "");
    assert_eq!(
        text(&out.stderr),
        "axterm exec: --input IO5=2: IO5 takes 1 (on) or 0 (off), not `2`\n"
    );

    let out = axterm(&[
        "exec",
        "--port",
        "/nonexistent/tty",
        "--protocol",
        "cmd4cr",
        "--input",
        "IO5=1",
        "IO5",
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "refused before opening the port"
    );
    assert!(
        text(&out.stderr).contains("--input IO5=1 drives an input of a simulator"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn axterm_sim_refuses_a_bad_setting_before_serving() {
    let out = axterm(&["sim", "cmd4cr", "--pty", "--input", "IO19=1"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(text(&out.stdout), "", "no pty was announced");
    let err = text(&out.stderr);
    assert!(
        err.contains(
            "--input IO19=1: IO19 cannot be driven: IOCFG 0xFFFF0000 makes IO19 an output"
        ),
        "{err}"
    );
    assert!(err.ends_with("axterm sim: nothing is served\n"), "{err}");
}

fn exec_on(pty: &str, lines: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_axterm"))
        .args(["exec", "--port", pty, "--protocol", "cmd4cr"])
        .args(lines)
        .output()
        .expect("run axterm exec");
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    text(&out.stdout)
}

#[test]
fn a_served_simulator_takes_settings_from_its_standard_input_while_serving() {
    let mut served = Served::start_driven("cmd4cr", &["--input", "AI1=1000"]);
    assert_eq!(exec_on(&served.pty, &["IO5", "AI1"]), "0\n1000\n");
    assert_eq!(served.next_answer(), "AI1 1000 mV", "the --input answer");
    assert_eq!(served.drive("IO5=1"), "IO5 on");
    assert_eq!(exec_on(&served.pty, &["IO5"]), "1\n");
    assert_eq!(
        served.drive("IO5=maybe"),
        "IO5 takes 1 (on) or 0 (off), not `maybe`"
    );
    assert_eq!(
        served.drive("EMG=1"),
        "EMG on (/CEMG low: every axis stops, none may start)"
    );
    // The end of its standard input does not end the server.
    served.end_input();
    assert_eq!(exec_on(&served.pty, &["IO5", "IO"]), "1\n16\n");
}
