//! `axterm asm` and `axterm disasm` as a script sees them: stdout, stderr,
//! exit codes and the files they write.

mod cli_support;

use cli_support::{axterm, axterm_stdin, stderr, stdout};

fn example(name: &str) -> String {
    format!("{}/tests/data/programs/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn asm_prints_the_image() {
    let out = axterm(&["asm", &example("s3_6_43_djnz_loop.tmc")]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        "// TMCL program image: 5 words, 7 bytes each (instruction, type, motor/bank, \
         value MSB first)\n\
         09 2A 02 00 00 00 64  // 0\n\
         04 01 00 00 00 C8 00  // 1\n\
         1B 01 00 00 00 00 00  // 2\n\
         1B 00 00 00 00 01 F4  // 3\n\
         31 2A 00 00 00 00 01  // 4\n"
    );
}

#[test]
fn asm_listing_shows_address_bytes_source_and_labels() {
    let out = axterm(&["asm", &example("s3_6_43_djnz_loop.tmc"), "--listing"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        "addr  bytes                 source\n   \
         0  09 2A 02 00 00 00 64  SGP 42, 2, 100\n                            \
         Loop:\n   \
         1  04 01 00 00 00 C8 00  MVP REL, 0, 51200\n   \
         2  1B 01 00 00 00 00 00  WAIT POS, 0, 0\n   \
         3  1B 00 00 00 00 01 F4  WAIT TICKS, 0, 500\n   \
         4  31 2A 00 00 00 00 01  DJNZ 42, Loop\n\
         \nlabels:\n  Loop  1\n"
    );
}

#[test]
fn asm_follows_includes_beside_the_source() {
    let out = axterm(&["asm", &example("s8_3_symbolic_constants.tmc"), "--listing"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("   0  05 04 00 00 00 07 FF  SAP APMaxPositioningSpeed"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn asm_errors_are_all_listed_and_nothing_is_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let source = dir.path().join("bad.tmc");
    let image = dir.path().join("bad.hex");
    std::fs::write(
        &source,
        "Loop: MVP ABS, 0, 1000\nJA Lop\nROL 0, 51200\nFOO\n",
    )
    .unwrap();
    let out = axterm(&[
        "asm",
        source.to_str().unwrap(),
        "-o",
        image.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    assert!(!image.exists());
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().collect();
    let name = source.to_str().unwrap();
    assert_eq!(lines.len(), 4, "{err}");
    assert!(lines[0].starts_with(&format!("{name}:2:4: JA: undefined label `Lop`")));
    assert!(lines[1].starts_with(&format!("{name}:3:8: ROL: velocity 51200 outside")));
    assert!(lines[2].starts_with(&format!("{name}:4:1: `FOO` is not a TMCL command")));
    assert_eq!(
        lines[3],
        format!("axterm asm: 3 errors in {name}; nothing written")
    );
}

#[test]
fn output_file_then_disasm_gives_source_that_assembles_to_the_same_image() {
    let dir = tempfile::tempdir().expect("temp dir");
    let image = dir.path().join("timer.hex");
    let out = axterm(&[
        "asm",
        &example("s3_5_6_4_timer_interrupt.tmc"),
        "-o",
        image.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), "");
    let written = std::fs::read_to_string(&image).unwrap();
    assert!(
        written.contains("\n25 00 00 00 00 00 09  // 0\n"),
        "{written}"
    );

    let out = axterm(&["disasm", image.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let source = stdout(&out);
    assert!(source.contains("    VECT 0, L_0009\n"), "{source}");
    assert!(source.contains("L_0013:\n    SIO 0, 2, 0\n"), "{source}");

    let again = axterm_stdin(&["asm", "-"], &source);
    assert_eq!(again.status.code(), Some(0), "{}", stderr(&again));
    assert_eq!(stdout(&again), written);
}

#[test]
fn disasm_reads_standard_input_and_names_bad_lines() {
    let out = axterm_stdin(&["disasm", "-"], "16 00 00 00 00 00 00\n");
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(
        stdout(&out),
        "// TMCL program, 1 word, disassembled by axterm\nL_0000:\n    JA L_0000\n"
    );
    let out = axterm_stdin(&["disasm", "-"], "16 00 00\nxx\n");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(stdout(&out), "");
    let err = stderr(&out);
    assert!(
        err.starts_with("<stdin>:1: 3 bytes where a program word has 7"),
        "{err}"
    );
    assert!(err.contains("<stdin>:2: `xx` is not a hex byte"), "{err}");
}

#[test]
fn disasm_without_an_image_reads_the_module_or_says_what_to_give() {
    let out = axterm(&["disasm"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("give an image file"),
        "{}",
        stderr(&out)
    );
    // A fresh simulator's program memory is blank.
    let out = axterm(&["disasm", "--sim", "tmcm1110"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "// TMCL program, 0 words, disassembled by axterm\n"
    );
}

#[test]
fn a_missing_source_is_named() {
    let out = axterm(&["asm", "no-such-program.tmc"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "axterm asm: cannot read no-such-program.tmc: no such file\n"
    );
}
