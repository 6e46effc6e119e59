//! The console's controller converts a typed line in an axis's unit with
//! the mechanics in force and the module's own settings, read first
//! (issue 20, point 3); a line that does not convert or validate sends
//! nothing.

use std::sync::{Arc, Mutex, RwLock};

use axterm::families::find_kind;
use axterm::link::LinkSpec;
use axterm::protocol::units::MechanicsTable;
use axterm::session::{ReplyValue, Session, SessionError, SessionOptions};
use axterm::sim::SimOptions;
use axterm::sim::faults::FaultPlan;
use axterm::ui::app::Controller;
use axterm::ui::live::SessionController;

async fn connect() -> Session {
    let kind = find_kind("tmcm1110").expect("registered");
    let spec = LinkSpec::Sim {
        kind: kind.name.into(),
        sim: Arc::new(Mutex::new((kind.build)(&SimOptions::default()))),
        baud: None,
        faults: FaultPlan::none(),
    };
    let family = axterm::families::family_of(kind).expect("family");
    Session::connect(spec, family, SessionOptions::default())
        .await
        .expect("the simulator link opens")
}

fn mechanics(text: &str) -> MechanicsTable {
    let (table, _) = MechanicsTable::parse_file(text).expect("mechanics");
    table
}

const MM_AXIS: &str = "[mechanics.0]\nunit = \"mm\"\nfull_steps_per_rev = 200\nmicrosteps = 256\n\
                       travel_per_rev = 5\n";

#[tokio::test(start_paused = true)]
async fn a_typed_unit_line_is_converted_with_the_module_s_settings() {
    let session = connect().await;
    let controller =
        SessionController::new(session.clone(), "sim".into(), SessionOptions::default())
            .with_mechanics(Arc::new(RwLock::new(MechanicsTable::default())));
    // None in force: refused, nothing sent.
    let refused = controller.execute("SAP 1, 0, 1mm".into()).await;
    assert!(
        matches!(&refused, Err(SessionError::Refused { message, .. }) if message.contains("no mechanics")),
        "{refused:?}"
    );
    controller
        .set_mechanics(mechanics(MM_AXIS))
        .expect("axis 0 is there");
    assert!(
        controller
            .set_mechanics(mechanics(&MM_AXIS.replace("mechanics.0", "mechanics.2")))
            .unwrap_err()
            .contains("axis 2")
    );
    let result = controller
        .execute("SAP 1, 0, 2.5mm".into())
        .await
        .expect("converted and sent");
    assert_eq!(result.line, "SAP 1, 0, 25600");
    let read = session.execute_line("GAP 1, 0").await.expect("read");
    assert_eq!(read.value, ReplyValue::Number(25600));
    session
        .execute_line("SAP 154, 0, 3")
        .await
        .expect("written");
    // §6.1.1: 51208.5 pps at divisor 3 is 1678; 5 mm/s is 51200 pps.
    let result = controller
        .execute("SAP 4, 0, 5mm/s".into())
        .await
        .expect("converted and sent");
    assert_eq!(result.line, "SAP 4, 0, 1678");
    let refused = controller.execute("SAP 4, 0, 500mm/s".into()).await;
    assert!(
        matches!(&refused, Err(SessionError::Refused { message, .. })
            if message.contains("500mm/s → 167772") && message.contains("1..2047")),
        "{refused:?}"
    );
    let read = session.execute_line("GAP 4, 0").await.expect("read");
    assert_eq!(
        read.value,
        ReplyValue::Number(1678),
        "the refused line sent nothing"
    );
}
