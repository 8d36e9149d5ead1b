//! Times as btx prints them: µs since the epoch as UTC dates, times of
//! day and RFC 3339, and the local zone's offset.

/// The local time zone's offset from UTC at `us` (µs since the epoch), in
/// seconds, as `date` finds it (the `TZ` environment, else the system's).
pub fn local_offset_s(us: i64) -> i64 {
    // time_t is 64 bits on every target btx builds for.
    let t: libc::time_t = us.div_euclid(1_000_000);
    // SAFETY: an all-zero `tm` is a valid value of this plain C struct.
    let mut tm: libc::tm = unsafe { std::mem::zeroed() };
    // SAFETY: localtime_r reads `t` and writes only `tm`, both ours.
    let ok = unsafe { !libc::localtime_r(&t, &mut tm).is_null() };
    if ok {
        tm.tm_gmtoff
    } else {
        0
    }
}

/// An offset from UTC in seconds as `UTC+05:30`.
pub fn utc_offset(secs: i64) -> String {
    let sign = if secs < 0 { '-' } else { '+' };
    let m = secs.abs() / 60;
    format!("UTC{sign}{:02}:{:02}", m / 60, m % 60)
}

/// A UTC time of µs since the epoch, as `2026-11-25 22:11:20.123`.
pub fn utc(us: i64) -> String {
    let secs = us.div_euclid(1_000_000);
    let ms = us.rem_euclid(1_000_000) / 1000;
    let (days, rest) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02}.{ms:03}",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// The UTC time of day of µs since the epoch, to the microsecond
/// (`01:55:41.796157`): as answers say a moment's time, exact, so that
/// `--at` given it goes to that very moment.
pub fn clock(us: i64) -> String {
    format!("{}{:06}", &utc(us)[11..20], us.rem_euclid(1_000_000))
}

/// A UTC time of µs since the epoch as RFC 3339 with microseconds:
/// `2026-11-25T22:11:20.123456Z`.
pub fn rfc3339(us: i64) -> String {
    let day = utc(us);
    format!(
        "{}T{}{:06}Z",
        &day[..10],
        &day[11..20],
        us.rem_euclid(1_000_000)
    )
}

#[cfg(test)]
mod utc_tests {
    #[test]
    fn utc_times_are_civil_dates() {
        assert_eq!(super::utc(0), "1970-01-01 00:00:00.000");
        assert_eq!(super::utc(1_795_646_839_875_037), "2026-11-25 22:47:19.875");
        assert_eq!(super::utc(951_782_400_000_000), "2000-02-29 00:00:00.000");
    }
}
