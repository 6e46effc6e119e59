//! SQPack macro files through `axterm run-macro`, against the simulator in
//! the process (`--sim sixpack2`): the file is checked whole first (nine
//! hex values a line, located errors, nothing sent), frames the family
//! wants confirmed need `--yes`, each frame is printed with its answer,
//! and a playback that fails ends with the emergency stop.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

/// §5.5.3.2's datasets as printed, then a `$28` waiting for motor 0 and a
/// `$20` reading it.
const HOMING: &str = "SendToPack($00, $15, $00, $10, $27, $00, $00, $10, $04).\n\
    SendToPack($00, $22, $00, $00, $00, $00, $00, $00, $00).\n\
    SendToPack($00, $28, $00, $01, $00, $00, $00, $00, $00)\n\
    SendToPack($00, $20, $00, $00, $00, $00, $00, $00, $00)\n";

fn macro_file(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("write the macro");
    path.to_string_lossy().into_owned()
}

#[test]
fn a_macro_is_played_frame_by_frame_with_the_answers_shown() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = macro_file(&dir, "homing.sqm", HOMING);
    let out = axterm(&["run-macro", "--sim", "sixpack2", "--yes", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        format!(
            "{file}:1: SetMotorParameters 0 10000 NullLeft,MechRef → sent\n\
             {file}:2: StartReferenceSearch 0 → sent\n\
             {file}:3: GetAllActivities 0 0 → m0=inactive m1=inactive m2=inactive m3=inactive \
             m4=inactive m5=inactive\n\
             {file}:4: GetPositionAndActivity 0 → posact=0 action=inactive stop=0\n"
        )
    );
    assert!(
        stderr(&out).contains("4 frame(s) sent, 2 answered"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn frames_to_confirm_need_yes_and_a_bad_file_sends_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = macro_file(&dir, "homing.sqm", HOMING);
    let out = axterm(&["run-macro", "--sim", "sixpack2", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(
        err.contains(&format!(
            "{file}:2: `StartReferenceSearch 0`: it stops the motor"
        )) && err.contains("not sent without --yes"),
        "{err}"
    );
    assert!(err.ends_with("nothing was sent\n"), "{err}");

    let bad = macro_file(
        &dir,
        "bad.sqm",
        "SendToPack($00, $23, $00, $10, $27, $00, $00, $00, $00)\n\
         SendToPack($00, $23, $07)\n\
         SendToPack($00, $23, $09, $10, $27, $00, $00, $00, $00)\n",
    );
    let out = axterm(&["run-macro", "--sim", "sixpack2", "--yes", &bad]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "", "not even the good first line");
    assert_eq!(
        stderr(&out),
        format!(
            "{bad}:2:25: a frame has 9 values (adr, cmd, p0..p6), this one 3\n\
             {bad}:3:22: StartRamp: motno 9 is outside 0..5 (Motor 1..6)\n\
             axterm run-macro: {bad}: nothing was sent\n"
        )
    );
    let out = axterm(&["run-macro", "--dry-run", "--yes", &file]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("checks, a playback of 4 frames would start from the host"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_playback_that_fails_ends_with_the_emergency_stop() {
    let dir = tempfile::tempdir().expect("temp dir");
    // A long ramp, then a query whose answer the link reads wrongly: the
    // simulator answers 8 bytes, the link takes 9-byte replies only.
    let file = macro_file(
        &dir,
        "fails.sqm",
        "SendToPack($00, $23, $00, $A0, $86, $01, $00, $00, $00)\n\
         SendToPack($00, $20, $00, $00, $00, $00, $00, $00, $00)\n",
    );
    let out = axterm(&[
        "run-macro",
        "--sim",
        "sixpack2",
        "--link-option",
        "framing=addr9",
        "--timeout",
        "200",
        &file,
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(err.contains("stopped at line 2 after 1 frame(s)"), "{err}");
    assert!(err.contains("  ConstantRotation 0 0 → sent"), "{err}");
    assert!(err.contains("  AbortReferenceSearch 5 → sent"), "{err}");
    assert!(
        err.contains("stop sent: every stop line went out, 18 of them never acknowledged"),
        "{err}"
    );
}

#[test]
fn the_macro_command_wants_a_sixpack2_connection() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = macro_file(&dir, "homing.sqm", HOMING);
    let out = axterm(&["run-macro", "--sim", "tmcm1110", "--yes", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out)
            .contains("SQPack macro is the SIXpack 2's language; this connection speaks tmcl"),
        "{}",
        stderr(&out)
    );
    let out = axterm(&["run-ascript", "--sim", "sixpack2", &file]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out)
            .contains("A-Script is the CMD-4CR's language; this connection speaks sixpack2"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn in_process_a_ramp_is_read_back_until_inactive_at_its_target() {
    // `exec`: the ramp is sent (never answered), the $20 reads it ramping.
    let out = axterm(&[
        "exec",
        "--sim",
        "sixpack2",
        "StartRamp 0 10000",
        "GetPositionAndActivity 0",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "sent");
    assert!(lines[1].contains("action=ramp"), "{text}");
    // `run`: read until the motor is inactive at its target.
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("ramp.txt");
    std::fs::write(
        &file,
        "StartRamp 0 10000\n\
         :expect GetPositionAndActivity 0 == action=ramp\n\
         :wait-until GetPositionAndActivity 0 == action=inactive timeout 30s\n\
         :expect GetPositionAndActivity 0 == posact=10000 action=inactive stop=0\n",
    )
    .expect("write");
    let out = axterm(&["run", "--sim", "sixpack2", &file.to_string_lossy()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
}
