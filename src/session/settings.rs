//! The settings written this session ([`SettingsCache`]), for a module
//! that cannot be asked for them: every line the session sends that the
//! family says writes a setting is recorded once it went out (and, if it
//! answers, was answered); a reset the family recognises, or the loss of
//! the link (the module may have been reset or powered off meanwhile),
//! makes them unknown.

use std::sync::Arc;

use tokio::sync::watch;

use super::Session;
use crate::device::LinkState;
use crate::protocol::console::{FamilyConsole, PreparedLine, Reading};
use crate::protocol::settings::SettingsCache;

/// Said of the settings written before the link was lost.
pub const LINK_LOST: &str = "the link was lost: the unit may have been reset or powered off";

/// The session's cache, shared by its clones.
pub(super) type SharedSettings = Arc<watch::Sender<SettingsCache>>;

/// A new cache that forgets what was written when the link `state` is
/// lost (watched by a task of the runtime the session is made in, if
/// any).
pub(super) fn new_cache(state: watch::Receiver<LinkState>) -> SharedSettings {
    let (cache, _) = watch::channel(SettingsCache::default());
    let cache = Arc::new(cache);
    if let Ok(runtime) = tokio::runtime::Handle::try_current() {
        let watched = Arc::downgrade(&cache);
        let mut state = state;
        runtime.spawn(async move {
            while state.changed().await.is_ok() {
                let lost = matches!(*state.borrow_and_update(), LinkState::Disconnected { .. });
                let Some(cache) = watched.upgrade() else {
                    return;
                };
                if lost {
                    cache.send_if_modified(|c| {
                        let had = !c.is_empty();
                        c.forget(LINK_LOST);
                        had
                    });
                }
            }
        });
    }
    cache
}

/// Record what `line` did to the settings, once sent and read as
/// `reading`.
pub(super) fn record(
    cache: &SharedSettings,
    console: &dyn FamilyConsole,
    line: &PreparedLine,
    reading: &Reading,
) {
    let lost = console.settings_lost(line, reading);
    let writes = console.settings_written(line);
    if lost.is_none() && writes.is_empty() {
        return;
    }
    cache.send_modify(|c| {
        if let Some(why) = &lost {
            c.forget(why);
        }
        c.record(&writes);
    });
}

impl Session {
    /// The settings written this session, as far as they are known (for a
    /// family whose module cannot be asked for them).
    pub fn settings(&self) -> watch::Receiver<SettingsCache> {
        self.settings.subscribe()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::parameters::Scope;
    use crate::protocol::settings::{KnownSetting, SettingWrite};
    use std::time::Duration;

    #[tokio::test(start_paused = true)]
    async fn a_lost_link_makes_what_was_written_unknown() {
        let (state, watched) = watch::channel(LinkState::Connected { link: "sim".into() });
        let cache = new_cache(watched);
        let mut settings = cache.subscribe();
        cache.send_modify(|c| {
            c.record(&[SettingWrite {
                scope: Scope::Axis(0),
                number: 0x1402,
                value: 300,
            }])
        });
        settings.borrow_and_update();
        state.send_replace(LinkState::Disconnected {
            reason: "unplugged".into(),
            attempts: 0,
            retry_in: Duration::from_millis(100),
        });
        settings.changed().await.expect("the cache is told");
        assert_eq!(
            settings.borrow().get(Scope::Axis(0), 0x1402),
            Some(&KnownSetting::Stale {
                was: 300,
                why: LINK_LOST.into()
            })
        );
    }
}
