//! The console's downloads of a text with nothing in it: a session does
//! not plan a download of an empty program in any family that downloads
//! over the wire (the editor's download key goes through it), and the
//! editor does not load the in-process simulator with an empty A-Script
//! program (CMD-4CR, whose manual documents no download), as `axterm
//! download` and `--program` refuse an empty file.

mod ui_support;

use std::sync::{Arc, Mutex};

use axterm::families::{FAMILIES, find_family};
use axterm::link::LinkSpec;
use axterm::protocol::program::{DownloadOptions, DownloadWay, NoIncludes, TransferJob};
use axterm::session::{Cancel, Session, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use axterm::ui::PaneSetup;
use axterm::ui::app::{AppEvent, Effect};
use axterm::ui::pane::Snapshot;
use ratatui::crossterm::event::KeyCode;
use ui_support::{console_with, key, screen};

fn cmd4cr_snapshot() -> Snapshot {
    let family = find_family("cmd4cr").expect("cmd4cr");
    Snapshot {
        family,
        link_name: "sim cmd4cr".into(),
        axes: family.console.axes().to_vec(),
        status: vec![Default::default(); family.console.axes().len()],
        ..ui_support::snapshot(Vec::new())
    }
}

#[test]
fn an_empty_text_is_not_loaded_into_the_simulator() {
    let mut app = console_with(&PaneSetup::default());
    assert!(app.focus("editor"));
    app.handle(AppEvent::Connected(cmd4cr_snapshot()));
    let effects = app.handle(key(KeyCode::F(4)));
    assert!(
        !effects
            .iter()
            .any(|e| matches!(e, Effect::LoadProgram { .. })),
        "{effects:?}"
    );
    let all = screen(&mut app, 160, 30).join("\n");
    assert!(
        all.contains("nothing loaded: the text holds no program"),
        "{all}"
    );
}

#[tokio::test(start_paused = true)]
async fn no_session_downloads_an_empty_program() {
    let mut tried = 0;
    for family in FAMILIES {
        let (Some(tool), Some(kind)) = (family.console.program(), family.simulators.first()) else {
            continue;
        };
        if tool.download_way() != DownloadWay::Wire {
            continue;
        }
        let Some(program) = tool.check("empty", "", &NoIncludes).program else {
            continue;
        };
        tried += 1;
        let spec = LinkSpec::Sim {
            kind: kind.name.into(),
            sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
            baud: Some(115_200),
            faults: FaultPlan::none(),
        };
        let session = Session::connect(spec, family, SessionOptions::default())
            .await
            .expect("the simulator link opens");
        let job = TransferJob::Download {
            program,
            options: DownloadOptions::default(),
        };
        let refused = session
            .run_job(&job, &Cancel::new(), &mut |_| {})
            .await
            .expect_err("nothing to download");
        assert!(refused.nothing_sent(), "{}: {refused}", family.name);
        assert!(
            refused.to_string().contains("holds nothing to download"),
            "{}: {refused}",
            family.name
        );
    }
    assert!(
        tried > 0,
        "no family downloads an empty source over the wire"
    );
}
