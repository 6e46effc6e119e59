//! Macros (Ch4, Ch10): MD, TM, MC, MJ, HO, RM, byte accounting and −18,
//! PCI volatile against ETH non-volatile.

use super::*;
use crate::sim::mccl::Model;

/// The Ch8 TM example's macros, as the FE homing example defines them.
const HOMING: [&str; 7] = [
    "MD1,1LM2,1LN3,MJ10",
    "MD10,1VM,1DI0,1SV10000,1GO,LU\"STATUS\",1RL@0,IS24,MJ11,NO,IS17,MJ13,NO,JR-8",
    "MD11,LU\"STATUS\",1RL@0,IC24,MJ12,NO,JR-5",
    "MD12,1ST,1WS.1,1DI1,1SV5000,1GO,MJ14",
    "MD13,1WS0.01,1MN,1DI1,1SV5000,1GO,MJ14",
    "MD14,1FE0,1ST,1WS.1,1MF,1MN,1PM,1MA-100",
    "MD15,LU\"STATUS\",1RL@0,IS10,BK,NO,JR-5",
];

#[test]
fn tm_lists_the_manuals_macros_as_printed() {
    // Ch8 TM: 1TM-1 lists each macro as MC<n>, and its commands.
    let mut s = Session::new();
    s.quiet(&HOMING);
    let expected: Vec<String> = HOMING.iter().map(|l| l.replacen("MD", "MC", 1)).collect();
    assert_eq!(s.line("1TM-1"), expected);
    assert_eq!(s.line("TM12"), [expected[3].clone()]);
    assert_eq!(s.error("TM2"), -6);
    assert_eq!(s.error("TM-2"), -5);
}

#[test]
fn a_macro_defined_runs_with_mc_and_its_axis_rules() {
    // Ch4: MD3,1MR1000,WS0.25,MR-1000,WS0.25 then MC3.
    let mut s = Session::new();
    s.quiet(&["1MN", "md3,1mr1000,ws0.25,mr-1000,ws0.25"]);
    assert_eq!(s.line("TM3"), ["MC3,1MR1000,WS0.25,MR-1000,WS0.25"]);
    let exchange = s.exchange("MC3", 5000);
    assert!(exchange.lines.is_empty());
    // Two 0.14 s moves and two 0.25 s waits.
    assert!((750..850).contains(&exchange.ms), "{} ms", exchange.ms);
    assert_eq!(s.tell("1TT"), 0.0);
}

#[test]
fn ho_runs_the_axis_macro_and_9_without_one() {
    let mut s = Session::new();
    s.quiet(&["MD1,AL1,AR100", "MD9,AL9,AR100"]);
    s.quiet(&["1HO"]);
    assert_eq!(s.line("TR100"), ["01 1"]);
    s.quiet(&["HO"]);
    assert_eq!(s.line("TR100"), ["01 9"]);
    assert_eq!(s.error("2HO"), -6);
}

#[test]
fn redefinitions_use_memory_until_rm_and_then_minus_18() {
    // Ch10 MD: the old version's memory "will not be reused until a Reset
    // Macro command is issued"; Ch4: 510K in all, then -18.
    let mut s = Session::new();
    let body = vec!["1WS.5"; 25].join(",");
    let line = format!("MD5,{body}");
    let fits = crate::sim::mccl::macros::MACRO_MEMORY / 250;
    for _ in 0..fits {
        s.quiet(&[line.as_str()]);
    }
    assert_eq!(s.sim.macros().used(), fits * 250);
    assert_eq!(s.error(&line), -18);
    assert_eq!(s.error("MD6,NO,NO,NO,NO,NO,NO,NO,NO,NO,NO,NO"), -18);
    s.quiet(&["RM", line.as_str()]);
    assert_eq!(s.sim.macros().used(), 250);
}

#[test]
fn a_pci_loses_its_macros_at_rt_and_an_eth_keeps_them() {
    let mut pci = Session::new();
    pci.quiet(&["MD5,NO", "RT"]);
    assert_eq!(pci.error("MC5"), -6);
    let mut eth = Session::with(SimConfig::eth(None));
    assert_eq!(eth.sim.model(), Model::Eth);
    eth.quiet(&["MD5,AL5,AR100", "RT", "MC5"]);
    assert_eq!(eth.line("TR100"), ["01 5"]);
}

#[test]
fn an_eth_keeps_its_macros_in_its_file_until_rm() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("macros.json");
    {
        let mut s = Session::with(SimConfig::eth(Some(file.clone())));
        s.quiet(&["MD7,AL7,AR100", "MD8,OT\"a,b\""]);
    }
    let mut s = Session::with(SimConfig::eth(Some(file.clone())));
    assert_eq!(s.line("TM-1"), ["MC7,AL7,AR100", "MC8,OT\"a,b\""]);
    s.quiet(&["MC7"]);
    assert_eq!(s.line("TR100"), ["01 7"]);
    s.quiet(&["RM"]);
    let s = Session::with(SimConfig::eth(Some(file)));
    assert_eq!(s.sim.macros().used(), 0);
}

#[test]
fn mj_does_not_return() {
    let mut s = Session::new();
    s.quiet(&["MD20,AL20,AR100", "MD21,MJ20,AL21,AR100"]);
    s.quiet(&["MC21,AL22,AR101"]);
    assert_eq!(s.line("TR100,TR101"), ["01 20", "01 22"]);
}

#[test]
fn a_macro_calling_itself_runs_out_of_nesting() {
    let mut s = Session::new();
    s.quiet(&["MD30,MC30"]);
    assert_eq!(s.error("MC30"), -18);
}

#[test]
fn single_step_as_the_ch4_transcript() {
    // Ch4: MC10 of 1MR1000,1WS.1,1TP,1MR-1000,1WS.1,1TP,BK"wait",RP1.
    let mut s = Session::new();
    s.quiet(&[
        "1MN",
        "MD10,1MR1000,1WS0.1,1TP,1MR-1000,1WS0.1,1TP,BK\"wait\",RP1",
    ]);
    let mut out = s.typed("mc10\r");
    out.push_str(&s.advance_ms(1000));
    let lines: Vec<&str> = out.split("\r\n").collect();
    assert_eq!(lines[0], "mc10");
    assert!(lines[1].starts_with("01 "), "{out:?}");
    assert_eq!(lines[2], "01 0");
    assert_eq!(lines[3], "BREAK AT COMMAND 6, MACRO 10");
    assert_eq!(lines[4], "wait");
    assert_eq!(lines[5], "{C7,M10} RP1 [REPEAT] <");
    assert!(s.sim.busy(), "stepping");
    // Space runs the next command (RP: back to the start) and shows the next.
    assert_eq!(s.typed(" "), "{C0,M10} 1MR1000 <");
    // Enter ends stepping; the macro runs to its end (one more round).
    s.typed("\r");
    let rest = s.advance_ms(1000);
    assert!(
        rest.contains("BREAK AT COMMAND 6, MACRO 10\r\nwait\r\n"),
        "{rest:?}"
    );
    s.typed("\r");
    let end = s.advance_ms(10);
    assert!(end.ends_with('>'), "{end:?}");
}

#[test]
fn a_corrupt_store_fault_changes_what_tm_lists() {
    // `--fault corrupt-store=2`: the second macro stored keeps a changed
    // parameter while the reply says all is well; TM shows it.
    use crate::sim::faults::FaultPlan;
    let mut s = Session::new();
    let plan = FaultPlan::parse("corrupt-store=2").expect("plan");
    s.sim.arm_faults(&plan);
    s.quiet(&["MD1,1MR1000", "MD2,1MR1000", "MD3,1MR1000"]);
    assert_eq!(
        s.line("TM-1"),
        ["MC1,1MR1000", "MC2,1MR1001", "MC3,1MR1000"]
    );
    assert_eq!(plan.counts().corrupted_stores, 1);
}

#[test]
fn help_names_the_model_and_every_choice() {
    let s = Session::new();
    let help = s.sim.help();
    assert!(help.starts_with("MultiFlex PCI simulator"), "{help}");
    for choice in crate::sim::mccl::choices::CHOICES {
        assert!(help.contains(choice.choice), "{}", choice.topic);
    }
    assert!(help.contains("LIM+1..LIM+8=0|1"), "{help}");
}
