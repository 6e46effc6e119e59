//! Wall-clock time as a technician reads it in a log or a recording's
//! header: the calendar date and time of day in UTC (no time-zone
//! database is needed, and a file read on another machine means the
//! same). Pure arithmetic on seconds since the Unix epoch; the caller
//! reads the clock.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// A moment as calendar fields (UTC).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CivilTime {
    pub year: i64,
    pub month: u32,
    pub day: u32,
    pub hour: u32,
    pub minute: u32,
    pub second: u32,
    pub millisecond: u32,
}

impl CivilTime {
    /// The calendar fields of `time` (before 1970: the epoch).
    pub fn of(time: SystemTime) -> CivilTime {
        CivilTime::since_epoch(time.duration_since(UNIX_EPOCH).unwrap_or(Duration::ZERO))
    }

    /// The calendar fields `since` after 1970-01-01 00:00:00 UTC.
    pub fn since_epoch(since: Duration) -> CivilTime {
        let seconds = since.as_secs();
        let days = i64::try_from(seconds / 86_400).unwrap_or(i64::MAX / 2);
        let of_day = seconds % 86_400;
        let (year, month, day) = civil_from_days(days);
        CivilTime {
            year,
            month,
            day,
            hour: (of_day / 3600) as u32,
            minute: (of_day % 3600 / 60) as u32,
            second: (of_day % 60) as u32,
            millisecond: since.subsec_millis(),
        }
    }

    /// `2025-03-07 14:05:09 UTC`, for headers.
    pub fn date_time(&self) -> String {
        format!(
            "{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC",
            self.year, self.month, self.day, self.hour, self.minute, self.second
        )
    }

    /// `2025-03-07T14:05:09.123Z` (ISO 8601), for a line of a log.
    pub fn stamp(&self) -> String {
        format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z",
            self.year, self.month, self.day, self.hour, self.minute, self.second, self.millisecond
        )
    }

    /// `axterm-20250307-140509.log`: the name `:log` picks when given none.
    pub fn log_file_name(&self) -> String {
        format!(
            "axterm-{:04}{:02}{:02}-{:02}{:02}{:02}.log",
            self.year, self.month, self.day, self.hour, self.minute, self.second
        )
    }
}

/// Year, month, day of the day `days` after 1970-01-01 (proleptic
/// Gregorian calendar; H. Hinnant's "days from civil" inverted).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn known_moments() {
        let epoch = CivilTime::since_epoch(Duration::ZERO);
        assert_eq!(epoch.date_time(), "1970-01-01 00:00:00 UTC");
        // 2000-02-29 (a leap day of a century leap year) 12:34:56.789.
        let leap = CivilTime::since_epoch(Duration::from_millis(951_827_696_789));
        assert_eq!(leap.stamp(), "2000-02-29T12:34:56.789Z");
        // 2024-12-31 23:59:59, the last second of a leap year.
        let end = CivilTime::since_epoch(Duration::from_secs(1_735_689_599));
        assert_eq!(end.date_time(), "2024-12-31 23:59:59 UTC");
        assert_eq!(end.log_file_name(), "axterm-20241231-235959.log");
        // 2100-03-01: 2100 is no leap year.
        let after = CivilTime::since_epoch(Duration::from_secs(4_107_542_400));
        assert_eq!(after.date_time(), "2100-03-01 00:00:00 UTC");
    }

    proptest! {
        #[test]
        fn fields_stay_in_range_and_days_follow_each_other(seconds in 0u64..10_000_000_000) {
            let t = CivilTime::since_epoch(Duration::from_secs(seconds));
            prop_assert!((1..=12).contains(&t.month));
            prop_assert!((1..=31).contains(&t.day));
            prop_assert!(t.hour < 24 && t.minute < 60 && t.second < 60);
            let next = CivilTime::since_epoch(Duration::from_secs(seconds + 86_400));
            // The next day is the day after: same month one day on, or the
            // first of the next month (or year).
            let follows = (next.year, next.month, next.day) == (t.year, t.month, t.day + 1)
                || (next.day == 1 && ((next.year, next.month) == (t.year, t.month + 1)
                    || (next.year, next.month, t.month) == (t.year + 1, 1, 12)));
            prop_assert!(follows, "{:?} then {:?}", t, next);
        }
    }
}
