//! Records at one rest, pooled for the labels.
//!
//! A rig that logs one reading per record at a fixed rate logs two or three records at a rest
//! where the robot waited. Their markers see the same wire: averaging them (marker by marker,
//! over the records that saw it) halves the motion-capture jitter the label is fitted to. A
//! record joins the rest of the record before it when each marker seen in both moved less
//! than the tolerance on average from the rest's first record; the first marker (at the
//! clamp) does not move and is left out of the comparison.

use ftwire_estimate::log::LogRecord;
use serde::Serialize;

/// How records were pooled.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Pooling {
    /// The tolerance \[mm\] (0: no pooling).
    pub tolerance_mm: f64,
    /// Rests found (groups of consecutive records; a record alone is a rest of one).
    pub rests: usize,
    /// Records that share their rest with another record (their labels are fitted to the
    /// rest's mean markers).
    pub pooled_records: usize,
}

/// The mean distance \[m\] between two records' markers seen in both (after the first);
/// `None` when they share none.
fn moved(a: &LogRecord, b: &LogRecord) -> Option<f64> {
    let (Some(ma), Some(mb)) = (&a.markers, &b.markers) else {
        return None;
    };
    if ma.len() != mb.len() {
        return None;
    }
    let d: Vec<f64> = ma
        .iter()
        .zip(mb)
        .skip(1)
        .filter_map(|(p, q)| {
            let (p, q) = (p.as_ref()?, q.as_ref()?);
            Some(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt())
        })
        .collect();
    #[allow(clippy::cast_precision_loss)] // a handful of markers
    (!d.is_empty()).then(|| d.iter().sum::<f64>() / d.len() as f64)
}

/// The records with each rest's markers replaced by their mean over the rest, and the counts.
/// `tolerance` \[m\]; zero leaves every record alone.
pub fn pool(records: &[LogRecord], tolerance: f64) -> (Vec<LogRecord>, Pooling) {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, record) in records.iter().enumerate() {
        let joins = groups.last().is_some_and(|g| {
            tolerance > 0.0
                && record.markers.is_some()
                && moved(&records[g[0]], record).is_some_and(|d| d < tolerance)
        });
        match groups.last_mut() {
            Some(g) if joins => g.push(k),
            _ => groups.push(vec![k]),
        }
    }
    let mut out = records.to_vec();
    let mut pooled_records = 0;
    for group in groups.iter().filter(|g| g.len() > 1) {
        pooled_records += group.len();
        let count = records[group[0]].markers.as_ref().map_or(0, Vec::len);
        let mean: Vec<Option<[f64; 3]>> = (0..count)
            .map(|j| {
                let seen: Vec<[f64; 3]> = group
                    .iter()
                    .filter_map(|&k| records[k].markers.as_ref()?.get(j).copied().flatten())
                    .collect();
                #[allow(clippy::cast_precision_loss)] // two or three records
                let n = seen.len() as f64;
                (!seen.is_empty())
                    .then(|| std::array::from_fn(|i| seen.iter().map(|p| p[i]).sum::<f64>() / n))
            })
            .collect();
        for &k in group {
            out[k].markers = Some(mean.clone());
        }
    }
    (
        out,
        Pooling {
            tolerance_mm: 1e3 * tolerance,
            rests: groups.len(),
            pooled_records,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(time: f64, x: f64) -> LogRecord {
        LogRecord {
            time,
            raw: Some([0.0; 6]),
            a: None,
            b: None,
            markers: Some(vec![Some([0.0; 3]), Some([x, 0.1, 0.0]), None]),
            gravity: None,
        }
    }

    #[test]
    fn records_within_the_tolerance_share_their_mean_markers() {
        let records = [
            record(0.0, 0.100),
            record(0.25, 0.1004),
            record(0.5, 0.117),
            record(0.75, 0.134),
            record(1.0, 0.1346),
        ];
        let (out, pooling) = pool(&records, 2e-3);
        assert_eq!(pooling.rests, 3);
        assert_eq!(pooling.pooled_records, 4);
        let x = |k: usize| out[k].markers.as_ref().and_then(|m| m[1]).map(|p| p[0]);
        assert_eq!(x(0), x(1));
        assert!((x(0).unwrap_or(0.0) - 0.1002).abs() < 1e-12);
        assert_eq!(x(2), Some(0.117));
        assert!(out[0].markers.as_ref().is_some_and(|m| m[2].is_none()));
        let (alone, none) = pool(&records, 0.0);
        assert_eq!(none.rests, 5);
        assert_eq!(none.pooled_records, 0);
        assert_eq!(alone, records.to_vec());
    }
}
