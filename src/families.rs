//! The registry: every controller family axterm speaks, each with its
//! built-in simulators. It sits above both `protocol/` (which knows the
//! families) and `sim/` (which knows the simulated controllers), so that
//! neither names the other's list. A new family is one entry in
//! [`FAMILIES`].

use std::ops::Deref;

use crate::protocol::{self, Family};
use crate::sim::{self, SimKind};

/// One family and its simulators.
pub struct Registered {
    pub family: &'static Family,
    /// The built-in simulators of controllers of this family (`--sim
    /// NAME`), in the order the connect screen offers them.
    pub simulators: &'static [SimKind],
}

impl Deref for Registered {
    type Target = Family;

    fn deref(&self) -> &Family {
        self.family
    }
}

/// Every family axterm speaks, in the order help and the connect screen
/// list them.
pub static FAMILIES: &[Registered] = &[
    Registered {
        family: &protocol::tmcl::FAMILY,
        simulators: &[sim::tmcm1110::KIND],
    },
    Registered {
        family: &protocol::cmd4cr::FAMILY,
        simulators: &[sim::cmd4cr::KIND],
    },
    Registered {
        family: &protocol::sixpack2::FAMILY_AUTO,
        simulators: &[sim::sixpack2::KIND],
    },
    Registered {
        family: &protocol::mccl::FAMILY,
        simulators: &[sim::mccl::KIND_PCI, sim::mccl::KIND_ETH],
    },
];

/// The family called `name` (case-insensitive).
pub fn find_family(name: &str) -> Option<&'static Family> {
    FAMILIES
        .iter()
        .find(|f| f.name.eq_ignore_ascii_case(name))
        .map(|f| f.family)
}

/// Names of every family, for error messages.
pub fn family_names() -> String {
    FAMILIES
        .iter()
        .map(|f| f.name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The simulators of `family`, also of a variant a link option chose (a
/// SIXpack 2 reading 8-byte replies only is still a SIXpack 2).
pub fn simulators_of(family: &Family) -> &'static [SimKind] {
    FAMILIES
        .iter()
        .find(|f| f.name == family.name)
        .map_or(&[], |f| f.simulators)
}

/// The family whose entry lists the simulator `kind` (the one it speaks).
pub fn family_of(kind: &SimKind) -> Option<&'static Family> {
    FAMILIES
        .iter()
        .find(|f| f.simulators.iter().any(|k| k.name == kind.name))
        .map(|f| f.family)
}

/// Every built-in simulator, in the order of the families that list them.
pub fn kinds() -> impl Iterator<Item = &'static SimKind> {
    FAMILIES.iter().flat_map(|f| f.simulators.iter())
}

/// The simulator called `name` (case-insensitive), if there is one.
pub fn find_kind(name: &str) -> Option<&'static SimKind> {
    kinds().find(|k| k.name.eq_ignore_ascii_case(name))
}

/// Names of every simulator, for error messages and help.
pub fn kind_names() -> String {
    kinds().map(|k| k.name).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_and_simulator_is_found_by_its_name_and_each_other() {
        for registered in FAMILIES {
            let family = find_family(&registered.name.to_uppercase()).expect("by name");
            assert!(std::ptr::eq(family, registered.family));
            assert!(!simulators_of(family).is_empty(), "{}", family.name);
            for kind in registered.simulators {
                assert!(std::ptr::eq(find_kind(kind.name).expect("by name"), kind));
                assert_eq!(family_of(kind).map(|f| f.name), Some(family.name));
            }
        }
        assert!(find_family("tmcm").is_none());
        assert!(find_kind("nothing").is_none());
    }

    #[test]
    fn a_variant_chosen_by_a_link_option_keeps_its_family_s_simulators() {
        let strict = protocol::with_link_options(
            find_family("sixpack2").expect("registered"),
            &["framing=cmd8".into()],
        )
        .expect("known");
        assert_eq!(
            simulators_of(strict)
                .iter()
                .map(|k| k.name)
                .collect::<Vec<_>>(),
            ["sixpack2"]
        );
    }
}
