//! Where and when a result was measured: the commit, the date and the machine, as a results
//! page states them beside its numbers (`ftwire reproduce --docs`).

use std::time::{SystemTime, UNIX_EPOCH};

use serde::Serialize;

use crate::header::{GIT_REVISION, VERSION};

/// The build, the date and the machine of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Provenance {
    /// The ftwire version.
    pub version: String,
    /// The git revision of the build (`unknown` when it was built outside a repository).
    pub commit: String,
    /// The day of the run, UTC, `YYYY-MM-DD`.
    pub date: String,
    /// The processor's model name (`/proc/cpuinfo`), or `unknown`.
    pub cpu: String,
    /// Threads the machine offers this process.
    pub cores: usize,
    /// Memory \[GiB\] (`/proc/meminfo`), when known.
    pub memory_gib: Option<f64>,
    /// Operating system and architecture, e.g. `linux x86_64`.
    pub os: String,
}

impl Provenance {
    /// The provenance of a run made now on this machine.
    pub fn here() -> Self {
        let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
        let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
        let days = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs() / 86_400);
        Self {
            version: VERSION.to_owned(),
            commit: GIT_REVISION.to_owned(),
            date: civil_date(days),
            cpu: cpu_model(&cpuinfo).unwrap_or_else(|| "unknown".to_owned()),
            cores: std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
            memory_gib: memory_gib(&meminfo),
            os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
        }
    }

    /// One line for a results page: `commit abc1234, 2026-11-28, Intel Xeon (2 threads,
    /// 23.4 GiB), linux x86_64`.
    pub fn line(&self) -> String {
        let memory = self
            .memory_gib
            .map_or_else(String::new, |gib| format!(", {gib:.1} GiB"));
        format!(
            "ftwire {} at commit `{}`, {}, {} ({} threads{memory}), {}",
            self.version, self.commit, self.date, self.cpu, self.cores, self.os
        )
    }
}

/// The first `model name` of a `/proc/cpuinfo` text.
fn cpu_model(cpuinfo: &str) -> Option<String> {
    cpuinfo
        .lines()
        .find(|line| line.starts_with("model name"))
        .and_then(|line| line.split_once(':'))
        .map(|(_, name)| name.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|name| !name.is_empty())
}

/// `MemTotal` of a `/proc/meminfo` text \[GiB\].
fn memory_gib(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|line| line.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / (1024.0 * 1024.0))
}

/// The date `YYYY-MM-DD` (proleptic Gregorian, UTC) of `days` since 1970-01-01, by the
/// civil-from-days algorithm (eras of 400 years, March-based years).
fn civil_date(days: u64) -> String {
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_fall_on_the_calendar() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(59), "1970-03-01");
        // 2000-02-29 (a leap day of a century divisible by 400) and the day after.
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(11_017), "2000-03-01");
        assert_eq!(civil_date(20_785), "2026-11-28");
    }

    #[test]
    fn the_machine_is_read_from_proc_texts() {
        let cpuinfo = "processor\t: 0\nmodel name\t: Intel(R)  Xeon(R) CPU\nflags\t: x\n";
        assert_eq!(cpu_model(cpuinfo).as_deref(), Some("Intel(R) Xeon(R) CPU"));
        assert_eq!(cpu_model("processor : 0\n"), None);
        let gib = memory_gib("MemTotal:       24576000 kB\nMemFree: 1 kB\n").unwrap_or(0.0);
        assert!((gib - 23.4375).abs() < 1e-9);
        let p = Provenance::here();
        assert!(p.cores >= 1);
        assert!(p.line().contains(&p.date));
    }
}
