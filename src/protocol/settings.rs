//! What the console knows of settings a module cannot be asked for (the
//! SIXpack 2 reads none back, §7): the values written to it this session,
//! by parameter (a row of the family's [`super::parameters::ParameterSet`]),
//! and which of them are no longer known because the module was reset or
//! the link was lost since.
//!
//! A family says which parameters a line writes
//! ([`super::console::FamilyConsole::settings_written`]) and which lines
//! or answers mean that the module has forgotten them
//! ([`super::console::FamilyConsole::settings_lost`]); the session keeps
//! the [`SettingsCache`]; the parameter table shows it, exports it and
//! compares files with it, and the family's cautions check new values
//! against it. Pure data, no I/O.

use std::collections::BTreeMap;

use super::parameters::Scope;

/// One parameter a line writes, and the value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SettingWrite {
    pub scope: Scope,
    /// The row's number in the family's parameter tables.
    pub number: u16,
    pub value: i64,
}

/// What the console knows of one setting.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum KnownSetting {
    /// Written this session and not forgotten since: the module holds it,
    /// as far as anyone can tell (it acknowledges no setting).
    Written(i64),
    /// Written earlier, then the module was reset or the link lost
    /// (`why`): its value now is not known.
    Stale { was: i64, why: String },
}

impl KnownSetting {
    /// The value, while it is known.
    pub fn value(&self) -> Option<i64> {
        match self {
            KnownSetting::Written(value) => Some(*value),
            KnownSetting::Stale { .. } => None,
        }
    }
}

/// Every setting written this session, by parameter.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SettingsCache {
    entries: BTreeMap<(Scope, u16), KnownSetting>,
    /// Why what was written before is no longer known, when something
    /// made it so (the last reason).
    forgotten: Option<String>,
}

impl SettingsCache {
    /// What is known of a parameter.
    pub fn get(&self, scope: Scope, number: u16) -> Option<&KnownSetting> {
        self.entries.get(&(scope, number))
    }

    /// Its value, while known.
    pub fn value(&self, scope: Scope, number: u16) -> Option<i64> {
        self.get(scope, number).and_then(KnownSetting::value)
    }

    /// Record what a line wrote.
    pub fn record(&mut self, writes: &[SettingWrite]) {
        for write in writes {
            self.entries.insert(
                (write.scope, write.number),
                KnownSetting::Written(write.value),
            );
        }
    }

    /// Everything written is no longer known, because of `why`.
    pub fn forget(&mut self, why: &str) {
        for entry in self.entries.values_mut() {
            if let KnownSetting::Written(was) = *entry {
                *entry = KnownSetting::Stale {
                    was,
                    why: why.to_string(),
                };
            }
        }
        self.forgotten = Some(why.to_string());
    }

    /// Why the settings written before are no longer known, if they are
    /// not (for a parameter never written too: it may have been written
    /// before that and is not known either way).
    pub fn forgotten(&self) -> Option<&str> {
        self.forgotten.as_deref()
    }

    /// Whether nothing was written yet.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Every parameter known of, in table order.
    pub fn entries(&self) -> impl Iterator<Item = (Scope, u16, &KnownSetting)> {
        self.entries.iter().map(|(&(s, n), k)| (s, n, k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(number: u16, value: i64) -> SettingWrite {
        SettingWrite {
            scope: Scope::Axis(0),
            number,
            value,
        }
    }

    #[test]
    fn written_values_are_known_until_forgotten_and_written_again() {
        let mut cache = SettingsCache::default();
        assert!(cache.is_empty());
        cache.record(&[write(1, 10), write(2, 20)]);
        assert_eq!(cache.value(Scope::Axis(0), 1), Some(10));
        assert_eq!(cache.value(Scope::Axis(1), 1), None, "another axis");
        cache.forget("the unit was reset");
        assert_eq!(cache.value(Scope::Axis(0), 1), None);
        assert_eq!(
            cache.get(Scope::Axis(0), 2),
            Some(&KnownSetting::Stale {
                was: 20,
                why: "the unit was reset".into()
            })
        );
        assert_eq!(cache.forgotten(), Some("the unit was reset"));
        cache.record(&[write(2, 21)]);
        assert_eq!(cache.value(Scope::Axis(0), 2), Some(21));
        cache.forget("the link was lost");
        assert_eq!(
            cache.get(Scope::Axis(0), 1),
            Some(&KnownSetting::Stale {
                was: 10,
                why: "the unit was reset".into()
            }),
            "what was stale keeps its first reason"
        );
        assert_eq!(cache.entries().count(), 2);
    }
}
