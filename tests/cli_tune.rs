//! `axterm tune step|stallguard` on the simulators: the MCCL servo's step
//! response from its own recording (figures that answer to the gains, a
//! trip that is said and exits 1), the TMCM-1110's StallGuard2 sweep
//! (readings that fall under load) and the suggestion from two sweeps; bad
//! input exits 2 with nothing sent.

mod cli_support;

use cli_support::{axterm, stderr, stdout};

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_str(stdout(out).trim()).unwrap_or_else(|e| panic!("{e}: {}", stdout(out)))
}

fn step(extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "tune",
        "step",
        "--sim",
        "mccl",
        "--axis",
        "1",
        "--distance",
        "1000",
        "--format",
        "json",
    ];
    args.extend(extra);
    let out = axterm(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    json(&out)
}

#[test]
fn a_step_prints_its_samples_and_figures_and_more_derivative_overshoots_less() {
    let plain = step(&[]);
    assert_eq!(plain["samples"].as_array().map(Vec::len), Some(400));
    assert_eq!(plain["sample_period_s"], 0.00025);
    assert_eq!(plain["samples"][1]["time_s"], 0.00025);
    assert_eq!(plain["gains"]["SG"], 0.04);
    assert_eq!(plain["ok"], true);
    let figures = &plain["figures"];
    assert_eq!(figures["target"], 1000.0);
    assert!(figures["rise_time_s"].as_f64().is_some(), "{figures}");
    let damped = step(&["--set", "SD=0.6"]);
    assert_eq!(damped["gains"]["SD"], 0.6);
    let overshoot = |v: &serde_json::Value| v["figures"]["overshoot_percent"].as_f64().unwrap();
    assert!(
        overshoot(&damped) < overshoot(&plain),
        "SD 0.6: {} %, SD 0.2: {} %",
        overshoot(&damped),
        overshoot(&plain)
    );
}

#[test]
fn an_unstable_step_trips_says_so_and_exits_1() {
    let out = axterm(&[
        "tune",
        "step",
        "--sim",
        "mccl",
        "--axis",
        "1",
        "--distance",
        "20",
        "--set",
        "SG=5,SE=40",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let said = stdout(&out);
    assert!(said.contains("TRIPPED: "), "{said}");
    assert!(said.contains("following error"), "{said}");
    assert!(said.contains("the axis was stopped"), "{said}");
}

#[test]
fn the_csv_has_a_header_and_a_row_per_sample() {
    let out = axterm(&[
        "tune",
        "step",
        "--sim",
        "mccl",
        "--distance",
        "50",
        "--samples",
        "32",
        "--format",
        "csv",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    let lines: Vec<&str> = said.lines().collect();
    assert_eq!(lines[0], "time_s,commanded,actual,following_error,output_v");
    assert_eq!(lines.len(), 33);
}

#[test]
fn bad_input_is_named_and_nothing_is_sent() {
    for (args, said) in [
        (
            &[
                "tune",
                "step",
                "--sim",
                "mccl",
                "--distance",
                "100",
                "--set",
                "KP=1",
            ][..],
            "KP is not a gain of this axis: the gains are SG, SD",
        ),
        (
            &[
                "tune",
                "step",
                "--sim",
                "mccl",
                "--distance",
                "100",
                "--set",
                "SG=11",
            ],
            "SG",
        ),
        (
            &[
                "tune",
                "step",
                "--sim",
                "mccl",
                "--distance",
                "100",
                "--samples",
                "2000",
            ],
            "1 … 1024 samples",
        ),
        (
            &[
                "tune",
                "step",
                "--sim",
                "mccl",
                "--axis",
                "9",
                "--distance",
                "100",
            ],
            "--axis 9: the mccl family's axes are 1",
        ),
        (
            &["tune", "step", "--sim", "tmcm1110", "--distance", "100"],
            "the tmcl family has no servo step-response test",
        ),
        (
            &[
                "tune",
                "stallguard",
                "--sim",
                "mccl",
                "--from",
                "1",
                "--to",
                "2",
            ],
            "the mccl family has no StallGuard2 sweep",
        ),
        (
            &[
                "tune",
                "stallguard",
                "--sim",
                "tmcm1110",
                "--from",
                "-100",
                "--to",
                "200",
            ],
            "crosses or touches 0",
        ),
    ] {
        let out = axterm(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(said), "{args:?}: {}", stderr(&out));
        assert!(stdout(&out).is_empty(), "{args:?}");
    }
}

fn sweep(load: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "tune",
        "stallguard",
        "--sim",
        "tmcm1110",
        "--input",
        load,
        "--from",
        "200",
        "--to",
        "1000",
        "--steps",
        "5",
    ];
    args.extend(extra);
    axterm(&args)
}

#[test]
fn a_sweep_reads_lower_under_load_and_two_sweeps_suggest_a_threshold() {
    let free = sweep("LOAD=0", &["--format", "json"]);
    assert_eq!(free.status.code(), Some(0), "{}", stderr(&free));
    let loaded = sweep("LOAD=60", &["--format", "json"]);
    assert_eq!(loaded.status.code(), Some(0), "{}", stderr(&loaded));
    let (free_json, loaded_json) = (json(&free), json(&loaded));
    let means = |v: &serde_json::Value| -> Vec<(i64, i64)> {
        v["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p["speed"].as_i64().unwrap(), p["mean"].as_i64().unwrap()))
            .collect()
    };
    let (free_means, loaded_means) = (means(&free_json), means(&loaded_json));
    assert_eq!(free_means.len(), 5);
    for (f, l) in free_means.iter().zip(&loaded_means) {
        assert_eq!(f.0, l.0);
        assert!(l.1 < f.1, "speed {}: loaded {} vs free {}", f.0, l.1, f.1);
    }
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("free.json");
    std::fs::write(&saved, stdout(&free)).unwrap();
    let out = sweep("LOAD=60", &["--compare", saved.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let said = stdout(&out);
    assert!(said.contains("to set it: SAP 174, 0, "), "{said}");
    assert!(said.contains("SAP 181, 0, "), "{said}");
    // An empty file is no sweep.
    let empty = dir.path().join("empty.json");
    std::fs::write(&empty, "").unwrap();
    let out = sweep("LOAD=60", &["--compare", empty.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("it holds no sweep"),
        "{}",
        stderr(&out)
    );
}

fn coolstep(load: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "tune",
        "coolstep",
        "--sim",
        "tmcm1110",
        "--input",
        load,
        "--set",
        "AP172=2",
        "--run",
        "1000",
        "--samples",
        "5",
        "--every",
        "400",
    ];
    args.extend(extra);
    axterm(&args)
}

#[test]
fn coolstep_lowers_the_current_without_load_and_shows_the_form_with_its_meanings() {
    let loaded = coolstep("LOAD=60", &["--format", "json"]);
    assert_eq!(loaded.status.code(), Some(0), "{}", stderr(&loaded));
    let free = coolstep("LOAD=0", &["--format", "json"]);
    assert_eq!(free.status.code(), Some(0), "{}", stderr(&free));
    let (loaded, free) = (json(&loaded), json(&free));
    let last = |v: &serde_json::Value| v["samples"][4]["share"].as_f64().unwrap();
    assert!(
        last(&free) < last(&loaded),
        "{} vs {}",
        last(&free),
        last(&loaded)
    );
    assert!(
        last(&loaded) < 1.0,
        "CoolStep lowers the current under 60 % load too"
    );
    let form = loaded["form"].as_array().unwrap();
    let ap172 = form.iter().find(|f| f["name"] == "AP172").expect("AP172");
    assert_eq!(ap172["value"], 2);
    assert!(
        ap172["meaning"]
            .as_str()
            .unwrap()
            .contains("turns CoolStep off")
    );
    // The motor turned at the asked speed while it was watched.
    assert_eq!(loaded["samples"][4]["speed"], 1000);
    let text = coolstep("LOAD=0", &[]);
    assert!(
        stdout(&text).contains("CoolStep saved"),
        "{}",
        stdout(&text)
    );
}

#[test]
fn coolstep_refuses_a_setting_outside_the_form_and_sends_nothing() {
    for (set, said) in [
        ("AP172=16", "AP172 takes 0..15, not 16"),
        ("AP180=3", "read only"),
        ("AP4=1", "not a CoolStep parameter"),
        ("AP172=1.5", "a whole number"),
    ] {
        let out = axterm(&["tune", "coolstep", "--sim", "tmcm1110", "--set", set]);
        assert_eq!(out.status.code(), Some(2), "{set}");
        assert!(stderr(&out).contains(said), "{set}: {}", stderr(&out));
        assert!(stdout(&out).is_empty());
    }
    let out = axterm(&["tune", "coolstep", "--sim", "cmd4cr"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no CoolStep current control"));
}

#[test]
fn the_stall_test_detects_a_stall_with_the_suggested_settings_and_not_without_load() {
    let apply = "SAP 174, 0, -16; SAP 181, 0, 600";
    let out = axterm(&[
        "tune",
        "stall-test",
        "--sim",
        "tmcm1110",
        "--input",
        "LOAD=60",
        "--speed",
        "800",
        "--apply",
        apply,
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("motor 0: stall detected"),
        "{}",
        stdout(&out)
    );
    let out = axterm(&[
        "tune",
        "stall-test",
        "--sim",
        "tmcm1110",
        "--input",
        "LOAD=0",
        "--speed",
        "800",
        "--give-up",
        "1",
        "--apply",
        apply,
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("NO stall detected within 1 s"),
        "{}",
        stdout(&out)
    );
    let out = axterm(&[
        "tune",
        "stall-test",
        "--sim",
        "tmcm1110",
        "--speed",
        "800",
        "--apply",
        "SAP 999, 0, 1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("parameter 999 outside 0..255 (nothing was sent)"));
}
