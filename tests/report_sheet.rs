//! The commissioning sheet built from facts directly: the page parsed
//! with a real HTML parser, each section's facts found where a reader
//! looks; hostile strings shown as text; plots with every point; the
//! verdict in words; and every sheet's JSON valid against the schema.

mod report_support;

use axterm::report::{
    CheckOutcome, Checks, EmergencyStop, Ending, Expectation, Identity, LineKind, LineOutcome,
    ModuleSheet, Plot, RunEnd, RunLine, Series, SettingRow, Settings, Sheet, Tuning, Wiring,
    plot_svg, sheet_html, sheet_json,
};
use scraper::{Html, Selector};

const HOSTILE: &str = "<script>alert(1)</script> & co";

fn line(number: usize, text: &str, answer: &str, outcome: LineOutcome) -> RunLine {
    RunLine {
        number,
        text: text.into(),
        kind: LineKind::ConsoleLine,
        answer: Some(answer.into()),
        outcome,
    }
}

fn expectation(number: usize, line: &str, expected: &str, actual: &str, pass: bool) -> Expectation {
    Expectation {
        number,
        directive: "expect".into(),
        line: line.into(),
        expected: expected.into(),
        actual: Some(actual.into()),
        outcome: if pass {
            CheckOutcome::Pass
        } else {
            CheckOutcome::Fail
        },
    }
}

fn module(address: u8, firmware: &str, right_switch: &str) -> ModuleSheet {
    let passes = right_switch == "0";
    ModuleSheet {
        identity: Identity {
            family: "tmcl".into(),
            link: "--sim tmcm1110".into(),
            address,
            firmware: firmware.into(),
        },
        settings: Settings {
            parameter_file: Some("axis.toml".into()),
            rows: vec![
                SettingRow {
                    scope: "axis 0".into(),
                    number: 4,
                    name: "maximum positioning speed".into(),
                    value: Some(1000),
                    note: None,
                    factory_default: Some(1000),
                    unit: String::new(),
                    value_text: None,
                    default_text: None,
                },
                SettingRow {
                    scope: "axis 0".into(),
                    number: 6,
                    name: "absolute max current".into(),
                    value: Some(128),
                    note: None,
                    factory_default: Some(255),
                    unit: String::new(),
                    value_text: None,
                    default_text: None,
                },
                SettingRow {
                    scope: "axis 0".into(),
                    number: 140,
                    name: "microstep resolution".into(),
                    value: None,
                    note: Some("no answer".into()),
                    factory_default: Some(4),
                    unit: String::new(),
                    value_text: None,
                    default_text: None,
                },
            ],
            eeprom_stored: true,
            read: None,
        },
        checks: Checks {
            lines: vec![
                RunLine {
                    number: 1,
                    text: format!("# {HOSTILE}"),
                    kind: LineKind::Comment,
                    answer: None,
                    outcome: LineOutcome::Nothing,
                },
                line(2, "SAP 4, 0, 1000", "ok", LineOutcome::Ok),
                line(3, "GAP 10, 0", right_switch, LineOutcome::Ok),
            ],
            expectations: vec![
                expectation(4, "GAP 10, 0", "0", right_switch, passes),
                expectation(5, "GAP 11, 0", "0", "0", true),
            ],
            wiring: Some(Wiring {
                findings: vec!["motor 0: right switch fired moving + at 51200".into()],
                wired_right: true,
                faults: Vec::new(),
            }),
            emergency_stop: (!passes).then(|| EmergencyStop {
                reason: "the run failed".into(),
                lines: vec!["MST 0: ok".into()],
            }),
            run_end: RunEnd {
                ending: if passes {
                    Ending::Completed
                } else {
                    Ending::Failed
                },
                summary: if passes {
                    "the run completed".into()
                } else {
                    "the run failed: every axis stopped".into()
                },
                stopped_axes: if passes {
                    vec![]
                } else {
                    vec!["motor 0".into()]
                },
            },
        },
        tuning: None,
    }
}

fn sheet(modules: Vec<ModuleSheet>) -> Sheet {
    Sheet {
        run_file: "commission.txt".into(),
        operator: "Ada & Bob".into(),
        axterm_version: "0.1.0".into(),
        started_utc: "2026-03-07T14:05:09.123Z".into(),
        ended_utc: "2026-03-07T14:06:10.456Z".into(),
        modules,
    }
}

fn select<'a>(page: &'a Html, css: &str) -> Vec<scraper::ElementRef<'a>> {
    let selector = Selector::parse(css).expect("selector");
    page.select(&selector).collect()
}

fn text_of(element: &scraper::ElementRef) -> String {
    element.text().collect::<String>()
}

fn assert_valid(sheet: &Sheet) {
    let json = sheet_json(sheet);
    let problems = report_support::validate(&report_support::schema(), &json);
    assert!(problems.is_empty(), "{problems:#?}\n{json:#}");
}

#[test]
fn a_passing_sheet_says_so_first_and_shows_each_section() {
    let sheet = sheet(vec![module(1, "TMCM-1110 V1.23", "0")]);
    let page = Html::parse_document(&sheet_html(&sheet));
    // The verdict is the first section, in words.
    let first = &select(&page, "body > section")[0];
    assert_eq!(first.value().attr("id"), Some("verdict"));
    let headline = text_of(&select(&page, "#verdict .headline")[0]);
    assert!(headline.contains("✓ PASS"), "{headline}");
    // Two expectations, the wiring check and the run's end.
    assert!(headline.contains("All 4 checks passed"), "{headline}");

    let run = text_of(&select(&page, "#run")[0]);
    for fact in [
        "commission.txt",
        "Ada & Bob",
        "0.1.0",
        "2026-03-07T14:05:09.123Z",
    ] {
        assert!(run.contains(fact), "{fact} not in {run}");
    }
    let identity = text_of(&select(&page, "#module-1 .identity")[0]);
    for fact in ["tmcl", "--sim tmcm1110", "TMCM-1110 V1.23"] {
        assert!(identity.contains(fact), "{fact} not in {identity}");
    }
    let settings = text_of(&select(&page, "#module-1 .settings")[0]);
    assert!(settings.contains("axis.toml"), "{settings}");
    assert!(settings.contains("1 of 3 settings differ"), "{settings}");
    // Exactly the setting that differs is flagged, in words.
    let flagged: Vec<String> = select(&page, "#module-1 .settings-table tr.differs")
        .iter()
        .map(text_of)
        .collect();
    assert_eq!(flagged.len(), 1, "{flagged:?}");
    assert!(flagged[0].contains("absolute max current") && flagged[0].contains("≠ differs"));
    let expectations: Vec<String> = select(&page, "#module-1 .expectations tbody tr")
        .iter()
        .map(text_of)
        .collect();
    assert_eq!(expectations.len(), 2);
    assert!(expectations[0].contains("GAP 10, 0") && expectations[0].contains("✓ PASS"));
    let wiring = text_of(&select(&page, "#module-1 .wiring")[0]);
    assert!(wiring.contains("right switch fired"), "{wiring}");
    let end = text_of(&select(&page, "#module-1 .run-end")[0]);
    assert!(
        end.contains("completed") && end.contains("No emergency stop"),
        "{end}"
    );
    let lines = select(&page, "#module-1 .lines tbody tr");
    assert_eq!(lines.len(), 3);
    let tuning = text_of(&select(&page, "#module-1 .tuning")[0]);
    assert!(tuning.contains("No tuning"), "{tuning}");
    assert_valid(&sheet);
}

#[test]
fn a_failing_sheet_names_what_failed_and_the_emergency_stop() {
    let sheet = sheet(vec![module(1, "TMCM-1110 V1.23", "1")]);
    let verdict = sheet.verdict();
    assert!(!verdict.passed);
    assert_eq!((verdict.failed, verdict.checks), (2, 4));
    assert!(
        verdict
            .headline
            .starts_with("2 of 4 checks failed: line 4 `GAP 10, 0` expected 0, got 1"),
        "{}",
        verdict.headline
    );
    let page = Html::parse_document(&sheet_html(&sheet));
    let headline = text_of(&select(&page, "#verdict .headline")[0]);
    assert!(headline.contains("✗ FAIL"), "{headline}");
    let failures = select(&page, "#verdict .failures li");
    assert_eq!(failures.len(), 2);
    let row = text_of(&select(&page, "#module-1 .expectations tbody tr.fail")[0]);
    assert!(row.contains("✗ FAIL") && row.contains('1'), "{row}");
    let stop = text_of(&select(&page, "#module-1 .emergency-stop")[0]);
    assert!(
        stop.contains("EMERGENCY STOP") && stop.contains("MST 0: ok"),
        "{stop}"
    );
    let end = text_of(&select(&page, "#module-1 .run-end")[0]);
    assert!(end.contains("Axes stopped at the end: motor 0"), "{end}");
    assert_valid(&sheet);
}

#[test]
fn hostile_strings_show_as_text_and_make_no_element() {
    let sheet = sheet(vec![module(1, HOSTILE, "0")]);
    let html = sheet_html(&sheet);
    let page = Html::parse_document(&html);
    assert!(
        select(&page, "script").is_empty(),
        "a script element got in"
    );
    let firmware = text_of(&select(&page, "#module-1 .identity")[0]);
    assert!(firmware.contains(HOSTILE), "{firmware}");
    let comment = text_of(&select(&page, "#module-1 .lines tr.comment")[0]);
    assert!(comment.contains(HOSTILE), "{comment}");
    assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt; &amp; co"));
    assert_valid(&sheet);
}

#[test]
fn the_page_is_self_contained_and_prints_on_a4() {
    let mut module = module(1, "TMCM-1110 V1.23", "0");
    module.tuning = Some(Tuning {
        plots: vec![Plot {
            title: "Step response".into(),
            x_label: "time (ms)".into(),
            y_label: "position".into(),
            series: vec![Series {
                name: "actual".into(),
                points: vec![(0.0, 0.0), (1.0, 5.0)],
            }],
        }],
        figures: vec!["rise time 12 ms".into()],
    });
    let html = sheet_html(&sheet(vec![module]));
    let page = Html::parse_document(&html);
    assert!(select(&page, "script, link, img, iframe, object").is_empty());
    for attribute in ["src", "href"] {
        assert!(
            select(&page, &format!("[{attribute}]")).is_empty(),
            "an element refers to something outside the page"
        );
    }
    let style = text_of(&select(&page, "head style")[0]);
    assert!(style.contains("@page { size: A4"), "{style}");
    assert!(!style.contains("url("), "{style}");
    assert!(select(&page, "#module-1 .tuning svg").len() == 1);
    assert!(text_of(&select(&page, "#module-1 .tuning")[0]).contains("rise time 12 ms"));
}

#[test]
fn a_plot_has_a_point_for_every_pair_and_a_line_through_them() {
    let plot = Plot {
        title: "Speed & <current>".into(),
        x_label: "time (s)".into(),
        y_label: "speed".into(),
        series: vec![
            Series {
                name: "demand".into(),
                points: (0..7).map(|i| (f64::from(i), f64::from(i * i))).collect(),
            },
            Series {
                name: "actual".into(),
                points: vec![(0.0, 1.0), (3.0, 2.0), (6.0, 30.0)],
            },
        ],
    };
    let page = Html::parse_fragment(&plot_svg(&plot));
    let series = select(&page, "g.series");
    assert_eq!(series.len(), 2);
    for (group, expected) in series.iter().zip([7, 3]) {
        let points = group
            .select(&Selector::parse(".point").expect("selector"))
            .count();
        assert_eq!(points, expected);
        let polyline = group
            .select(&Selector::parse("polyline").expect("selector"))
            .next()
            .expect("a polyline");
        let pairs = polyline.value().attr("points").expect("points");
        assert_eq!(pairs.split_whitespace().count(), expected, "{pairs}");
    }
    let title = text_of(&select(&page, "title")[0]);
    assert_eq!(title, "Speed & <current>");
}

#[test]
fn several_modules_get_a_section_each_and_the_verdict_names_the_module() {
    let sheet = sheet(vec![module(1, "A", "0"), module(2, "B", "1")]);
    let verdict = sheet.verdict();
    assert_eq!((verdict.failed, verdict.checks), (2, 8));
    assert!(
        verdict.failures[0].starts_with("module 2 on --sim tmcm1110: line 4"),
        "{:?}",
        verdict.failures
    );
    let page = Html::parse_document(&sheet_html(&sheet));
    assert_eq!(select(&page, "section.module").len(), 2);
    let second = text_of(&select(&page, "#module-2 .verdict")[0]);
    assert!(second.contains("✗ FAIL"), "{second}");
    assert_valid(&sheet);
}

#[test]
fn the_schema_rejects_a_sheet_that_breaks_it() {
    // The validator is not a yes-machine: a wrong version, a missing
    // field and an unknown outcome are each found.
    let mut json = sheet_json(&sheet(vec![module(1, "A", "0")]));
    json["version"] = 2.into();
    json["modules"][0]["checks"]["expectations"][0]["outcome"] = "maybe".into();
    json.as_object_mut().expect("object").remove("operator");
    let problems = report_support::validate(&report_support::schema(), &json);
    assert_eq!(problems.len(), 3, "{problems:#?}");
}
